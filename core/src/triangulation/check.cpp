// Mesh invariants, checked exactly (check_mesh, mesh.hpp). The pipeline does not call it
// (its stages keep the invariants by construction); the tests call it on every mesh.

#include <algorithm>
#include <unordered_set>

#include "meshd/core/mesh.hpp"
#include "triangulation/triangle_soup.hpp"
#include "kernel/predicates.hpp"

namespace meshd::core {

std::vector<std::string> check_mesh(const Mesh& m, bool delaunay) {
    std::vector<std::string> out;
    auto fail = [&](std::string s) {
        if (out.size() < 50) out.push_back(std::move(s));
    };
    const size_t nv = m.point_count();
    const size_t nt = m.triangles.size();
    std::vector<char> used(nv, 0);
    for (size_t t = 0; t < nt; ++t) {
        const Triangle& T = m.triangles[t];
        bool ok = true;
        for (auto v : T.v) {
            if (v >= nv) {
                fail("triangle " + std::to_string(t) + " has a vertex out of range");
                ok = false;
            } else {
                used[v] = 1;
            }
        }
        if (!ok) continue;
        if (orient2d(m.point(T.v[0]), m.point(T.v[1]), m.point(T.v[2])) != Orientation::Left)
            fail("triangle " + std::to_string(t) + " is not counter-clockwise with positive area");
        for (std::uint32_t i = 0; i < 3; ++i) {
            const TriangleId u = T.n[i];
            if (u == kNoTriangle) continue;
            if (u >= nt) {
                fail("triangle " + std::to_string(t) + " has a neighbour out of range");
                continue;
            }
            const Triangle& U = m.triangles[u];
            const std::uint32_t a = T.v[(i + 1) % 3], b = T.v[(i + 2) % 3];
            bool back = false;
            for (std::uint32_t j = 0; j < 3; ++j)
                if (U.n[j] == t && U.v[(j + 1) % 3] == b && U.v[(j + 2) % 3] == a) back = true;
            if (!back) fail("triangles " + std::to_string(t) + " and " + std::to_string(u) + " disagree on adjacency");
        }
    }
    for (size_t v = 0; v < nv; ++v)
        if (!used[v]) fail("point " + std::to_string(v) + " is in no triangle");

    // Edges: count them, and find the edges without a neighbour.
    std::unordered_set<std::uint64_t> all, open;
    for (const Triangle& T : m.triangles) {
        for (std::uint32_t i = 0; i < 3; ++i) {
            const std::uint32_t a = T.v[(i + 1) % 3], b = T.v[(i + 2) % 3];
            all.insert(detail::edge_key(a, b));
            if (T.n[i] == kNoTriangle) open.insert(detail::directed_key(a, b));
        }
    }
    size_t loop_edges = 0;
    for (const MeshEdge& e : m.edges) {
        if (!all.count(detail::edge_key(e.a, e.b)))
            fail("edge " + std::to_string(e.a) + "-" + std::to_string(e.b) + " of the boundary is not a mesh edge");
        if (!e.embedded) {
            ++loop_edges;
            if (!open.count(detail::directed_key(e.a, e.b)))
                fail("loop edge " + std::to_string(e.a) + "-" + std::to_string(e.b) +
                     " does not have the mesh on its left only");
        }
    }
    if (open.size() != loop_edges)
        fail(std::to_string(open.size()) + " edges bound the mesh but there are " + std::to_string(loop_edges) +
             " loop edges");
    const long long euler = static_cast<long long>(nv) - static_cast<long long>(all.size()) + static_cast<long long>(nt);
    if (euler != 1 - static_cast<long long>(m.holes))
        fail("Euler characteristic V - E + F = " + std::to_string(euler) + ", expected " +
             std::to_string(1 - static_cast<long long>(m.holes)));

    if (delaunay) {
        for (size_t t = 0; t < nt; ++t) {
            const Triangle& T = m.triangles[t];
            for (std::uint32_t i = 0; i < 3; ++i) {
                const TriangleId u = T.n[i];
                if (u == kNoTriangle || u < t || edge_bit(T.constrained, i)) continue;
                const Triangle& U = m.triangles[u];
                std::uint32_t q = 0;
                for (std::uint32_t j = 0; j < 3; ++j)
                    if (U.n[j] == t) q = U.v[j];
                if (incircle(m.point(T.v[0]), m.point(T.v[1]), m.point(T.v[2]), m.point(q)) > 0)
                    fail("the circumcircle of triangle " + std::to_string(t) + " holds point " + std::to_string(q));
            }
        }
    }
    return out;
}

}  // namespace meshd::core
