// Incremental constrained Delaunay triangulation (the default triangulator).
//
// 1. Points are inserted in a biased randomised insertion order (BRIO: rounds growing
//    eightfold, each sorted along a Hilbert curve; the points are stored in that order) into
//    a Delaunay triangulation inside a large enclosing triangle; each point is located by a
//    visibility walk from the previous insertion, splits its triangle (or the edge it lies
//    on) and is legalised by Lawson flips of the edges opposite it. While the points go in,
//    each link to a neighbour also names the shared edge's index in it (3 u + j), so that
//    splits and flips reach back into their neighbours without searching them (20% less
//    time for this stage on the load run's square than TriangleSoup's splits and flips).
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

#include "triangulation/triangle_soup.hpp"
#include "kernel/spatial_order.hpp"
#include "kernel/memory.hpp"
#include "meshd/core/errors.hpp"
#include "meshd/core/observer.hpp"
#include "kernel/predicates.hpp"

namespace meshd::core {



namespace {

using detail::next3;
using detail::prev3;

class IncrementalCdt {
public:
    // The points are stored in insertion order (BRIO), so that vertices inserted one after
    // the other, which are near each other, are also near in memory; their input indices
    // stay their perturbation ranks, so the result does not depend on this renumbering.
    IncrementalCdt(std::span<const Vec2> input, Observer* obs) : n_(input.size()), obs_(obs) {
        rank_ = detail::brio_order(input);
        detail::assign_huge(inverse_, n_, std::uint32_t{0});
        detail::reserve_filled(pts_, n_ + 3);
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
        detail::reserve_filled(tris_, 2 * n_ + 16);  // about 2n triangles, the outside's included
        tris_.push_back({{static_cast<std::uint32_t>(n_), static_cast<std::uint32_t>(n_ + 1), static_cast<std::uint32_t>(n_ + 2)},
                         {kNoTriangle, kNoTriangle, kNoTriangle}, 0, 0});
        soup_ = std::make_unique<detail::TriangleSoup>(pts_, tris_, true, rank_.data());
        detail::assign_huge(alias_, n_, std::uint32_t{0});
        for (size_t i = 0; i < n_; ++i) alias_[i] = static_cast<std::uint32_t>(i);
    }

    void insert_all() {
        MESHD_INTERNAL_CHECK(4 * (2 * n_ + 16) < kNoTriangle, "too many points for the triangulation's links");
        TriangleId hint = 0;
        for (size_t k = 0; k < n_; ++k) {
            if ((k & 4095) == 0 && obs_) {
                if (obs_->should_stop()) throw Cancelled();
                obs_->on_progress(Stage::Triangulation, 0.8 * static_cast<double>(k) / static_cast<double>(n_));
            }
            hint = insert(static_cast<std::uint32_t>(k), hint);
        }
        // The links become triangle ids again, and the soup learns a triangle of every vertex.
        for (Triangle& T : tris_)
            for (auto& h : T.n) h = h == kNoTriangle ? kNoTriangle : across(h);
        soup_->rebuild_vertex_index();
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
        Array<char> gone;
        detail::assign_huge(gone, tris_.size(), char{0});
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
        // The kept triangles with their corners' input indices, in the order of the largest
        // (what order_by_largest_corner asks of a mesh).
        for (TriangleId t = 0; t < tris_.size(); ++t) {
            if (gone[t]) continue;
            for (auto& v : tris_[t].v) {
                MESHD_INTERNAL_CHECK(v < n_, "the enclosing triangle reached the domain: a loop is open");
                v = rank_[v];
            }
        }
        TriangulationResult r;
        r.alias.resize(n_);
        for (size_t i = 0; i < n_; ++i) r.alias[i] = rank_[alias_[inverse_[i]]];
        // Nothing else is needed now but the triangles: the points, the soup's index and the
        // orders go before the ordered copy of the triangles is made, and their blocks make
        // part of it (at 10^7 points the stage then takes no fresh pages, 274 MB without).
        soup_.reset();
        Array<Vec2>().swap(pts_);
        Array<std::uint32_t>().swap(rank_);
        Array<std::uint32_t>().swap(inverse_);
        Array<std::uint32_t>().swap(alias_);
        detail::order_by_largest_corner(tris_, n_, gone.data());
        r.triangles = std::move(tris_);
        r.stats = stats_;
        return r;
    }

private:
    // Visibility walk from `t` to the triangle holding p (inside or on its boundary). In
    // `on_edge`, the last edge of that triangle found to pass through p (-1: none); the walk's
    // last step has asked every edge, so the insertion need not ask again.
    TriangleId locate(const Vec2& p, TriangleId t, int& on_edge) {
        std::uint32_t r = 0;
        // In a Delaunay triangulation a visibility walk never comes back to a triangle, so it
        // takes at most as many steps as there are triangles; more is a broken triangulation,
        // reported rather than walked forever.
        size_t steps = 0;
        for (;;) {
            const Triangle& T = tris_[t];
            bool moved = false;
            r = r * 1103515245u + 12345u;  // vary the first edge tried: no cycling
            std::uint32_t i = (r >> 16) % 3;
            on_edge = -1;
            for (std::uint32_t k = 0; k < 3; ++k, i = next3(i)) {
                const Vec2& a = pts_[T.v[next3(i)]];
                const Vec2& b = pts_[T.v[prev3(i)]];
                const Orientation o = orient2d(a, b, p);
                if (o == Orientation::Right) {
                    MESHD_INTERNAL_CHECK(T.n[i] != kNoTriangle, "point outside the enclosing triangle");
                    MESHD_INTERNAL_CHECK(++steps <= tris_.size(), "point location does not terminate");
                    t = across(T.n[i]);
                    moved = true;
                    ++stats_.walk_steps;
                    break;
                }
                if (o == Orientation::Collinear) on_edge = static_cast<int>(i);
            }
            if (!moved) return t;
        }
    }

    TriangleId insert(std::uint32_t v, TriangleId hint) {
        const Vec2& p = pts_[v];
        int on_edge = -1;
        const TriangleId t = locate(p, hint, on_edge);
        Triangle& T = tris_[t];
        if (on_edge >= 0) {
            // Only a point on an edge can be one of its corners.
            for (std::uint32_t i = 0; i < 3; ++i) {
                if (pts_[T.v[i]] == p) {
                    alias_[v] = T.v[i];
                    ++stats_.duplicates;
                    return t;
                }
            }
        }
        queue_.clear();
        TriangleId last = on_edge < 0 ? split_triangle(t, v) : split_edge(t, static_cast<std::uint32_t>(on_edge), v);
        // Lawson's flips: after an insertion only the edges opposite v can be illegal, and
        // each flip leaves v at corner 0 of both its triangles, opposite the two new outer
        // edges of the quad. Each flip makes one more edge at v, so a valid triangulation
        // takes fewer flips than it has triangles; more is a broken one, reported rather than
        // flipped forever.
        size_t flips = 0;
        while (!queue_.empty()) {
            const auto [f, i] = queue_.back();
            queue_.pop_back();
            if (!illegal(f, i)) continue;
            MESHD_INTERNAL_CHECK(++flips <= tris_.size(), "an insertion's flips do not terminate");
            const TriangleId u = flip(f, i);
            ++stats_.flips;
            last = f;
            queue_.emplace_back(f, 0);
            queue_.emplace_back(u, 0);
        }
        return last;  // the newest triangle around v: the next walk starts there
    }

    // The insertions' own splits and flips. While the points go in, a link n[i] holds
    // 4 u + j, where u is the neighbour across edge i and j the index of that edge in u
    // (kNoTriangle: none), so that a flip finds its way back into each neighbour without
    // searching the neighbour's links; insert_all() turns them into triangle ids at the end.
    // (4 rather than 3: a shift and a mask to read a link back, not a multiplication for
    // each of the quotient and the remainder; 4% fewer instructions in this stage.)
    // No edge is constrained yet. Each makes the same triangles in the same slots, turned the
    // same way, as TriangleSoup's split_triangle, split_edge and flip (the constraints'
    // recovery and everything after it use those), so the result does not depend on which
    // made them.
    static std::uint32_t link(TriangleId t, std::uint32_t i) { return 4 * t + i; }
    static TriangleId across(std::uint32_t h) { return h >> 2; }
    static std::uint32_t edge_in(std::uint32_t h) { return h & 3; }

    // Points the link h (from the far side) at edge i of t.
    void link_back(std::uint32_t h, TriangleId t, std::uint32_t i) {
        if (h != kNoTriangle) tris_[across(h)].n[edge_in(h)] = link(t, i);
    }

    TriangleId new_triangle() {
        tris_.push_back({});
        return static_cast<TriangleId>(tris_.size() - 1);
    }

    // v inside t = (a, b, c): t becomes (a, b, v), and (b, c, v), (c, a, v) are new. Returns
    // the last of them; v is corner 2 of each, opposite the edge queued for the flips.
    TriangleId split_triangle(TriangleId t, std::uint32_t v) {
        const Triangle T = tris_[t];
        const std::uint32_t a = T.v[0], b = T.v[1], c = T.v[2];
        const TriangleId ab = t, bc = new_triangle(), ca = new_triangle();
        tris_[ab] = {{a, b, v}, {link(bc, 1), link(ca, 0), T.n[2]}, 0, 0};
        tris_[bc] = {{b, c, v}, {link(ca, 1), link(ab, 0), T.n[0]}, 0, 0};
        tris_[ca] = {{c, a, v}, {link(ab, 1), link(bc, 0), T.n[1]}, 0, 0};
        link_back(T.n[2], ab, 2);
        link_back(T.n[0], bc, 2);
        link_back(T.n[1], ca, 2);
        queue_.emplace_back(ab, 2);
        queue_.emplace_back(bc, 2);
        queue_.emplace_back(ca, 2);
        return ca;
    }

    // v on edge i of t = (a, b, c) (a = v[i]), shared with u = (d, c, b): four triangles,
    // t = (a, b, v), (a, v, c), u = (d, c, v), (d, v, b). Returns the last.
    TriangleId split_edge(TriangleId t, std::uint32_t i, std::uint32_t v) {
        const Triangle T = tris_[t];
        MESHD_INTERNAL_CHECK(T.n[i] != kNoTriangle, "a point on the enclosing triangle's side");
        const TriangleId u = across(T.n[i]);
        const std::uint32_t j = edge_in(T.n[i]);
        const Triangle U = tris_[u];
        const std::uint32_t a = T.v[i], b = T.v[next3(i)], c = T.v[prev3(i)], d = U.v[j];
        const std::uint32_t h_ab = T.n[prev3(i)], h_ca = T.n[next3(i)];
        const std::uint32_t h_dc = U.n[prev3(j)], h_bd = U.n[next3(j)];
        const TriangleId t1 = t, t2 = new_triangle(), t3 = u, t4 = new_triangle();
        tris_[t1] = {{a, b, v}, {link(t4, 0), link(t2, 2), h_ab}, 0, 0};
        tris_[t2] = {{a, v, c}, {link(t3, 0), h_ca, link(t1, 1)}, 0, 0};
        tris_[t3] = {{d, c, v}, {link(t2, 0), link(t4, 2), h_dc}, 0, 0};
        tris_[t4] = {{d, v, b}, {link(t1, 0), h_bd, link(t3, 1)}, 0, 0};
        link_back(h_ab, t1, 2);
        link_back(h_ca, t2, 1);
        link_back(h_dc, t3, 2);
        link_back(h_bd, t4, 1);
        queue_.emplace_back(t1, 2);
        queue_.emplace_back(t2, 1);
        queue_.emplace_back(t3, 2);
        queue_.emplace_back(t4, 1);
        return t4;
    }

    // True when edge i of t is not locally Delaunay (perturbed by rank, as the soup's).
    bool illegal(TriangleId t, std::uint32_t i) const {
        const Triangle& T = tris_[t];
        const std::uint32_t h = T.n[i];
        if (h == kNoTriangle) return false;
        const std::uint32_t q = tris_[across(h)].v[edge_in(h)];
        const int s = incircle(pts_[T.v[0]], pts_[T.v[1]], pts_[T.v[2]], pts_[q]);
        return s != 0 ? s > 0 : soup_->cocircular_illegal(T, q);
    }

    // Flips edge i of t = (p, b, c) (p = v[i]) with u = (q, c, b) across it: t = (p, b, q),
    // u = (p, q, c), as TriangleSoup::flip draws it. Returns u.
    TriangleId flip(TriangleId t, std::uint32_t i) {
        Triangle& T = tris_[t];
        const TriangleId u = across(T.n[i]);
        const std::uint32_t j = edge_in(T.n[i]);
        Triangle& U = tris_[u];
        const std::uint32_t p = T.v[i], b = T.v[next3(i)], c = T.v[prev3(i)], q = U.v[j];
        const std::uint32_t h_pb = T.n[prev3(i)], h_cp = T.n[next3(i)];
        const std::uint32_t h_bq = U.n[next3(j)], h_qc = U.n[prev3(j)];
        T.v = {p, b, q};
        T.n = {h_bq, link(u, 2), h_pb};
        U.v = {p, q, c};
        U.n = {h_qc, h_cp, link(t, 1)};
        link_back(h_bq, t, 0);
        link_back(h_pb, t, 2);
        link_back(h_qc, u, 0);
        link_back(h_cp, u, 1);
        return u;
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
        // The triangle around a whose wedge holds the direction to b; a neighbour of a on
        // the segment splits it there.
        std::uint32_t l = 0, r = 0, on_segment = kNoVertex;
        const TriangleId t = soup_->around(a, [&](TriangleId x) {
            const Triangle& T = tris_[x];
            const std::uint32_t k = detail::TriangleSoup::index_of(T, a);
            const std::uint32_t v1 = T.v[next3(k)], v2 = T.v[prev3(k)];
            const Orientation o1 = orient2d(pa, pb, pts_[v1]);
            const Orientation o2 = orient2d(pa, pb, pts_[v2]);
            if (o1 == Orientation::Collinear && dot(pts_[v1] - pa, pb - pa) > 0.0) {
                on_segment = v1;
                return true;
            }
            if (o1 == Orientation::Right && o2 == Orientation::Left) {
                r = v1;
                l = v2;
                return true;
            }
            return false;
        });
        MESHD_INTERNAL_CHECK(t != kNoTriangle, "constraint start not found around its vertex");
        if (on_segment != kNoVertex) {
            recover_segment(a, on_segment, loop, depth + 1);
            recover_segment(on_segment, b, loop, depth + 1);
            return;
        }
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
    Array<Vec2> pts_;
    Array<Triangle> tris_;
    std::unique_ptr<detail::TriangleSoup> soup_;
    Array<std::uint32_t> rank_;     // internal index -> input index (and perturbation rank)
    Array<std::uint32_t> inverse_;  // input index -> internal index
    Array<std::uint32_t> alias_;    // internal index -> the internal index it coincides with
    std::vector<std::pair<std::uint32_t, std::uint32_t>> loop_edges_;
    std::vector<std::pair<TriangleId, std::uint32_t>> queue_;
    TriangulationStats stats_;
};

}  // namespace

TriangulationResult triangulate_delaunay(std::span<const Vec2> points,
                                         const std::vector<Constraint>& constraints, Observer* observer) {
    IncrementalCdt b(points, observer);
    b.insert_all();
    b.recover(constraints);
    return b.finish();
}

}  // namespace meshd::core
