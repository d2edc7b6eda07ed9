// The pipeline of mesher.hpp.

#include "meshd/core/mesher.hpp"

#include <chrono>

#include "meshd/core/errors.hpp"
#include "meshd/core/predicates.hpp"
#include "cdt.hpp"
#include "spatial_order.hpp"

namespace meshd::core {

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

}  // namespace

MeshResult generate_mesh(const Domain& domain, SizeField& rho, const MeshOptions& options, Observer* observer) {
    MeshResult r;
    reset_predicate_counters();
    const auto t_start = Clock::now();

    // Boundary.
    auto t0 = Clock::now();
    BoundaryOptions bopt;
    bopt.spline_spacing = options.spline_spacing;
    bopt.max_points = options.max_points;
    Discretisation d = discretise_boundary(domain, rho, bopt, observer);
    if (rho.interpolates()) set_interpolation_sources(rho, d);
    if (rho.gradation()) {
        // Limit the growth of the field sampled from the first boundary, then place the
        // boundary points again along the limited field (and interpolate from those).
        set_gradation_sources(rho, d, observer);
        d = discretise_boundary(domain, rho, bopt, observer);
        if (rho.interpolates()) set_interpolation_sources(rho, d);
    }
    if (options.max_points) {
        // Refuse before the interior work when the mesh would clearly be too large.
        const double limit = static_cast<double>(options.max_points);
        const double estimate = estimate_point_count(d, rho, limit, observer);
        if (estimate > limit)
            throw GeometryError(GeometryErrorKind::TooManyPoints,
                                "the mesh would have about " + std::to_string(static_cast<long long>(estimate)) +
                                    " points or more, above the limit of " + std::to_string(options.max_points));
    }
    r.timings.boundary_ms = ms_since(t0);

    // Interior.
    t0 = Clock::now();
    InteriorOptions iopt = options.interior;
    iopt.max_points = options.max_points;
    std::vector<Vec2> inner = generate_interior_points(domain, d, rho, iopt, observer, &r.stats.interior);
    {
        // Along a Hilbert curve: neighbours in the mesh become neighbours in memory, which
        // the triangle order (triangulation.hpp) and every later sweep profit from.
        const std::vector<std::uint32_t> order = detail::hilbert_order(inner);
        std::vector<Vec2> sorted(inner.size());
        for (size_t i = 0; i < order.size(); ++i) sorted[i] = inner[order[i]];
        inner = std::move(sorted);
    }
    r.timings.interior_ms = ms_since(t0);

    // Triangulation.
    t0 = Clock::now();
    std::vector<Vec2> pts = points_of(d);
    pts.insert(pts.end(), inner.begin(), inner.end());
    const std::vector<Constraint> cons = constraints_of(d);
    TriangulationResult tr = options.triangulator == Triangulator::Delaunay
                                 ? triangulate_delaunay(pts, cons, observer)
                                 : triangulate_advancing_front(pts, cons, observer);
    for (size_t i = 0; i < tr.alias.size(); ++i)
        MESHD_INTERNAL_CHECK(tr.alias[i] == i, "two mesh points coincide");
    r.stats.triangulation = tr.stats;

    Mesh& m = r.mesh;
    m.x.reserve(pts.size());
    m.y.reserve(pts.size());
    for (const Vec2& p : pts) {
        m.x.push_back(p.x);
        m.y.push_back(p.y);
    }
    m.kind.assign(pts.size(), PointKind::Interior);
    std::vector<bool> embedded_curve(domain.curves().size(), false);
    for (CurveId c : domain.embedded()) embedded_curve[c] = true;
    for (VertexId v = 0; v < d.size(); ++v) {
        if (d.curve[v] == kNoCurve) m.kind[v] = PointKind::Corner;
        else m.kind[v] = embedded_curve[d.curve[v]] ? PointKind::Embedded : PointKind::Boundary;
    }
    m.triangles = std::move(tr.triangles);
    detail::order_by_largest_corner(m.triangles, m.point_count());
    for (size_t i = 0; i < d.segments.size(); ++i) {
        const auto& s = d.segments[i];
        m.edges.push_back({s.a, s.b, domain.curves()[s.curve].tag, i >= d.loop_segment_count});
    }
    m.tags = domain.tags();
    m.holes = domain.hole_count();
    r.timings.triangulation_ms = ms_since(t0);

    // Smoothing.
    t0 = Clock::now();
    if (options.smoothing_iterations > 0)
        r.stats.smoothing_moves = smooth(m, options.smoothing_iterations, &r.stats.smoothing_flips, observer);
    if (options.min_angle_deg > 0.0)
        r.stats.refinement_points = refine_min_angle(m, rho, options.min_angle_deg, options.max_points, observer);
    r.timings.smoothing_ms = ms_since(t0);

    if (observer) observer->on_progress(Stage::Quality, 0.0);
    r.quality = measure_quality(m, rho);
    m.target_size.resize(m.point_count());
    for (std::uint32_t v = 0; v < m.point_count(); ++v) m.target_size[v] = rho.interior(m.point(v));
    r.timings.total_ms = ms_since(t_start);
    const PredicateCounters pc = predicate_counters();
    r.stats.orient_exact = pc.orient_exact;
    r.stats.incircle_exact = pc.incircle_exact;
    return r;
}

}  // namespace meshd::core
