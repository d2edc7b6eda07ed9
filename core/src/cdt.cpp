// Incremental constrained Delaunay triangulation (the default triangulator).
//
// 1. Points are inserted in a biased randomised insertion order (BRIO: rounds growing
//    eightfold, each sorted along a Hilbert curve; the points are stored in that order) into
//    a Delaunay triangulation inside a large enclosing triangle; each point is located by a
//    visibility walk from the previous insertion, splits its triangle (or the edge it lies
//    on) and is legalised by Lawson flips of the edges opposite it.
// 2. Each constraint is recovered by flipping the edges that cross it (Sloan 1993): a crossing
//    edge whose quad is convex is flipped; if the new diagonal still crosses, it goes back in
//    the queue. The edges made this way are then legalised. A constraint passing through
//    another point is split there.
// 3. A flood fill from the enclosing triangle and from the outer side of every loop segment,
//    never crossing a loop segment, finds the outside and the holes, which are dropped.
// All decisions are exact signs (orient2d, incircle_perturbed).

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <memory>

#include "cdt.hpp"
#include "spatial_order.hpp"
#include "meshd/core/errors.hpp"
#include "meshd/core/observer.hpp"
#include "meshd/core/predicates.hpp"

namespace meshd::core {

namespace detail {

std::uint32_t TriangleSoup::back_index(TriangleId u, TriangleId t) const {
    const Triangle& tu = t_[u];
    return tu.n[0] == t ? 0u : (tu.n[1] == t ? 1u : 2u);
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
    const std::uint32_t cons_t = T.constrained, bnd_t = T.boundary;
    const std::uint32_t cons_u = U.constrained, bnd_u = U.boundary;
    auto bit = [](std::uint32_t flags, std::uint32_t k) { return (flags >> k) & 1u; };
    const std::uint32_t c_pb = bit(cons_t, prev3(i)), b_pb = bit(bnd_t, prev3(i));
    const std::uint32_t c_cp = bit(cons_t, next3(i)), b_cp = bit(bnd_t, next3(i));
    const std::uint32_t c_bq = bit(cons_u, next3(j)), b_bq = bit(bnd_u, next3(j));
    const std::uint32_t c_qc = bit(cons_u, prev3(j)), b_qc = bit(bnd_u, prev3(j));
    // t = (p, b, q): opp p (b,q) -> n_bq; opp b (q,p) -> u; opp q (p,b) -> n_pb.
    T.v = {p, b, q};
    T.n = {n_bq, u, n_pb};
    T.constrained = static_cast<std::uint8_t>(c_bq | (c_pb << 2));
    T.boundary = static_cast<std::uint8_t>(b_bq | (b_pb << 2));
    // u = (p, q, c): opp p (q,c) -> n_qc; opp q (c,p) -> n_cp; opp c (p,q) -> t.
    U.v = {p, q, c};
    U.n = {n_qc, n_cp, t};
    U.constrained = static_cast<std::uint8_t>(c_qc | (c_cp << 1));
    U.boundary = static_cast<std::uint8_t>(b_qc | (b_cp << 1));
    if (n_bq != kNoTriangle) t_[n_bq].n[back_index(n_bq, u)] = t;
    if (n_cp != kNoTriangle) t_[n_cp].n[back_index(n_cp, t)] = u;
    if (track_) {
        vtri_[p] = t;
        vtri_[b] = t;
        vtri_[q] = u;
        vtri_[c] = u;
    }
}

bool TriangleSoup::illegal(TriangleId t, std::uint32_t i) const {
    const Triangle& T = t_[t];
    const TriangleId u = T.n[i];
    if (u == kNoTriangle || edge_bit(T.constrained, i)) return false;
    const std::uint32_t q = t_[u].v[back_index(u, t)];
    const Vec2 a = pts_[T.v[0]], b = pts_[T.v[1]], c = pts_[T.v[2]], d = pts_[q];
    const int s = incircle(a, b, c, d);
    if (s != 0) return s > 0;
    auto rank = [&](std::uint32_t v) { return rank_ ? (*rank_)[v] : v; };
    return detail::incircle_tie(a, b, c, d, rank(T.v[0]), rank(T.v[1]), rank(T.v[2]), rank(q)) > 0;
}

template <bool kInsertion>
std::uint64_t TriangleSoup::lawson(std::vector<std::pair<TriangleId, std::uint32_t>>& queue,
                                   std::vector<TriangleId>* changed) {
    std::uint64_t flips = 0;
    while (!queue.empty()) {
        const auto [t, i] = queue.back();
        queue.pop_back();
        if (!illegal(t, i)) continue;
        const TriangleId u = t_[t].n[i];
        flip(t, i);  // p = old t.v[i] is now v[0] of both t = (p, b, q) and u = (p, q, c)
        ++flips;
        if (changed) {
            changed->push_back(t);
            changed->push_back(u);
        }
        // The outer edges of the quad: t's edges 0 and 2, u's edges 0 and 1; after an
        // insertion only those opposite p (t's 0, u's 0) can be illegal.
        if (kInsertion) {
            queue.emplace_back(t, 0);
            queue.emplace_back(u, 0);
        } else {
            queue.emplace_back(t, 0);
            queue.emplace_back(t, 2);
            queue.emplace_back(u, 0);
            queue.emplace_back(u, 1);
        }
    }
    return flips;
}

std::uint64_t TriangleSoup::legalize(std::vector<std::pair<TriangleId, std::uint32_t>>& queue,
                                     std::vector<TriangleId>* changed) {
    return lawson<false>(queue, changed);
}

std::uint64_t TriangleSoup::legalize_insertion(std::vector<std::pair<TriangleId, std::uint32_t>>& queue) {
    return lawson<true>(queue, nullptr);
}

std::pair<TriangleId, std::uint32_t> TriangleSoup::find_edge(std::uint32_t a, std::uint32_t b) const {
    const TriangleId start = vtri_[a];
    if (start == kNoTriangle) return {kNoTriangle, 0};
    // Clockwise around a first (across the edge (a, v[k+1])), then counter-clockwise, so
    // that a vertex on the outer boundary (open fan) is fully covered.
    TriangleId t = start;
    do {
        const std::uint32_t k = index_of(t_[t], a);
        if (t_[t].v[next3(k)] == b) return {t, k};
        t = t_[t].n[prev3(k)];
    } while (t != kNoTriangle && t != start);
    if (t == start) return {kNoTriangle, 0};
    t = start;
    for (;;) {
        const std::uint32_t k = index_of(t_[t], a);
        const TriangleId nt = t_[t].n[next3(k)];
        if (nt == kNoTriangle) break;
        t = nt;
        const std::uint32_t kk = index_of(t_[t], a);
        if (t_[t].v[next3(kk)] == b) return {t, kk};
    }
    return {kNoTriangle, 0};
}

void TriangleSoup::rebuild_vertex_index() {
    std::uint32_t max_v = 0;
    for (const auto& t : t_)
        for (auto v : t.v) max_v = std::max(max_v, v);
    vtri_.assign(std::max<size_t>(pts_.size(), static_cast<size_t>(max_v) + 1), kNoTriangle);
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
    // Rotate each so that p is at index 0 for legalize's convention? legalize works with
    // any (t, i): the edge opposite p is index 2 here.
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


void order_by_largest_corner(std::vector<Triangle>& tris, size_t point_count) {
    std::vector<std::uint32_t> start(point_count + 1, 0);
    auto corner = [](const Triangle& t) { return std::max({t.v[0], t.v[1], t.v[2]}); };
    for (const Triangle& t : tris) ++start[corner(t)];
    std::uint32_t sum = 0;
    for (auto& c : start) {
        const std::uint32_t n = c;
        c = sum;
        sum += n;
    }
    std::vector<TriangleId> remap(tris.size());
    for (TriangleId t = 0; t < tris.size(); ++t) remap[t] = start[corner(tris[t])]++;
    std::vector<Triangle> out(tris.size());
    for (TriangleId t = 0; t < tris.size(); ++t) {
        Triangle& o = out[remap[t]];
        o = tris[t];
        for (auto& nb : o.n) nb = nb == kNoTriangle ? kNoTriangle : remap[nb];
    }
    tris = std::move(out);
}

}  // namespace detail

namespace {

using detail::next3;
using detail::prev3;

class Builder {
public:
    // The points are stored in insertion order (BRIO), so that vertices inserted one after
    // the other, which are near each other, are also near in memory; their input indices
    // stay their perturbation ranks, so the result does not depend on this renumbering.
    Builder(const std::vector<Vec2>& input, Observer* obs) : n_(input.size()), obs_(obs) {
        rank_ = detail::brio_order(input);
        inverse_.resize(n_);
        pts_.reserve(n_ + 3);
        for (size_t k = 0; k < n_; ++k) {
            pts_.push_back(input[rank_[k]]);
            inverse_[rank_[k]] = static_cast<std::uint32_t>(k);
        }
        Box box;
        for (const Vec2& p : input) box.add(p);
        if (box.empty()) box.add(Vec2{0, 0});
        const Vec2 c = 0.5 * (box.lo + box.hi);
        const double d = std::fmax(std::fmax(box.hi.x - box.lo.x, box.hi.y - box.lo.y), 1e-300) * 64.0;
        pts_.push_back({c.x - 2 * d, c.y - d});
        pts_.push_back({c.x + 2 * d, c.y - d});
        pts_.push_back({c.x, c.y + 2 * d});
        for (size_t k = n_; k < n_ + 3; ++k) rank_.push_back(static_cast<std::uint32_t>(k));
        tris_.reserve(2 * n_ + 16);
        tris_.push_back({{static_cast<std::uint32_t>(n_), static_cast<std::uint32_t>(n_ + 1), static_cast<std::uint32_t>(n_ + 2)},
                         {kNoTriangle, kNoTriangle, kNoTriangle}, 0, 0});
        soup_ = std::make_unique<detail::TriangleSoup>(pts_, tris_, true, &rank_);
        alias_.resize(n_);
        for (size_t i = 0; i < n_; ++i) alias_[i] = static_cast<std::uint32_t>(i);
    }

    void insert_all() {
        TriangleId hint = 0;
        for (size_t k = 0; k < n_; ++k) {
            if ((k & 4095) == 0 && obs_) {
                if (obs_->should_stop()) throw Cancelled();
                obs_->on_progress(Stage::Triangulation, 0.8 * static_cast<double>(k) / static_cast<double>(n_));
            }
            hint = insert(static_cast<std::uint32_t>(k), hint);
        }
    }

    void recover(const std::vector<Constraint>& constraints) {
        for (size_t k = 0; k < constraints.size(); ++k) {
            if ((k & 1023) == 0 && obs_ && obs_->should_stop()) throw Cancelled();
            const Constraint& c = constraints[k];
            recover_segment(alias_[inverse_[c.a]], alias_[inverse_[c.b]], c.loop, 0);
        }
    }

    TriangulationResult finish() {
        // Flood fill of what goes: from the enclosing triangle's corner and from the outer
        // side of every loop segment, never across a loop segment. This region (the outside
        // and the holes) is usually much smaller than the domain.
        std::vector<char> gone(tris_.size(), 0);
        std::vector<TriangleId> stack;
        auto seed = [&](TriangleId t) {
            if (t == kNoTriangle || gone[t]) return;
            gone[t] = 1;
            stack.push_back(t);
        };
        seed(soup_->vertex_triangle(static_cast<std::uint32_t>(n_)));
        std::vector<TriangleId> inner;
        inner.reserve(loop_edges_.size());
        for (const auto& [a, b] : loop_edges_) {
            const auto [t, k] = soup_->find_edge(a, b);
            MESHD_INTERNAL_CHECK(t != kNoTriangle, "a loop segment is missing after recovery");
            inner.push_back(t);
            seed(tris_[t].n[prev3(k)]);
        }
        while (!stack.empty()) {
            const TriangleId t = stack.back();
            stack.pop_back();
            for (std::uint32_t i = 0; i < 3; ++i)
                if (!edge_bit(tris_[t].boundary, i)) seed(tris_[t].n[i]);
        }
        for (const TriangleId t : inner)
            MESHD_INTERNAL_CHECK(!gone[t], "the outside reached the domain: a loop is open or turns the wrong way");
        // Compact in place (a triangle only moves down), then renumber neighbours and corners.
        std::vector<TriangleId> remap(tris_.size(), kNoTriangle);
        TriangleId kept = 0;
        for (TriangleId t = 0; t < tris_.size(); ++t) {
            if (gone[t]) continue;
            remap[t] = kept;
            tris_[kept++] = tris_[t];
        }
        tris_.resize(kept);
        for (Triangle& t : tris_) {
            for (auto& nb : t.n) nb = nb == kNoTriangle ? kNoTriangle : remap[nb];
            for (auto& v : t.v) {
                MESHD_INTERNAL_CHECK(v < n_, "the enclosing triangle reached the domain: a loop is open");
                v = rank_[v];
            }
        }
        TriangulationResult r;
        r.triangles = std::move(tris_);
        r.alias.resize(n_);
        for (size_t i = 0; i < n_; ++i) r.alias[i] = rank_[alias_[inverse_[i]]];
        r.stats = stats_;
        return r;
    }

private:
    // Visibility walk from `t` to the triangle holding p (inside or on its boundary).
    TriangleId locate(const Vec2& p, TriangleId t) {
        std::uint32_t r = 0;
        for (;;) {
            const Triangle& T = tris_[t];
            bool moved = false;
            r = r * 1103515245u + 12345u;  // vary the first edge tried: no cycling
            const std::uint32_t off = (r >> 16) % 3;
            for (std::uint32_t k = 0; k < 3; ++k) {
                const std::uint32_t i = (off + k) % 3;
                const Vec2& a = pts_[T.v[next3(i)]];
                const Vec2& b = pts_[T.v[prev3(i)]];
                if (orient2d(a, b, p) == Orientation::Right) {
                    t = T.n[i];
                    MESHD_INTERNAL_CHECK(t != kNoTriangle, "point outside the enclosing triangle");
                    moved = true;
                    ++stats_.walk_steps;
                    break;
                }
            }
            if (!moved) return t;
        }
    }

    TriangleId insert(std::uint32_t v, TriangleId hint) {
        const Vec2& p = pts_[v];
        const TriangleId t = locate(p, hint);
        Triangle& T = tris_[t];
        int on_edge = -1;
        for (std::uint32_t i = 0; i < 3; ++i) {
            if (pts_[T.v[i]] == p) {
                alias_[v] = T.v[i];
                ++stats_.duplicates;
                return t;
            }
        }
        for (std::uint32_t i = 0; i < 3; ++i) {
            if (orient2d(pts_[T.v[next3(i)]], pts_[T.v[prev3(i)]], p) == Orientation::Collinear) on_edge = static_cast<int>(i);
        }
        std::vector<std::pair<TriangleId, std::uint32_t>>& queue = queue_;
        queue.clear();
        if (on_edge < 0) soup_->split_triangle(t, v, queue);
        else soup_->split_edge(t, static_cast<std::uint32_t>(on_edge), v, queue);
        stats_.flips += soup_->legalize_insertion(queue);
        return soup_->vertex_triangle(v);
    }

    void mark_constraint(std::uint32_t a, std::uint32_t b, bool loop) {
        const auto [t, k] = soup_->find_edge(a, b);
        MESHD_INTERNAL_CHECK(t != kNoTriangle, "constraint edge not found");
        soup_->set_flag(t, prev3(k), true, loop || edge_bit(tris_[t].boundary, prev3(k)));
        if (loop) loop_edges_.emplace_back(a, b);
    }

    void recover_segment(std::uint32_t a, std::uint32_t b, bool loop, int depth) {
        if (a == b) return;
        MESHD_INTERNAL_CHECK(depth < 100000, "constraint recovery does not terminate");
        if (soup_->find_edge(a, b).first != kNoTriangle) {
            mark_constraint(a, b, loop);
            return;
        }
        if (soup_->find_edge(b, a).first != kNoTriangle) {
            mark_constraint(a, b, loop);  // exists in the other direction: find_edge(a, b) fails
            return;
        }
        const Vec2 pa = pts_[a], pb = pts_[b];
        // The triangle around a whose wedge holds the direction to b.
        TriangleId t = soup_->vertex_triangle(a);
        const TriangleId start = t;
        std::uint32_t l = 0, r = 0;
        bool found = false;
        do {
            const Triangle& T = tris_[t];
            const std::uint32_t k = detail::TriangleSoup::index_of(T, a);
            const std::uint32_t v1 = T.v[next3(k)], v2 = T.v[prev3(k)];
            const Orientation o1 = orient2d(pa, pb, pts_[v1]);
            const Orientation o2 = orient2d(pa, pb, pts_[v2]);
            if (o1 == Orientation::Collinear && dot(pts_[v1] - pa, pb - pa) > 0.0) {
                // v1 lies on the segment: split there.
                recover_segment(a, v1, loop, depth + 1);
                recover_segment(v1, b, loop, depth + 1);
                return;
            }
            if (o1 == Orientation::Right && o2 == Orientation::Left) {
                r = v1;
                l = v2;
                found = true;
                break;
            }
            t = T.n[next3(k)];  // counter-clockwise around a: across (v2, a)
        } while (t != start && t != kNoTriangle);
        MESHD_INTERNAL_CHECK(found, "constraint start not found around its vertex");
        // Walk to b collecting the crossing edges (l left of a->b, r right of it).
        std::deque<std::pair<std::uint32_t, std::uint32_t>> crossing;
        crossing.emplace_back(l, r);
        TriangleId cur = t;
        for (;;) {
            const Triangle& C = tris_[cur];
            // Edge (r, l) of cur is opposite the vertex that is neither: cross it.
            std::uint32_t opp = 0;
            for (std::uint32_t i = 0; i < 3; ++i)
                if (C.v[i] != l && C.v[i] != r) opp = i;
            const TriangleId nxt = C.n[opp];
            MESHD_INTERNAL_CHECK(nxt != kNoTriangle, "constraint walk left the triangulation");
            const Triangle& N = tris_[nxt];
            std::uint32_t w = 0;
            for (std::uint32_t i = 0; i < 3; ++i)
                if (N.v[i] != l && N.v[i] != r) w = N.v[i];
            if (w == b) break;
            const Orientation o = orient2d(pa, pb, pts_[w]);
            if (o == Orientation::Collinear) {
                // A point on the segment: recover the two halves separately.
                recover_segment(a, w, loop, depth + 1);
                recover_segment(w, b, loop, depth + 1);
                return;
            }
            if (o == Orientation::Left) l = w; else r = w;
            crossing.emplace_back(l, r);
            cur = nxt;
        }
        // Flip the crossing edges away.
        std::vector<std::pair<std::uint32_t, std::uint32_t>> fresh;
        size_t guard = 0;
        while (!crossing.empty()) {
            MESHD_INTERNAL_CHECK(++guard < 100000000, "constraint flipping does not terminate");
            const auto [x, y] = crossing.front();
            crossing.pop_front();
            auto [et, ek] = soup_->find_edge(x, y);
            std::uint32_t ei;
            if (et == kNoTriangle) {
                auto rev = soup_->find_edge(y, x);
                et = rev.first;
                ei = prev3(rev.second);
            } else {
                ei = prev3(ek);
            }
            MESHD_INTERNAL_CHECK(et != kNoTriangle, "crossing edge vanished");
            const Triangle& E = tris_[et];
            const TriangleId nb = E.n[ei];
            const std::uint32_t p = E.v[ei];
            const std::uint32_t q = tris_[nb].v[soup_->back_index(nb, et)];
            const std::uint32_t s1 = E.v[next3(ei)], s2 = E.v[prev3(ei)];
            // Convex quad p, s1, q, s2: the diagonals cross properly.
            const bool convex = orient2d(pts_[p], pts_[q], pts_[s1]) != orient2d(pts_[p], pts_[q], pts_[s2]) &&
                                orient2d(pts_[p], pts_[q], pts_[s1]) != Orientation::Collinear &&
                                orient2d(pts_[p], pts_[q], pts_[s2]) != Orientation::Collinear;
            if (!convex) {
                crossing.emplace_back(x, y);
                continue;
            }
            soup_->flip(et, ei);
            ++stats_.flips;
            const Orientation op = orient2d(pa, pb, pts_[p]);
            const Orientation oq = orient2d(pa, pb, pts_[q]);
            const bool still = op != Orientation::Collinear && oq != Orientation::Collinear && op != oq &&
                               p != a && p != b && q != a && q != b;
            if (still) crossing.emplace_back(op == Orientation::Left ? p : q, op == Orientation::Left ? q : p);
            else fresh.emplace_back(p, q);
        }
        mark_constraint(a, b, loop);
        // Legalise the new edges (except the constraint itself).
        queue_.clear();
        for (const auto& [x, y] : fresh) {
            if ((x == a && y == b) || (x == b && y == a)) continue;
            auto [et, ek] = soup_->find_edge(x, y);
            if (et != kNoTriangle) queue_.emplace_back(et, prev3(ek));
        }
        stats_.flips += soup_->legalize(queue_);
    }

    size_t n_;
    Observer* obs_;
    std::vector<Vec2> pts_;
    std::vector<Triangle> tris_;
    std::unique_ptr<detail::TriangleSoup> soup_;
    std::vector<std::uint32_t> rank_;     // internal index -> input index (and perturbation rank)
    std::vector<std::uint32_t> inverse_;  // input index -> internal index
    std::vector<std::uint32_t> alias_;    // internal index -> the internal index it coincides with
    std::vector<std::pair<std::uint32_t, std::uint32_t>> loop_edges_;
    std::vector<std::pair<TriangleId, std::uint32_t>> queue_;
    TriangulationStats stats_;
};

}  // namespace

TriangulationResult triangulate_delaunay(const std::vector<Vec2>& points,
                                         const std::vector<Constraint>& constraints, Observer* observer) {
    Builder b(points, observer);
    b.insert_all();
    b.recover(constraints);
    return b.finish();
}

std::uint64_t make_delaunay(const std::vector<Vec2>& points, std::vector<Triangle>& triangles) {
    detail::TriangleSoup soup(points, triangles, false);
    std::vector<std::pair<TriangleId, std::uint32_t>> queue;
    queue.reserve(3 * triangles.size());
    for (TriangleId t = 0; t < triangles.size(); ++t)
        for (std::uint32_t i = 0; i < 3; ++i)
            if (triangles[t].n[i] != kNoTriangle && triangles[t].n[i] > t) queue.emplace_back(t, i);
    return soup.legalize(queue);
}

}  // namespace meshd::core
