#pragma once
// The quality figures of a mesh (QualityMetrics, mesh.hpp) and the measures of one
// triangle that smoothing shares.

#include <array>
#include <cstdint>

#include "density/size_field.hpp"
#include "meshd/core/mesh.hpp"

namespace meshd::core {

/// The largest cotangent of the three angles of a counter-clockwise triangle of positive
/// area, i.e. that of its smallest angle (the cotangent falls as the angle grows), and the
/// corner (0, 1, 2 for a, b, c) where it is. Divisions only: for scans over whole meshes.
struct CornerCot {
    double cot;
    int corner;
};
CornerCot smallest_angle_cot(Vec2 a, Vec2 b, Vec2 c);

/// The figures of a mesh. rho gives the target size (interior density, or the curve's on
/// boundary edges).
QualityMetrics measure_quality(const Mesh& mesh, const SizeField& rho);

}  // namespace meshd::core
