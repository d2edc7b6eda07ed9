// The paper's triangulator (section 5, after Lo 1989): the Delaunay advancing front.
//
// The front starts as the loop segments (domain on their left) and the embedded segments
// in both directions, each split at the input points on it. For the last front edge AB,
// the candidates are the live points on its left within a radius R of its midpoint (R
// starts at |AB|); among those visible from AB (AC and BC cross no front edge) the one
// whose circle through A, B holds no other visible candidate is C*. Circles through A and
// B are nested on the left of AB, so the smallest of all is C* when it is visible (nearly
// always: the crossing test is asked once), and else one pass that replaces C* by any
// visible candidate inside its circle finds it. If that circle reaches beyond the searched
// disk, R grows and the search repeats, so the choice is exact. ABC* is formed; its edges
// close matching front edges or join the front. Decisions are exact and use the same
// perturbed in-circle test as the incremental triangulator, so both give the same
// triangles.

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <array>
#include <memory>
#include <numeric>
#include <unordered_map>

#include "triangulation/triangle_soup.hpp"
#include "kernel/size_grid.hpp"
#include "kernel/kdtree.hpp"
#include "meshd/core/errors.hpp"
#include "meshd/core/observer.hpp"
#include "kernel/constructions.hpp"
#include "kernel/predicates.hpp"
#include "triangulation/triangulation.hpp"

namespace meshd::core {

namespace {

using detail::CellMap;
using detail::SizeClasses;

// Disk queries over the static tree of kdtree.hpp.
class PointTree {
public:
    explicit PointTree(std::span<const Vec2> pts) : pts_(pts), tree_(pts) {}

    template <class F>
    void query(Vec2 c, double r, F&& visit) const {
        const double r2 = r * r;
        detail::depth_first(tree_.nodes, [&](const detail::KdNode& n) {
            if (n.box.distance2(c) > r2) return detail::Descend::No;
            if (n.left == 0) {
                for (std::uint32_t i = n.begin; i < n.end; ++i)
                    if (norm2(pts_[tree_.order[i]] - c) <= r2) visit(tree_.order[i]);
                return detail::Descend::No;
            }
            return detail::Descend::RightFirst;
        });
    }

private:
    std::span<const Vec2> pts_;
    detail::KdLayout tree_;
};


class DelaunayFront {
public:
    DelaunayFront(std::span<const Vec2> pts, const std::vector<Constraint>& cons, Observer* obs)
        : pts_(pts), obs_(obs), tree_(pts), front_degree_(pts.size(), 0), touched_(pts.size(), 0) {
        Box box;
        for (const Vec2& p : pts) box.add(p);
        extent_ = std::fmax(box.diagonal(), 1e-300);
        classes_ = std::make_unique<SizeClasses>(box.lo - Vec2{extent_, extent_}, extent_);
        require_distinct();
        cons_ = split_at_points(cons);
        for (const Constraint& c : cons_) {
            add_front(c.a, c.b);
            if (!c.loop) add_front(c.b, c.a);
        }
    }

    TriangulationResult run() {
        std::uint64_t steps = 0;
        while (!stack_.empty()) {
            const std::uint32_t f = stack_.back();
            stack_.pop_back();
            if (!edges_[f].alive) continue;
            if ((++steps & 4095) == 0 && obs_) {
                if (obs_->should_stop()) throw Cancelled();
                obs_->on_progress(Stage::Triangulation, std::fmin(0.99, static_cast<double>(tris_.size()) / (2.0 * static_cast<double>(pts_.size()))));
            }
            advance(f);
        }
        return finish();
    }

private:
    // Coinciding points are not merged here (the incremental triangulator merges them into
    // the one it inserted first; the mesher's points never coincide): refused.
    void require_distinct() const {
        std::vector<std::uint32_t> by(pts_.size());
        std::iota(by.begin(), by.end(), 0u);
        const auto less = [&](std::uint32_t u, std::uint32_t w) {
            return pts_[u].x != pts_[w].x ? pts_[u].x < pts_[w].x : pts_[u].y < pts_[w].y;
        };
        std::sort(by.begin(), by.end(), less);
        for (size_t i = 1; i < by.size(); ++i)
            MESHD_INTERNAL_CHECK(pts_[by[i]] != pts_[by[i - 1]], "advancing front: two input points coincide");
    }

    // A constraint through other input points becomes its pieces between them, as the
    // incremental triangulator's recovery splits it. The points on a segment are in the disk
    // over it (widened by the rounding of its centre and radius, so none is missed), tested
    // exactly, and ordered from a to b by the coordinate that changes along the segment.
    std::vector<Constraint> split_at_points(const std::vector<Constraint>& cons) const {
        std::vector<Constraint> out;
        out.reserve(cons.size());
        std::vector<std::uint32_t> on;
        for (const Constraint& c : cons) {
            const Vec2 pa = pts_[c.a], pb = pts_[c.b];
            const double scale = std::fmax(std::fmax(std::fabs(pa.x), std::fabs(pa.y)), std::fmax(std::fabs(pb.x), std::fabs(pb.y)));
            const double r = 0.5 * distance(pa, pb) * (1.0 + 1e-12) + 8.0 * DBL_EPSILON * scale;
            on.clear();
            tree_.query(0.5 * (pa + pb), r, [&](std::uint32_t v) {
                if (inside_segment(pa, pb, pts_[v])) on.push_back(v);
            });
            if (on.empty()) {
                out.push_back(c);
                continue;
            }
            const bool by_x = pa.x != pb.x;
            const bool up = by_x ? pa.x < pb.x : pa.y < pb.y;
            std::sort(on.begin(), on.end(), [&](std::uint32_t u, std::uint32_t w) {
                const double su = by_x ? pts_[u].x : pts_[u].y, sw = by_x ? pts_[w].x : pts_[w].y;
                return up ? su < sw : su > sw;
            });
            std::uint32_t from = c.a;
            for (std::uint32_t v : on) {
                out.push_back({from, v, c.loop});
                from = v;
            }
            out.push_back({from, c.b, c.loop});
        }
        return out;
    }

    struct FrontEdge {
        std::uint32_t a, b;
        bool alive;
        int k;  // size class
    };

    void add_front(std::uint32_t a, std::uint32_t b) {
        const auto id = static_cast<std::uint32_t>(edges_.size());
        const Vec2 pa = pts_[a], pb = pts_[b];
        const int k = classes_->class_of(distance(pa, pb));
        edges_.push_back({a, b, true, k});
        front_[detail::directed_key(a, b)] = id;
        stack_.push_back(id);
        ++front_degree_[a];
        ++front_degree_[b];
        touched_[a] = touched_[b] = 1;
        for (auto x = classes_->ix(std::fmin(pa.x, pb.x), k); x <= classes_->ix(std::fmax(pa.x, pb.x), k); ++x)
            for (auto y = classes_->iy(std::fmin(pa.y, pb.y), k); y <= classes_->iy(std::fmax(pa.y, pb.y), k); ++y)
                grid_.push(k, x, y, id);
        class_edges_[static_cast<size_t>(k)].push_back(id);
        ++class_alive_[static_cast<size_t>(k)];
    }

    void remove_front(std::uint32_t id) {
        FrontEdge& e = edges_[id];
        e.alive = false;
        front_.erase(detail::directed_key(e.a, e.b));
        --front_degree_[e.a];
        --front_degree_[e.b];
        const auto k = static_cast<size_t>(e.k);
        --class_alive_[k];
        // Keep each class's list about as long as its live edges.
        std::vector<std::uint32_t>& list = class_edges_[k];
        if (list.size() > 2 * class_alive_[k] + 32)
            std::erase_if(list, [&](std::uint32_t i) { return !edges_[i].alive; });
    }

    bool alive_point(std::uint32_t v) const { return !touched_[v] || front_degree_[v] > 0; }

    bool crosses(std::uint32_t p, std::uint32_t q, std::uint32_t id) const {
        const FrontEdge& f = edges_[id];
        if (!f.alive || f.a == p || f.b == p || f.a == q || f.b == q) return false;
        return segments_intersect(pts_[p], pts_[q], pts_[f.a], pts_[f.b]);
    }

    bool cell_blocks(std::uint32_t p, std::uint32_t q, int k, std::int64_t x, std::int64_t y) const {
        for (auto e = grid_.head(k, x, y); e != CellMap::kNone; e = grid_.next(e))
            if (crosses(p, q, grid_.item(e))) return true;
        return false;
    }

    // Does segment p-q cross a live front edge (other than at shared ends)? In each size class
    // an edge crossing p-q is listed in a cell p-q passes through (its box holds the crossing
    // point), so either those cells are searched, one column (or row) at a time, or, when the
    // class has fewer live edges than that walk has cells (an edge far smaller than p-q), the
    // class's own list.
    bool blocked(std::uint32_t p, std::uint32_t q) const {
        const Vec2 pp = pts_[p], pq = pts_[q];
        for (int k = 1; k <= SizeClasses::kMax; ++k) {
            const auto kk = static_cast<size_t>(k);
            if (class_alive_[kk] == 0) continue;
            const std::int64_t x0 = classes_->ix(std::fmin(pp.x, pq.x), k), x1 = classes_->ix(std::fmax(pp.x, pq.x), k);
            const std::int64_t y0 = classes_->iy(std::fmin(pp.y, pq.y), k), y1 = classes_->iy(std::fmax(pp.y, pq.y), k);
            const double cols = static_cast<double>(x1) - static_cast<double>(x0) + 1.0;
            const double rows = static_cast<double>(y1) - static_cast<double>(y0) + 1.0;
            if (4.0 * std::fmin(cols, rows) + std::fmax(cols, rows) >= static_cast<double>(class_edges_[kk].size())) {
                for (std::uint32_t id : class_edges_[kk])
                    if (crosses(p, q, id)) return true;
                continue;
            }
            // Walk along the longer direction; in each column (row) the segment covers a range
            // of rows (columns), widened by one for rounding.
            const bool by_x = cols >= rows;
            const Vec2 a = by_x ? (pp.x <= pq.x ? pp : pq) : (pp.y <= pq.y ? pp : pq);
            const Vec2 b = by_x ? (pp.x <= pq.x ? pq : pp) : (pp.y <= pq.y ? pq : pp);
            const double c = classes_->cell(k);
            const std::int64_t i0 = by_x ? x0 : y0, i1 = by_x ? x1 : y1;
            for (std::int64_t i = i0; i <= i1; ++i) {
                // The part of a-b over the slab of column i.
                const double lo_edge = (by_x ? classes_->origin().x : classes_->origin().y) + static_cast<double>(i) * c;
                const double s_a = by_x ? a.x : a.y, s_b = by_x ? b.x : b.y;
                const double u0 = std::fmax(s_a, lo_edge), u1 = std::fmin(s_b, lo_edge + c);
                auto across = [&](double u) {
                    if (s_b == s_a) return by_x ? a.y : a.x;
                    const double t = std::clamp((u - s_a) / (s_b - s_a), 0.0, 1.0);
                    return by_x ? a.y + t * (b.y - a.y) : a.x + t * (b.x - a.x);
                };
                const double v0 = across(u0), v1 = across(u1);
                const std::int64_t j0 = (by_x ? classes_->iy(std::fmin(v0, v1), k) : classes_->ix(std::fmin(v0, v1), k)) - 1;
                const std::int64_t j1 = (by_x ? classes_->iy(std::fmax(v0, v1), k) : classes_->ix(std::fmax(v0, v1), k)) + 1;
                for (std::int64_t j = j0; j <= j1; ++j)
                    if (by_x ? cell_blocks(p, q, k, i, j) : cell_blocks(p, q, k, j, i)) return true;
            }
        }
        return false;
    }

    void advance(std::uint32_t f) {
        const std::uint32_t a = edges_[f].a, b = edges_[f].b;
        const Vec2 pa = pts_[a], pb = pts_[b];
        const Vec2 mid = 0.5 * (pa + pb);
        double r = distance(pa, pb);
        std::vector<std::uint32_t>& cand = cand_;
        for (int round = 0; round < 200; ++round) {
            cand.clear();
            tree_.query(mid, r, [&](std::uint32_t v) {
                if (v != a && v != b && alive_point(v) && orient2d(pa, pb, pts_[v]) == Orientation::Left) cand.push_back(v);
            });
            const auto visible = [&](std::uint32_t c) { return !blocked(a, c) && !blocked(b, c); };
            std::uint32_t best = smallest_circle(a, b, cand, [](std::uint32_t) { return true; });
            // Hidden: the smallest circle of the visible candidates.
            if (best != UINT32_MAX && !visible(best)) best = smallest_circle(a, b, cand, visible);
            // A disk this large holds every point: the search is complete.
            const bool everything = r >= 2.0 * extent_;
            if (best != UINT32_MAX) {
                // Is the circle through a, b, best inside the searched disk? Its centre is
                // computed in floating point, with an error that grows as the triangle flattens
                // (1 / sin of its angle at a): that much is added, so that a nearly degenerate
                // triangle (best 2^-40 from b: a huge circle computed as a small one) makes the
                // search grow instead of ending early.
                const Vec2 centre = circumcentre(pa, pb, pts_[best]);
                const Vec2 d = pb - pa, e = pts_[best] - pa;
                const double flat = norm(d) * norm(e) / std::fabs(cross(d, e));
                const double radius = distance(centre, pa);
                const double slack = 64.0 * DBL_EPSILON * (radius + norm(d) + norm(e)) * flat;
                double need = distance(centre, mid) + radius + slack;
                if (!std::isfinite(need)) need = HUGE_VAL;
                if (everything || need <= r * (1.0 - 1e-12)) {
                    form(f, a, b, best);
                    return;
                }
                r = std::fmin(need * 1.01, 2.0 * extent_);
            } else {
                MESHD_INTERNAL_CHECK(!everything, "advancing front: no point for a front edge");
                r = std::fmin(r * 2.0, 2.0 * extent_);
            }
        }
        throw InternalError("advancing front: candidate search does not settle", __FILE__, __LINE__);
    }

    // Of the candidates that `keep` accepts, the one whose circle through a and b holds no
    // other (UINT32_MAX: none). The circles on the left of ab are nested, and the perturbed
    // in-circle test orders them strictly, so one pass that takes any kept candidate inside
    // the circle so far finds it, asking `keep` (the crossing test, the search's dearest part)
    // only of those.
    template <class Keep>
    std::uint32_t smallest_circle(std::uint32_t a, std::uint32_t b, const std::vector<std::uint32_t>& cand, Keep&& keep) const {
        const Vec2 pa = pts_[a], pb = pts_[b];
        std::uint32_t best = UINT32_MAX;
        for (std::uint32_t c : cand)
            if ((best == UINT32_MAX || incircle_perturbed(pa, pb, pts_[best], pts_[c], a, b, best, c) > 0) && keep(c))
                best = c;
        return best;
    }

    void form(std::uint32_t f, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
        tris_.push_back({{a, b, c}, {kNoTriangle, kNoTriangle, kNoTriangle}, 0, 0});
        remove_front(f);
        touched_[c] = 1;
        // Edge b -> c: closes front edge b -> c, or opens c -> b. Likewise c -> a.
        for (auto [u, w] : {std::pair{b, c}, std::pair{c, a}}) {
            auto it = front_.find(detail::directed_key(u, w));
            if (it != front_.end()) remove_front(it->second);
            else add_front(w, u);
        }
    }

    TriangulationResult finish() {
        TriangulationResult r;
        r.triangles = std::move(tris_);
        std::unordered_map<std::uint64_t, std::pair<TriangleId, std::uint32_t>> by_edge;
        by_edge.reserve(3 * r.triangles.size());
        for (TriangleId t = 0; t < r.triangles.size(); ++t)
            for (std::uint32_t i = 0; i < 3; ++i) {
                const Triangle& T = r.triangles[t];
                by_edge[detail::directed_key(T.v[(i + 1) % 3], T.v[(i + 2) % 3])] = {t, i};
            }
        for (TriangleId t = 0; t < r.triangles.size(); ++t)
            for (std::uint32_t i = 0; i < 3; ++i) {
                Triangle& T = r.triangles[t];
                auto it = by_edge.find(detail::directed_key(T.v[(i + 2) % 3], T.v[(i + 1) % 3]));
                if (it != by_edge.end()) T.n[i] = it->second.first;
            }
        for (const Constraint& c : cons_) {
            for (auto [u, w] : {std::pair{c.a, c.b}, std::pair{c.b, c.a}}) {
                auto it = by_edge.find(detail::directed_key(u, w));
                if (it == by_edge.end()) continue;
                Triangle& T = r.triangles[it->second.first];
                const std::uint8_t bit = static_cast<std::uint8_t>(1u << it->second.second);
                T.constrained |= bit;
                if (c.loop) T.boundary |= bit;
                if (c.loop) T.n[it->second.second] = kNoTriangle;
            }
        }
        r.alias.resize(pts_.size());
        std::iota(r.alias.begin(), r.alias.end(), 0u);
        return r;
    }

    std::span<const Vec2> pts_;
    std::vector<Constraint> cons_;  // the input's, split at the points on them
    Observer* obs_;
    PointTree tree_;
    std::vector<std::uint32_t> front_degree_;
    std::vector<char> touched_;
    double extent_ = 1.0;
    std::unique_ptr<SizeClasses> classes_;
    std::vector<FrontEdge> edges_;
    std::unordered_map<std::uint64_t, std::uint32_t> front_;
    std::vector<std::uint32_t> stack_;
    CellMap grid_;
    std::array<std::vector<std::uint32_t>, SizeClasses::kMax + 1> class_edges_;  // live and some dead
    std::array<size_t, SizeClasses::kMax + 1> class_alive_{};
    Array<Triangle> tris_;
    std::vector<std::uint32_t> cand_;
};

}  // namespace

TriangulationResult triangulate_advancing_front(std::span<const Vec2> points,
                                                const std::vector<Constraint>& constraints, Observer* observer) {
    DelaunayFront front(points, constraints, observer);
    return front.run();
}

}  // namespace meshd::core
