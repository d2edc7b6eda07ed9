// The constrained Delaunay triangulation on near-degenerate input: points on a 16 x 16 grid
// (collinear and cocircular by the hundred), some moved by one unit in the last place or by
// 2^-40, inside a square loop; segments between them as embedded constraints, those that
// would cross, overlap or repeat another dropped (the domain builder never makes those). A
// segment through other points stays: both triangulators split it there.
// Oracles: check_mesh (orientation, adjacency, every constraint's pieces edges, Euler, empty
// circles) and the two triangulators giving the same triangles.
//
// Input: pairs of bytes. A pair with the high bit of the first byte clear is a point
// (4 bits x, 4 bits y, then the perturbation in the second byte); set, a segment between the
// points numbered by the rest of the two bytes.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <vector>

#include "core/fixtures.hpp"
#include "kernel/predicates.hpp"
#include "meshd/core/mesh.hpp"
#include "triangulation/triangulation.hpp"

using namespace meshd::core;

namespace {

bool segments_conflict(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
    const Orientation o1 = orient2d(a, b, c), o2 = orient2d(a, b, d);
    const Orientation o3 = orient2d(c, d, a), o4 = orient2d(c, d, b);
    if (o1 != Orientation::Collinear && o2 != Orientation::Collinear && o3 != Orientation::Collinear &&
        o4 != Orientation::Collinear)
        return o1 != o2 && o3 != o4;  // a proper crossing
    // Touching or collinear: a conflict unless they only share an end.
    return inside_segment(a, b, c) || inside_segment(a, b, d) || inside_segment(c, d, a) ||
           inside_segment(c, d, b);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size > 2 * 400) return 0;
    // The square loop: corners 0..3, outside the grid.
    std::vector<Vec2> pts = {{-1, -1}, {16, -1}, {16, 16}, {-1, 16}};
    std::vector<Constraint> cons = {{0, 1, true}, {1, 2, true}, {2, 3, true}, {3, 0, true}};
    std::set<std::pair<double, double>> seen;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> wanted;
    for (std::size_t i = 0; i + 1 < size; i += 2) {
        const std::uint8_t b0 = data[i], b1 = data[i + 1];
        if (b0 & 0x80) {
            wanted.push_back({static_cast<std::uint32_t>(b0 & 0x7f), b1});
            continue;
        }
        Vec2 p{static_cast<double>(b0 & 0x0f), static_cast<double>(b1 & 0x0f)};
        switch (b1 >> 4) {
            // One unit in the last place; at zero that would be a subnormal number, whose
            // products underflow (the predicates assume they do not, and the domain builder
            // refuses domains that small): 2^-40 there instead.
            case 1: p.x = p.x != 0.0 ? std::nextafter(p.x, HUGE_VAL) : 0x1p-40; break;
            case 2: p.y = p.y != 0.0 ? std::nextafter(p.y, -HUGE_VAL) : -0x1p-40; break;
            case 3: p.x += 0x1p-40; break;
            case 4: p.y -= 0x1p-40; break;
            case 5: p = {p.x + 0.5, p.y + 0.25}; break;
            default: break;
        }
        if (seen.insert({p.x, p.y}).second) pts.push_back(p);
    }
    for (auto [i, j] : wanted) {
        const std::uint32_t a = 4 + i, b = 4 + j;
        if (a >= pts.size() || b >= pts.size() || a == b) continue;
        bool ok = true;
        for (const Constraint& c : cons) {
            const bool same = (c.a == a && c.b == b) || (c.a == b && c.b == a);  // the builder never repeats one
            ok = ok && !same && !segments_conflict(pts[a], pts[b], pts[c.a], pts[c.b]);
        }
        if (ok) cons.push_back({a, b, false});
    }
    // A constraint through other points is split there: its pieces are the edges the result
    // must have. Ordered along it: u comes before w when u lies between the start and w.
    std::vector<Constraint> pieces;
    for (const Constraint& c : cons) {
        std::vector<std::uint32_t> on;
        for (std::uint32_t k = 0; k < pts.size(); ++k)
            if (inside_segment(pts[c.a], pts[c.b], pts[k])) on.push_back(k);
        std::sort(on.begin(), on.end(),
                  [&](std::uint32_t u, std::uint32_t w) { return inside_segment(pts[c.a], pts[w], pts[u]); });
        std::uint32_t from = c.a;
        for (std::uint32_t k : on) {
            pieces.push_back({from, k, c.loop});
            from = k;
        }
        pieces.push_back({from, c.b, c.loop});
    }

    const TriangulationResult r = triangulate_delaunay(pts, cons);
    const Mesh m = meshd::test::mesh_of(pts, 0, r, pieces);
    const auto broken = check_mesh(m);
    if (!broken.empty()) {
        std::fprintf(stderr, "%zu points, %zu constraints: %s\n", pts.size(), cons.size(), broken.front().c_str());
        std::abort();
    }
    const TriangulationResult f = triangulate_advancing_front(pts, cons);
    if (meshd::test::canonical(f.triangles) != meshd::test::canonical(r.triangles)) {
        std::fprintf(stderr, "the triangulators disagree on %zu points, %zu constraints\n", pts.size(), cons.size());
        std::abort();
    }
    return 0;
}
