#pragma once
// Quality refinement for options.min_angle_deg.

#include <cstdint>

#include "density/size_field.hpp"
#include "meshd/core/domain.hpp"
#include "meshd/core/mesh.hpp"
#include "meshd/core/observer.hpp"

namespace meshd::core {

/// Inserts circumcentres (or splits the constrained edges they encroach) until no triangle
/// has an angle below min_angle_deg, except between two constrained edges and in triangles
/// whose shortest edge is below a tenth of the local size; keeps the mesh constrained
/// Delaunay. A split boundary edge gets its new point on the domain's curve (at the mean
/// parameter of its ends), not on the chord. Stops at max_points (0: no limit). Returns the
/// number of points added.
std::uint64_t refine_min_angle(Mesh& mesh, const Domain& domain, const SizeField& rho,
                               double min_angle_deg, size_t max_points = 0,
                               Observer* observer = nullptr);

}  // namespace meshd::core
