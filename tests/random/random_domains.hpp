#pragma once
// Random valid domains for the property tests and the census tool (meshd-random-census):
// star-shaped outer loops of lines, a spline or a circle; circular and polygonal holes, some
// with an embedded spoke ending on the circle; an embedded line from a corner of the outer
// loop into the domain; constant, linear or radial densities; everything scaled by
// 10^-6..10^6 and shifted up to 10^5 of its own size away from the origin. A seed always
// gives the same case.

#include <cstdint>
#include <optional>
#include <string>
#include <utility>

#include "meshd/core/density.hpp"
#include "meshd/core/domain.hpp"
#include "meshd/core/mesh.hpp"
#include "meshd/core/mesher.hpp"

namespace meshd::test {

struct RandomCase {
    core::DomainSpec domain;
    core::DensitySpec density;
    std::string summary;
};

// Seed's domain and density.
RandomCase random_case(std::uint64_t seed);

// Boundary layers for seed's case on its holes, its spline outer loop or the lines' inlet
// side (whichever of those tags the domain has; a random first height from 1e-5 to 1e-3 of
// the domain, growth 1.1 to 1.3, 5 to 30 layers), or nothing when it has none of them.
std::optional<core::BoundaryLayerSpec> layers_for(std::uint64_t seed, const RandomCase& rc, const core::Domain& domain);

// The smallest angle of the isotropic triangles of m but for those filling a wedge of the
// domain alone (both sides on curves), and where it is.
std::pair<double, core::Vec2> smallest_free_angle(const core::Mesh& m);

// Whether two meshes are the same bit for bit: the points in the same order, and the same
// corners for each triangle (what the interior's crossing proofs must leave unchanged).
bool same_mesh(const core::Mesh& a, const core::Mesh& b);

}  // namespace meshd::test
