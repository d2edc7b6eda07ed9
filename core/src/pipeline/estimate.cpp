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

#include "meshd/core/errors.hpp"

namespace meshd::core {

namespace {

// Visits samples (place, rho) of the domain at about the local size: the leaves of the
// bisection described above. f returns false to stop. Bisection keeps the smallest angle
// within half of the triangle's own, so a sliver's leaves stay slivers, each worth a small
// fraction of a point: the visits stop after max_visits, whatever the count then.
template <class F>
void for_each_sample(const BoundaryTriangulation& walls, const SizeField& rho, Observer* observer,
                     double max_visits, F&& f) {
    const std::vector<Vec2>& pts = walls.points;
    std::uint64_t visited = 0;
    struct Tri { Vec2 a, b, c; int depth; };
    std::vector<Tri> stack;
    for (const Triangle& t : walls.triangles) {
        stack.push_back({pts[t.v[0]], pts[t.v[1]], pts[t.v[2]], 0});
        while (!stack.empty()) {
            const Tri x = stack.back();
            stack.pop_back();
            const Vec2 g = (x.a + x.b + x.c) / 3.0;
            const double r = rho.interior(g);
            const double area = 0.5 * std::fabs(cross(x.b - x.a, x.c - x.a));
            const double longest = std::fmax(distance(x.a, x.b), std::fmax(distance(x.b, x.c), distance(x.c, x.a)));
            if ((++visited & 0xffff) == 0 && observer && observer->should_stop()) throw Cancelled();
            if (static_cast<double>(visited) > max_visits) return;
            if (longest > 2.0 * r && x.depth < 100) {
                // Bisect across the longest edge: rotate so that it is a-b.
                Vec2 a = x.a, b = x.b, c = x.c;
                if (distance(x.b, x.c) == longest) { a = x.b; b = x.c; c = x.a; }
                else if (distance(x.c, x.a) == longest) { a = x.c; b = x.a; c = x.b; }
                const Vec2 m = 0.5 * (a + b);
                stack.push_back({a, m, c, x.depth + 1});
                stack.push_back({m, b, c, x.depth + 1});
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

void set_gradation_sources(SizeField& rho, const Discretisation& d, const BoundaryTriangulation& walls,
                           size_t max_points, Observer* observer) {
    // The boundary points with their curve densities, then the interior at its own size. The
    // samples are as many as the mesh would have points, about: the estimate runs along, and
    // a field that would exceed the limit is refused before the sampling does.
    std::vector<Vec2> pts = walls.points;
    std::vector<double> sizes = d.rho;
    double total = static_cast<double>(d.size());
    const double limit = static_cast<double>(max_points);
    for_each_sample(walls, rho, observer, max_visits(limit), [&](Vec2 g, double r, double area) {
        pts.push_back(g);
        sizes.push_back(r);
        total += kPointsPerArea * area / (r * r);
        return total <= limit;
    });
    if (total > limit) refuse_too_many(total, max_points);
    rho.set_gradation_sources(std::move(pts), std::move(sizes));
}

}  // namespace meshd::core
