#include "meshd/core/quality.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace meshd::core {

double radius_ratio(Vec2 a, Vec2 b, Vec2 c) {
    // 2 r_in / R = 16 A^2 / (abc (a + b + c)) with A the area and a, b, c the side lengths.
    const double la = distance(b, c), lb = distance(c, a), lc = distance(a, b);
    const double area = 0.5 * std::fabs(cross(b - a, c - a));
    const double denom = la * lb * lc * (la + lb + lc);
    return denom > 0.0 ? std::clamp(16.0 * area * area / denom, 0.0, 1.0) : 0.0;
}

QualityMetrics measure_quality(const Mesh& m, const SizeField& rho) {
    QualityMetrics q;
    q.points = m.point_count();
    for (PointKind k : m.kind) (k == PointKind::Interior ? q.interior_points : q.boundary_points)++;
    q.triangles = m.triangles.size();
    if (m.triangles.empty()) return q;
    double angle_sum = 0.0, quality_sum = 0.0;
    q.angle_min = 180.0;
    q.quality_min = 1.0;
    const double to_deg = 180.0 / std::numbers::pi;
    for (const Triangle& t : m.triangles) {
        const Vec2 p[3] = {m.point(t.v[0]), m.point(t.v[1]), m.point(t.v[2])};
        for (int i = 0; i < 3; ++i) {
            const Vec2 u = p[(i + 1) % 3] - p[i], w = p[(i + 2) % 3] - p[i];
            const double ang = std::atan2(std::fabs(cross(u, w)), dot(u, w)) * to_deg;
            q.angle_min = std::fmin(q.angle_min, ang);
            q.angle_max = std::fmax(q.angle_max, ang);
            angle_sum += ang;
        }
        const double rr = radius_ratio(p[0], p[1], p[2]);
        q.quality_min = std::fmin(q.quality_min, rr);
        quality_sum += rr;
        q.quality_histogram[std::min<size_t>(9, static_cast<size_t>(rr * 10.0))]++;
    }
    q.angle_mean = angle_sum / (3.0 * static_cast<double>(m.triangles.size()));
    q.quality_mean = quality_sum / static_cast<double>(m.triangles.size());
    // Each edge once: from the triangle with the larger index across it, or without neighbour.
    double ratio_sum = 0.0;
    size_t edges = 0, within = 0;
    const double s2 = std::sqrt(2.0);
    for (TriangleId t = 0; t < m.triangles.size(); ++t) {
        const Triangle& T = m.triangles[t];
        for (std::uint32_t i = 0; i < 3; ++i) {
            if (T.n[i] != kNoTriangle && T.n[i] < t) continue;
            const Vec2 a = m.point(T.v[(i + 1) % 3]), b = m.point(T.v[(i + 2) % 3]);
            const double target = rho.interior(0.5 * (a + b));
            const double r = distance(a, b) / target;
            ratio_sum += r;
            ++edges;
            within += (r >= 1.0 / s2 && r <= s2) ? 1 : 0;
        }
    }
    q.size_ratio_mean = ratio_sum / static_cast<double>(edges);
    q.size_ratio_within_sqrt2 = static_cast<double>(within) / static_cast<double>(edges);
    return q;
}

}  // namespace meshd::core
