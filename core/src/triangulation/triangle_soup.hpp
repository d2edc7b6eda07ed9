#pragma once
// The triangle soup with adjacency (the Triangle of mesh.hpp) that the triangulators, the
// interior stage's domain walks, smoothing and refinement all work on: walks around a
// vertex and along a segment, flips, splits, edge lookups, Lawson legalisation.

#include <cstdint>
#include <vector>

#include "kernel/predicates.hpp"
#include "triangulation/triangulation.hpp"

namespace meshd::core::detail {

inline std::uint32_t next3(std::uint32_t i) { return i == 2 ? 0 : i + 1; }
inline std::uint32_t prev3(std::uint32_t i) { return i == 0 ? 2 : i - 1; }

/// Keys of edges for hash maps: a -> b, and {a, b} whatever the direction.
inline std::uint64_t directed_key(VertexId a, VertexId b) { return (static_cast<std::uint64_t>(a) << 32) | b; }
inline std::uint64_t edge_key(VertexId a, VertexId b) { return a < b ? directed_key(a, b) : directed_key(b, a); }

/// Where a straight walk ended: the triangle holding the target (edge -1), or the triangle
/// and edge through which the segment leaves across a constrained edge or the mesh's
/// boundary; triangle kNoTriangle when the walk took too many steps (a degenerate path).
struct WalkEnd {
    TriangleId triangle;
    int edge;
};

class TriangleSoup {
public:
    /// `rank`, when given, is the symbolic-perturbation rank of every vertex (default: the
    /// vertex index itself).
    TriangleSoup(const Array<Vec2>& points, Array<Triangle>& tris, bool track_vertices,
                 const std::uint32_t* rank = nullptr)
        : pts_(points), t_(tris), track_(track_vertices), rank_(rank) {
        if (track_) rebuild_vertex_index();
    }

    const Vec2& p(std::uint32_t v) const { return pts_[v]; }
    Array<Triangle>& tris() { return t_; }

    /// Index of vertex v in triangle t (which must contain it).
    static std::uint32_t index_of(const Triangle& t, std::uint32_t v) {
        return t.v[0] == v ? 0u : (t.v[1] == v ? 1u : 2u);
    }
    /// Visits the triangles around vertex v: counter-clockwise from vertex_triangle(v), and
    /// when the fan is open (v on the boundary of the soup) then clockwise from there. Stops
    /// at the first triangle for which visit(t) is true and returns it; else kNoTriangle.
    /// Needs the vertex index.
    /// A fan that takes more steps than the soup has triangles never closes: a broken soup,
    /// reported (InternalError) rather than walked forever.
    template <class Visit>
    TriangleId around(VertexId v, Visit&& visit) const {
        const TriangleId start = vtri_[v];
        if (start == kNoTriangle) return kNoTriangle;
        TriangleId t = start;
        size_t steps = 0;
        do {
            if (visit(t)) return t;
            t = t_[t].n[next3(index_of(t_[t], v))];
            if (++steps > t_.size()) fan_does_not_close();
        } while (t != kNoTriangle && t != start);
        if (t == start) return kNoTriangle;
        for (t = t_[start].n[prev3(index_of(t_[start], v))]; t != kNoTriangle; t = t_[t].n[prev3(index_of(t_[t], v))]) {
            if (visit(t)) return t;
            if (++steps > t_.size()) fan_does_not_close();
        }
        return kNoTriangle;
    }

    /// The triangle around v whose closed wedge at v holds the direction to c (the start of
    /// a walk from v towards c), or kNoTriangle.
    TriangleId wedge(VertexId v, Vec2 c) const;

    /// Walks the segment from `from` (inside triangle t or on its boundary) towards `to`,
    /// crossing unconstrained edges only, for at most max_steps triangles.
    WalkEnd walk(TriangleId t, Vec2 from, Vec2 to, int max_steps) const;

    /// Index in u of the edge shared with t.
    std::uint32_t back_index(TriangleId u, TriangleId t) const {
        const Triangle& tu = t_[u];
        return tu.n[0] == t ? 0u : (tu.n[1] == t ? 1u : 2u);
    }

    bool constrained(TriangleId t, std::uint32_t i) const { return edge_bit(t_[t].constrained, i); }
    void set_flag(TriangleId t, std::uint32_t i, bool constrained, bool boundary);

    /// Flips edge i of t (t and its neighbour must form a convex quad; the edge must not be
    /// constrained). With t = (p, b, c) rotated so that p = t.v[i], and q the neighbour's
    /// vertex opposite the edge, afterwards t = (p, b, q) and the neighbour u = (p, q, c): p is
    /// v[0] of both (the drawing is above TriangleSoup::flip in triangle_soup.cpp).
    void flip(TriangleId t, std::uint32_t i);

    /// True when edge i of t is not locally Delaunay (perturbed, ranks = vertex ids, or those
    /// given). Inline, as the flips of the refinement and of the smoothing ask it for every
    /// edge they touch; the rare exact tie is out of line.
    bool illegal(TriangleId t, std::uint32_t i) const {
        const Triangle& T = t_[t];
        const TriangleId u = T.n[i];
        if (u == kNoTriangle || edge_bit(T.constrained, i)) return false;
        // u's corner off the shared edge, without a search: its corners' sum less the edge's.
        const Triangle& U = t_[u];
        const std::uint32_t q = U.v[0] + U.v[1] + U.v[2] - T.v[next3(i)] - T.v[prev3(i)];
        const int s = incircle(pts_[T.v[0]], pts_[T.v[1]], pts_[T.v[2]], pts_[q]);
        return s != 0 ? s > 0 : cocircular_illegal(T, q);
    }

    /// illegal() for a fourth point q exactly on the circle of T: the perturbation decides
    /// (by the soup's ranks). Out of line, as it is rare.
    bool cocircular_illegal(const Triangle& T, std::uint32_t q) const;

    /// Lawson: flips until every edge in the queue (and every edge touched by a flip) is
    /// locally Delaunay. Edges as (triangle, index). Returns the number of flips; the two
    /// triangles of every flip are appended to `changed` when given.
    std::uint64_t legalize(std::vector<std::pair<TriangleId, std::uint32_t>>& queue,
                           std::vector<TriangleId>* changed = nullptr);

    /// The triangle holding the directed edge a -> b (a at index k, b at k+1), or kNoTriangle.
    /// Needs the vertex index.
    std::pair<TriangleId, std::uint32_t> find_edge(std::uint32_t a, std::uint32_t b) const;

    /// Inserts vertex p inside triangle t (three triangles) or on its edge i (the two
    /// triangles across it become four; a constrained edge stays constrained in its halves).
    /// Queues the edges opposite p for legalize().
    void split_triangle(TriangleId t, std::uint32_t p, std::vector<std::pair<TriangleId, std::uint32_t>>& queue);
    void split_edge(TriangleId t, std::uint32_t i, std::uint32_t p, std::vector<std::pair<TriangleId, std::uint32_t>>& queue);

    TriangleId vertex_triangle(std::uint32_t v) const { return vtri_[v]; }
    /// Room in the vertex index for points added after construction.
    void grow_vertices(size_t n) {
        if (track_ && vtri_.size() < n) vtri_.resize(n, kNoTriangle);
    }
    void touch(TriangleId t) {
        if (track_)
            for (auto v : t_[t].v) vtri_[v] = t;
    }
    void rebuild_vertex_index();

private:
    TriangleId new_triangle();
    void relink(TriangleId nb, TriangleId old_t, TriangleId new_t);

    [[noreturn]] static void fan_does_not_close();
    const Array<Vec2>& pts_;
    Array<Triangle>& t_;
    bool track_;
    const std::uint32_t* rank_;  // by vertex, or null
    Array<TriangleId> vtri_;
};

/// Puts triangles in the order of their largest corner index (neighbours renumbered): with
/// points in a spatial order, the triangles around a point then lie near each other in memory.
/// With `gone` (a flag per triangle), the flagged ones are dropped as well, and links to them
/// become kNoTriangle; their corners need not be below point_count.
void order_by_largest_corner(Array<Triangle>& tris, size_t point_count, const char* gone = nullptr);

}  // namespace meshd::core::detail
