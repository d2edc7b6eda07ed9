// Interior points by the advancing front (algorithm 4.1); see interior.hpp.

#include "interior/interior.hpp"
#include "interior/crossing_proof.hpp"

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "triangulation/triangle_soup.hpp"
#include "kernel/size_grid.hpp"
#include "kernel/memory.hpp"
#include "meshd/core/errors.hpp"
#include "kernel/predicates.hpp"

namespace meshd::core {

namespace {

using detail::CellGrid;
using detail::SizeClasses;
using detail::next3;
using detail::prev3;

// The points' grid holds copies of the coordinates and sizes (a proximity test reads one
// chain entry and nothing else), and is where the sizes are kept: each point is entered once,
// in the order of the ids, so its entry is its id. The segments' grid holds front segment
// indices (copies made its entries ten times larger and the stage twice slower). Both tests
// tell the points A and B of the tested segment by their ids.
struct GridPoint {
    Vec2 p;
    double rho;
};
constexpr std::uint32_t kNoPoint = UINT32_MAX;
/// The front closes on a point its candidate came too close to (close_on) only where the
/// candidate's size is more than this many times the smaller of its segment's ends': below
/// where the front starts to die (a square's sides at 0.02 held at 0.0244 inside and died at
/// 0.025).
constexpr double kCloseGrowth = 1.2;
/// The Newton step's candidate within this fraction of the size from the first takes the
/// size found there instead of asking rho again: over 1% of a size a field that grows by at
/// most a quarter per element (eq. 6.1 under its cones from the boundary) moves by under
/// 0.25%, well within what the front's spacing resolves. On Fig. 9's eq. 6.1 field two steps
/// in three are that short (a third of the front's evaluations of the field); the NACA
/// example's expression changes faster and is asked again on almost every step. (At 2%, 94%
/// of Fig. 9's steps, one of the layered random domains fell to 29.9 degrees.)
constexpr double kSameSizeStep = 0.01;
using GridSegment = std::uint32_t;
/// What a block of the short segments' grid knows of the segments it holds, for the proof made
/// block by block: the size classes of their ends and the least and largest of the smaller
/// size at each segment's ends. A block poisoned (class_lo = INT_MIN) is never passed over.
struct ShortSummary {
    int class_lo = INT_MAX, class_hi = INT_MIN;
    double m_lo = HUGE_VAL, m_hi = 0.0;
};
/// The grids' cells are c_k wide (size_grid.hpp: an object of class k is c_k / 2 to c_k long).
/// Against 2 c_k, the default, a query looks at more cells but at about half the entries:
/// 1.4% to 1.8% fewer instructions on the examples, the same meshes (each example's file,
/// and the point totals of 3,367 random domains); cells of 0.75 c_k and of 1.5 c_k did no
/// better.
constexpr double kCells = 1.0;
/// Each front segment is entered once, in the segments' grid cell of its midpoint, and the
/// crossing test widens its box by the largest half extent of the segments of each class so
/// far, times this (room for the rounding of the differences). Entered in every cell its box
/// met, a segment took 4.2 entries: 67 bytes a point, whose fresh pages the kernel zeroes (at
/// 10^7 points, a tenth of the run on one VM). The extents are kept rather than taken from the
/// class (at most c_k / 2): the classes are clamped, and a segment longer than half the
/// domain's extent is in class 1 all the same.
constexpr double kMidpointMargin = 1.0 + 0x1p-20;

// Eight bytes: the point ids are at most kMaxPointsLimit (2^28; the stage refuses more
// points whatever its budget), and the flags take the bits above them (12 bytes a segment as
// plain fields, two segments a point: 8 bytes a point less of fresh pages, which a large
// mesh pays the host for).
struct FrontSegment {
    FrontSegment(std::uint32_t from, std::uint32_t to, bool on_boundary)
        : a(from & kIdBits), alive(1), boundary(on_boundary ? 1 : 0), b(to & kIdBits), consumed(0) {}
    static constexpr std::uint32_t kIdBits = (std::uint32_t{1} << 30) - 1;
    std::uint32_t a : 30, alive : 1;
    std::uint32_t boundary : 1;  // a segment of the discretised boundary (never split onto itself)
    std::uint32_t b : 31;
    std::uint32_t consumed : 1;  // gave its point: the triangle of A, B and that point is on its left
};
static_assert(sizeof(FrontSegment) == 8);
static_assert(kMaxPointsLimit < (std::uint32_t{1} << 30));

class AdvancingFront {
public:
    AdvancingFront(const Domain& domain, const Discretisation& d, const BoundaryTriangulation& walls,
                   const SizeField& rho, const InteriorOptions& opt, InteriorBudget budget, Observer* obs,
                   InteriorStats& stats)
        : rho_(rho), opt_(opt), max_points_(budget.max_points && budget.max_points < kMaxPointsLimit ? budget.max_points : kMaxPointsLimit),
          obs_(obs), stats_(stats),
          box_(domain.box()),
          classes_(domain.box().lo - Vec2{domain.extent(), domain.extent()}, domain.extent(), kCells),
          wall_points_(walls.points), wall_triangles_(walls.triangles),
          walls_(wall_points_, wall_triangles_, true) {
        // Points: the boundary's, with their curve densities.
        const size_t nb = d.size();
        // Counted on the benchmark case: two front segments per point, each with one entry in
        // the segments' grid, and one entry per point in the points' grid.
        // A forecast far too large only reserves address space: untouched pages cost nothing.
        size_t n = std::max(nb * 4, budget.expected_points + budget.expected_points / 8);
        n = std::min(n, max_points_ + 1);
        detail::reserve_huge(pts_, n);
        detail::reserve_huge(home_, n);
        detail::reserve_huge(front_, 2 * n);
        points_.reserve(n);
        jumps_to_stop_ = budget.jumps_to_stop;
        extra_bytes_ = budget.extra_bytes;
        candidates_at_start_ = stats_.candidates;
        jumps_at_start_ = stats_.jumps;
        // No forecast (0): nothing to report against.
        report_at_ = budget.expected_points ? 2 * std::max(budget.expected_points, nb) : SIZE_MAX;
        segment_room_ = 2 * n + n / 4;
        proof_ = local_ = opt_.crossing_proof && opt_.proximity > 0.0;
        detail::reserve_huge(unsafe_, n);
        for (VertexId v = 0; v < nb; ++v) {
            // The crossing proof (crossing_proof.hpp) needs points spaced as (4.22) asks: the
            // front's are (the test itself, and step()'s check of a new point against its
            // segment's ends), the boundary's are checked here. Two that are not are both
            // unsafe: no segment at either is left to the proof.
            bool crowded = false;
            if (local_)
                for_each_near_point(d.point(v), d.rho[v], [&](std::uint32_t u) {
                    unsafe_[u] = 1;
                    crowded = true;
                });
            add_point(d.point(v), d.rho[v], kNoTriangle);
            if (crowded) {
                unsafe_[v] = 1;
                proof_ = false;
            }
        }
        boundary_count_ = nb;
        if (!proof_) {
            segments_.reserve(segment_room_);
            if (local_) short_.reserve(segment_room_);  // address space: only what is used is made
        }
        for (size_t i = 0; i < d.segments.size(); ++i) {
            const auto& s = d.segments[i];
            push_segment(s.a, s.b, true);
            if (i >= d.loop_segment_count) push_segment(s.b, s.a, true);  // embedded: both sides
        }
    }

    Array<Vec2> run() {
        std::uint64_t steps = 0;
        while (!stack_.empty()) {
            if ((++steps & 1023) == 0 && obs_) {
                if (obs_->should_stop()) throw Cancelled();
                obs_->on_progress(Stage::Interior, std::fmin(0.99, static_cast<double>(stats_.accepted) /
                                                                      static_cast<double>(stats_.accepted + stack_.size() + 1)));
            }
            const std::uint32_t s = stack_.back();
            stack_.pop_back();
            if (!front_[s].alive) continue;
            step(s);
        }
        // The boundary's points moved out of the way in place (no second array's fresh pages).
        pts_.erase(pts_.begin(), pts_.begin() + static_cast<std::ptrdiff_t>(boundary_count_));
        return std::move(pts_);
    }

private:
    void add_point(Vec2 p, double r, TriangleId home) {
        pts_.push_back(p);
        home_.push_back(home);
        unsafe_.push_back(0);
        const int k = classes_.class_of(r);
        largest_rho_[static_cast<size_t>(k)] = fmax_inline(largest_rho_[static_cast<size_t>(k)], r);
        points_.push(k, classes_.ix(p.x, k), classes_.iy(p.y, k), GridPoint{p, r});  // entry pts_.size() - 1
        size_lo_ = fmin_inline(size_lo_, r);
        size_hi_ = fmax_inline(size_hi_, r);
        class_lo_ = std::min(class_lo_, k);
        class_hi_ = std::max(class_hi_, k);
        if (proof_ && class_hi_ - class_lo_ > 1) drop_proof();
        if (pts_.size() > max_points_)
            throw GeometryError(GeometryErrorKind::TooManyPoints,
                                "the mesh needs more than " + std::to_string(max_points_) + " points");
        if (pts_.size() > report_at_) {
            // Past twice what was forecast, and at each doubling after: the memory reserved
            // for the forecast no longer covers the run (Observer::on_forecast).
            report_at_ *= 2;
            if (obs_)
                obs_->on_forecast(static_cast<double>(pts_.size()),
                                  peak_bytes_for(static_cast<double>(pts_.size())) + extra_bytes_);
        }
    }

    void push_segment(std::uint32_t a, std::uint32_t b, bool boundary) {
        const auto id = static_cast<std::uint32_t>(front_.size());
        front_.emplace_back(a, b, boundary);
        stack_.push_back(id);
        // A boundary segment's ends are spaced like any other two points (the constructor
        // checks), so the proof covers the short ones too.
        if (!proof_ ||
            distance(pts_[a], pts_[b]) > detail::kShortSegment * fmin_inline(points_.item(a).rho, points_.item(b).rho))
            enter(id);
    }

    // Segment `id` entered in the crossing test's grids: a short one whose ends are safe in
    // the short segments' grid, with its block's summary brought up to date; any other in
    // the grid of those the test always looks at.
    void enter(std::uint32_t id) {
        const std::uint32_t ia = front_[id].a, ib = front_[id].b;
        const Vec2 pa = pts_[ia], pb = pts_[ib];
        const double len = distance(pa, pb);
        const int k = classes_.class_of(len);
        const Vec2 mid = 0.5 * (pa + pb);
        const std::int64_t x = classes_.ix(mid.x, k), y = classes_.iy(mid.y, k);
        const double ra = points_.item(ia).rho, rb = points_.item(ib).rho, m = fmin_inline(ra, rb);
        if (local_ && !unsafe_[ia] && !unsafe_[ib] && len <= detail::kShortSegment * m) {
            const int ka = classes_.class_of(ra), kb = classes_.class_of(rb);
            short_.push_summarised(k, x, y, id, [&](ShortSummary& sum) {
                sum.class_lo = std::min({sum.class_lo, ka, kb});
                sum.class_hi = std::max({sum.class_hi, ka, kb});
                sum.m_lo = fmin_inline(sum.m_lo, m);
                sum.m_hi = fmax_inline(sum.m_hi, m);
            });
        } else {
            segments_.push(k, x, y, id);
        }
        Vec2& reach = segment_reach_[static_cast<size_t>(k)];
        // Plus a few units in the last place of the coordinates: the midpoint's rounding, which
        // a short segment far from the origin can make larger than a share of its extent.
        auto half = [](double u, double v) {
            return kMidpointMargin * 0.5 * std::fabs(v - u) + 0x1p-50 * (std::fabs(u) + std::fabs(v));
        };
        reach = {fmax_inline(reach.x, half(pa.x, pb.x)), fmax_inline(reach.y, half(pa.y, pb.y))};
    }

    // From here on every segment is in the grid, as if the proof had never been used: the grid
    // is built again, each segment entered in the order of the ids, as push_segment would have.
    void drop_proof() {
        proof_ = false;
        segments_ = CellGrid<GridSegment, true>();
        short_ = CellGrid<GridSegment, true, ShortSummary>();
        segments_.reserve(std::max(segment_room_, front_.size()));
        if (local_) short_.reserve(std::max(segment_room_, front_.size()));
        segment_reach_.fill(Vec2{0.0, 0.0});
        for (std::uint32_t id = 0; id < front_.size(); ++id) enter(id);
    }

    // The candidate of (4.3)/(4.7)/(4.12)/(4.19) for segment a -> b with radii ra, rb.
    static bool candidate(Vec2 a, Vec2 b, double ra, double rb, bool boundary, Vec2& c) {
        const Vec2 ab = b - a;
        const double l2 = norm2(ab), l = std::sqrt(l2);
        if (!(l > 0.0)) return false;
        if (ra + rb > l && ra + l > rb && rb + l > ra) {
            // C = A + x u + h v with u = AB / l, v = perp(u), x = (l^2 + ra^2 - rb^2) / 2l and
            // h = sqrt(ra^2 - x^2), written in x / l and h / l: one division and one square
            // root in a row instead of two of each (the length's root is only compared).
            const double inv = 1.0 / l2;
            const double xl = 0.5 * (l2 + ra * ra - rb * rb) * inv;
            const double hl = std::sqrt(fmax_inline(ra * ra * inv - xl * xl, 0.0));
            c = a + xl * ab + hl * perp(ab);
            return is_finite(c);
        }
        const Vec2 u = ab / l, v = perp(u);
        if (ra + rb <= l) {
            // (4.7-4.9): the point dividing AB as ra : rb. On a segment of the boundary that
            // would put a point on the boundary; there the apex of the equilateral triangle
            // is used instead.
            if (boundary) c = 0.5 * (a + b) + (0.5 * std::sqrt(3.0) * l) * v;
            else c = a + (ra / (ra + rb)) * ab;
        } else if (ra + l <= rb) {
            const double ad = std::sqrt(rb * rb - l * l);
            const double ac = ad - (ad - ra) / (1.0 + rb / ra);  // (4.17-4.18)
            c = a + ac * v;
        } else {
            const double bd = std::sqrt(ra * ra - l * l);
            const double bc = bd - (bd - rb) / (1.0 + ra / rb);  // (4.20)
            c = b + bc * v;
        }
        return is_finite(c);
    }

    // (4.22) against the points of classes k-3 .. k+1 around the class k of C, so points up
    // to 16 times coarser than C are seen (their reach is largest) and down to 4 times finer.
    // Each point is in the grid of its own class; C's class and its neighbours are looked at
    // first, as they hold the offending point of most rejected candidates, and any offending
    // point decides: its id, or kNoPoint.
    std::uint32_t near_other_point(Vec2 c, double rc, std::uint32_t a, std::uint32_t b) const {
        std::uint32_t found = kNoPoint;
        // The distance first: A and B are rarely within reach, and the ids are cheaper to
        // tell apart than the coordinates.
        auto near = [&](const GridPoint& q, std::uint32_t id) {
            const double lim = opt_.proximity * 0.5 * (rc + q.rho);
            if (!(norm2(q.p - c) < lim * lim) || id == a || id == b) return false;
            found = id;
            return true;
        };
        const int k = classes_.class_of(rc);
        for (int j : {k, k - 1, k + 1, k - 2, k - 3}) {
            if (j < 1 || j > SizeClasses::kMax || !points_.has_class(j)) continue;
            // The reach is (rc + the largest rho of class j so far) / 2.
            const double reach = opt_.proximity * 0.5 * (rc + largest_rho_[static_cast<size_t>(j)]);
            if (points_.any_entry_in(j, classes_.ix(c.x - reach, j), classes_.ix(c.x + reach, j), classes_.iy(c.y - reach, j),
                                     classes_.iy(c.y + reach, j), near))
                return found;
        }
        return kNoPoint;
    }

    // visit(id) for every point (4.22) would find too close to c, as near_other_point looks
    // (the classes k-3 .. k+1 around c's).
    template <class Visit>
    void for_each_near_point(Vec2 c, double rc, Visit&& visit) const {
        const int k = classes_.class_of(rc);
        for (int j = k - 3; j <= k + 1; ++j) {
            if (j < 1 || j > SizeClasses::kMax || !points_.has_class(j)) continue;
            const double reach = opt_.proximity * 0.5 * (rc + largest_rho_[static_cast<size_t>(j)]);
            points_.any_entry_in(j, classes_.ix(c.x - reach, j), classes_.ix(c.x + reach, j), classes_.iy(c.y - reach, j),
                                 classes_.iy(c.y + reach, j), [&](const GridPoint& q, std::uint32_t id) {
                                     const double lim = opt_.proximity * 0.5 * (rc + q.rho);
                                     if (norm2(q.p - c) < lim * lim) visit(id);
                                     return false;
                                 });
        }
    }

    // Point u is not spaced from some other point as (4.22) asks: no segment at u may be left
    // to the proof. Those entered already are in the short segments' grid near u, within the
    // reach of their class (their midpoints' cells): every block there is poisoned.
    void mark_unsafe(std::uint32_t u) {
        if (unsafe_[u]) return;
        unsafe_[u] = 1;
        const Vec2 p = pts_[u];
        for (int k = 1; k <= SizeClasses::kMax; ++k) {
            if (!short_.has_class(k)) continue;
            const Vec2 reach = segment_reach_[static_cast<size_t>(k)];
            short_.update_summaries(k, classes_.ix(p.x - reach.x, k), classes_.ix(p.x + reach.x, k),
                                    classes_.iy(p.y - reach.y, k), classes_.iy(p.y + reach.y, k),
                                    [](ShortSummary& sum) { sum.class_lo = INT_MIN; });
        }
    }

    // Does AC or BC cross a segment of the front (any segment ever made but those that gave
    // their point)? Each is checked against the segments of its class and the two next to it,
    // in one scan of the cells around ABC.
    // A segment that gave its point lies inside the region the front has covered (its
    // point's triangle on one side, what was covered before on the other), and that region's
    // border is made of segments that gave none: live, or dead without a point. A side from
    // a front point that reaches such a segment has crossed that border, or has gone into
    // the covered region at its start, where its end lies within reach of a covered
    // triangle's corners and (4.22), tested first, has refused it. So the crossing test
    // retires those segments from the grid's chains as it meets them (44% of the entries it
    // visited on the load run's square); with them and without, every example's mesh was the
    // same, and so were the point totals of 2,840 random domains.
    // With `ic` (the id of c when c is a point of the front, not a candidate), segments
    // ending at c meet AC and BC there by construction too.
    // For a candidate (no `ic`), of size rc, the blocks of short segments whose summaries
    // satisfy the proof's premise for every side that looks at them are passed over
    // (crossing_proof.hpp): (4.22) saw every two of the points involved, and their sizes lie
    // where short segments cannot cross. A closing's C is a point of the front, which points
    // made after it were not all tested against: its test looks at every block.
    bool crosses_front(std::uint32_t ia, std::uint32_t ib, Vec2 c, double rc, std::uint32_t ic = kNoPoint) {
        if (segments_.empty() && short_.empty()) return false;  // the crossing proof left every segment out
        const Vec2 a = pts_[ia], b = pts_[ib];
        struct Edge {
            Vec2 p, lo, hi;
            int k;
        };
        const Edge edges[2] = {
            {a, {std::min(a.x, c.x), std::min(a.y, c.y)}, {std::max(a.x, c.x), std::max(a.y, c.y)}, classes_.class_of(distance(a, c))},
            {b, {std::min(b.x, c.x), std::min(b.y, c.y)}, {std::max(b.x, c.x), std::max(b.y, c.y)}, classes_.class_of(distance(b, c))}};
        // For each side XC: its length, X's size and the classes the sizes at a passed-over
        // block's segment ends must lie in. C's (4.22) test saw the classes kC - 3 .. kC + 1;
        // of X and a point P, the later one's test saw the other if their classes are at
        // most one apart (each test sees one class coarser and three finer than its own).
        struct Side {
            double d, rx;
            int lo, hi;
        };
        Side sides[2]{};
        const bool local = local_ && ic == kNoPoint && !short_.empty();
        if (local) {
            const int kc = classes_.class_of(rc);
            for (int i = 0; i < 2; ++i) {
                const double rx = points_.item(i == 0 ? ia : ib).rho;
                const int kx = classes_.class_of(rx);
                sides[i] = {distance(edges[i].p, c), rx, std::max(kc - 3, kx - 1), std::min(kc + 1, kx + 1)};
            }
        }
        const int k_lo = std::max(1, std::min(edges[0].k, edges[1].k) - 1);
        const int k_hi = std::min(SizeClasses::kMax, std::max(edges[0].k, edges[1].k) + 1);
        for (int k = k_lo; k <= k_hi; ++k) {
            const bool longs = segments_.has_class(k), shorts = short_.has_class(k);
            if (!longs && !shorts) continue;
            const bool use[2] = {std::abs(k - edges[0].k) <= 1, std::abs(k - edges[1].k) <= 1};
            Box box;
            for (int i = 0; i < 2; ++i)
                if (use[i]) {
                    box.add(edges[i].lo);
                    box.add(edges[i].hi);
                }
            // A segment is in the cell of its midpoint (push_segment), which lies within its
            // half extent of every point of its box in each axis.
            const Vec2 reach = segment_reach_[static_cast<size_t>(k)];
            box.lo = box.lo - reach;
            box.hi = box.hi + reach;
            bool checking = false;  // the block being looked at would have been passed over
            auto crossed = [&](const GridSegment& si) {
                const FrontSegment& f = front_[si];
                const Vec2 sa = pts_[f.a], sb = pts_[f.b];
                if (checking) check_premise(f, ia, ib, edges[0].p, edges[1].p, c, rc, use, sides);
                const Vec2 slo{std::min(sa.x, sb.x), std::min(sa.y, sb.y)};
                const Vec2 shi{std::max(sa.x, sb.x), std::max(sa.y, sb.y)};
                // Whether the boxes meet, for each side of this class (| rather than ||: no
                // branch per comparison). Most segments of the cells meet neither.
                bool meets[2];
                for (int i = 0; i < 2; ++i) {
                    const Edge& g = edges[i];
                    meets[i] = use[i] & (shi.x >= g.lo.x) & (slo.x <= g.hi.x) & (shi.y >= g.lo.y) & (slo.y <= g.hi.y);
                }
                if (!(meets[0] | meets[1])) return false;
                // Segments sharing an end with AB meet AC or BC there by construction.
                if (f.a == ia || f.a == ib || f.b == ia || f.b == ib || f.a == ic || f.b == ic) return false;
                for (int i = 0; i < 2; ++i)
                    if (meets[i] && segments_intersect(edges[i].p, c, sa, sb)) {
                        if (checking) ++stats_.proof_violations;
                        return true;
                    }
                return false;
            };
            auto retired = [&](const GridSegment& si) { return front_[si].consumed; };
            const std::int64_t x0 = classes_.ix(box.lo.x, k), x1 = classes_.ix(box.hi.x, k);
            const std::int64_t y0 = classes_.iy(box.lo.y, k), y1 = classes_.iy(box.hi.y, k);
            if (longs && segments_.any_in_retiring(k, x0, x1, y0, y1, retired, crossed)) return true;
            if (!shorts) continue;
            if (!local) {
                if (short_.any_in_retiring(k, x0, x1, y0, y1, retired, crossed)) return true;
                continue;
            }
            auto proven = [&](const ShortSummary& sum) {
                checking = false;
                for (int i = 0; i < 2; ++i)
                    if (use[i] && !(sum.class_lo >= sides[i].lo && sum.class_hi <= sides[i].hi &&
                                    detail::short_segments_cannot_cross(sides[i].d, sides[i].rx, rc, sum.m_lo, sum.m_hi,
                                                                        opt_.proximity)))
                        return false;
                ++stats_.blocks_proven;
                // Checking: the block is looked at all the same, each segment against the premise.
                checking = opt_.check_crossing_proof;
                return !checking;
            };
            if (short_.any_in_retiring_unless(k, x0, x1, y0, y1, proven, retired, crossed)) return true;
        }
        return false;
    }

    // For check_crossing_proof: whether segment f, in a block the proof would pass over for
    // candidate c (size rc) of segment ia -> ib, is covered by the proof's premise for every
    // side XC that looks at the block (crossing_proof.hpp): short, the sizes at its ends in
    // the side's classes and the smaller of them, m, where two segments of that size cannot
    // cross XC, and its ends (unless they are A or B, whose segments the test leaves anyway)
    // outside the disks about X and C that (4.22) keeps points out of, neither of them unsafe.
    template <class Side>
    void check_premise(const FrontSegment& f, std::uint32_t ia, std::uint32_t ib, Vec2 a, Vec2 b, Vec2 c, double rc,
                       const bool use[2], const Side sides[2]) {
        if (f.a == ia || f.a == ib || f.b == ia || f.b == ib) return;
        const Vec2 sa = pts_[f.a], sb = pts_[f.b];
        const double ra = points_.item(f.a).rho, rb = points_.item(f.b).rho, m = fmin_inline(ra, rb);
        // Neither end unsafe: a point found too close to another after its segments went into
        // this grid poisons their blocks (mark_unsafe).
        bool ok = distance(sa, sb) <= detail::kShortSegment * m && !unsafe_[f.a] && !unsafe_[f.b];
        const double h = 0.5 * opt_.proximity;
        for (int i = 0; i < 2; ++i) {
            if (!use[i]) continue;
            const Vec2 x = i == 0 ? a : b;
            for (const double r : {ra, rb}) {
                const int k = classes_.class_of(r);
                ok = ok && k >= sides[i].lo && k <= sides[i].hi;
            }
            ok = ok && detail::short_segments_cannot_cross(sides[i].d, sides[i].rx, rc, m, m, opt_.proximity);
            for (const Vec2 q : {sa, sb}) {
                const double lx = h * (sides[i].rx + m), lc = h * (rc + m);
                ok = ok && !(norm2(q - x) < lx * lx) && !(norm2(q - c) < lc * lc);
            }
        }
        if (!ok) ++stats_.proof_violations;
    }

    // The triangle of the boundary triangulation that holds c, reached by a straight walk
    // from `from` in triangle t without crossing a constraint; kNoTriangle when the way is
    // blocked, leaves the domain or is degenerate (a walk this long: refuse the point).
    TriangleId inside(TriangleId t, Vec2 from, Vec2 c) const {
        const detail::WalkEnd end = walls_.walk(t, from, c, 100000);
        return end.edge < 0 ? end.triangle : kNoTriangle;
    }

    // Triangle of the boundary triangulation from which to walk out of point v.
    TriangleId start_of(std::uint32_t v, Vec2 target) const {
        if (v < boundary_count_) return walls_.wedge(v, target);
        return home_[v];
    }

    // The segment of the front from u to v (any ever made), or kNoPoint.
    std::uint32_t find_segment(std::uint32_t u, std::uint32_t v) const {
        // In the cell of its midpoint, computed as push_segment did.
        const Vec2 pu = pts_[u], pv = pts_[v];
        const int k = classes_.class_of(distance(pu, pv));
        const Vec2 mid = 0.5 * (pu + pv);
        const std::int64_t x = classes_.ix(mid.x, k), y = classes_.iy(mid.y, k);
        std::uint32_t found = kNoPoint;
        auto is_it = [&](const GridSegment& si) {
            if (front_[si].a != u || front_[si].b != v) return false;
            found = si;
            return true;
        };
        // In either grid: u or v may have become unsafe after the segment was entered.
        if (!segments_.any_in_all(k, x, x, y, y, is_it) && local_) short_.any_in_all(k, x, x, y, y, is_it);
        return found;
    }

    // AB's candidate came too close to point P of the front, where the field is coarser than
    // the front's points by more than kCloseGrowth: the front closes on P instead, AB giving
    // way to AP and PB, when P is AB's neighbour along the front (a live segment B -> P or
    // P -> A), lies on AB's left, and AP and BP cross no segment. There the first row takes
    // only every other place over the front (its candidates are the field apart, the front's
    // points closer), and each new segment's candidate falls into a place not taken: the
    // front died, the inside empty but for one row (a unit square's sides at 0.02 under 0.028
    // inside: 96 inner points instead of 1,367). Where the field is as fine as the front, a
    // segment that dies leaves its place to its neighbours' points, and nothing changes. Not
    // when A, B and P are all points of the boundary: the triangle would be theirs alone. A
    // side whose opposite is a live segment meets it (both end). No point is added, so (4.22)
    // holds as before; at most one closing per point.
    void close_on(const FrontSegment& seg, std::uint32_t p) {
        if (closings_ >= pts_.size()) return;
        if (p < boundary_count_ && seg.a < boundary_count_ && seg.b < boundary_count_) return;
        const Vec2 a = pts_[seg.a], b = pts_[seg.b], c = pts_[p];
        if (orient2d(a, b, c) != Orientation::Left) return;
        // The closing looks segments up in the grid, and its segments may be long.
        if (proof_) drop_proof();
        const std::uint32_t bp = find_segment(seg.b, p), pa = find_segment(p, seg.a);
        if (!((bp != kNoPoint && front_[bp].alive) || (pa != kNoPoint && front_[pa].alive))) return;
        if (crosses_front(seg.a, seg.b, c, 0.0, p)) return;
        ++closings_;
        for (const auto& [u, v] : {std::pair{seg.a, p}, std::pair{p, seg.b}}) {
            if (const std::uint32_t back = find_segment(v, u); back != kNoPoint && front_[back].alive) {
                front_[back].alive = false;
                continue;
            }
            if (find_segment(u, v) == kNoPoint) push_segment(u, v, false);
        }
    }

    void step(std::uint32_t s) {
        const FrontSegment seg = front_[s];
        const Vec2 a = pts_[seg.a], b = pts_[seg.b];
        const double ra = points_.item(seg.a).rho, rb = points_.item(seg.b).rho;
        Vec2 c;
        ++stats_.candidates;
        if (!candidate(a, b, ra, rb, seg.boundary, c)) {
            front_[s].alive = false;
            return;
        }
        if (orient2d(a, b, c) != Orientation::Left) {
            front_[s].alive = false;
            return;
        }
        // Outside the domain's box (far outside when the radii are very unequal): no search
        // should span the plane for it, nor rho be asked there.
        if (!box_.contains(c)) {
            ++stats_.rejected_outside;
            front_[s].alive = false;
            return;
        }
        double rc = rho_.interior(c);
        if (opt_.newton) {
            // One step towards the fixed point of (4.4): the radii become the mean sizes of
            // the new edges. (A second step changed the figures of the benchmark case by
            // less than 1e-3 and cost 9% of this stage.)
            Vec2 c2;
            if (candidate(a, b, 0.5 * (ra + rc), 0.5 * (rb + rc), seg.boundary, c2) &&
                orient2d(a, b, c2) == Orientation::Left && box_.contains(c2)) {
                const bool moved = distance(c, c2) > kSameSizeStep * rc;
                c = c2;
                if (moved) rc = rho_.interior(c);
            }
        }
        if (rc > kFieldJump * fmax_inline(ra, rb) || kFieldJump * rc < fmin_inline(ra, rb)) {
            ++stats_.jumps;
            // Jumps are counted from this stage's start: the closing rounds run it again.
            if (jumps_to_stop_ &&
                stats_.jumps - jumps_at_start_ >= jumps_to_stop_ + (stats_.candidates - candidates_at_start_) / 1024)
                throw FieldJumps{};
        }
        // The cheap local tests first: (4.22) rejects about half of all candidates.
        if (const std::uint32_t p = near_other_point(c, rc, seg.a, seg.b); p != kNoPoint) {
            ++stats_.rejected_near;
            front_[s].alive = false;
            if (rc > kCloseGrowth * fmin_inline(ra, rb)) close_on(seg, p);
            return;
        }
        if (proof_) {
            // C's (4.22) test saw every point when C's class and theirs are two neighbours at most.
            const int k = classes_.class_of(rc);
            const double p = opt_.proximity;
            if (std::max(class_hi_, k) - std::min(class_lo_, k) > 1 ||
                !detail::short_segments_cannot_cross(distance(a, c), ra, rc, size_lo_, size_hi_, p) ||
                !detail::short_segments_cannot_cross(distance(b, c), rb, rc, size_lo_, size_hi_, p))
                drop_proof();
            else
                ++stats_.crossings_proven;
        }
        if (crosses_front(seg.a, seg.b, c, rc)) {
            ++stats_.rejected_crossing;
            front_[s].alive = false;
            return;
        }
        // Paths from A and B to C must stay in the domain (this also decides C is inside).
        const TriangleId ta = start_of(seg.a, c);
        const TriangleId home_c = ta == kNoTriangle ? kNoTriangle : inside(ta, a, c);
        // An interior B in the triangle that holds C: BC lies in that (convex) triangle, and
        // the walk from B would end there at its first step.
        const bool b_beside = seg.b >= boundary_count_ && home_c != kNoTriangle && home_[seg.b] == home_c;
        const TriangleId tb = home_c == kNoTriangle || b_beside ? home_c : start_of(seg.b, c);
        if (home_c == kNoTriangle || tb == kNoTriangle || (!b_beside && inside(tb, b, c) == kNoTriangle)) {
            ++stats_.rejected_outside;
            front_[s].alive = false;
            return;
        }
        // C's (4.22) test left out A and B: the proof needs them spaced too. Where C is too
        // close to one, both are unsafe from here on.
        bool near_a = false, near_b = false;
        if (local_) {
            const double la = opt_.proximity * 0.5 * (ra + rc), lb = opt_.proximity * 0.5 * (rb + rc);
            near_a = norm2(c - a) < la * la;
            near_b = norm2(c - b) < lb * lb;
            if (proof_ && (near_a || near_b)) drop_proof();
        }
        const auto id = static_cast<std::uint32_t>(pts_.size());
        add_point(c, rc, home_c);
        if (near_a || near_b) {
            unsafe_[id] = 1;
            if (near_a) mark_unsafe(seg.a);
            if (near_b) mark_unsafe(seg.b);
        }
        ++stats_.accepted;
        front_[s].alive = false;
        front_[s].consumed = true;
        push_segment(seg.a, id, false);
        push_segment(id, seg.b, false);
    }

    const SizeField& rho_;
    const InteriorOptions& opt_;
    size_t max_points_;
    Observer* obs_;
    InteriorStats& stats_;
    Box box_;
    SizeClasses classes_;
    // The constrained triangulation of the boundary, for the walks that decide "inside".
    Array<Vec2> wall_points_;
    Array<Triangle> wall_triangles_;
    detail::TriangleSoup walls_;
    Array<Vec2> pts_;
    Array<TriangleId> home_;
    size_t boundary_count_ = 0;
    Array<FrontSegment> front_;
    Array<std::uint32_t> stack_;
    size_t closings_ = 0;
    size_t report_at_ = SIZE_MAX;  // the next count the observer hears of
    size_t extra_bytes_ = 0;       // InteriorBudget::extra_bytes
    std::uint64_t jumps_to_stop_ = 0, jumps_at_start_ = 0, candidates_at_start_ = 0;
    CellGrid<GridPoint> points_;
    std::array<double, SizeClasses::kMax + 1> largest_rho_{};  // of the points in each class
    std::array<Vec2, SizeClasses::kMax + 1> segment_reach_{};  // the segments' largest half extents, by class
    CellGrid<GridSegment, true> segments_;
    // The short segments whose ends are safe, once the proof is made block by block.
    CellGrid<GridSegment, true, ShortSummary> short_;
    Array<char> unsafe_;  // by point: too close to another point for (4.22)'s spacing (mark_unsafe)
    size_t segment_room_ = 0;  // entries reserved in segments_ when every segment is entered
    // While proof_ holds, short segments (the boundary's too) stay out of the segments' grid,
    // and each candidate's crossing test first proves that they cannot cross its sides
    // (crossing_proof.hpp). The proof needs every two points spaced as (4.22) asks, which
    // (4.22) ensures only for the classes it looks at: it holds while all sizes are in two
    // neighbouring classes (each point's test then sees every other), the boundary's points
    // are spaced (checked at the start) and each new point is spaced from its segment's ends.
    // The first time any of this fails, or a closing needs the grid, every segment goes into
    // the grids (drop_proof) and the proof is made block by block from then on: the mesh is
    // the same either way.
    bool proof_ = true;
    // The proof block by block (enter, crosses_front): short segments with safe ends in short_,
    // whose blocks' summaries say where they cannot cross. In use wherever the whole-domain
    // proof may be (InteriorOptions::crossing_proof).
    bool local_ = true;
    double size_lo_ = HUGE_VAL, size_hi_ = 0.0;  // the least and largest size of the points
    int class_lo_ = INT_MAX, class_hi_ = INT_MIN;  // and their classes
};

}  // namespace

Array<Vec2> generate_interior_points(const Domain& domain, const Discretisation& boundary,
                                     const BoundaryTriangulation& walls, const SizeField& rho,
                                     const InteriorOptions& options, InteriorBudget budget,
                                     Observer* observer, InteriorStats* stats) {
    InteriorStats local;
    AdvancingFront af(domain, boundary, walls, rho, options, budget, observer, stats ? *stats : local);
    return af.run();
}

}  // namespace meshd::core
