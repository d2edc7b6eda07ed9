// The paper's triangulator (section 5, after Lo 1989): the Delaunay advancing front.
//
// The front starts as the loop segments (domain on their left) and the embedded segments
// in both directions, each split at the input points on it. For the last front edge AB,
// the candidates are the live points on its left within a radius R of its midpoint (R
// starts at |AB|); among those visible from AB (AC and BC cross no constraint) the one
// whose circle through A, B holds no other visible candidate is C*. Circles through A and
// B are nested on the left of AB, so the smallest of all is C* when it is visible (nearly
// always: the crossing test is asked once), and else one pass that replaces C* by any
// visible candidate inside its circle finds it. If that circle reaches beyond the searched
// disk, R grows and the search repeats, so the choice is exact. ABC* is formed; its edges
// close matching front edges or join the front. Decisions are exact and use the same
// perturbed in-circle test as the incremental triangulator, so both give the same
// triangles.
//
// Why only the constraints can hide a candidate (not the rest of the front): every front
// edge is an edge of the constrained Delaunay triangulation, and so is the triangle ABC* to
// be found. AC* and BC* are its edges, so they cross no constraint: C* is visible. A point C
// on the left of AB inside the circle of ABC* lies in the cap beyond AC* or beyond BC*, and
// the circle of a CDT triangle holds only points hidden from its inside by constraints; the
// segment from B (or A) to a point in the cap beyond AC* (BC*) passes through that side's
// inside, so it meets a constraint that hides C (a constraint ending on it included, as
// segments_intersect counts touching). So C is not visible in this sense, and the smallest
// circle of the visible candidates is ABC*'s. The constraints never change: their crossing
// test is a query of a static tree of boxes, where the live front edges needed a grid kept
// up to date and a walk through every size class.

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <array>
#include <numeric>
#include <tuple>

#include "triangulation/triangle_soup.hpp"
#include "kernel/kdtree.hpp"
#include "meshd/core/errors.hpp"
#include "meshd/core/observer.hpp"
#include "kernel/constructions.hpp"
#include "kernel/predicates.hpp"
#include "triangulation/triangulation.hpp"

namespace meshd::core {

namespace {

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
        require_distinct();
        cons_ = split_at_points(cons);
        build_walls();
        out_.assign(pts.size(), kNone);
        for (const Constraint& c : cons_) {
            const std::uint32_t id = add_front(c.a, c.b, kNoTriangle, 0);
            edges_[id].kind = c.loop ? kLoop : kEmbedded;
            if (c.loop) continue;
            const std::uint32_t back = add_front(c.b, c.a, kNoTriangle, 0);
            edges_[back].kind = kEmbedded;
            edges_[id].partner = back;
            edges_[back].partner = id;
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

    static constexpr std::uint32_t kNone = UINT32_MAX;
    enum Kind : std::uint8_t { kInner, kLoop, kEmbedded };

    // A front edge a -> b (the part still to triangulate on its left). Each made by a triangle
    // is that triangle's edge `side` (t on its right: the neighbour of the triangle that will
    // take it); the sides of an embedded constraint get the triangle the other side took.
    struct FrontEdge {
        std::uint32_t a, b;
        TriangleId t = kNoTriangle;
        std::uint32_t side = 0;
        std::uint32_t next = kNone;     // the next live front edge out of a
        std::uint32_t partner = kNone;  // an embedded constraint's other side
        Kind kind = kInner;
        bool alive = true;
    };

    std::uint32_t add_front(std::uint32_t a, std::uint32_t b, TriangleId t, std::uint32_t side) {
        const auto id = static_cast<std::uint32_t>(edges_.size());
        FrontEdge e;
        e.a = a;
        e.b = b;
        e.t = t;
        e.side = side;
        e.next = out_[a];
        edges_.push_back(e);
        out_[a] = id;
        stack_.push_back(id);
        ++front_degree_[a];
        ++front_degree_[b];
        touched_[a] = touched_[b] = 1;
        return id;
    }

    void remove_front(std::uint32_t id) {
        FrontEdge& e = edges_[id];
        e.alive = false;
        std::uint32_t* link = &out_[e.a];
        while (*link != id) link = &edges_[*link].next;
        *link = e.next;
        --front_degree_[e.a];
        --front_degree_[e.b];
    }

    // The live front edge u -> w, or kNone. A point has few live front edges (two, where the
    // front passes through it once).
    std::uint32_t find_front(std::uint32_t u, std::uint32_t w) const {
        for (std::uint32_t e = out_[u]; e != kNone; e = edges_[e].next)
            if (edges_[e].b == w) return e;
        return kNone;
    }

    // The constraints in a tree of median splits over their midpoints, each node with the box
    // of its constraints (not only of their midpoints).
    void build_walls() {
        std::vector<Vec2> mids(cons_.size());
        for (size_t i = 0; i < cons_.size(); ++i) mids[i] = 0.5 * (pts_[cons_[i].a] + pts_[cons_[i].b]);
        const detail::KdLayout layout(mids);
        wall_order_ = layout.order;
        wall_nodes_ = layout.nodes;
        // Children come after their parents: from the last node back, each box is its
        // constraints' (a leaf) or its children's.
        for (size_t i = wall_nodes_.size(); i-- > 0;) {
            detail::KdNode& n = wall_nodes_[i];
            n.box = Box{};
            if (n.left == 0) {
                for (std::uint32_t j = n.begin; j < n.end; ++j) {
                    n.box.add(pts_[cons_[wall_order_[j]].a]);
                    n.box.add(pts_[cons_[wall_order_[j]].b]);
                }
            } else {
                n.box.add(wall_nodes_[n.left].box);
                n.box.add(wall_nodes_[n.right].box);
            }
        }
    }

    bool alive_point(std::uint32_t v) const { return !touched_[v] || front_degree_[v] > 0; }

    // Does segment p-q meet a constraint other than at a shared end?
    bool blocked(std::uint32_t p, std::uint32_t q) const {
        const Vec2 pp = pts_[p], pq = pts_[q];
        const Box box{{std::fmin(pp.x, pq.x), std::fmin(pp.y, pq.y)}, {std::fmax(pp.x, pq.x), std::fmax(pp.y, pq.y)}};
        bool found = false;
        detail::depth_first(wall_nodes_, [&](const detail::KdNode& n) {
            if (n.box.hi.x < box.lo.x || n.box.lo.x > box.hi.x || n.box.hi.y < box.lo.y || n.box.lo.y > box.hi.y)
                return detail::Descend::No;
            if (n.left != 0) return detail::Descend::LeftFirst;
            for (std::uint32_t j = n.begin; j < n.end; ++j) {
                const Constraint& c = cons_[wall_order_[j]];
                if (c.a == p || c.b == p || c.a == q || c.b == q) continue;
                if (segments_intersect(pp, pq, pts_[c.a], pts_[c.b])) {
                    found = true;
                    return detail::Descend::Stop;
                }
            }
            return detail::Descend::No;
        });
        return found;
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
    // the circle so far finds it, asking `keep` (the crossing test) only of those.
    template <class Keep>
    std::uint32_t smallest_circle(std::uint32_t a, std::uint32_t b, const std::vector<std::uint32_t>& cand, Keep&& keep) const {
        const Vec2 pa = pts_[a], pb = pts_[b];
        std::uint32_t best = UINT32_MAX;
        for (std::uint32_t c : cand)
            if ((best == UINT32_MAX || incircle_perturbed(pa, pb, pts_[best], pts_[c], a, b, best, c) > 0) && keep(c))
                best = c;
        return best;
    }

    // Triangle a, b, c on front edge f (a -> b). Its edges close the front edges they meet
    // (linked to the triangles that made them) or join the front.
    void form(std::uint32_t f, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
        const auto t = static_cast<TriangleId>(tris_.size());
        tris_.push_back({{a, b, c}, {kNoTriangle, kNoTriangle, kNoTriangle}, 0, 0});
        take(t, 2, f);
        touched_[c] = 1;
        // Edge b -> c (edge 0): closes front edge b -> c, or opens c -> b. Likewise c -> a.
        for (auto [u, w, side] : {std::tuple{b, c, 0u}, std::tuple{c, a, 1u}}) {
            const std::uint32_t g = find_front(u, w);
            if (g != kNone) take(t, side, g);
            else add_front(w, u, t, side);
        }
    }

    // Edge `side` of triangle t is front edge g: linked to the triangle that made g, marked
    // when g is a constraint's side, handed to an embedded constraint's other side; g goes.
    void take(TriangleId t, std::uint32_t side, std::uint32_t g) {
        const FrontEdge& e = edges_[g];
        Triangle& T = tris_[t];
        if (e.t != kNoTriangle) {
            T.n[side] = e.t;
            tris_[e.t].n[e.side] = t;
        }
        if (e.kind != kInner) {
            T.constrained = static_cast<std::uint8_t>(T.constrained | (1u << side));
            if (e.kind == kLoop) T.boundary = static_cast<std::uint8_t>(T.boundary | (1u << side));
        }
        if (e.partner != kNone && edges_[e.partner].alive) {
            edges_[e.partner].t = t;
            edges_[e.partner].side = side;
        }
        remove_front(g);
    }

    TriangulationResult finish() {
        TriangulationResult r;
        r.triangles = std::move(tris_);
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
    std::vector<FrontEdge> edges_;
    std::vector<std::uint32_t> out_;  // by point: its first live front edge out (FrontEdge::next)
    std::vector<std::uint32_t> stack_;
    std::vector<std::uint32_t> wall_order_;    // constraints in the tree's order
    std::vector<detail::KdNode> wall_nodes_;  // the tree of the constraints (build_walls)
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
