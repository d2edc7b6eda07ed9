#include "improve/quality.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "kernel/constructions.hpp"

namespace meshd::core {

namespace {

// radius_ratio() from the side lengths la = |bc|, lb = |ca|, lc = |ab| (as distance() gives them).
double radius_ratio_of(Vec2 a, Vec2 b, Vec2 c, double la, double lb, double lc) {
    // 2 r_in / R = 16 A^2 / (abc (a + b + c)) with A the area and a, b, c the side lengths.
    const double area = 0.5 * std::fabs(cross(b - a, c - a));
    const double denom = la * lb * lc * (la + lb + lc);
    return denom > 0.0 ? std::clamp(16.0 * area * area / denom, 0.0, 1.0) : 0.0;
}

}  // namespace

double radius_ratio(Vec2 a, Vec2 b, Vec2 c) {
    return radius_ratio_of(a, b, c, distance(b, c), distance(c, a), distance(a, b));
}

namespace {

std::array<double, 3> cotangents(Vec2 a, Vec2 b, Vec2 c) {
    const double inv = 1.0 / cross(b - a, c - a);
    return {dot(b - a, c - a) * inv, dot(c - b, a - b) * inv, dot(a - c, b - c) * inv};
}

// The angle at corner k of triangle abc, in degrees.
double angle_deg(Vec2 a, Vec2 b, Vec2 c, int k) {
    const Vec2 p[3] = {a, b, c};
    const Vec2 u = p[(k + 1) % 3] - p[k], w = p[(k + 2) % 3] - p[k];
    return angle_between(u, w) * (180.0 / std::numbers::pi);
}

}  // namespace

CornerCot smallest_angle_cot(Vec2 a, Vec2 b, Vec2 c) {
    const auto k = cotangents(a, b, c);
    const int i = k[0] >= k[1] ? (k[0] >= k[2] ? 0 : 2) : (k[1] >= k[2] ? 1 : 2);
    return {k[static_cast<size_t>(i)], i};
}

QualityMetrics measure_quality(const Mesh& m, const SizeField& rho) {
    QualityMetrics q;
    q.points = m.point_count();
    for (PointKind k : m.kind)
        (k == PointKind::Interior || k == PointKind::Layer ? q.interior_points : q.boundary_points)++;
    q.triangles = m.triangles.size();
    q.quads = m.quads.size();
    // The isotropic triangles' figures: the boundary layers' cells have their own.
    size_t isotropic = 0;
    for (const Triangle& T : m.triangles) isotropic += T.layer ? 0 : 1;
    if (isotropic == 0) return q;
    // The extreme angles are found by their cotangents; only those two get an atan2. The
    // sizes of the edges against the field, in the same pass: each edge once, from the
    // triangle with the larger index across it or without a neighbour there, the midpoints'
    // sizes asked in batches (SizeField::interior over an array); the side lengths serve
    // both.
    double quality_sum = 0.0;
    q.quality_min = 1.0;
    CornerCot lo{-HUGE_VAL, 0}, hi{HUGE_VAL, 0};
    TriangleId lo_t = 0, hi_t = 0;
    double ratio_sum = 0.0;
    size_t edges = 0, within = 0;
    const double s2 = std::sqrt(2.0);
    constexpr size_t kBatch = 256;
    std::array<Vec2, kBatch> mid;
    std::array<double, kBatch> length, target;
    size_t batch = 0;
    auto flush = [&] {
        rho.interior(mid.data(), batch, target.data());
        for (size_t k = 0; k < batch; ++k) {
            const double r = length[k] / target[k];
            ratio_sum += r;
            within += (r >= 1.0 / s2 && r <= s2) ? 1 : 0;
        }
        edges += batch;
        batch = 0;
    };
    for (TriangleId t = 0; t < m.triangles.size(); ++t) {
        const Triangle& T = m.triangles[t];
        if (T.layer) continue;
        const std::array<Vec2, 3> p{m.point(T.v[0]), m.point(T.v[1]), m.point(T.v[2])};
        const auto k = cotangents(p[0], p[1], p[2]);
        for (int i = 0; i < 3; ++i) {
            const double cot = k[static_cast<size_t>(i)];
            if (cot > lo.cot) {
                lo = {cot, i};
                lo_t = t;
            }
            if (cot < hi.cot) {
                hi = {cot, i};
                hi_t = t;
            }
        }
        // Side i, opposite corner i, from corner i + 1 to corner i + 2.
        const std::array<double, 3> side{distance(p[1], p[2]), distance(p[2], p[0]), distance(p[0], p[1])};
        const double rr = radius_ratio_of(p[0], p[1], p[2], side[0], side[1], side[2]);
        q.quality_min = fmin_inline(q.quality_min, rr);  // libm's fmin is a call through the PLT
        quality_sum += rr;
        q.quality_histogram[std::min<size_t>(9, static_cast<size_t>(rr * 10.0))]++;
        for (std::uint32_t i = 0; i < 3; ++i) {
            if (T.n[i] != kNoTriangle && T.n[i] < t && !m.triangles[T.n[i]].layer) continue;
            mid[batch] = 0.5 * (p[(i + 1) % 3] + p[(i + 2) % 3]);
            length[batch] = side[i];
            if (++batch == kBatch) flush();
        }
    }
    flush();
    auto corner_angle = [&](TriangleId t, int k) {
        const Triangle& T = m.triangles[t];
        return angle_deg(m.point(T.v[0]), m.point(T.v[1]), m.point(T.v[2]), k);
    };
    q.angle_min = corner_angle(lo_t, lo.corner);
    q.angle_max = corner_angle(hi_t, hi.corner);
    q.angle_mean = 60.0;  // the angles of every triangle sum to 180 degrees
    q.quality_mean = quality_sum / static_cast<double>(isotropic);
    q.size_ratio_mean = ratio_sum / static_cast<double>(edges);
    q.size_ratio_within_sqrt2 = static_cast<double>(within) / static_cast<double>(edges);
    return q;
}

}  // namespace meshd::core
