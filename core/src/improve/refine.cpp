// Quality refinement (options.min_angle_deg): Ruppert/Chew-style insertion of circumcentres
// into the finished constrained Delaunay mesh.
//
// A triangle whose smallest angle is below the bound gets its circumcentre inserted, unless
// the way from the triangle to that centre crosses a constrained edge, or the centre lies in
// the diametral circle of a constrained edge nearby: then that edge is split at its midpoint
// instead. Each insertion is followed by Lawson flips (constrained edges never flip), so the
// mesh stays constrained Delaunay. Angles between two constrained edges (input corners such
// as a sharp trailing edge) cannot be improved and are left alone; so are triangles already
// far below the local size, and the work stops at the point limit. A split boundary or
// embedded edge gets its new point on its curve, at the mean of its ends' parameters: a
// curved wall stays on the curve (the split is skipped when that point would invert a
// triangle next to the edge). Where neither can be done (a boundary layer's outer edge, which
// is never split, stands between the triangle and its centre), a point goes beside the sharp
// corner instead (beside_corner). Bad triangles are taken worst first. A bound above
// kCentresUpTo is reached in steps (run()): centres alone cascade there.

#include <algorithm>
#include <cmath>
#include <numbers>
#include <queue>
#include <unordered_map>

#include "improve/refine.hpp"
#include "improve/pattern_search.hpp"

#include "geometry/curve.hpp"
#include "meshd/core/errors.hpp"
#include "triangulation/triangle_soup.hpp"
#include "kernel/constructions.hpp"
#include "kernel/predicates.hpp"

namespace meshd::core {

namespace {

using detail::next3;
using detail::prev3;

// Circumcentres serve bounds up to this many degrees. There a triangle's circumradius is at
// least its shortest edge, and the refinement runs out of bad triangles in practice; above it
// the new triangles around a centre are often below the bound themselves, and each round of
// them is finer: asked for 34 degrees, a 408-point mesh at 31 degrees (smoothing 0) grew to
// 16,232 points at 18.2 degrees, and 33 of 147 generated requests (fuzz/general_requests.py)
// grew more than 1.5-fold with the default smoothing, one 35-fold.
constexpr double kCentresUpTo = 30.0;


class Refiner {
public:
    Refiner(Mesh& m, const Domain& domain, const SizeField& rho, double min_angle_deg, size_t max_points,
            Observer* obs)
        : m_(m), domain_(domain), rho_(rho), obs_(obs), max_points_(max_points) {
        target_deg_ = min_angle_deg;
        pts_.reserve(m.point_count() * 2);
        for (std::uint32_t v = 0; v < m.point_count(); ++v) pts_.push_back(m.point(v));
        soup_ = std::make_unique<detail::TriangleSoup>(pts_, m.triangles, true);
        chains_.resize(m.edges.size());
        for (size_t e = 0; e < m.edges.size(); ++e) {
            chains_[e] = {m.edges[e].a, m.edges[e].b};
            edge_of_[detail::edge_key(m.edges[e].a, m.edges[e].b)] = e;
        }
    }

    std::uint64_t run() {
        // Up to kCentresUpTo degrees by circumcentres. A bound above it by circumcentres too
        // where they reach it within a budget (most meshes the smoothing left near it); else
        // the mesh as it was at kCentresUpTo, and points that leave their cavity better than
        // the triangle they mend, a few per triangle still below the bound.
        std::uint64_t inserted = refine(std::min(target_deg_, kCentresUpTo), Pass::Centres).inserted;
        if (target_deg_ > kCentresUpTo && any_bad(target_deg_)) {
            const Mesh mesh = m_;  // (a copy only where there is work: on a large mesh, 50 bytes a point)
            const Array<Vec2> pts = pts_;
            const auto chains = chains_;
            const auto edge_of = edge_of_;
            const double worst_before = worst_cos();
            const Outcome centres = refine(target_deg_, Pass::BudgetedCentres);
            // Kept when it ran out of bad triangles within the budget and left no corner
            // sharper than before (the triangles it could not mend may be new ones).
            if (centres.finished && worst_cos() <= worst_before) {
                inserted += centres.inserted;
            } else {
                m_ = mesh;
                pts_ = pts;
                chains_ = chains;
                edge_of_ = edge_of;
                soup_ = std::make_unique<detail::TriangleSoup>(pts_, m_.triangles, true);
                inserted += refine(target_deg_, Pass::Improving).inserted;
            }
        }
        finish();
        return inserted;
    }

private:
    enum class Pass {
        Centres,          // by_centre() and its fallback, until no triangle is bad
        BudgetedCentres,  // the same, at most kCentresPerBad insertions per bad triangle
        Improving,        // only points whose fan beats the triangle they mend, a few each
    };
    struct Outcome {
        std::uint64_t inserted = 0;
        bool finished = false;  // no bad triangle left
    };
    // Insertions per triangle below the bound at the start of a budgeted pass: a budget that
    // the meshes which reach 34 degrees without a cascade stay well within.
    static constexpr size_t kCentresPerBad = 8;

    // One pass of refinement to `bound_deg`.
    Outcome refine(double bound_deg, Pass pass) {
        cos_bound_ = std::cos(bound_deg * std::numbers::pi / 180.0);
        queue_bad_ = {};
        // The worst first (the largest cosine of a smallest angle), as Triangle takes them:
        // each insertion then mends the sharpest corner around it before the ones its own new
        // triangles could mend on the way.
        for (TriangleId t = 0; t < m_.triangles.size(); ++t) push(t);
        fallbacks_left_ = 16 + 4 * queue_bad_.size();
        size_t budget = pass == Pass::Centres ? SIZE_MAX
                        : pass == Pass::Improving ? fallbacks_left_
                                                  : 16 + kCentresPerBad * queue_bad_.size();
        Outcome out;
        std::uint64_t steps = 0;
        while (!queue_bad_.empty()) {
            if ((++steps & 255) == 0 && obs_) {
                if (obs_->should_stop()) throw Cancelled();
                obs_->on_progress(Stage::Quality, 0.0);
            }
            if (max_points_ && pts_.size() >= max_points_) return out;
            const auto [was, t] = queue_bad_.top();
            queue_bad_.pop();
            const double now = badness(t);
            if (now < -1.0) continue;
            if (now != was) {  // changed since it was queued: in its place again
                queue_bad_.push({now, t});
                continue;
            }
            if (budget == 0) return out;
            --budget;
            const size_t before = m_.triangles.size();
            if (!(pass == Pass::Improving ? beside_corner(t, true) : fix(t))) continue;
            ++out.inserted;
            // New or changed triangles: the ones made now, those around the new point, and t
            // itself when the insertion was a segment split elsewhere.
            for (TriangleId u = static_cast<TriangleId>(before); u < m_.triangles.size(); ++u) push(u);
            around(static_cast<std::uint32_t>(pts_.size() - 1));
            push(t);
        }
        out.finished = true;
        return out;
    }

    // Whether any triangle is bad at `bound_deg`.
    bool any_bad(double bound_deg) {
        cos_bound_ = std::cos(bound_deg * std::numbers::pi / 180.0);
        for (TriangleId t = 0; t < m_.triangles.size(); ++t)
            if (badness(t) >= -1.0) return true;
        return false;
    }

    // The largest cosine of a corner of the mesh that is not between two constrained edges
    // (the smallest free angle's).
    double worst_cos() const {
        double worst = -1.0;
        for (const Triangle& T : m_.triangles) {
            const Vec2 p[3] = {pts_[T.v[0]], pts_[T.v[1]], pts_[T.v[2]]};
            for (std::uint32_t i = 0; i < 3; ++i)
                if (!input_corner(T, i)) worst = std::max(worst, corner_cos(p, i));
        }
        return worst;
    }

    // The cosine of the angle at corner i of the triangle p.
    static double corner_cos(const Vec2 p[3], std::uint32_t i) {
        const Vec2 u = p[next3(i)] - p[i], w = p[prev3(i)] - p[i];
        return dot(u, w) / std::sqrt(norm2(u) * norm2(w));
    }

    // Whether corner i of T lies between two constrained edges: an input angle.
    static bool input_corner(const Triangle& T, std::uint32_t i) {
        return edge_bit(T.constrained, next3(i)) && edge_bit(T.constrained, prev3(i));
    }

    // The cosine of t's smallest angle when t is bad, else -2: below the bound, but not at an
    // input corner and not far below the local size.
    double badness(TriangleId t) const {
        const Triangle& T = m_.triangles[t];
        const Vec2 p[3] = {pts_[T.v[0]], pts_[T.v[1]], pts_[T.v[2]]};
        double best_cos = -2.0;
        std::uint32_t corner = 0;
        for (std::uint32_t i = 0; i < 3; ++i) {
            const double c = corner_cos(p, i);
            if (c > best_cos) {
                best_cos = c;
                corner = i;
            }
        }
        if (best_cos <= cos_bound_ || input_corner(T, corner)) return -2.0;
        const double shortest = std::min({distance(p[0], p[1]), distance(p[1], p[2]), distance(p[2], p[0])});
        const Vec2 g = (p[0] + p[1] + p[2]) / 3.0;
        return shortest > 0.1 * rho_.interior(g) ? best_cos : -2.0;
    }

    void push(TriangleId t) {
        if (const double c = badness(t); c >= -1.0) queue_bad_.push({c, t});
    }

    // Every bad triangle around vertex v into the queue.
    void around(std::uint32_t v) {
        soup_->around(v, [&](TriangleId t) {
            push(t);
            return false;
        });
    }

    // Fixes triangle t by one insertion; false when nothing could be inserted.
    bool fix(TriangleId t) {
        if (by_centre(t)) return true;
        // The centre could not go in (a boundary layer's outer edge, which cannot be split, in
        // the way or too near): a point beside the sharp corner instead.
        return fallbacks_left_ > 0 && beside_corner(t);
    }

    bool by_centre(TriangleId t) {
        const Triangle& T = m_.triangles[t];
        const Vec2 a = pts_[T.v[0]], b = pts_[T.v[1]], c = pts_[T.v[2]];
        const Vec2 centre = circumcentre(a, b, c);
        if (!is_finite(centre)) return false;
        // Walk from the centroid to the centre; stop at the first constrained edge crossed.
        const detail::WalkEnd end = soup_->walk(t, (a + b + c) / 3.0, centre, 10000);
        if (end.triangle == kNoTriangle) return false;
        if (end.edge >= 0) return split_segment(end.triangle, static_cast<std::uint32_t>(end.edge));
        const TriangleId cur = end.triangle;
        // A constrained edge of the triangle found (or of its neighbours) whose diametral
        // circle holds the centre is split instead.
        for (TriangleId x : {cur, m_.triangles[cur].n[0], m_.triangles[cur].n[1], m_.triangles[cur].n[2]}) {
            if (x == kNoTriangle) continue;
            const Triangle& X = m_.triangles[x];
            for (std::uint32_t i = 0; i < 3; ++i) {
                if (!edge_bit(X.constrained, i)) continue;
                const Vec2 e0 = pts_[X.v[next3(i)]], e1 = pts_[X.v[prev3(i)]];
                if (dot(e0 - centre, e1 - centre) < 0.0) return split_segment(x, i);
            }
        }
        // Beside a boundary layer's outer edge, which cannot be split, a centre can land close
        // to a column's top, in a notch between columns: the triangles it makes there with
        // the layer's points are then worse than t, and each such insertion makes the next
        // worse still (a smallest angle of 22 degrees went to 3 with min_angle_deg 28). Such
        // a centre is not inserted.
        if (smallest_angle_after(cur, centre) < smallest_angle(a, b, c)) return false;
        return insert_in(cur, centre);
    }

    // Point p into triangle cur, which holds it, and the Lawson flips after it; false when p
    // is one of cur's corners or lies on a constrained edge (which takes a point of its curve).
    bool insert_in(TriangleId cur, Vec2 p) {
        const Triangle& C = m_.triangles[cur];
        for (auto v : C.v)
            if (pts_[v] == p) return false;
        int on_edge = -1;
        for (std::uint32_t i = 0; i < 3; ++i)
            if (orient2d(pts_[C.v[next3(i)]], pts_[C.v[prev3(i)]], p) == Orientation::Collinear) on_edge = static_cast<int>(i);
        if (on_edge >= 0 && edge_bit(C.constrained, static_cast<std::uint32_t>(on_edge))) return false;
        const std::uint32_t v = add_point(p, PointKind::Interior, kNoCurve, 0.0);
        queue_.clear();
        if (on_edge < 0) soup_->split_triangle(cur, v, queue_);
        else soup_->split_edge(cur, static_cast<std::uint32_t>(on_edge), v, queue_);
        soup_->legalize(queue_);
        return true;
    }

    // The fallback for a triangle t whose centre cannot go in: its sharp corner k lies between
    // two edges, and a new point in the triangle across one of them (where that edge is free)
    // lets the flips take that edge away, and with it the sharp wedge at k. For each such
    // neighbour u the point starts at u's centroid; the triangles whose circumcircles hold it
    // (reached without crossing a constrained edge: the cavity the insertion opens) are
    // replaced by the fan from the point to the cavity's outline, and the point moves (a
    // pattern search) to where the fan's smallest angle is largest. The best of the two goes
    // in when the cavity holds t and the fan's smallest angle beats t's (and so every angle
    // the cavity holds now): the flips after the insertion leave no worse there (of a quad's
    // two diagonals they keep the one with the larger smallest angle). The smoothing's repair
    // then places the point once more. Seed 145352 of the random domains with layers: a
    // triangle of three fixed points in a narrow gap between two holes' layers, at 25.3
    // degrees, whose centre lay past the layers' outer edge.
    bool beside_corner(TriangleId t, bool from_centre = false) {
        const Triangle& T = m_.triangles[t];
        const Vec2 p[3] = {pts_[T.v[0]], pts_[T.v[1]], pts_[T.v[2]]};
        std::uint32_t k = 0;
        double sharpest = HUGE_VAL;
        for (std::uint32_t i = 0; i < 3; ++i) {
            const double angle = corner_angle(p[i], p[next3(i)], p[prev3(i)]);
            if (angle < sharpest) {
                sharpest = angle;
                k = i;
            }
        }
        double best = sharpest;  // what a point must beat
        Vec2 best_at{}, best_start{};
        TriangleId best_from = kNoTriangle;
        auto consider = [&](TriangleId u, Vec2 start) {
            if (!open_cavity(u, start) || std::find(cavity_.begin(), cavity_.end(), t) == cavity_.end()) return;
            const auto [at, angle] = best_in_fan(start, u);
            if (angle > best) {
                best = angle;
                best_at = at;
                best_start = start;
                best_from = u;
            }
        };
        if (from_centre) {
            // The circumcentre as a start too, where it is reached without crossing a
            // constrained edge.
            const Vec2 centre = circumcentre(p[0], p[1], p[2]);
            if (is_finite(centre)) {
                const detail::WalkEnd end = soup_->walk(t, (p[0] + p[1] + p[2]) / 3.0, centre, 10000);
                if (end.triangle != kNoTriangle && end.edge < 0) consider(end.triangle, centre);
            }
        }
        for (const std::uint32_t i : {next3(k), prev3(k)}) {
            const TriangleId u = T.n[i];
            if (u == kNoTriangle || edge_bit(T.constrained, i)) continue;
            const Triangle& U = m_.triangles[u];
            consider(u, (pts_[U.v[0]] + pts_[U.v[1]] + pts_[U.v[2]]) / 3.0);
        }
        if (best_from == kNoTriangle) return false;
        const detail::WalkEnd end = soup_->walk(best_from, best_start, best_at, 10000);
        if (end.triangle == kNoTriangle || end.edge >= 0) return false;
        if (!insert_in(end.triangle, best_at)) return false;
        --fallbacks_left_;
        return true;
    }

    // The angle at a between b and c (radians).
    static double corner_angle(Vec2 a, Vec2 b, Vec2 c) { return std::atan2(std::fabs(cross(b - a, c - a)), dot(b - a, c - a)); }

    // The cavity a point at c opens from triangle u (into cavity_) and its outline (into
    // outline_, each edge as its triangle had it, counter-clockwise); false past kCavityLimit
    // triangles or where a constrained edge would lie inside it.
    bool open_cavity(TriangleId u, Vec2 c) {
        outline_.clear();
        std::vector<std::pair<std::uint32_t, std::uint32_t>> walls;  // constrained outline edges
        const bool whole = grow_cavity(u, c, [&](const Triangle& T, std::uint32_t i) {
            if (edge_bit(T.constrained, i)) walls.push_back({T.v[next3(i)], T.v[prev3(i)]});
            outline_.push_back({pts_[T.v[next3(i)]], pts_[T.v[prev3(i)]]});
        });
        if (!whole) return false;
        // A constrained edge reached from both sides is inside: the fan would take it away.
        for (const auto& [a, b] : walls)
            if (std::find(walls.begin(), walls.end(), std::pair{b, a}) != walls.end()) return false;
        // An edge put on the outline before the triangle beyond it joined the cavity is inside.
        std::erase_if(outline_, [&](const std::array<Vec2, 2>& e) {
            return std::any_of(outline_.begin(), outline_.end(), [&](const std::array<Vec2, 2>& f) { return f[0] == e[1] && f[1] == e[0]; });
        });
        return true;
    }

    // The smallest angle of the fan from c to outline_; -1 where a triangle of it is not
    // counter-clockwise with positive area.
    double fan_angle(Vec2 c) const {
        double worst = std::numbers::pi;
        for (const auto& e : outline_) {
            if (!(cross(e[1] - e[0], c - e[0]) > 0.0)) return -1.0;
            worst = std::min(worst, smallest_angle(e[0], e[1], c));
        }
        return worst;
    }

    // Pattern search (eight directions, halving steps) from `start` in triangle u for the
    // point whose fan has the largest smallest angle.
    std::pair<Vec2, double> best_in_fan(Vec2 start, TriangleId u) const {
        const Triangle& U = m_.triangles[u];
        double h = HUGE_VAL;
        for (const auto v : U.v) h = std::min(h, 0.5 * distance(start, pts_[v]));
        double best = fan_angle(start);
        const Vec2 at = detail::pattern_search(start, h, 1e-3 * h, 100, best, [&](Vec2 q, double) { return fan_angle(q); });
        return {at, best};
    }

    static double smallest_angle(Vec2 a, Vec2 b, Vec2 c) {
        const double area2 = std::fabs(cross(b - a, c - a));
        const double angle_a = std::atan2(area2, dot(b - a, c - a));
        const double angle_b = std::atan2(area2, dot(c - b, a - b));
        return std::min({angle_a, angle_b, std::numbers::pi - angle_a - angle_b});
    }

    // The smallest angle (radians) of the triangles with a boundary layer's point that
    // inserting c into triangle cur makes: c joined to the edges around its cavity, the
    // triangles whose circumcircle holds c that are reached from cur without crossing a
    // constrained edge (what the Lawson flips after the insertion leave). (Held to all the
    // new triangles, the test refused most of the insertions that take domains without
    // layers to the bound: their new triangles are often worse for a while.) A cavity past
    // kCavityLimit triangles is not followed further.
    double smallest_angle_after(TriangleId cur, Vec2 c) {
        double worst = std::numbers::pi;
        grow_cavity(cur, c, [&](const Triangle& T, std::uint32_t i) {
            const std::uint32_t e0 = T.v[next3(i)], e1 = T.v[prev3(i)];
            if (m_.kind[e0] == PointKind::Layer || m_.kind[e1] == PointKind::Layer)
                worst = std::min(worst, smallest_angle(pts_[e0], pts_[e1], c));
        });
        return worst;
    }

    // The triangles whose circumcircles hold c, reached from `from` without crossing a
    // constrained edge, into cavity_ (up to kCavityLimit of them); edge(T, i) for each edge
    // of a cavity triangle that the cavity did not grow across (at the time: a triangle can
    // join it later by another way). False when the limit stopped the growth.
    template <class Edge>
    bool grow_cavity(TriangleId from, Vec2 c, Edge&& edge) {
        constexpr size_t kCavityLimit = 64;
        cavity_.assign(1, from);
        size_t k = 0;
        for (; k < cavity_.size() && cavity_.size() < kCavityLimit; ++k) {
            const Triangle& T = m_.triangles[cavity_[k]];
            for (std::uint32_t i = 0; i < 3; ++i) {
                const TriangleId u = T.n[i];
                if (u != kNoTriangle && std::find(cavity_.begin(), cavity_.end(), u) != cavity_.end()) continue;
                if (u != kNoTriangle && !edge_bit(T.constrained, i)) {
                    const Triangle& U = m_.triangles[u];
                    if (incircle(pts_[U.v[0]], pts_[U.v[1]], pts_[U.v[2]], c) > 0) {
                        cavity_.push_back(u);
                        continue;
                    }
                }
                edge(T, i);
            }
        }
        return k == cavity_.size();
    }

    bool split_segment(TriangleId t, std::uint32_t i) {
        const Triangle& T = m_.triangles[t];
        const std::uint32_t a = T.v[next3(i)], b = T.v[prev3(i)];
        const Vec2 mid = 0.5 * (pts_[a] + pts_[b]);
        if (!(distance(pts_[a], pts_[b]) > 0.1 * rho_.interior(mid))) return false;
        auto it = edge_of_.find(detail::edge_key(a, b));
        if (it == edge_of_.end()) return false;  // constrained but not a mesh edge: leave it
        const size_t e = it->second;
        const CurveId c = m_.edges[e].curve;
        const double tp = 0.5 * (param_on(c, a, b) + param_on(c, b, a));
        const Vec2 p_at = domain_.curves()[c].geometry->point(tp);
        // The triangles on either side of a-b, split at p, must keep their orientation.
        for (const auto& [x, k] : {std::pair{t, i}, std::pair{T.n[i], 0u}}) {
            if (x == kNoTriangle) continue;
            const Triangle& X = m_.triangles[x];
            const std::uint32_t kk = x == t ? k : soup_->back_index(x, t);
            const Vec2 apex = pts_[X.v[kk]], s0 = pts_[X.v[next3(kk)]], s1 = pts_[X.v[prev3(kk)]];
            if (orient2d(apex, s0, p_at) != Orientation::Left || orient2d(apex, p_at, s1) != Orientation::Left)
                return false;
        }
        const std::uint32_t p = add_point(p_at, m_.edges[e].embedded ? PointKind::Embedded : PointKind::Boundary, c, tp);
        queue_.clear();
        soup_->split_edge(t, i, p, queue_);
        soup_->legalize(queue_);
        // The segment's chain of points gains p between a and b.
        auto& chain = chains_[e];
        for (size_t k = 0; k + 1 < chain.size(); ++k) {
            if ((chain[k] == a && chain[k + 1] == b) || (chain[k] == b && chain[k + 1] == a)) {
                chain.insert(chain.begin() + static_cast<std::ptrdiff_t>(k) + 1, p);
                break;
            }
        }
        edge_of_.erase(it);
        edge_of_[detail::edge_key(a, p)] = e;
        edge_of_[detail::edge_key(p, b)] = e;
        return true;
    }

    // The parameter of vertex v on curve c, where v is an end of an edge v-other of c: its
    // own for points of the curve, else (a curve end) the start or the end of the curve.
    double param_on(CurveId c, std::uint32_t v, std::uint32_t other) const {
        if (m_.curve[v] == c) return m_.param[v];
        const DomainCurve& dc = domain_.curves()[c];
        const Curve& g = *dc.geometry;
        if (dc.from != dc.to) return distance(pts_[v], g.start()) <= distance(pts_[v], g.end()) ? g.t_begin() : g.t_end();
        // The closing point of a closed curve: the end on the side of the edge's other point.
        const double t_other = m_.curve[other] == c ? m_.param[other] : g.t_begin();
        return t_other - g.t_begin() < g.t_end() - t_other ? g.t_begin() : g.t_end();
    }

    std::uint32_t add_point(Vec2 p, PointKind kind, CurveId curve, double param) {
        pts_.push_back(p);
        m_.x.push_back(p.x);
        m_.y.push_back(p.y);
        m_.kind.push_back(kind);
        m_.curve.push_back(curve);
        m_.param.push_back(param);
        soup_->grow_vertices(pts_.size());
        return static_cast<std::uint32_t>(pts_.size() - 1);
    }

    void finish() {
        std::vector<MeshEdge> edges;
        edges.reserve(m_.edges.size());
        for (size_t e = 0; e < m_.edges.size(); ++e)
            for (size_t k = 0; k + 1 < chains_[e].size(); ++k)
                edges.push_back({chains_[e][k], chains_[e][k + 1], m_.edges[e].tag, m_.edges[e].curve, m_.edges[e].embedded});
        m_.edges = std::move(edges);
    }

    Mesh& m_;
    const Domain& domain_;
    const SizeField& rho_;
    Observer* obs_;
    size_t max_points_;
    double target_deg_;
    double cos_bound_ = 1.0;
    Array<Vec2> pts_;
    std::unique_ptr<detail::TriangleSoup> soup_;
    std::vector<std::vector<std::uint32_t>> chains_;
    std::unordered_map<std::uint64_t, size_t> edge_of_;
    std::vector<std::pair<TriangleId, std::uint32_t>> queue_;
    std::vector<TriangleId> cavity_;
    std::priority_queue<std::pair<double, TriangleId>> queue_bad_;  // (badness, triangle)
    std::vector<std::array<Vec2, 2>> outline_;
    // Points beside a sharp corner (beside_corner) are few: each must beat what its cavity
    // holds, and this bounds them besides.
    size_t fallbacks_left_ = 0;
};

}  // namespace

std::uint64_t refine_min_angle(Mesh& mesh, const Domain& domain, const SizeField& rho, double min_angle_deg,
                               size_t max_points, Observer* observer) {
    if (!(min_angle_deg > 0.0)) return 0;
    Refiner r(mesh, domain, rho, min_angle_deg, max_points, observer);
    return r.run();
}

}  // namespace meshd::core
