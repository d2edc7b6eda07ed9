// The pipeline of mesher.hpp: boundary, interior, triangulation, improvement, figures.

#include "meshd/core/mesher.hpp"

#include <chrono>

#include "boundary/boundary.hpp"
#include "density/size_field.hpp"
#include "improve/quality.hpp"
#include "pipeline/second_order.hpp"
#include "improve/refine.hpp"
#include "improve/smooth.hpp"
#include "interior/interior.hpp"
#include "kernel/predicates.hpp"
#include "kernel/spatial_order.hpp"
#include "meshd/core/errors.hpp"
#include "pipeline/estimate.hpp"
#include "triangulation/triangle_soup.hpp"
#include "triangulation/triangulation.hpp"

namespace meshd::core {

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// The mesh's points, triangles and edges from the triangulation of the boundary and
// interior points (boundary points first, in the discretisation's order).
void assemble(Mesh& m, const Domain& domain, const Discretisation& d, const std::vector<Vec2>& inner,
              std::vector<Triangle> triangles) {
    const size_t n = d.size() + inner.size();
    m.x.reserve(n);
    m.y.reserve(n);
    m.x.assign(d.x.begin(), d.x.end());
    m.y.assign(d.y.begin(), d.y.end());
    for (const Vec2& p : inner) {
        m.x.push_back(p.x);
        m.y.push_back(p.y);
    }
    m.kind.assign(n, PointKind::Interior);
    m.curve.assign(n, kNoCurve);
    m.param.assign(n, 0.0);
    std::vector<bool> embedded_curve(domain.curves().size(), false);
    for (CurveId c : domain.embedded()) embedded_curve[c] = true;
    for (VertexId v = 0; v < d.size(); ++v) {
        m.curve[v] = d.curve[v];
        m.param[v] = d.param[v];
        if (d.curve[v] == kNoCurve) m.kind[v] = PointKind::Corner;
        else m.kind[v] = embedded_curve[d.curve[v]] ? PointKind::Embedded : PointKind::Boundary;
    }
    m.triangles = std::move(triangles);
    detail::order_by_largest_corner(m.triangles, m.point_count());
    m.edges.reserve(d.segments.size());
    for (size_t i = 0; i < d.segments.size(); ++i) {
        const BoundarySegment& s = d.segments[i];
        m.edges.push_back({s.a, s.b, domain.curves()[s.curve].tag, s.curve, i >= d.loop_segment_count});
    }
    m.tags = domain.tags();
    m.holes = domain.hole_count();
    m.curve_ends.assign(domain.curves().size(), {kNoVertex, kNoVertex});
    for (CurveId c = 0; c < domain.curves().size(); ++c)
        if (!d.curve_vertices[c].empty()) m.curve_ends[c] = {d.curve_vertices[c].front(), d.curve_vertices[c].back()};
    m.loops.clear();
    for (const DomainLoop& l : domain.loops()) {
        std::vector<Mesh::LoopCurve> curves;
        for (const CurveUse& u : l.items) curves.push_back({u.curve, u.reversed});
        m.loops.push_back(std::move(curves));
    }
}

}  // namespace

MeshResult generate_mesh(const Domain& domain, const DensitySpec& density, const MeshOptions& asked,
                         Observer* observer) {
    MeshOptions options = asked;
    if (options.max_points == 0 || options.max_points > kMaxPointsLimit) options.max_points = kMaxPointsLimit;
    MeshResult r;
    reset_predicate_counters();
    const auto t_start = Clock::now();

    // Admission: a mesh forecast above the limit is refused before any work that grows with it.
    auto t0 = Clock::now();
    {
        const PointForecast forecast = forecast_points(domain, density, {}, observer);
        r.stats.forecast_points = forecast.total();
        if (forecast.total() > static_cast<double>(options.max_points))
            refuse_too_many(forecast.total(), options.max_points);
        if (observer) observer->on_forecast(forecast.total(), peak_bytes_for(forecast.total()));
    }

    // Boundary.
    SizeField rho(density, domain);
    BoundaryOptions bopt;
    bopt.spline_spacing = options.spline_spacing;
    bopt.max_points = options.max_points;
    Discretisation d = discretise_boundary(domain, rho, bopt, observer);
    if (rho.interpolates()) set_interpolation_sources(rho, d);
    BoundaryTriangulation walls = triangulate_boundary(d);
    if (rho.gradation()) {
        // Limit the growth of the field sampled from the first boundary, then place the
        // boundary points again along the limited field (and interpolate from those).
        set_gradation_sources(rho, d, walls, options.max_points, observer);
        d = discretise_boundary(domain, rho, bopt, observer);
        if (rho.interpolates()) set_interpolation_sources(rho, d);
        walls = triangulate_boundary(d);
    }
    if (asked.max_points) {
        // Refuse before the interior work when the mesh would clearly be too large.
        const double limit = static_cast<double>(options.max_points);
        const double estimate = estimate_point_count(d, walls, rho, limit, observer);
        if (estimate > limit) refuse_too_many(estimate, options.max_points);
    }
    r.timings.boundary_ms = ms_since(t0);

    // Each stage is announced as it begins, so that progress (and a stop) is seen in the
    // right stage.
    auto begin = [&](Stage stage) {
        if (observer) observer->on_progress(stage, 0.0);
    };

    // Interior.
    begin(Stage::Interior);
    t0 = Clock::now();
    std::vector<Vec2> inner = generate_interior_points(domain, d, walls, rho, options.interior, options.max_points,
                                                       observer, &r.stats.interior);
    {
        // Along a Hilbert curve: neighbours in the mesh become neighbours in memory, which
        // the triangle order (order_by_largest_corner) and every later sweep profit from.
        const std::vector<std::uint32_t> order = detail::hilbert_order(inner);
        std::vector<Vec2> sorted(inner.size());
        for (size_t i = 0; i < order.size(); ++i) sorted[i] = inner[order[i]];
        inner = std::move(sorted);
    }
    r.timings.interior_ms = ms_since(t0);

    // Triangulation.
    begin(Stage::Triangulation);
    t0 = Clock::now();
    std::vector<Vec2> pts = std::move(walls.points);
    pts.insert(pts.end(), inner.begin(), inner.end());
    const std::vector<Constraint> cons = constraints_of(d);
    TriangulationResult tr = options.triangulator == Triangulator::Delaunay
                                 ? triangulate_delaunay(pts, cons, observer)
                                 : triangulate_advancing_front(pts, cons, observer);
    for (size_t i = 0; i < tr.alias.size(); ++i)
        MESHD_INTERNAL_CHECK(tr.alias[i] == i, "two mesh points coincide");
    r.stats.triangulation = tr.stats;
    Mesh& m = r.mesh;
    assemble(m, domain, d, inner, std::move(tr.triangles));
    r.timings.triangulation_ms = ms_since(t0);

    // Improvement.
    begin(Stage::Smoothing);
    t0 = Clock::now();
    if (options.smoothing_iterations > 0)
        r.stats.smoothing_moves = smooth(m, options.smoothing_iterations, &r.stats.smoothing_flips, observer);
    if (options.min_angle_deg > 0.0)
        r.stats.refinement_points =
            refine_min_angle(m, domain, rho, options.min_angle_deg, options.max_points, observer);
    r.timings.smoothing_ms = ms_since(t0);

    EdgeNodeCounts edge_nodes;
    if (options.order == 2) edge_nodes = add_edge_nodes(m, domain);

    begin(Stage::Quality);
    r.quality = measure_quality(m, rho);
    r.quality.curved_edges = edge_nodes.curved;
    r.quality.straightened_edges = edge_nodes.straightened;
    if (m.order() == 2)
        for (TriangleId t = 0; t < m.triangles.size(); ++t)
            r.quality.scaled_jacobian_min = std::min(r.quality.scaled_jacobian_min, min_scaled_jacobian(m, t));
    m.target_size.resize(m.point_count());
    for (VertexId v = 0; v < m.point_count(); ++v) m.target_size[v] = rho.interior(m.point(v));
    r.timings.total_ms = ms_since(t_start);
    const PredicateCounters pc = predicate_counters();
    r.stats.orient_exact = pc.orient_exact;
    r.stats.incircle_exact = pc.incircle_exact;
    return r;
}

MeshResult generate_mesh(const DomainSpec& geometry, const DensitySpec& density, const MeshOptions& options,
                         Observer* observer) {
    return generate_mesh(build_domain(geometry, observer), density, options, observer);
}

}  // namespace meshd::core
