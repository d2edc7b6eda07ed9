// The triangle soup of triangle_soup.hpp: flips, splits, Lawson legalisation, edge lookup.

#include "triangulation/triangle_soup.hpp"

#include <algorithm>

#include "kernel/memory.hpp"
#include "kernel/predicates.hpp"
#include "meshd/core/errors.hpp"

namespace meshd::core {

namespace detail {

void TriangleSoup::fan_does_not_close() {
    throw InternalError("the triangles around a vertex do not close", __FILE__, __LINE__);
}

void TriangleSoup::set_flag(TriangleId t, std::uint32_t i, bool constrained, bool boundary) {
    auto set = [&](TriangleId tt, std::uint32_t ii) {
        const std::uint8_t bit = static_cast<std::uint8_t>(1u << ii);
        t_[tt].constrained = static_cast<std::uint8_t>(constrained ? (t_[tt].constrained | bit) : (t_[tt].constrained & ~bit));
        t_[tt].boundary = static_cast<std::uint8_t>(boundary ? (t_[tt].boundary | bit) : (t_[tt].boundary & ~bit));
    };
    set(t, i);
    const TriangleId u = t_[t].n[i];
    if (u != kNoTriangle) set(u, back_index(u, t));
}

/* Before:                         After:
          c                             c
        / | \                         /   \
      p   |   q      flip edge      p ----- q
        \ | /        b-c  =>          \   /
          b                             b
   t = (p, b, c), u = (q, c, b)    t = (p, b, q), u = (p, q, c) */
void TriangleSoup::flip(TriangleId t, std::uint32_t i) {
    Triangle& T = t_[t];
    const TriangleId u = T.n[i];
    const std::uint32_t j = back_index(u, t);
    Triangle& U = t_[u];
    const std::uint32_t p = T.v[i], b = T.v[next3(i)], c = T.v[prev3(i)];
    const std::uint32_t q = U.v[j];
    // Outer neighbours and their edge flags.
    const TriangleId n_pb = T.n[prev3(i)];   // across (p, b), opposite c in t
    const TriangleId n_cp = T.n[next3(i)];   // across (c, p), opposite b in t
    const TriangleId n_bq = U.n[next3(j)];   // across (b, q), opposite c in u
    const TriangleId n_qc = U.n[prev3(j)];   // across (q, c), opposite b in u
    // The edge flags with both flag bytes of a triangle in one word (constrained in bits 0-2,
    // boundary in 8-10: far enough apart that the turn moves no bit into the other group),
    // turned so that edge i of t (j of u) is bit 0: then bit 1 is the edge after it and bit 2
    // the one before.
    auto turned = [](const Triangle& x, std::uint32_t k) {
        const std::uint32_t f = x.constrained | (static_cast<std::uint32_t>(x.boundary) << 8);
        return ((f >> k) | (f << (3 - k))) & 0x707u;
    };
    const std::uint32_t ft = turned(T, i), fu = turned(U, j);
    // t = (p, b, q): opp p (b,q) -> n_bq; opp b (q,p) -> u; opp q (p,b) -> n_pb.
    // Its edge 0 is u's next3(j) (bit 1 of fu), its edge 2 t's prev3(i) (bit 2 of ft).
    const std::uint32_t new_t = ((fu >> 1) & 0x101u) | (ft & 0x404u);
    // u = (p, q, c): opp p (q,c) -> n_qc; opp q (c,p) -> n_cp; opp c (p,q) -> t.
    // Its edge 0 is u's prev3(j) (bit 2 of fu), its edge 1 t's next3(i) (bit 1 of ft).
    const std::uint32_t new_u = ((fu >> 2) & 0x101u) | (ft & 0x202u);
    T.v = {p, b, q};
    T.n = {n_bq, u, n_pb};
    T.constrained = static_cast<std::uint8_t>(new_t & 7u);
    T.boundary = static_cast<std::uint8_t>(new_t >> 8);
    U.v = {p, q, c};
    U.n = {n_qc, n_cp, t};
    U.constrained = static_cast<std::uint8_t>(new_u & 7u);
    U.boundary = static_cast<std::uint8_t>(new_u >> 8);
    if (n_bq != kNoTriangle) t_[n_bq].n[back_index(n_bq, u)] = t;
    if (n_cp != kNoTriangle) t_[n_cp].n[back_index(n_cp, t)] = u;
    if (track_) {
        vtri_[p] = t;
        vtri_[b] = t;
        vtri_[q] = u;
        vtri_[c] = u;
    }
}

bool TriangleSoup::cocircular_illegal(const Triangle& T, std::uint32_t q) const {
    auto rank = [&](std::uint32_t v) { return rank_ ? rank_[v] : v; };
    return detail::incircle_tie(pts_[T.v[0]], pts_[T.v[1]], pts_[T.v[2]], pts_[q], rank(T.v[0]), rank(T.v[1]),
                                rank(T.v[2]), rank(q)) > 0;
}

std::uint64_t TriangleSoup::legalize(std::vector<std::pair<TriangleId, std::uint32_t>>& queue,
                                     std::vector<TriangleId>* changed) {
    std::uint64_t flips = 0;
    // Lawson's flips never bring back an edge they removed (each lowers the lifted surface),
    // so they end within one flip per pair of points; more is a broken triangulation.
    const std::uint64_t n = pts_.size(), most = n * (n - 1) / 2;
    while (!queue.empty()) {
        const auto [t, i] = queue.back();
        queue.pop_back();
        if (!illegal(t, i)) continue;
        MESHD_INTERNAL_CHECK(flips < most, "Lawson's flips do not terminate");
        const TriangleId u = t_[t].n[i];
        flip(t, i);  // p = old t.v[i] is now v[0] of both t = (p, b, q) and u = (p, q, c)
        ++flips;
        if (changed) {
            changed->push_back(t);
            changed->push_back(u);
        }
        // The outer edges of the quad: t's edges 0 and 2, u's edges 0 and 1.
        queue.emplace_back(t, 0);
        queue.emplace_back(t, 2);
        queue.emplace_back(u, 0);
        queue.emplace_back(u, 1);
    }
    return flips;
}

std::pair<TriangleId, std::uint32_t> TriangleSoup::find_edge(std::uint32_t a, std::uint32_t b) const {
    const TriangleId t = around(a, [&](TriangleId x) { return t_[x].v[next3(index_of(t_[x], a))] == b; });
    return {t, t == kNoTriangle ? 0u : index_of(t_[t], a)};
}

TriangleId TriangleSoup::wedge(VertexId v, Vec2 c) const {
    const Vec2 pv = pts_[v];
    return around(v, [&](TriangleId t) {
        const Triangle& T = t_[t];
        const std::uint32_t k = index_of(T, v);
        return orient2d(pv, pts_[T.v[next3(k)]], c) != Orientation::Right &&
               orient2d(pv, pts_[T.v[prev3(k)]], c) != Orientation::Left;
    });
}

// The walk leaves a triangle through the first edge (in index order) that has `to` strictly
// beyond it and that the line from -> to meets (closed). An edge it leaves through runs, in the
// triangle's counter-clockwise order, from the line's right (or on it) to its left (or on
// it), and the next triangle is entered through the same edge the other way round, so `to`
// is not beyond it there. Where the edge it came through had its ends strictly on either
// side of the line, and the next triangle's far corner w is strictly on one side too, the
// line can only leave through the one edge whose ends are on opposite sides: w's side names
// it, and `to` beyond it or not decides the step. Two orientations a triangle instead of four
// or five, the same steps as the whole test (which the first triangle, and any where the line
// meets a corner, still take).
WalkEnd TriangleSoup::walk(TriangleId t, Vec2 from, Vec2 to, int max_steps) const {
    TriangleId came_from = kNoTriangle;  // set when the edge crossed had its ends strictly apart
    for (int steps = 0; steps < max_steps; ++steps) {
        const Triangle& T = t_[t];
        int exit = -1;
        bool apart = false;
        if (came_from != kNoTriangle) {
            // Edge k, the way in, runs from its left end L = v[k+1] to its right end R = v[k+2].
            const std::uint32_t k = back_index(t, came_from);
            const Orientation ow = orient2d(from, to, pts_[T.v[k]]);
            if (ow != Orientation::Collinear) {
                // w on the left: out through R -> w (edge k+1); on the right: w -> L (edge k+2).
                const std::uint32_t i = ow == Orientation::Left ? next3(k) : prev3(k);
                if (orient2d(pts_[T.v[next3(i)]], pts_[T.v[prev3(i)]], to) != Orientation::Right) return {t, -1};
                exit = static_cast<int>(i);
                apart = true;
            }
        }
        if (exit < 0) {
            for (std::uint32_t i = 0; i < 3; ++i) {
                const Vec2 a = pts_[T.v[next3(i)]], b = pts_[T.v[prev3(i)]];
                if (orient2d(a, b, to) != Orientation::Right) continue;  // `to` not beyond edge i
                // Does the segment leave through edge i (closed)?
                const Orientation oa = orient2d(from, to, a);
                if (oa == Orientation::Left) continue;
                const Orientation ob = orient2d(from, to, b);
                if (ob == Orientation::Right) continue;
                exit = static_cast<int>(i);
                apart = oa != Orientation::Collinear && ob != Orientation::Collinear;
                break;
            }
            if (exit < 0) return {t, -1};  // `to` is in t (closed)
        }
        const auto i = static_cast<std::uint32_t>(exit);
        if (edge_bit(T.constrained, i) || T.n[i] == kNoTriangle) return {t, exit};
        came_from = apart ? t : kNoTriangle;
        t = T.n[i];
    }
    return {kNoTriangle, -1};
}

void TriangleSoup::rebuild_vertex_index() {
    std::uint32_t max_v = 0;
    for (const auto& t : t_)
        for (auto v : t.v) max_v = std::max(max_v, v);
    assign_huge(vtri_, std::max<size_t>(pts_.size(), static_cast<size_t>(max_v) + 1), kNoTriangle);
    for (TriangleId t = 0; t < t_.size(); ++t)
        for (auto v : t_[t].v) vtri_[v] = t;
}

namespace {
std::uint32_t bit(std::uint8_t flags, std::uint32_t i) { return edge_bit(flags, i) ? 1u : 0u; }
}  // namespace

TriangleId TriangleSoup::new_triangle() {
    t_.push_back({});
    return static_cast<TriangleId>(t_.size() - 1);
}


void TriangleSoup::relink(TriangleId nb, TriangleId old_t, TriangleId new_t) {
    if (nb == kNoTriangle) return;
    Triangle& N = t_[nb];
    for (auto& x : N.n)
        if (x == old_t) { x = new_t; return; }
}


void TriangleSoup::split_triangle(TriangleId t, std::uint32_t p, std::vector<std::pair<TriangleId, std::uint32_t>>& queue) {
    const Triangle T = t_[t];
    const std::uint32_t a = T.v[0], b = T.v[1], c = T.v[2];
    const TriangleId t_ab = t, t_bc = new_triangle(), t_ca = new_triangle();
    // (a, b, p): opp a (b,p) -> t_bc; opp b (p,a) -> t_ca; opp p (a,b) -> T.n[2]
    t_[t_ab] = {{a, b, p}, {t_bc, t_ca, T.n[2]}, static_cast<std::uint8_t>(bit(T.constrained, 2) << 2),
                   static_cast<std::uint8_t>(bit(T.boundary, 2) << 2)};
    // (b, c, p): opp b (c,p) -> t_ca; opp c (p,b) -> t_ab; opp p (b,c) -> T.n[0]
    t_[t_bc] = {{b, c, p}, {t_ca, t_ab, T.n[0]}, static_cast<std::uint8_t>(bit(T.constrained, 0) << 2),
                   static_cast<std::uint8_t>(bit(T.boundary, 0) << 2)};
    // (c, a, p): opp c (a,p) -> t_ab; opp a (p,c) -> t_bc; opp p (c,a) -> T.n[1]
    t_[t_ca] = {{c, a, p}, {t_ab, t_bc, T.n[1]}, static_cast<std::uint8_t>(bit(T.constrained, 1) << 2),
                   static_cast<std::uint8_t>(bit(T.boundary, 1) << 2)};
    relink(T.n[0], t, t_bc);
    relink(T.n[1], t, t_ca);
    touch(t_ab);
    touch(t_bc);
    touch(t_ca);
    // In each new triangle p is v[2]: the edge opposite p, the one to test, is edge 2.
    queue.emplace_back(t_ab, 2);
    queue.emplace_back(t_bc, 2);
    queue.emplace_back(t_ca, 2);
}

void TriangleSoup::split_edge(TriangleId t, std::uint32_t i, std::uint32_t p, std::vector<std::pair<TriangleId, std::uint32_t>>& queue) {
    const Triangle T = t_[t];
    const std::uint32_t a = T.v[i], b = T.v[next3(i)], c = T.v[prev3(i)];
    const TriangleId u = T.n[i];
    if (u == kNoTriangle) {
        // An edge on the boundary of the mesh: only t splits.
        const std::uint32_t e_cons = bit(T.constrained, i), e_bnd = bit(T.boundary, i);
        const TriangleId n_ab = T.n[prev3(i)], n_ca = T.n[next3(i)];
        const std::uint32_t c_ab = bit(T.constrained, prev3(i)), b_ab = bit(T.boundary, prev3(i));
        const std::uint32_t c_ca = bit(T.constrained, next3(i)), b_ca = bit(T.boundary, next3(i));
        const TriangleId t1 = t, t2 = new_triangle();
        auto flags = [](std::uint32_t f0, std::uint32_t f1, std::uint32_t f2) {
            return static_cast<std::uint8_t>(f0 | (f1 << 1) | (f2 << 2));
        };
        t_[t1] = {{a, b, p}, {kNoTriangle, t2, n_ab}, flags(e_cons, 0, c_ab), flags(e_bnd, 0, b_ab)};
        t_[t2] = {{a, p, c}, {kNoTriangle, n_ca, t1}, flags(e_cons, c_ca, 0), flags(e_bnd, b_ca, 0)};
        relink(n_ca, t, t2);
        touch(t1);
        touch(t2);
        queue.emplace_back(t1, 2);
        queue.emplace_back(t2, 1);
        return;
    }
    const Triangle U = t_[u];
    const std::uint32_t j = back_index(u, t);
    const std::uint32_t d = U.v[j];
    const std::uint32_t e_cons = bit(T.constrained, i), e_bnd = bit(T.boundary, i);
    const TriangleId n_ab = T.n[prev3(i)], n_ca = T.n[next3(i)];
    const std::uint32_t c_ab = bit(T.constrained, prev3(i)), b_ab = bit(T.boundary, prev3(i));
    const std::uint32_t c_ca = bit(T.constrained, next3(i)), b_ca = bit(T.boundary, next3(i));
    // In u = (d, c, b): across (d, c) is opposite b = U.n[prev3(j)], across (b, d) opposite c = U.n[next3(j)].
    const TriangleId n_dc = U.n[prev3(j)], n_bd = U.n[next3(j)];
    const std::uint32_t c_dc = bit(U.constrained, prev3(j)), b_dc = bit(U.boundary, prev3(j));
    const std::uint32_t c_bd = bit(U.constrained, next3(j)), b_bd = bit(U.boundary, next3(j));
    const TriangleId t1 = t, t2 = new_triangle(), t3 = u, t4 = new_triangle();
    auto flags = [](std::uint32_t f0, std::uint32_t f1, std::uint32_t f2) {
        return static_cast<std::uint8_t>(f0 | (f1 << 1) | (f2 << 2));
    };
    // t1 = (a, b, p): opp a (b,p) -> t4; opp b (p,a) -> t2; opp p (a,b) -> n_ab
    t_[t1] = {{a, b, p}, {t4, t2, n_ab}, flags(e_cons, 0, c_ab), flags(e_bnd, 0, b_ab)};
    // t2 = (a, p, c): opp a (p,c) -> t3; opp p (c,a) -> n_ca; opp c (a,p) -> t1
    t_[t2] = {{a, p, c}, {t3, n_ca, t1}, flags(e_cons, c_ca, 0), flags(e_bnd, b_ca, 0)};
    // t3 = (d, c, p): opp d (c,p) -> t2; opp c (p,d) -> t4; opp p (d,c) -> n_dc
    t_[t3] = {{d, c, p}, {t2, t4, n_dc}, flags(e_cons, 0, c_dc), flags(e_bnd, 0, b_dc)};
    // t4 = (d, p, b): opp d (p,b) -> t1; opp p (b,d) -> n_bd; opp b (d,p) -> t3
    t_[t4] = {{d, p, b}, {t1, n_bd, t3}, flags(e_cons, c_bd, 0), flags(e_bnd, b_bd, 0)};
    relink(n_ca, t, t2);
    relink(n_bd, u, t4);
    for (TriangleId x : {t1, t2, t3, t4}) touch(x);
    queue.emplace_back(t1, 2);
    queue.emplace_back(t2, 1);
    queue.emplace_back(t3, 2);
    queue.emplace_back(t4, 1);
}


void order_by_largest_corner(Array<Triangle>& tris, size_t point_count, const char* gone) {
    auto corner = [](const Triangle& t) { return std::max({t.v[0], t.v[1], t.v[2]}); };
    auto kept = [&](TriangleId t) { return gone == nullptr || !gone[t]; };
    if (gone == nullptr &&
        std::is_sorted(tris.begin(), tris.end(), [&](const Triangle& a, const Triangle& b) { return corner(a) < corner(b); }))
        return;  // the Delaunay triangulator's output is
    // A counting sort, into storage on huge pages.
    Array<std::uint32_t> start;
    assign_huge(start, point_count + 1, std::uint32_t{0});
    for (TriangleId t = 0; t < tris.size(); ++t)
        if (kept(t)) ++start[corner(tris[t]) + 1];
    for (size_t v = 0; v < point_count; ++v) start[v + 1] += start[v];
    Array<TriangleId> remap;
    assign_huge(remap, tris.size(), kNoTriangle);
    for (TriangleId t = 0; t < tris.size(); ++t)
        if (kept(t)) remap[t] = start[corner(tris[t])]++;
    Array<Triangle> out;
    assign_huge(out, static_cast<size_t>(start[point_count]), Triangle{});
    for (TriangleId t = 0; t < tris.size(); ++t) {
        if (!kept(t)) continue;
        Triangle& o = out[remap[t]];
        o = tris[t];
        for (auto& nb : o.n) nb = nb == kNoTriangle ? kNoTriangle : remap[nb];
    }
    tris = std::move(out);
}

}  // namespace detail

}  // namespace meshd::core
