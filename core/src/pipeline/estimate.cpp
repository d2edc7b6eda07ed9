// How many points a mesh will have, before making it: the boundary's count plus the
// integral of 1 / (area per point) over the domain, area per point = (sqrt 3 / 2) rho^2 for
// equilateral triangles of side rho (two triangles a point). The integral runs over the
// constrained triangulation of the boundary, each triangle bisected across its longest edge
// while that edge is longer than twice rho at the centroid (bisection, unlike a split in four,
// does not refine the short direction of the long slivers such a triangulation has); it stops
// as soon as it passes the limit, so refusing a request that is far too large costs little.

#include <cmath>
#include <string>
#include <vector>

#include "pipeline/estimate.hpp"

#include "kernel/memory.hpp"

#include "meshd/core/errors.hpp"
#include "meshd/core/mesher.hpp"

namespace meshd::core {

namespace {

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
    // rho at a corner; where it cannot be had (between a curve and its flattening), the
    // corner gives no reason to split.
    auto at_corner = [&](Vec2 p) {
        try {
            return rho.interior(p);
        } catch (const GeometryError& e) {
            if (e.kind() != GeometryErrorKind::DensityInvalid) throw;
            return HUGE_VAL;
        }
    };
    std::vector<double> corner(pts.size(), -1.0);  // rho at the boundary's points, once each
    auto at_point = [&](std::uint32_t v) {
        if (corner[v] < 0.0) corner[v] = at_corner(pts[v]);
        return corner[v];
    };
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
// The memory a gradation source takes while the sources are gathered and the field's tree is
// built (the gathered arrays, grown by doubling, beside the field's copy and its nodes): an
// upper bound of what it keeps.
constexpr size_t kGradationBytesPerSource = 96;
// The observer hears of the sources from this many on (then at each doubling, and once at the
// end): fewer are within what the forecast's peak allows for.
constexpr size_t kFirstSourcesReport = size_t{1} << 16;
}  // namespace

size_t set_gradation_sources(SizeField& rho, const Discretisation& d, const BoundaryTriangulation& walls,
                             size_t max_points, Observer* observer, double forecast_points) {
    // The boundary points with their curve densities, then the interior at its own size. The
    // samples are as many as the mesh would have points, about: the estimate runs along, and
    // a field that would exceed the limit is refused before the sampling does.
    // On pages of 2 MiB: a far field's samples run to millions (2.8 million on the NACA 0006
    // case), and growing them on 4 KiB pages was 12% of that run, much of it page faults.
    Array<Vec2> pts(walls.points.begin(), walls.points.end());
    Array<double> sizes(d.rho.begin(), d.rho.end());
    double total = static_cast<double>(d.size());
    const double limit = static_cast<double>(max_points);
    // The samples run to 20 a mesh point where the boundary's triangulation has slivers (2.8
    // million, 200 MB, for the 145,000 points of the NACA 0006 case with a gradation, whose
    // forecast peak is 68 MB): a budget that reserved the forecast's peak hears of them.
    size_t report_at = kFirstSourcesReport;
    auto report = [&] {
        if (observer)
            observer->on_forecast(forecast_points, peak_bytes_for(forecast_points) + kGradationBytesPerSource * pts.size());
    };
    for_each_sample(walls, rho, observer, max_visits(limit), [&](Vec2 g, double r, double area) {
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
