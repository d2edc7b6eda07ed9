// Mesh invariants, checked exactly (check_mesh, mesh.hpp). The pipeline does not call it
// (its stages keep the invariants by construction); the tests call it on every mesh.

#include <algorithm>
#include <unordered_map>
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
    // Quads: in range, strictly convex and counter-clockwise.
    const size_t nq = m.quads.size();
    for (size_t q = 0; q < nq; ++q) {
        const auto& Q = m.quads[q];
        if (std::any_of(Q.begin(), Q.end(), [&](VertexId v) { return v >= nv; })) {
            fail("quad " + std::to_string(q) + " has a vertex out of range");
            continue;
        }
        for (VertexId v : Q) used[v] = 1;
        for (size_t i = 0; i < 4; ++i)
            if (orient2d(m.point(Q[i]), m.point(Q[(i + 1) % 4]), m.point(Q[(i + 2) % 4])) != Orientation::Left)
                fail("quad " + std::to_string(q) + " is not strictly convex and counter-clockwise at its corner " +
                     std::to_string((i + 1) % 4));
    }
    for (size_t v = 0; v < nv; ++v)
        if (!used[v]) fail("point " + std::to_string(v) + " is in no cell");

    // Edges: every cell's sides as half-edges. A half-edge twice means two cells overlap;
    // one without its opposite bounds the mesh. A triangle's neighbour across an edge is the
    // triangle on the other side, and none where a quad or nothing is.
    std::unordered_map<std::uint64_t, std::int64_t> half;  // directed edge -> triangle, or -1 - quad
    auto add_half = [&](VertexId a, VertexId b, std::int64_t cell) {
        if (!half.emplace(detail::directed_key(a, b), cell).second)
            fail("edge " + std::to_string(a) + "-" + std::to_string(b) + " is in two cells on the same side");
    };
    for (size_t t = 0; t < nt; ++t)
        for (std::uint32_t i = 0; i < 3; ++i) {
            const Triangle& T = m.triangles[t];
            if (T.v[0] < nv && T.v[1] < nv && T.v[2] < nv)
                add_half(T.v[(i + 1) % 3], T.v[(i + 2) % 3], static_cast<std::int64_t>(t));
        }
    for (size_t q = 0; q < nq; ++q)
        for (size_t i = 0; i < 4; ++i) add_half(m.quads[q][i], m.quads[q][(i + 1) % 4], -1 - static_cast<std::int64_t>(q));
    std::unordered_set<std::uint64_t> all, open;
    for (const auto& [k, cell] : half) {
        const VertexId a = static_cast<VertexId>(k >> 32), b = static_cast<VertexId>(k & 0xffffffffu);
        all.insert(detail::edge_key(a, b));
        auto opposite = half.find(detail::directed_key(b, a));
        if (opposite == half.end()) open.insert(k);
        if (cell >= 0) {
            const Triangle& T = m.triangles[static_cast<size_t>(cell)];
            for (std::uint32_t i = 0; i < 3; ++i) {
                if (T.v[(i + 1) % 3] != a || T.v[(i + 2) % 3] != b) continue;
                const TriangleId expect = opposite != half.end() && opposite->second >= 0
                                              ? static_cast<TriangleId>(opposite->second)
                                              : kNoTriangle;
                if (T.n[i] != expect)
                    fail("triangle " + std::to_string(cell) + " names the wrong neighbour across edge " +
                         std::to_string(a) + "-" + std::to_string(b));
            }
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
    const long long euler = static_cast<long long>(nv) - static_cast<long long>(all.size()) +
                            static_cast<long long>(nt) + static_cast<long long>(nq);
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
                if (T.layer || U.layer) continue;  // the layers' cells are stretched on purpose
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
