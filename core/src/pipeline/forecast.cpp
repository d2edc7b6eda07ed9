// The forecast of estimate.hpp: how many points a mesh will have, from the domain and the
// density alone, at a cost that does not depend on the answer.
//
// Boundary: n_b = sum over the used curves of the integral of |C'(t)| / rho(C(t)) dt (Lo's
// spacing puts one segment per rho of length). Interior: n_i = k * integral of rho^-2 over
// the domain, k = kPointsPerArea. Both integrals are adaptive midpoint rules that always split
// the piece holding the most points (an interval of a curve, a square cell of the plane), so
// the samples spread like the points of the mesh itself, until either every piece holds less
// than a quarter of a point (the integral is then resolved) or a fixed number of samples is
// spent. A feature of rho narrower than the samples can be missed; the stages count what they
// make against the limit and catch that.
//
// The domain is the outlines of its loops (Domain::outlines, from the geometry alone). Each
// cell knows the winding number of the outlines around its sample point: the root's by a ray,
// a child's from its parent's by the outline segments the path between the two samples
// crosses; only the segments through the parent can be crossed, and each cell keeps those.
// A cell no segment passes through is wholly inside or wholly outside.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <queue>
#include <vector>

#include "geometry/curve.hpp"
#include "kernel/predicates.hpp"
#include "density/gradation.hpp"
#include "meshd/core/errors.hpp"
#include "pipeline/agreement.hpp"
#include "pipeline/estimate.hpp"

namespace meshd::core {

namespace {

// A piece holding fewer points than this is resolved: splitting it changes the count little.
constexpr double kResolved = 0.25;
// A piece holding less than this fraction of its integral's count so far is resolved too:
// a small mesh is forecast from about one sample per point, not four (the sample budget binds
// long before this on large meshes). For the interior's cells each of 1/4096 -> 1/1024 ->
// 1/256 moved the forecast of every example by at most 1.5% of its points and halved the
// samples of a small request; the last took 18% off the load run's boundary stage. The
// curves' intervals stop at it too (they stopped at a quarter of a point: 800 samples for the
// load run's 199 boundary points): every example's forecast moved by under 0.3%, and the
// whole forecast took half the samples or fewer (bench/forecast_driver.cpp,
// docs/benchmarks.md).
constexpr double kRelativeResolution = 1.0 / 256.0;

// Where in its cell a sample sits: off the centre, so that the samples of cells on a regular
// grid rarely fall exactly on the (often axis-aligned, round-numbered) outline.
constexpr double kSampleAt = 0.5 + 0.0137;

struct Interval {
    CurveId curve;
    double ta, tb;
    Vec2 at;         // the curve at the midpoint
    double size;     // rho there
    double count;    // (tb - ta) |C'(tm)| / rho(C(tm))
};

struct ByCount {
    bool operator()(const Interval& a, const Interval& b) const { return a.count < b.count; }
};

// Polls the observer every 1024 samples.
class Poll {
public:
    explicit Poll(Observer* o) : observer_(o) {}
    void operator()() {
        if ((++n_ & 1023) == 0 && observer_ && observer_->should_stop()) throw Cancelled();
    }

private:
    Observer* observer_;
    std::uint64_t n_ = 0;
};

// The boundary integral. Leaves the resolved intervals in `out` (the sources of eq. 6.1).
double forecast_boundary(const Domain& domain, const SizeField& rho, size_t budget, Poll& poll,
                         std::vector<Interval>& out, size_t& samples) {
    std::vector<bool> used(domain.curves().size(), false);
    for (const DomainLoop& l : domain.loops())
        for (const CurveUse& u : l.items) used[u.curve] = true;
    for (CurveId c : domain.embedded()) used[c] = true;

    // The count of the intervals so far, for the relative resolution (as the interior's): each
    // interval made adds its count, a split interval's is taken off.
    double sum = 0.0;
    auto make = [&](CurveId c, double ta, double tb) {
        const Curve& g = *domain.curves()[c].geometry;
        const double tm = 0.5 * (ta + tb);
        const Vec2 p = g.point(tm);
        const double h = rho.on_curve(c, p);
        ++samples;
        poll();
        const Interval x{c, ta, tb, p, h, (tb - ta) * norm(g.derivative(tm)) / h};
        sum += x.count;
        return x;
    };
    std::priority_queue<Interval, std::vector<Interval>, ByCount> queue;
    for (CurveId c = 0; c < domain.curves().size(); ++c) {
        if (!used[c]) continue;
        const Curve& g = *domain.curves()[c].geometry;
        std::vector<double> cuts{g.t_begin()};
        for (double t : g.breaks()) cuts.push_back(t);
        cuts.push_back(g.t_end());
        for (size_t k = 0; k + 1 < cuts.size(); ++k) {
            const double ta = cuts[k], tb = cuts[k + 1];
            for (int i = 0; i < 4; ++i) queue.push(make(c, ta + (tb - ta) * i / 4, ta + (tb - ta) * (i + 1) / 4));
        }
    }
    while (!queue.empty() && samples + 2 <= budget && queue.top().count > std::max(kResolved, kRelativeResolution * sum)) {
        const Interval x = queue.top();
        queue.pop();
        const double tm = 0.5 * (x.ta + x.tb);
        if (!(tm > x.ta && tm < x.tb)) {  // cannot be split further
            out.push_back(x);
            continue;
        }
        sum -= x.count;
        queue.push(make(x.curve, x.ta, tm));
        queue.push(make(x.curve, tm, x.tb));
    }
    double total = 0.0;
    out.reserve(out.size() + queue.size());
    for (; !queue.empty(); queue.pop()) out.push_back(queue.top());
    for (const Interval& x : out) total += x.count;
    return total;
}

struct Segment {
    Vec2 a, b;
};

struct Cell {
    Vec2 lo;
    double size;
    int winding;             // of the outlines around the sample
    double f;                // points per area at the sample (or inherited)
    double count;            // points forecast in the cell
    double priority;         // its claim to be split next
    std::uint32_t segs_from; // the outline segments through the cell: segs_from.. in the pool
    std::uint32_t segs_count;
};

Vec2 sample_of(Vec2 lo, double size) { return {lo.x + kSampleAt * size, lo.y + kSampleAt * size}; }

// Left of the directed line a -> b (on it counts as right: a consistent tie rule).
bool left_of(Vec2 a, Vec2 b, Vec2 p) { return orient2d(a, b, p) == Orientation::Left; }

// Change of the winding number from p to q across the segment a -> b: +1 when the path
// enters its left side.
int crossing(const Segment& s, Vec2 p, Vec2 q) {
    if (left_of(p, q, s.a) == left_of(p, q, s.b)) return 0;
    const bool lp = left_of(s.a, s.b, p), lq = left_of(s.a, s.b, q);
    if (lp == lq) return 0;
    return lq ? 1 : -1;
}

// Could the segment meet the closed square? (Conservative: a margin for rounding.)
bool meets(const Segment& s, Vec2 lo, double size) {
    const double m = 1e-9 * size;
    const Vec2 hi{lo.x + size, lo.y + size};
    if (std::fmax(s.a.x, s.b.x) < lo.x - m || std::fmin(s.a.x, s.b.x) > hi.x + m ||
        std::fmax(s.a.y, s.b.y) < lo.y - m || std::fmin(s.a.y, s.b.y) > hi.y + m)
        return false;
    const Vec2 d = s.b - s.a;
    const double tol = 1e-9 * norm(d) * size;
    int pos = 0, neg = 0;
    for (Vec2 c : {lo, Vec2{hi.x, lo.y}, hi, Vec2{lo.x, hi.y}}) {
        const double side = cross(d, c - s.a);
        pos += side > -tol;
        neg += side < tol;
    }
    return pos > 0 && neg > 0;
}

// The interior integral over the outlines.
double forecast_interior(const Domain& domain, const SizeField& rho, size_t budget, Poll& poll,
                         size_t& samples) {
    std::vector<Segment> segs;
    Box box;
    for (const std::vector<Vec2>& ring : domain.outlines()) {
        for (size_t i = 0, n = ring.size(); i < n; ++i) {
            segs.push_back({ring[i], ring[(i + 1) % n]});
            box.add(ring[i]);
        }
    }
    if (segs.empty() || box.empty()) return 0.0;
    const double size = 1.0001 * std::fmax(box.hi.x - box.lo.x, box.hi.y - box.lo.y) + 1e-300;
    const Vec2 centre = 0.5 * (box.lo + box.hi);

    // Points per area at an inside sample; a density that cannot be evaluated there (outside
    // the true curves, between a curve and its flattening) counts as nothing here: the stages
    // report it where it matters.
    double inside_count = 0.0, inside_area = 0.0;  // of the inside samples so far
    double leaves = 0.0;                            // the count of the cells not split
    auto density_at = [&](Vec2 p, double& f) {
        try {
            const double h = rho.interior_scattered(p);
            f = kPointsPerArea / (h * h);
            return true;
        } catch (const GeometryError& e) {
            if (e.kind() != GeometryErrorKind::DensityInvalid) throw;
            return false;
        }
    };
    // The cells in one array and their segment lists in one pool (a split cell's list is
    // left in place): a small mesh's forecast makes thousands of cells, and an allocation
    // each cost more than their samples.
    std::vector<Cell> cells;
    std::vector<std::uint32_t> pool;
    cells.reserve(std::min<size_t>(budget, 4096) + 4);
    // Every cell made is a sample, whether rho was evaluated there or not.
    auto finish = [&](Cell& c, double inherited_f) {
        ++samples;
        poll();
        const double area = c.size * c.size;
        double f = 0.0;
        if (c.winding > 0 && density_at(sample_of(c.lo, c.size), f)) {
            c.f = f;
            c.count = c.priority = area * f;
            inside_count += c.count;
            leaves += c.count;
            inside_area += area;
        } else {
            // Outside at the sample: nothing counted, but a cell the outline passes through
            // may still hold part of the domain: refine it as if inside, at the density of
            // the nearest ancestor that had one, else at the mean so far (or first, when no
            // sample was inside yet).
            c.f = inherited_f;
            c.count = 0.0;
            if (c.segs_count == 0) c.priority = 0.0;
            else if (inherited_f > 0.0) c.priority = area * inherited_f;
            else if (inside_area > 0.0) c.priority = area * inside_count / inside_area;
            else c.priority = 1e300 * area;
        }
    };

    {
        Cell root{};
        root.lo = {centre.x - 0.5 * size, centre.y - 0.5 * size};
        root.size = size;
        pool.resize(segs.size());
        for (std::uint32_t i = 0; i < segs.size(); ++i) pool[i] = i;
        root.segs_from = 0;
        root.segs_count = static_cast<std::uint32_t>(segs.size());
        // Winding number around the sample by a ray towards +x.
        const Vec2 p = sample_of(root.lo, size);
        int w = 0;
        for (const Segment& s : segs) {
            if (s.a.y <= p.y) {
                if (s.b.y > p.y && orient2d(s.a, s.b, p) == Orientation::Left) ++w;
            } else if (s.b.y <= p.y && orient2d(s.a, s.b, p) == Orientation::Right) {
                --w;
            }
        }
        root.winding = w;
        finish(root, 0.0);
        cells.push_back(root);
    }
    auto by_priority = [&cells](std::uint32_t a, std::uint32_t b) { return cells[a].priority < cells[b].priority; };
    std::priority_queue<std::uint32_t, std::vector<std::uint32_t>, decltype(by_priority)> queue(by_priority);
    queue.push(0);

    while (!queue.empty() && samples + 4 <= budget &&
           cells[queue.top()].priority > std::max(kResolved, kRelativeResolution * leaves)) {
        const std::uint32_t p = queue.top();
        queue.pop();
        const Cell parent = cells[p];
        const double half = 0.5 * parent.size;
        if (!(half > 0.0) || parent.lo.x + half == parent.lo.x || parent.lo.y + half == parent.lo.y) continue;
        const Vec2 from = sample_of(parent.lo, parent.size);
        for (int k = 0; k < 4; ++k) {
            Cell child{};
            child.lo = {parent.lo.x + (k & 1) * half, parent.lo.y + (k >> 1) * half};
            child.size = half;
            child.segs_from = static_cast<std::uint32_t>(pool.size());
            const Vec2 to = sample_of(child.lo, half);
            int w = parent.winding;
            for (std::uint32_t j = 0; j < parent.segs_count; ++j) {
                const std::uint32_t i = pool[parent.segs_from + j];
                w += crossing(segs[i], from, to);
                if (meets(segs[i], child.lo, half)) pool.push_back(i);
            }
            child.segs_count = static_cast<std::uint32_t>(pool.size()) - child.segs_from;
            child.winding = w;
            finish(child, parent.f);
            cells.push_back(child);  // before the queue's comparison reads it
            queue.push(static_cast<std::uint32_t>(cells.size() - 1));
        }
        leaves -= parent.count;
        cells[p].count = cells[p].priority = 0.0;  // now held by its children
    }
    double total = 0.0;
    for (const Cell& c : cells) total += c.count;  // inner cells gave theirs to their children
    return total;
}

// The sources of eq. 6.1 as the boundary stage would make them: one per segment, where
// the running count along each curve passes the middle of a segment, with the curve's size
// there; at least one per curve. (Taking the resolved intervals themselves as sources would
// weigh each curve by how finely its intervals happened to be split.) When the boundary would
// have more than kMaxSources segments, one source stands for `stride` of them, on every curve
// alike, which leaves the weighted mean of eq. 6.1 as it is.
void set_interpolation_sources(SizeField& rho, const Domain& domain, std::vector<Interval>& intervals,
                               double boundary) {
    constexpr double kMaxSources = 8192.0;
    const double stride = std::fmax(1.0, boundary / kMaxSources);
    std::sort(intervals.begin(), intervals.end(), [](const Interval& a, const Interval& b) {
        return a.curve != b.curve ? a.curve < b.curve : a.ta < b.ta;
    });
    std::vector<Vec2> starts;
    std::vector<double> lengths;
    for (size_t i = 0; i < intervals.size();) {
        size_t j = i;
        const CurveId c = intervals[i].curve;
        const Curve& g = *domain.curves()[c].geometry;
        double run = 0.0, next = 0.5 * stride;
        bool any = false;
        for (; j < intervals.size() && intervals[j].curve == c; ++j) {
            const Interval& x = intervals[j];
            for (; run + x.count >= next; next += stride) {
                const double w = x.count > 0.0 ? (next - run) / x.count : 0.5;
                starts.push_back(g.point(x.ta + w * (x.tb - x.ta)));
                lengths.push_back(x.size);
                any = true;
            }
            run += x.count;
        }
        if (!any) {
            const Interval& x = intervals[(i + j) / 2];
            starts.push_back(x.at);
            lengths.push_back(x.size);
        }
        i = j;
    }
    // A percent on rho is two on the count: enough for a forecast, and several times cheaper
    // than the stages' 10^-3.
    rho.set_boundary_segments(std::move(starts), std::move(lengths), 1e-2);
}

// The curves' intervals capped as agree_with_interior caps the curves (agreement.hpp): the
// field probed half a local size off each interval (on both sides: the forecast does not
// know which side is the domain's, and takes the larger value), caps where the interval's size is
// more than kAgreementRatio times it. Returns the boundary count after the caps. (The
// interior caps at fine segments are not forecast: they add few points.)
double agree_intervals(const Domain& domain, SizeField& rho, std::vector<Interval>& intervals, double boundary,
                       Poll& poll) {
    std::vector<Vec2> caps;
    std::vector<double> sizes;
    for (int round = 0; round < kAgreementRounds; ++round) {
        const size_t before = caps.size();
        for (const Interval& x : intervals) {
            poll();
            const Curve& g = *domain.curves()[x.curve].geometry;
            const Vec2 t = g.derivative(0.5 * (x.ta + x.tb));
            const double lt = norm(t);
            if (!(lt > 0.0)) continue;
            const Vec2 off = (0.5 * x.size / lt) * perp(t);
            const double f = std::fmax(probe_interior(rho, x.at + off), probe_interior(rho, x.at - off));
            if (!(x.size > kAgreementRatio * f)) continue;
            caps.push_back(x.at);
            sizes.push_back(f);
        }
        if (caps.size() == before) break;
        const GradationField cap(caps, sizes, kAgreementCapRatio, GradationField::Spread::Curves);
        boundary = 0.0;
        for (Interval& x : intervals) {
            const double h = std::fmax(std::fmin(x.size, cap(x.at)), rho.least_size());
            x.count *= x.size / h;
            x.size = h;
            boundary += x.count;
        }
        if (rho.interpolates()) set_interpolation_sources(rho, domain, intervals, boundary);
    }
    return boundary;
}

}  // namespace

PointForecast forecast_points(const Domain& domain, const DensitySpec& density, const ForecastBudget& budget,
                              Observer* observer) {
    PointForecast f;
    SizeField rho(density, domain);
    Poll poll(observer);
    std::vector<Interval> intervals;
    f.boundary = forecast_boundary(domain, rho, budget.boundary_samples, poll, intervals, f.boundary_samples);
    if (rho.interpolates()) set_interpolation_sources(rho, domain, intervals, f.boundary);
    if (budget.curve_agreement) f.boundary = agree_intervals(domain, rho, intervals, f.boundary, poll);
    f.interior = forecast_interior(domain, rho, budget.interior_samples, poll, f.interior_samples);
    return f;
}

}  // namespace meshd::core
