// Laplacian smoothing with guards; see mesher.hpp.

#include <algorithm>
#include <cmath>
#include <vector>

#include "meshd/core/errors.hpp"
#include "meshd/core/mesher.hpp"
#include "meshd/core/predicates.hpp"

namespace meshd::core {

std::uint64_t smooth(Mesh& m, int iterations, std::uint64_t* flips, Observer* observer) {
    const size_t nv = m.point_count();
    std::uint64_t moves = 0;
    std::vector<std::uint32_t> offset(nv + 1), incident;
    std::vector<Vec2> pts(nv);
    std::vector<double> quality, star_quality;
    for (int it = 0; it < iterations; ++it) {
        if (observer) {
            if (observer->should_stop()) throw Cancelled();
            observer->on_progress(Stage::Smoothing, static_cast<double>(it) / iterations);
        }
        // Triangles around each vertex (compressed rows), rebuilt after each sweep's flips.
        std::fill(offset.begin(), offset.end(), 0);
        for (const Triangle& t : m.triangles)
            for (auto v : t.v) ++offset[v + 1];
        for (size_t v = 0; v < nv; ++v) offset[v + 1] += offset[v];
        incident.assign(offset[nv], 0);
        std::vector<std::uint32_t> fill(offset.begin(), offset.end() - 1);
        for (TriangleId t = 0; t < m.triangles.size(); ++t)
            for (auto v : m.triangles[t].v) incident[fill[v]++] = t;

        // Radius ratio of every triangle, kept current as points move: the "before" side of
        // each star's test costs lookups only.
        quality.resize(m.triangles.size());
        for (TriangleId t = 0; t < m.triangles.size(); ++t) {
            const Triangle& T = m.triangles[t];
            quality[t] = radius_ratio(m.point(T.v[0]), m.point(T.v[1]), m.point(T.v[2]));
        }
        std::uint64_t moved = 0;
        for (std::uint32_t v = 0; v < nv; ++v) {
            if (m.kind[v] != PointKind::Interior) continue;
            const Vec2 old = m.point(v);
            // Mean of the neighbours: each appears in two triangles of the closed star, so
            // summing the two other vertices of every triangle counts each twice.
            Vec2 sum{0, 0};
            size_t count = 0;
            double worst_before = 1.0;
            for (auto k = offset[v]; k < offset[v + 1]; ++k) {
                const Triangle& t = m.triangles[incident[k]];
                for (auto w : t.v)
                    if (w != v) { sum += m.point(w); ++count; }
                worst_before = std::fmin(worst_before, quality[incident[k]]);
            }
            if (count == 0) continue;
            const Vec2 target = sum / static_cast<double>(count);
            for (double step : {1.0, 0.5}) {
                const Vec2 p = old + step * (target - old);
                m.x[v] = p.x;
                m.y[v] = p.y;
                bool ok = true;
                double worst_after = 1.0;
                star_quality.clear();
                for (auto k = offset[v]; k < offset[v + 1] && ok; ++k) {
                    const Triangle& t = m.triangles[incident[k]];
                    const Vec2 a = m.point(t.v[0]), b = m.point(t.v[1]), c = m.point(t.v[2]);
                    if (orient2d(a, b, c) != Orientation::Left) ok = false;
                    star_quality.push_back(radius_ratio(a, b, c));
                    worst_after = std::fmin(worst_after, star_quality.back());
                }
                if (ok && worst_after >= worst_before) {
                    for (auto k = offset[v]; k < offset[v + 1]; ++k) quality[incident[k]] = star_quality[k - offset[v]];
                    ++moved;
                    break;
                }
                m.x[v] = old.x;
                m.y[v] = old.y;
            }
        }
        moves += moved;
        for (size_t v = 0; v < nv; ++v) pts[v] = m.point(static_cast<std::uint32_t>(v));
        const std::uint64_t f = make_delaunay(pts, m.triangles);
        if (flips) *flips += f;
        if (moved == 0) break;
    }
    return moves;
}

}  // namespace meshd::core
