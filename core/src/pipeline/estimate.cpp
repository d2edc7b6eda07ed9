// How many points a mesh will have, before making it: the boundary's count plus the
// integral of 1 / (area per point) over the domain, area per point = (sqrt 3 / 2) rho^2 for
// equilateral triangles of side rho (two triangles a point). The integral runs over the
// constrained triangulation of the boundary, each triangle bisected across its longest edge
// while that edge is longer than twice rho at the centroid (bisection, unlike a split in four,
// does not refine the short direction of the long slivers such a triangulation has); it stops
// as soon as it passes the limit, so refusing a request that is far too large costs little.
// A gradation's samples of rho come from square cells at the local size instead (below): the
// bisection's leaves in the slivers are many to a size squared, each a source of the envelope.

#include <array>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <string>
#include <vector>

#include "pipeline/estimate.hpp"

#include "kernel/memory.hpp"
#include "kernel/predicates.hpp"

#include "meshd/core/errors.hpp"
#include "meshd/core/mesher.hpp"

namespace meshd::core {

namespace {

// rho at p; where it cannot be had (between a curve and its flattening), infinity: such a
// place gives no reason to split.
double rho_or_infinity(const SizeField& rho, Vec2 p) {
    try {
        return rho.interior(p);
    } catch (const GeometryError& e) {
        if (e.kind() != GeometryErrorKind::DensityInvalid) throw;
        return HUGE_VAL;
    }
}

// rho at the boundary's points, each evaluated once, when first asked.
class PointSizes {
public:
    PointSizes(const SizeField& rho, const Array<Vec2>& pts) : rho_(rho), pts_(pts), at_(pts.size(), -1.0) {}
    double operator()(std::uint32_t v) {
        if (at_[v] < 0.0) at_[v] = rho_or_infinity(rho_, pts_[v]);
        return at_[v];
    }

private:
    const SizeField& rho_;
    const Array<Vec2>& pts_;
    std::vector<double> at_;
};

// Visits samples (place, rho) of the domain at about the local size: the leaves of the
// bisection described above. f returns false to stop. Bisection keeps the smallest angle
// within half of the triangle's own, so a sliver's leaves stay slivers, each worth a small
// fraction of a point: the visits stop after max_visits, whatever the count then.
// A triangle is split while its longest edge is above twice rho at its centroid, or twice
// rho at both ends of one of its edges (the larger of the two). The boundary's triangles
// span the domain from wall to wall, and rho at the centroid alone missed any fine region
// narrower than they are: with sizes of 0.0005 in a strip 0.01 wide along one wall of a unit
// square and 0.2 beyond, no centroid fell in the strip, so the gradation grew the field from
// the wall's points alone, 11 times too large at the strip's edge (27.6 degrees with a
// gradation of 1.5), and the estimate counted a tenth of the points. With the edges, the
// slivers on the fine wall are split along their length, the half that keeps the wall's edge
// again and again, and the centroids of the other halves fall in the strip. (Both ends of an
// edge: with any one corner, every half that kept one of the wall's points was split again,
// 1.2 million samples for a mesh of 45,000 points instead of 260,000.) The sample itself is
// still rho at the centroid.
template <class F>
void for_each_sample(const BoundaryTriangulation& walls, const SizeField& rho, Observer* observer,
                     double max_visits, F&& f) {
    const Array<Vec2>& pts = walls.points;
    std::uint64_t visited = 0;
    auto at_corner = [&](Vec2 p) { return rho_or_infinity(rho, p); };
    PointSizes at_point(rho, pts);
    struct Tri {
        Vec2 a, b, c;
        double ra, rb, rc;
        int depth;
    };
    std::vector<Tri> stack;
    for (const Triangle& t : walls.triangles) {
        stack.push_back({pts[t.v[0]], pts[t.v[1]], pts[t.v[2]], at_point(t.v[0]), at_point(t.v[1]), at_point(t.v[2]), 0});
        while (!stack.empty()) {
            const Tri x = stack.back();
            stack.pop_back();
            const Vec2 g = (x.a + x.b + x.c) / 3.0;
            const double r = rho.interior(g);
            const double edge = std::fmin(std::fmax(x.ra, x.rb), std::fmin(std::fmax(x.rb, x.rc), std::fmax(x.rc, x.ra)));
            const double finest = std::fmin(r, edge);
            const double area = 0.5 * std::fabs(cross(x.b - x.a, x.c - x.a));
            const double longest = std::fmax(distance(x.a, x.b), std::fmax(distance(x.b, x.c), distance(x.c, x.a)));
            if ((++visited & 0xffff) == 0 && observer && observer->should_stop()) throw Cancelled();
            if (static_cast<double>(visited) > max_visits) return;
            if (longest > 2.0 * finest && x.depth < 100) {
                // Bisect across the longest edge: rotate so that it is a-b.
                Tri y = x;
                if (distance(x.b, x.c) == longest) y = {x.b, x.c, x.a, x.rb, x.rc, x.ra, x.depth};
                else if (distance(x.c, x.a) == longest) y = {x.c, x.a, x.b, x.rc, x.ra, x.rb, x.depth};
                const Vec2 m = 0.5 * (y.a + y.b);
                const double rm = at_corner(m);
                stack.push_back({y.a, m, y.c, y.ra, rm, y.rc, x.depth + 1});
                stack.push_back({m, y.b, y.c, rm, y.rb, y.rc, x.depth + 1});
                continue;
            }
            if (!f(g, r, area)) return;
        }
    }
}

// Visits samples (place, rho) of the domain on square cells of one lattice: the cells of
// side S / 2^l from the corner of the boundary's box (S a power of two at least its extent).
// Each triangle of the boundary's triangulation is covered by the cells that meet it, from the
// level whose cells are at least its extent down: such a cell is split in four while its side
// is above the finest of rho at its centre, rho at both ends of one of its sides (the larger of
// the two; a fine region along a wall reaches the corners on it), and rho at a corner of the
// triangle inside it. A leaf whose centre is in the triangle is its sample, of the cell's area.
// Unlike the bisection above, whose leaves in the slivers of such a triangulation are many to
// a size squared (2.8 million samples for the 145,000 points of a far field), there are one to
// four samples a size squared wherever the triangles lie. f returns false to stop; the visits
// (a cell for a triangle) stop after max_visits.
//
// The triangles share one walk of the lattice: a cell carries the triangles that still meet
// it, and rho at its centre and at the middles of its sides is evaluated once for all of
// them. Each triangle's leaves are those of a walk of its own (the split asks the same of the
// same lattice points); walked one triangle at a time, a cell that several slivers of a far
// field cross was evaluated for each (a NACA 0012 wake box: 6 evaluations of rho a lattice
// point, a quarter of the run).
template <class F>
void for_each_cell_sample(const BoundaryTriangulation& walls, const SizeField& rho, Observer* observer,
                          double max_visits, F&& f) {
    const Array<Vec2>& pts = walls.points;
    Box box;
    for (const Vec2& p : pts) box.add(p);
    if (box.empty()) return;
    const double extent = std::fmax(box.hi.x - box.lo.x, box.hi.y - box.lo.y);
    int exponent = 0;
    (void)std::frexp(extent, &exponent);  // extent < 2^exponent
    const double side = std::ldexp(1.0, exponent);
    if (!(extent > 0.0) || !std::isfinite(side)) return;
    const Vec2 origin = box.lo;
    // rho at a point of the boundary's box, sides included; beyond it, infinity. (Cells reach
    // past the box, and a field finer beyond the domain than in it split the cells along its
    // side down to that size: a square whose field was 10^-6 beyond one side took 340 ms to
    // sample instead of 1. Holes are inside the box: a field much finer inside a hole than
    // around it still splits the cells along its edge.)
    auto at = [&](Vec2 p) { return box.contains(p) ? rho_or_infinity(rho, p) : HUGE_VAL; };
    auto corner_of = [&](std::int64_t i, std::int64_t j, double cs) {
        return Vec2{origin.x + static_cast<double>(i) * cs, origin.y + static_cast<double>(j) * cs};
    };
    PointSizes at_point(rho, pts);
    struct Tri {
        Vec2 v[3];
        double rv[3];
        double side_length[3];
        Box tb;
        int level;  // the level whose cells are at least its extent: at most two a side meet it
    };
    std::vector<Tri> tris;
    tris.reserve(walls.triangles.size());
    for (const Triangle& t : walls.triangles) {
        Tri x{};
        for (size_t k = 0; k < 3; ++k) {
            x.v[k] = pts[t.v[k]];
            x.rv[k] = at_point(t.v[k]);
            x.tb.add(x.v[k]);
        }
        for (size_t k = 0; k < 3; ++k) x.side_length[k] = distance(x.v[k], x.v[(k + 1) % 3]);
        double s = side;
        const double te = std::fmax(x.tb.hi.x - x.tb.lo.x, x.tb.hi.y - x.tb.lo.y);
        while (x.level < 60 && 0.5 * s >= te) {
            s *= 0.5;
            ++x.level;
        }
        tris.push_back(x);
    }
    if (tris.empty()) return;
    // A cell, rho at its corners (in the order of `q` below), which its parent evaluated, and
    // its triangles: entries [begin, end) of `carried`. A cell's children share their
    // parent's list of the triangles split there; as the walk is depth first, the lists of a
    // cell's finished descendants are above its own when it is taken, and are dropped then.
    struct Cell {
        std::int64_t i, j;
        int level;
        double cs;  // its side: its parent's halved, exactly (no ldexp a cell)
        std::array<double, 4> rq;
        std::uint32_t begin, end;
    };
    std::vector<std::uint32_t> carried(tris.size());
    std::iota(carried.begin(), carried.end(), 0u);
    std::vector<Cell> stack;
    stack.push_back({0, 0, 0, side,
                     {at(corner_of(0, 0, side)), at(corner_of(1, 0, side)), at(corner_of(1, 1, side)),
                      at(corner_of(0, 1, side))},
                     0, static_cast<std::uint32_t>(tris.size())});
    std::uint64_t visited = 0;
    while (!stack.empty()) {
        const Cell c = stack.back();
        stack.pop_back();
        carried.resize(c.end);
        const double cs = c.cs, half = 0.5 * cs;
        const Vec2 lo = corner_of(c.i, c.j, cs), hi = corner_of(c.i + 1, c.j + 1, cs);
        const Vec2 q[4] = {lo, {hi.x, lo.y}, hi, {lo.x, hi.y}};
        const std::array<double, 4>& rq = c.rq;
        // The centre, as a child's corner would be placed; rho there once a triangle asks.
        const Vec2 m = corner_of(2 * c.i + 1, 2 * c.j + 1, half);
        double r = 0.0, shared = 0.0;
        bool evaluated = false;
        const auto split_from = static_cast<std::uint32_t>(carried.size());
        for (std::uint32_t k = c.begin; k < c.end; ++k) {
            const std::uint32_t ti = carried[k];
            const Tri& t = tris[ti];
            if (hi.x < t.tb.lo.x || lo.x > t.tb.hi.x || hi.y < t.tb.lo.y || lo.y > t.tb.hi.y) continue;
            if (c.level < t.level) {  // above the triangle's own level: on to its cells
                carried.push_back(ti);
                continue;
            }
            // Separated by a side of the (counter-clockwise) triangle: every corner beyond it.
            bool apart = false;
            for (int e = 0; e < 3 && !apart; ++e) {
                const Vec2 a = t.v[e], b = t.v[(e + 1) % 3];
                const double tol = 1e-12 * (t.side_length[e] + cs) * (t.side_length[e] + cs);
                apart = true;
                for (const Vec2& p : q) apart = apart && cross(b - a, p - a) < -tol;
            }
            if (apart) continue;
            if ((++visited & 0xffff) == 0 && observer && observer->should_stop()) throw Cancelled();
            if (static_cast<double>(visited) > max_visits) return;
            if (!evaluated) {
                r = at(m);
                shared = r;
                for (size_t e = 0; e < 4; ++e) shared = std::fmin(shared, std::fmax(rq[e], rq[(e + 1) % 4]));
                evaluated = true;
            }
            double finest = shared;
            for (int e = 0; e < 3; ++e)
                if (t.v[e].x >= lo.x && t.v[e].x <= hi.x && t.v[e].y >= lo.y && t.v[e].y <= hi.y)
                    finest = std::fmin(finest, t.rv[e]);
            if (cs > finest && c.level < 60) {
                carried.push_back(ti);
                continue;
            }
            if (!std::isfinite(r) || orient2d(t.v[0], t.v[1], m) == Orientation::Right ||
                orient2d(t.v[1], t.v[2], m) == Orientation::Right || orient2d(t.v[2], t.v[0], m) == Orientation::Right)
                continue;
            if (!f(m, r, cs * cs)) return;
        }
        const auto split_to = static_cast<std::uint32_t>(carried.size());
        if (split_to == split_from) continue;
        // The children's corners: the cell's own, the middles of its sides, its centre.
        if (!evaluated) r = at(m);
        const std::int64_t i = 2 * c.i, j = 2 * c.j;
        const double below = at(corner_of(i + 1, j, half)), right = at(corner_of(i + 2, j + 1, half));
        const double above = at(corner_of(i + 1, j + 2, half)), left = at(corner_of(i, j + 1, half));
        const int next = c.level + 1;
        stack.push_back({i, j, next, half, {rq[0], below, r, left}, split_from, split_to});
        stack.push_back({i + 1, j, next, half, {below, rq[1], right, r}, split_from, split_to});
        stack.push_back({i + 1, j + 1, next, half, {r, right, rq[2], above}, split_from, split_to});
        stack.push_back({i, j + 1, next, half, {left, r, above, rq[3]}, split_from, split_to});
    }
}

// Samples a count up to `limit` may take: a few per point on the triangulations of boundaries
// with fair angles.
double max_visits(double limit) { return 16.0 * limit + 65536.0; }

}  // namespace

double estimate_point_count(const Discretisation& d, const BoundaryTriangulation& walls, const SizeField& rho,
                            double limit, Observer* observer) {
    double total = static_cast<double>(d.size());
    for_each_sample(walls, rho, observer, max_visits(limit), [&](Vec2, double r, double area) {
        total += kPointsPerArea * area / (r * r);
        return total <= limit;
    });
    return total;
}

void refuse_too_many(double estimate, size_t limit) {
    // Whole numbers up to 10^15; beyond, and for an overflow to infinity, a power of ten.
    std::string about;
    if (estimate < 1e15) {
        about = "about " + std::to_string(static_cast<long long>(estimate));
    } else {
        const double e = std::isfinite(estimate) ? std::floor(std::log10(estimate)) : 308.0;
        about = "more than 10^" + std::to_string(static_cast<int>(e));
    }
    throw GeometryError(GeometryErrorKind::TooManyPoints,
                        "the mesh would have " + about + " points, above the limit of " + std::to_string(limit));
}

namespace {
// The observer hears of the sources from this many on (then at each doubling, and once at the
// end): fewer are within what the forecast's peak allows for.
constexpr size_t kFirstSourcesReport = size_t{1} << 16;
}  // namespace

size_t set_gradation_sources(SizeField& rho, const Discretisation& d, const BoundaryTriangulation& walls,
                             size_t max_points, Observer* observer, double forecast_points) {
    // The boundary points with their curve densities, then the interior at its own size. The
    // samples are as many as the mesh would have points, about: the estimate runs along, and
    // a field that would exceed the limit is refused before the sampling does.
    // On pages of 2 MiB: a far field's samples run to hundreds of thousands (323,000 on the
    // NACA 0006 case), and growing them on 4 KiB pages was much of that run in page faults.
    Array<Vec2> pts(walls.points.begin(), walls.points.end());
    Array<double> sizes(d.rho.begin(), d.rho.end());
    double total = static_cast<double>(d.size());
    const double limit = static_cast<double>(max_points);
    // The samples run to a few a mesh point (323,000, 31 MB as counted here, for the 145,000
    // points of the NACA 0006 far field with a gradation, whose forecast peak is 71 MB; the
    // bisection's leaves were 2.8 million): a budget that reserved the forecast's peak hears
    // of them.
    size_t report_at = kFirstSourcesReport;
    auto report = [&] {
        if (observer)
            observer->on_forecast(forecast_points, peak_bytes_for(forecast_points) + kGradationBytesPerSource * pts.size());
    };
    for_each_cell_sample(walls, rho, observer, max_visits(limit), [&](Vec2 g, double r, double area) {
        pts.push_back(g);
        sizes.push_back(r);
        if (pts.size() >= report_at) {
            report_at *= 2;
            report();
        }
        total += kPointsPerArea * area / (r * r);
        return total <= limit;
    });
    if (total > limit) refuse_too_many(total, max_points);
    if (pts.size() >= kFirstSourcesReport) report();
    rho.set_gradation_sources(pts, sizes);
    return kGradationBytesPerSource * pts.size();
}

}  // namespace meshd::core
