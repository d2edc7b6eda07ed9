// Laplacian smoothing with guards, then a repair of the smallest angles; see smooth.hpp.
//
// A sweep visits the points that are still settling: a point whose Laplacian move is below
// kSettled of its spoke length stays put, and only the neighbours of points that moved are
// visited again. The edges opposite each point (its star's outer edges) come from a table
// built once, since nothing flips during the sweeps, and the guard's figures before a move
// are computed again from them rather than kept per triangle (a third less time in the
// sweeps than reaching the points through the triangles and a cache of shapes). The Delaunay
// property is restored by flips once, after them (restoring it after every sweep gave the
// same quality figures on the benchmark case at a third more time). The repair then walks
// stars in the triangle adjacency, which its flips keep current.

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <span>
#include <vector>

#include "kernel/memory.hpp"
#include "triangulation/triangle_soup.hpp"
#include "meshd/core/errors.hpp"
#include "improve/smooth.hpp"
#include "improve/pattern_search.hpp"
#include "kernel/predicates.hpp"
#include "improve/quality.hpp"
#include "geometry/curve.hpp"

namespace meshd::core {

namespace {

using detail::next3;
using detail::prev3;
using detail::TriangleSoup;

// A move shorter than this fraction of the root mean square spoke is not made: the point
// has settled.
constexpr double kSettled = 0.02;
// A move may lower the worst shape of its star (the mean ratio, below) as long as every
// triangle of the star stays at this or better (a triangle of mean ratio 0.8 has no angle
// below 32.3 degrees): below it, no move makes the star's worst triangle worse. Refusing
// every move that lowered the star's worst shape held the points off their neighbours' mean
// in nearly regular stars, where the mean trades a little of the worst triangle for the
// rest: the benchmark case's mean radius ratio went from 0.9728 to 0.9758 with this, at the
// same smallest angle and time.
constexpr double kFreeShape = 0.8;
// A shape above this is a counter-clockwise triangle whatever the rounding of its area.
constexpr double kShapeCertain = 1e-9;
// Triangles with an angle below this (degrees) get their interior corners optimised. Each
// round after the first looks only at the stars of points that moved; the layered random
// domains below 30 degrees went from 34 to 22 of 277 between 3 and 8 rounds (21 at 12).
constexpr double kRepairAngle = 34.0;
constexpr int kRepairRounds = 8;
// Points on curves slide along them only for triangles still below this after the interior
// corners were placed: the curves keep the paper's placement wherever it already gives this.
constexpr double kSlideAngle = 30.0;

// The cotangents of those angles: a triangle is below one when its smallest angle's
// cotangent is above it.
const double kRepairCot = 1.0 / std::tan(kRepairAngle * std::numbers::pi / 180.0);
const double kSlideCot = 1.0 / std::tan(kSlideAngle * std::numbers::pi / 180.0);
// Triangles still below this (degrees) after the slide are past what one flip mends: the last
// step of a round leaves them (on a density too steep for any mesh, trying them made the
// smoothing ten times slower for nothing).
const double kFloorCot = 1.0 / std::tan(15.0 * std::numbers::pi / 180.0);

// A score of the smallest angle theta of a triangle that rises with it: 1 / (1 + cot theta),
// that is A / (A + d) with A twice the area and d the dot product of the smallest angle's
// sides (the largest of the three, as the smallest angle has the largest cotangent). It is in
// (0, 0.634] for a counter-clockwise triangle, whose smallest angle is at most 60 degrees, and
// -1 for any other. The repair only compares smallest angles, so this serves where the angle
// itself took two arc tangents a triangle (5% of a small request's time).
double angle_score(Vec2 a, Vec2 b, Vec2 c) {
    if (orient2d(a, b, c) != Orientation::Left) return -1.0;
    const double area2 = cross(b - a, c - a);
    const double d = std::max({dot(b - a, c - a), dot(c - b, a - b), dot(a - c, b - c)});
    return area2 / (area2 + d);
}

// The guard's measure of shape: the mean ratio 4 sqrt(3) A / (la^2 + lb^2 + lc^2), 1 for an
// equilateral triangle like the radius ratio of the figures, but free of square roots.
// (With it the benchmark case ends with the same figures as with the radius ratio, and the
// sweeps take 12% less time.)
double shape(Vec2 a, Vec2 b, Vec2 c) {
    const double area2 = cross(b - a, c - a);
    return 2.0 * std::numbers::sqrt3 * area2 / (norm2(b - a) + norm2(c - b) + norm2(a - c));
}

class Smoother {
public:
    Smoother(Mesh& m, const Domain* domain, Observer* observer)
        : m_(m), domain_(domain), observer_(observer), pts_(points_of(m)), soup_(pts_, m.triangles, true) {}

    ~Smoother() = default;
    Smoother(const Smoother&) = delete;
    Smoother& operator=(const Smoother&) = delete;

    std::uint64_t sweeps(int iterations) {
        const size_t nv = pts_.size();
        // The edges opposite each interior point, as pairs (a, b) of its triangles (v, a, b):
        // fixed during the sweeps, as nothing flips until they end. Each neighbour of a
        // closed fan is the first of exactly one pair.
        detail::assign_huge(offset_, nv + 1, std::uint32_t{0});
        for (const Triangle& t : m_.triangles)
            for (const auto v : t.v)
                if (m_.kind[v] == PointKind::Interior) ++offset_[v + 1];
        for (size_t v = 0; v < nv; ++v) offset_[v + 1] += offset_[v];
        detail::assign_huge(opposite_, offset_[nv], std::array<std::uint32_t, 2>{});
        {
            Array<std::uint32_t> fill(offset_.begin(), offset_.end() - 1);
            for (const Triangle& t : m_.triangles)
                for (std::uint32_t i = 0; i < 3; ++i)
                    if (m_.kind[t.v[i]] == PointKind::Interior)
                        opposite_[fill[t.v[i]]++] = {t.v[next3(i)], t.v[prev3(i)]};
        }
        // A sweep after the first tries the points that moved in the sweep before or have a
        // neighbour that did. Each move records only itself, and a point that did not move
        // looks at its neighbours until one did, rather than each move marking all of its own
        // (the load run's square: 6,398 moves of 10,415 tries over five sweeps; 6% fewer
        // instructions in the sweeps). A point that is not interior has no pairs: it is never
        // tried.
        Array<char> moved_before, moved_now;
        detail::assign_huge(moved_before, nv, char{0});
        detail::assign_huge(moved_now, nv, char{0});
        auto to_try = [&](std::uint32_t v) {
            if (moved_before[v]) return true;
            for (auto e = offset_[v]; e < offset_[v + 1]; ++e)
                if (moved_before[opposite_[e][0]]) return true;
            return false;
        };
        std::uint64_t moves = 0;
        for (int it = 0; it < iterations; ++it) {
            if (observer_) {
                if (observer_->should_stop()) throw Cancelled();
                observer_->on_progress(Stage::Smoothing, 0.9 * it / iterations);
            }
            std::uint64_t moved = 0;
            for (std::uint32_t v = 0; v < nv; ++v) {
                if ((it > 0 && !to_try(v)) || !laplace(v)) continue;
                ++moved;
                moved_now[v] = 1;
            }
            moves += moved;
            if (moved == 0) break;
            moved_before.swap(moved_now);
            std::fill(moved_now.begin(), moved_now.end(), 0);
        }
        // The tables go before the flips and the repair, which do not use them (a third of
        // the smoothing's memory; the pipeline's peak was in the repair).
        Array<std::uint32_t>().swap(offset_);
        Array<std::array<std::uint32_t, 2>>().swap(opposite_);
        // The Delaunay property, once.
        if (moves > 0) restore_delaunay();
        return moves;
    }

    std::uint64_t flips() const { return flips_; }

    // The repair moves only points from `first` on (repair_angles' first_movable).
    void movable_from(std::uint32_t first) { first_movable_ = first; }

    void write_back() {
        for (std::uint32_t v = 0; v < pts_.size(); ++v) {
            m_.x[v] = pts_[v].x;
            m_.y[v] = pts_[v].y;
        }
    }

    // Optimises the position of the interior corners of triangles with an angle below
    // kRepairAngle: a pattern search for the largest smallest angle of the star. A few
    // rounds, as moving one corner changes its neighbours' stars; after the first, only the
    // triangles around the corners that moved are looked at again.
    std::uint64_t repair() {
        // Made here rather than with the smoother: the sweeps' tables are gone by now.
        if (seen_.size() != m_.triangles.size()) detail::assign_huge(seen_, m_.triangles.size(), std::uint32_t{0});
        Array<TriangleId> suspects(m_.triangles.size());
        for (TriangleId t = 0; t < suspects.size(); ++t) suspects[t] = t;
        std::uint64_t total = 0;
        std::vector<std::uint32_t> moved;
        for (int round = 0; round < kRepairRounds && !suspects.empty(); ++round) {
            poll(true);
            repair_round(suspects, moved);
            total += moved.size();
            ++stamp_;
            suspects.clear();
            for (const std::uint32_t v : moved) {
                if (!walk_star(v, false)) continue;
                for (const TriangleId t : star_)
                    if (seen_[t] != stamp_) {
                        seen_[t] = stamp_;
                        suspects.push_back(t);
                    }
            }
        }
        return total;
    }

private:
    // The repair's rounds can be long where the field changes faster than the mesh can follow
    // (every corner of thousands of triangles searched, eight rounds): the observer is asked
    // at each round and every kPollEvery corners or triangles within one, so a cancelled or
    // late job stops there.
    static constexpr std::uint32_t kPollEvery = 64;
    bool movable(std::uint32_t v) const { return v >= first_movable_; }
    std::uint32_t first_movable_ = 0;
    void poll(bool now = false) {
        if (observer_ == nullptr || (!now && ++polls_ % kPollEvery != 0)) return;
        if (observer_->should_stop()) throw Cancelled();
    }

    static Array<Vec2> points_of(const Mesh& m) {
        Array<Vec2> pts;
        detail::reserve_filled(pts, m.point_count());
        for (std::uint32_t v = 0; v < m.point_count(); ++v) pts.push_back(m.point(v));
        return pts;
    }

    // One round of repair() over the given triangles; `moved` gets the corners that moved.
    void repair_round(std::span<const TriangleId> suspects, std::vector<std::uint32_t>& moved) {
        moved.clear();
        std::vector<std::uint32_t> corners;
        std::vector<TriangleId> low;  // below kRepairAngle
        for (const TriangleId t : suspects) {
            if (!bad(t)) continue;
            low.push_back(t);
            for (const auto v : m_.triangles[t].v)
                if (m_.kind[v] == PointKind::Interior && movable(v)) corners.push_back(v);
        }
        // A corner that moved is recorded and its star made Delaunay again; the triangles it
        // changed (its star, the flips) join `low`, as they may have come below kSlideAngle.
        auto settle = [&](std::uint32_t v) {
            moved.push_back(v);
            restore_delaunay_around(v);
            low.insert(low.end(), star_.begin(), star_.end());
            low.insert(low.end(), changed_.begin(), changed_.end());
        };
        // Each corner once, moved by `move`.
        auto move_each = [&](auto&& move) {
            std::sort(corners.begin(), corners.end());
            corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
            for (const std::uint32_t v : corners) {
                poll();
                if (move(v)) settle(v);
            }
        };
        const std::vector<TriangleId> initial = low;  // before the moves
        move_each([&](std::uint32_t v) { return optimise(v); });
        // The triangles of `list` still below the limit get a flip of one of their edges
        // (flip_and_place); `fixed_only`: only those with no interior corner.
        std::vector<std::uint32_t> placed;
        auto flip_each = [&](std::vector<TriangleId> list, double cot_limit, bool fixed_only) {
            std::sort(list.begin(), list.end());
            list.erase(std::unique(list.begin(), list.end()), list.end());
            for (const TriangleId t : list) {
                poll();
                if (!bad(t, cot_limit)) continue;  // an earlier move or flip may have mended it
                const auto& v = m_.triangles[t].v;
                if (fixed_only && std::any_of(v.begin(), v.end(), [&](auto w) { return m_.kind[w] == PointKind::Interior && movable(w); }))
                    continue;
                if (!fixed_only && bad(t, kFloorCot)) continue;  // beyond what one flip mends
                placed.clear();
                if (flip_and_place(t, low, placed))
                    for (const std::uint32_t w : placed) settle(w);
            }
        };
        // First the triangles of fixed points only, where no corner could move.
        flip_each(initial, kRepairCot, true);
        // Then the points on curves of triangles still below kSlideAngle slide along them.
        if (domain_ != nullptr) {
            corners.clear();
            for (const TriangleId t : low) {
                if (!bad(t, kSlideCot)) continue;
                for (const auto v : m_.triangles[t].v)
                    if ((m_.kind[v] == PointKind::Boundary || m_.kind[v] == PointKind::Embedded) && movable(v)) corners.push_back(v);
            }
            move_each([&](std::uint32_t v) { return slide(v); });
        }
        // Last, any triangle still below kSlideAngle but above the floor (the next round
        // places the corners its flips moved again, and slides once more).
        flip_each(low, kSlideCot, false);
    }

    // The parameter on curve c of w, a neighbour along it of the point of c at parameter t0:
    // its own, or for the vertex at an end of c that end's (at a closed curve's seam, the one
    // nearer t0); NaN for anything else: a boundary layer's top standing on c, or a corner
    // that ends another curve (a layer's outer edge can run from a point of c to it).
    double param_on(CurveId c, std::uint32_t w, double t0) const {
        if (m_.curve[w] == c) return m_.param[w];
        if (c >= m_.curve_ends.size()) return std::nan("");
        const auto& ends = m_.curve_ends[c];
        const Curve& g = *domain_->curves()[c].geometry;
        if (ends[0] == w && ends[1] == w)
            return std::abs(t0 - g.t_begin()) <= std::abs(g.t_end() - t0) ? g.t_begin() : g.t_end();
        if (ends[0] == w) return g.t_begin();
        if (ends[1] == w) return g.t_end();
        return std::nan("");
    }

    // Moves point v of a curve along it, between its two neighbours on the curve, to where
    // the smallest angle of its star is largest (a pattern search in the parameter). Points
    // at a corner of their curve's geometry stay. True when v moved.
    bool slide(std::uint32_t v) {
        const CurveId c = m_.curve[v];
        if (c == kNoCurve || !walk_star(v, false)) return false;
        const Curve& g = *domain_->curves()[c].geometry;
        const double t0 = m_.param[v];
        const double span = g.t_end() - g.t_begin();
        for (const double k : g.corners())
            if (std::abs(k - t0) <= 1e-9 * std::abs(span)) return false;
        // The neighbours along the curve: the other ends of v's constrained edges.
        double lo = -HUGE_VAL, hi = HUGE_VAL;
        int ends = 0;
        for (const TriangleId t : star_) {
            const Triangle& T = m_.triangles[t];
            const std::uint32_t k = TriangleSoup::index_of(T, v);
            for (const std::uint32_t i : {next3(k), prev3(k)}) {
                if (!edge_bit(T.constrained, i)) continue;
                const std::uint32_t w = T.v[i == next3(k) ? prev3(k) : next3(k)];
                const double tw = param_on(c, w, t0);
                if (std::isnan(tw)) return false;
                if (tw < t0) lo = std::max(lo, tw);
                else if (tw > t0) hi = std::min(hi, tw);
                ++ends;
            }
        }
        if (ends == 0 || !(lo < t0 && t0 < hi) || !std::isfinite(lo) || !std::isfinite(hi)) return false;
        const double start = star_score();
        const Vec2 old = pts_[v];
        double best = start, t = t0, h = 0.25 * std::min(t0 - lo, hi - t0);
        for (int iter = 0; iter < 40 && h > 1e-4 * (hi - lo); ++iter) {
            double best_t = t;
            for (const double d : {-h, h}) {
                const double s = t + d;
                if (s <= lo || s >= hi) continue;
                pts_[v] = g.point(s);
                const double f = star_score(best);
                if (f > best) {
                    best = f;
                    best_t = s;
                }
            }
            if (best_t == t) h *= 0.5;
            t = best_t;
        }
        if (!(best > start)) {
            pts_[v] = old;
            return false;
        }
        pts_[v] = g.point(t);
        m_.param[v] = t;
        return true;
    }

    // True when t has an angle whose cotangent is above `cot_limit` (kRepairCot: below
    // kRepairAngle).
    bool bad(TriangleId t, double cot_limit = kRepairCot) const {
        const Triangle& T = m_.triangles[t];
        return smallest_angle_cot(pts_[T.v[0]], pts_[T.v[1]], pts_[T.v[2]]).cot > cot_limit;
    }

    // Triangle t is still below the repair's limits after its interior corners were placed
    // (or has none: curves meeting at a wide angle, a short curve beside a coarser one). Of
    // its free edges whose quad is convex, the one whose flip alone leaves the best smallest
    // angle is flipped and the quad's interior corners are placed again; kept when the
    // smallest angle over the two triangles and those corners' stars beats what it was (the Delaunay
    // flips that follow keep it: for one quad they choose the diagonal with the larger
    // smallest angle). So a fixed triangle's edge goes to the interior point beyond it, and a
    // fixed point's fan with one triangle too many for its angle (a layer's top, a curve's
    // corner) gives one up. The interior corners of a kept flip go to `moved_corners`; the
    // two triangles of every flip to `touched` (a flip undone swaps their slots). True when
    // a flip was kept.
    bool flip_and_place(TriangleId t, std::vector<TriangleId>& touched, std::vector<std::uint32_t>& moved_corners) {
        // The edges by the corner opposite them (a flip undone moves the triangle to another
        // slot, turned).
        const std::array<std::uint32_t, 3> order = m_.triangles[t].v;
        // Flips the edge opposite order[r] and places the interior corners (not when `quick`:
        // to rank the edges); kept when `keep` and better than before, else undone. The
        // smallest angle after, -1 when not tried.
        auto attempt = [&](std::uint32_t r, bool keep, bool quick) -> double {
            const Triangle& T = m_.triangles[t];
            const std::uint32_t i = TriangleSoup::index_of(T, order[r]);
            const TriangleId u = T.n[i];
            if (u == kNoTriangle || soup_.constrained(t, i) || m_.triangles[u].layer) return -1.0;
            const std::uint32_t p = T.v[i], b = T.v[next3(i)], c = T.v[prev3(i)];
            const std::uint32_t q = m_.triangles[u].v[soup_.back_index(u, t)];
            // The quad p, b, q, c must stay convex for the flip to (p, b, q), (p, q, c).
            if (orient2d(pts_[p], pts_[b], pts_[q]) != Orientation::Left ||
                orient2d(pts_[p], pts_[q], pts_[c]) != Orientation::Left)
                return -1.0;
            std::array<std::uint32_t, 4> free{};
            size_t nfree = 0;
            for (const std::uint32_t v : {p, b, q, c})
                if (m_.kind[v] == PointKind::Interior && movable(v)) free[nfree++] = v;
            if (nfree == 0) return -1.0;
            std::array<Vec2, 4> old{};
            for (size_t k = 0; k < nfree; ++k) old[k] = pts_[free[k]];
            auto region_min = [&] {
                const Triangle &A = m_.triangles[t], &B = m_.triangles[u];
                double worst = std::min(angle_score(pts_[A.v[0]], pts_[A.v[1]], pts_[A.v[2]]),
                                        angle_score(pts_[B.v[0]], pts_[B.v[1]], pts_[B.v[2]]));
                for (size_t k = 0; k < nfree; ++k) {
                    if (!walk_star(free[k])) return -1.0;
                    worst = std::min(worst, star_score());
                }
                return worst;
            };
            const double before = region_min();
            if (before < 0.0) return -1.0;
            soup_.flip(t, i);  // t = (p, b, q), u = (p, q, c)
            if (!quick)
                for (size_t k = 0; k < nfree; ++k) optimise(free[k]);
            const double after = region_min();
            if (keep && after > before) {
                ++flips_;
                touched.push_back(t);
                touched.push_back(u);
                moved_corners.insert(moved_corners.end(), free.begin(), free.begin() + static_cast<std::ptrdiff_t>(nfree));
                return after;
            }
            for (size_t k = 0; k < nfree; ++k) pts_[free[k]] = old[k];
            soup_.flip(t, 1);  // back: (p, b, c) and (q, c, b), in each other's slots
            touched.push_back(t);
            touched.push_back(u);
            t = u;  // where the triangle is now
            return quick ? after : (after > before ? after : -1.0);
        };
        // The edge whose flip alone does best is flipped and its quad's corners placed.
        double best = -1.0;
        std::uint32_t best_r = 3;
        for (std::uint32_t r = 0; r < 3; ++r) {
            const double f = attempt(r, false, true);
            if (f > best) {
                best = f;
                best_r = r;
            }
        }
        return best_r < 3 && attempt(best_r, true, false) >= 0.0;
    }

    // The triangles around interior point v into star_; false when the fan is not closed
    // (then v is not an interior point) or unusually large.
    // With `closed` false the fan may be open (v on a loop).
    bool walk_star(std::uint32_t v, bool closed = true) {
        star_.clear();
        first_ = 0;
        soup_.around(v, [&](TriangleId t) {
            star_.push_back(t);
            return star_.size() > 64;
        });
        if (star_.empty() || star_.size() > 64) return false;
        if (!closed) return true;
        const Triangle& last = m_.triangles[star_.back()];
        return last.n[next3(TriangleSoup::index_of(last, v))] == star_.front();
    }

    // One guarded Laplacian move of v (full step, else half). True when v moved.
    bool laplace(std::uint32_t v) {
        const std::uint32_t first = offset_[v], last = offset_[v + 1];
        if (first == last) return false;
        Vec2 sum{0, 0};
        double spokes2 = 0.0;
        const Vec2 old = pts_[v];
        for (auto e = first; e < last; ++e) {
            const Vec2 a = pts_[opposite_[e][0]];
            sum += a;
            spokes2 += norm2(a - old);
        }
        const double k = static_cast<double>(last - first);
        const Vec2 target = sum / k;
        if (norm2(target - old) < kSettled * kSettled * spokes2 / k) return false;
        // The star's worst shape before the move only when a triangle after it is below
        // kFreeShape: a move that keeps every triangle at kFreeShape or better is made
        // whatever the star was (most moves are of that kind).
        double least = kFreeShape;
        bool least_known = false;
        for (const double step : {1.0, 0.5}) {
            const Vec2 p = old + step * (target - old);
            bool ok = true;
            for (auto e = first; e < last && ok; ++e) {
                const Vec2 a = pts_[opposite_[e][0]], b = pts_[opposite_[e][1]];
                const double q = shape(p, a, b);
                if (q < least && !least_known) {
                    least_known = true;
                    for (auto f = first; f < last; ++f)
                        least = std::min(least, shape(old, pts_[opposite_[f][0]], pts_[opposite_[f][1]]));
                }
                // The shape alone cannot tell a sliver from an inverted triangle when its
                // area is lost in rounding: the exact orientation decides those.
                ok = q >= least && (q > kShapeCertain || orient2d(p, a, b) == Orientation::Left);
            }
            if (ok) {
                pts_[v] = p;
                return true;
            }
        }
        return false;
    }

    // The score (angle_score) of the smallest angle in star_, -1 when a triangle is inverted.
    // With `floor`: once a triangle scores at or below it, that score (the star's smallest is
    // no higher). The searches below only ask whether a trial beats their best so far, and
    // most trials do not: they stop at the first triangle that says so, starting from the
    // one that said so last time (a step that spoils one triangle usually spoils it again).
    // A trial that beats the best reads every triangle, so its score is exact.
    double star_score(double floor = -HUGE_VAL) {
        const size_t n = star_.size();
        double worst = 1.0;
        size_t i = first_ < n ? first_ : 0;
        for (size_t k = 0; k < n; ++k) {
            const Triangle& T = m_.triangles[star_[i]];
            worst = std::min(worst, angle_score(pts_[T.v[0]], pts_[T.v[1]], pts_[T.v[2]]));
            if (worst <= floor || worst < 0.0) {
                first_ = i;
                break;
            }
            i = i + 1 == n ? 0 : i + 1;
        }
        return worst;
    }

    // Pattern search (eight directions, halving steps) for the position of v that maximises
    // the smallest angle of its star. True when v moved.
    bool optimise(std::uint32_t v) {
        if (!walk_star(v)) return false;
        const Vec2 old = pts_[v];
        double shortest = HUGE_VAL;
        for (const TriangleId t : star_) {
            const Triangle& T = m_.triangles[t];
            shortest = std::fmin(shortest, distance(old, pts_[T.v[next3(TriangleSoup::index_of(T, v))]]));
        }
        const double start = star_score();
        double best = start;
        const Vec2 p = detail::pattern_search(old, 0.25 * shortest, 1e-4 * shortest, 60, best, [&](Vec2 q, double bound) {
            pts_[v] = q;
            return star_score(bound);
        });
        pts_[v] = p;
        if (best > start) return true;
        pts_[v] = old;
        return false;
    }

    // Lawson flips: the queue is legalised; the flipped triangles go to changed_.
    void legalize_queue() {
        changed_.clear();
        flips_ += soup_.legalize(queue_, &changed_);
    }

    // Every edge once (a pass in memory order; far cheaper than walking the stars of all
    // the points that moved, and few edges need a flip).
    void restore_delaunay() {
        queue_.clear();
        for (TriangleId t = 0; t < m_.triangles.size(); ++t)
            for (std::uint32_t i = 0; i < 3; ++i) {
                const TriangleId u = m_.triangles[t].n[i];
                if (u != kNoTriangle && u > t && soup_.illegal(t, i)) queue_.emplace_back(t, i);
            }
        legalize_queue();
    }

    // The edges of the star of v and those opposite v.
    void restore_delaunay_around(std::uint32_t v) {
        queue_.clear();
        if (!walk_star(v, false)) return;
        for (const TriangleId t : star_)
            for (std::uint32_t i = 0; i < 3; ++i) queue_.emplace_back(t, i);
        legalize_queue();
    }

    Mesh& m_;
    const Domain* domain_;
    Observer* observer_;
    Array<Vec2> pts_;
    TriangleSoup soup_;
    Array<std::uint32_t> seen_;
    std::uint32_t stamp_ = 0;
    std::vector<TriangleId> star_, changed_;
    size_t first_ = 0;  // where star_score starts (the triangle that last stopped it)
    std::uint32_t polls_ = 0;
    Array<std::uint32_t> offset_;
    Array<std::array<std::uint32_t, 2>> opposite_;
    std::vector<std::pair<TriangleId, std::uint32_t>> queue_;
    std::uint64_t flips_ = 0;
};

}  // namespace

std::uint64_t smooth(Mesh& m, int iterations, const Domain* domain, std::uint64_t* flips, Observer* observer) {
    if (iterations <= 0 || m.triangles.empty()) return 0;
    Smoother s(m, domain, observer);
    std::uint64_t moves = s.sweeps(iterations);
    if (observer) {
        if (observer->should_stop()) throw Cancelled();
        observer->on_progress(Stage::Smoothing, 0.9);
    }
    moves += s.repair();
    s.write_back();
    if (flips) *flips += s.flips();
    return moves;
}

std::uint64_t repair_angles(Mesh& m, const Domain* domain, std::uint64_t* flips, Observer* observer,
                            VertexId first_movable) {
    if (m.triangles.empty()) return 0;
    Smoother s(m, domain, observer);
    s.movable_from(first_movable);
    const std::uint64_t moves = s.repair();
    s.write_back();
    if (flips) *flips += s.flips();
    return moves;
}

}  // namespace meshd::core
