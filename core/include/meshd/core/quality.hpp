#pragma once
/// Mesh quality figures, as the service reports them (API.md, "metrics").

#include <array>
#include <cstdint>

#include "meshd/core/density.hpp"
#include "meshd/core/mesh.hpp"

namespace meshd::core {

struct QualityMetrics {
    size_t points = 0, boundary_points = 0, interior_points = 0, triangles = 0;
    double angle_min = 0, angle_max = 0, angle_mean = 0;  ///< degrees
    /// Radius ratio 2 r_in / r_circ: 1 for an equilateral triangle.
    double quality_min = 0, quality_mean = 0;
    std::array<std::uint64_t, 10> quality_histogram{};  ///< 10 equal bins over [0, 1]
    /// Edge length / rho at the edge's midpoint, over all edges.
    double size_ratio_mean = 0;
    double size_ratio_within_sqrt2 = 0;  ///< fraction with a ratio in [1/sqrt 2, sqrt 2]
};

/// Radius ratio of a triangle (0 when degenerate).
double radius_ratio(Vec2 a, Vec2 b, Vec2 c);

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
