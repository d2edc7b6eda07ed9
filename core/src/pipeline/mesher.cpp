// The pipeline of mesher.hpp: boundary, interior, triangulation, improvement, figures.

#include "meshd/core/mesher.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <optional>
#include <span>
#include <unordered_map>

#include "boundary/boundary.hpp"
#include "density/size_field.hpp"
#include "improve/quality.hpp"
#include "pipeline/second_order.hpp"
#include "improve/refine.hpp"
#include "improve/smooth.hpp"
#include "interior/interior.hpp"
#include "layers/layers.hpp"
#include "kernel/memory.hpp"
#include "kernel/predicates.hpp"
#include "kernel/spatial_order.hpp"
#include "meshd/core/errors.hpp"
#include "pipeline/agreement.hpp"
#include "pipeline/estimate.hpp"
#include "triangulation/triangle_soup.hpp"
#include "triangulation/triangulation.hpp"

namespace meshd::core {

namespace {

#if defined(MESHD_X86_LEVEL) && defined(__x86_64__) && !defined(__clang__)
// A build for an x86-64 level (CMakeLists.txt, MESHD_ARCH) on a processor without it would
// stop with SIGILL at the first instruction of that level, wherever that is. This runs before
// the program's own initialisers (priority 101; the shared libraries' run earlier and are
// built for the baseline) and is itself compiled for the baseline, so such a processor gets a
// sentence and exit status 70 instead. (GCC's builtin knows the levels by name; Clang 16's
// does not, and the Clang builds, the fuzzers, run where they are built.)
__attribute__((constructor(101), target("arch=x86-64"))) void refuse_a_processor_below_the_build() {
    __builtin_cpu_init();
    if (__builtin_cpu_supports(MESHD_X86_LEVEL)) return;
    std::fputs("meshd: this program was built for " MESHD_X86_LEVEL
               " processors and this processor is older; build it with -DMESHD_ARCH=x86-64\n",
               stderr);
    std::_Exit(70);
}
#endif

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// The mesh's points, triangles and edges from the triangulation of the boundary and
// interior points (boundary points first, in the discretisation's order). `d` holds the
// points (with boundary layers: the layers' outer edge after the original's points), `edges`
// the boundary's own segments and curves.
void assemble(Mesh& m, const Domain& domain, const Discretisation& d, const Discretisation& edges,
              std::span<const Vec2> inner, Array<Triangle> triangles) {
    const size_t n = d.size() + inner.size();
    detail::reserve_filled(m.x, n);
    detail::reserve_filled(m.y, n);
    m.x.assign(d.x.begin(), d.x.end());
    m.y.assign(d.y.begin(), d.y.end());
    for (const Vec2& p : inner) {
        m.x.push_back(p.x);
        m.y.push_back(p.y);
    }
    detail::assign_huge(m.kind, n, PointKind::Interior);
    detail::assign_huge(m.curve, n, kNoCurve);
    detail::assign_huge(m.param, n, 0.0);
    std::vector<bool> embedded_curve(domain.curves().size(), false);
    for (CurveId c : domain.embedded()) embedded_curve[c] = true;
    for (VertexId v = 0; v < d.size(); ++v) {
        m.curve[v] = d.curve[v];
        m.param[v] = d.param[v];
        if (v >= edges.size()) m.kind[v] = PointKind::Layer;
        else if (d.curve[v] == kNoCurve) m.kind[v] = PointKind::Corner;
        else m.kind[v] = embedded_curve[d.curve[v]] ? PointKind::Embedded : PointKind::Boundary;
    }
    m.triangles = std::move(triangles);
    detail::order_by_largest_corner(m.triangles, m.point_count());
    m.edges.reserve(edges.segments.size());
    for (size_t i = 0; i < edges.segments.size(); ++i) {
        const BoundarySegment& s = edges.segments[i];
        m.edges.push_back({s.a, s.b, domain.curves()[s.curve].tag, s.curve, i >= edges.loop_segment_count});
    }
    m.tags = domain.tags();
    m.holes = domain.hole_count();
    m.curve_ends.assign(domain.curves().size(), {kNoVertex, kNoVertex});
    for (CurveId c = 0; c < domain.curves().size(); ++c)
        if (!edges.curve_vertices[c].empty())
            m.curve_ends[c] = {edges.curve_vertices[c].front(), edges.curve_vertices[c].back()};
    m.loops.clear();
    for (const DomainLoop& l : domain.loops()) {
        std::vector<Mesh::LoopCurve> curves;
        for (const CurveUse& u : l.items) curves.push_back({u.curve, u.reversed});
        m.loops.push_back(std::move(curves));
    }
}

// The boundary layers' cells joined to the mesh: their hidden points after the mesh's,
// their triangles after the others (marked `layer`, with neighbours both ways), their quads.
void add_layers(Mesh& m, const GrownLayers& g) {
    const VertexId hidden0 = static_cast<VertexId>(m.point_count());
    for (const Vec2& p : g.hidden) {
        m.x.push_back(p.x);
        m.y.push_back(p.y);
        m.kind.push_back(PointKind::Layer);
        m.curve.push_back(kNoCurve);
        m.param.push_back(0.0);
    }
    auto id = [&](std::uint32_t v) { return v & GrownLayers::kHidden ? hidden0 + (v & ~GrownLayers::kHidden) : v; };
    for (const auto& q : g.quads) m.quads.push_back({id(q[0]), id(q[1]), id(q[2]), id(q[3])});
    const TriangleId first = static_cast<TriangleId>(m.triangles.size());
    for (const auto& t : g.triangles) {
        Triangle T{{id(t[0]), id(t[1]), id(t[2])}, {kNoTriangle, kNoTriangle, kNoTriangle}};
        T.layer = 1;
        m.triangles.push_back(T);
    }
    // Neighbours: the open half-edges of every triangle, matched with their opposites.
    std::unordered_map<std::uint64_t, std::pair<TriangleId, std::uint32_t>> open;
    using detail::directed_key;
    for (TriangleId t = 0; t < m.triangles.size(); ++t)
        for (std::uint32_t i = 0; i < 3; ++i)
            if (m.triangles[t].n[i] == kNoTriangle)
                open.emplace(directed_key(m.triangles[t].v[(i + 1) % 3], m.triangles[t].v[(i + 2) % 3]), std::pair{t, i});
    for (TriangleId t = first; t < m.triangles.size(); ++t) {
        for (std::uint32_t i = 0; i < 3; ++i) {
            Triangle& T = m.triangles[t];
            auto it = open.find(directed_key(T.v[(i + 2) % 3], T.v[(i + 1) % 3]));
            if (it == open.end()) continue;
            const auto [u, j] = it->second;
            T.n[i] = u;
            m.triangles[u].n[j] = t;
            // The layers' outer edge is no loop edge of the mesh.
            m.triangles[u].boundary = static_cast<std::uint8_t>(m.triangles[u].boundary & ~(1u << j));
        }
    }
    // Layer triangles on a wall: loop edges.
    std::unordered_map<std::uint64_t, bool> walls;
    for (const MeshEdge& e : m.edges) walls.emplace(directed_key(e.a, e.b), e.embedded);
    for (TriangleId t = first; t < m.triangles.size(); ++t) {
        Triangle& T = m.triangles[t];
        for (std::uint32_t i = 0; i < 3; ++i) {
            auto it = walls.find(directed_key(T.v[(i + 1) % 3], T.v[(i + 2) % 3]));
            if (it == walls.end()) continue;
            T.constrained = static_cast<std::uint8_t>(T.constrained | (1u << i));
            if (!it->second) T.boundary = static_cast<std::uint8_t>(T.boundary | (1u << i));
        }
    }
}

/// Rounds of growing the layers again, lower beside sharp triangles, at most.
constexpr int kLayerRounds = 3;
/// The tangent of the angle below which a triangle beside the layers lowers the columns at
/// its corners, and one of fixed points alone places the curves again (cap_closing_
/// triangles): 30 degrees, the smallest angle issue 15 asks of every domain.
constexpr double kSharpTan = std::numbers::inv_sqrt3;
constexpr double kSharpAngleDeg = 30.0;  // the same angle, for refine_min_angle

// Whether triangle t has a corner sharper than kSharpTan, but for a corner between two
// constrained edges (the domain's own, the layers' outer edge where it bends). Without an
// arc tangent: it runs over every triangle of a mesh with layers.
bool sharp(const Mesh& m, const Triangle& t) {
    for (std::uint32_t i = 0; i < 3; ++i) {
        if ((t.constrained >> ((i + 1) % 3) & 1u) && (t.constrained >> ((i + 2) % 3) & 1u)) continue;
        const Vec2 a = m.point(t.v[i]), u = m.point(t.v[(i + 1) % 3]) - a, w = m.point(t.v[(i + 2) % 3]) - a;
        const double along = dot(u, w);
        if (along > 0.0 && std::fabs(cross(u, w)) < kSharpTan * along) return true;
    }
    return false;
}

// Whether any triangle is sharp(). A triangle's smallest angle, at the corner between its two
// longer sides b and c, is below 30 degrees when its sine, |cross| / (b c), is below 1/2: when
// 4 cross^2 a^2 < a^2 b^2 c^2 (a the shortest side, squares throughout), with no division,
// square root or branch; a slack of 1e-9 keeps the borderline ones, and sharp() decides for
// the few this passes (half the time of sharp() over every triangle: 12 us for the load
// run's 4,813 triangles).
bool any_sharp(const Mesh& m) {
    for (const Triangle& t : m.triangles) {
        const double ax = m.x[t.v[0]], ay = m.y[t.v[0]], bx = m.x[t.v[1]], by = m.y[t.v[1]];
        const double cx = m.x[t.v[2]], cy = m.y[t.v[2]];
        const double ux = bx - ax, uy = by - ay, wx = cx - ax, wy = cy - ay, vx = cx - bx, vy = cy - by;
        const double lu = ux * ux + uy * uy, lw = wx * wx + wy * wy, lv = vx * vx + vy * vy;
        const double area2 = ux * wy - uy * wx;
        const double shortest = fmin_inline(lu, fmin_inline(lw, lv));
        if (4.0 * area2 * area2 * shortest < (1.0 + 1e-9) * (lu * lw * lv) && sharp(m, t)) return true;
    }
    return false;
}

// The columns of the layers with a point at a corner of a sharp triangle (sharp()) (the
// highest of those points, where there are several) are held, in
// `limits`, to a third fewer layers than that point's level, one at least: a narrow gap
// between two walls' layers widened, a steep fall of the outer edge from a tall column to a
// short one flattened (lowering the short one would steepen it). True when any was.
bool lower_columns_at_sharp_triangles(const Mesh& m, const GrownLayers& g, std::vector<LayerColumn>& limits) {
    const auto column_at = [&](VertexId v) -> const LayerColumn* {
        return v < g.column_of.size() && g.column_of[v] >= 0 ? &g.columns[static_cast<size_t>(g.column_of[v])] : nullptr;
    };
    const size_t before = limits.size();
    for (const Triangle& t : m.triangles) {
        int highest = 0;
        for (const VertexId v : t.v)
            if (const LayerColumn* col = column_at(v)) highest = std::max(highest, col->levels);
        if (highest == 0 || !sharp(m, t)) continue;
        for (const VertexId v : t.v) {
            const LayerColumn* col = column_at(v);
            if (!col || col->levels < highest) continue;
            limits.push_back({col->base, col->dir, col->levels - std::max(1, col->levels / 3)});
        }
    }
    return limits.size() > before;
}

/// Rounds of placing the curves again for triangles of fixed points alone, at most.
constexpr int kClosingRounds = 2;
// Jumps of the size field (kFieldJump) the interior stage meets before the mesh is made again
// with MeshOptions::jump_gradation (and one more per 1,024 candidates): no example and none of
// 5,741 random domains meets more than 2 (layer tops beside a coarser field); a size that
// changes tenfold across a line meets about 80, a fine strip along a wall thousands.
constexpr std::uint64_t kJumpsToGrade = 16;
/// A closing round is made only for a mesh below this share of max_points.
constexpr double kClosingRoom = 0.8;

// Triangles made of fixed points alone (curve points and the layers' outer edge, no interior
// point) with a corner sharper than 30 degrees (sharp()): a gap between two curves too small
// for the interior to put a point in, closed by the curves' points alone (a square hole's side
// and a triangular hole's corner across a gap 1.4 times the field: 23.6 degrees; two holes'
// bare walls and a layer top between them: 28.7). No placement of interior points mends them,
// and the smoothing cannot move their corners. The same with one interior corner, which the
// smoothing's repair moved as far as it could: a gap the interior put a single point in (a
// triangular hole's corner and a small octagonal hole: 28.5). The curves at their corners are
// capped at the shortest side over kAgreementRatio, added to `closing`: placed again finer
// there, the curves make the interior finer beside them (the agreement's interior cap) and
// the gap is meshed with points of its own. The mesh itself is the test of whether the
// interior could open the gap, which the walls alone cannot tell. Only a smoothed mesh is
// looked at, as for the layers' rounds: without the smoothing's flips many more triangles
// of fixed points stay sharp, and a mesh asked for unsmoothed is the paper's placement as it
// comes. True when any was found.
bool cap_closing_triangles(const Mesh& m, SizeCaps& closing) {
    const size_t before = closing.points.size();
    const auto fixed = [&](VertexId v) { return m.kind[v] != PointKind::Interior; };
    for (const Triangle& t : m.triangles) {
        const int fixed_corners = int{fixed(t.v[0])} + int{fixed(t.v[1])} + int{fixed(t.v[2])};
        if (fixed_corners < 2 || !sharp(m, t)) continue;
        const Vec2 a = m.point(t.v[0]), b = m.point(t.v[1]), c = m.point(t.v[2]);
        const double shortest = std::fmin(distance(a, b), std::fmin(distance(b, c), distance(c, a)));
        for (const Vec2 p : {a, b, c}) {
            closing.points.push_back(p);
            closing.sizes.push_back(shortest / kAgreementRatio);
        }
    }
    return closing.points.size() > before;
}

/// Rounds of spacing curves finer where their chords cross or leave a loop out, at most: each
/// halves the offending chords (their distance from the curve falls fourfold).
constexpr int kChordRounds = 12;

// discretise_boundary, with the curves spaced finer where its chords would cross one another
// or leave a loop or an embedded curve out of the domain where the curves themselves do not
// (CoarseChords): the density is a request for sizes, and a far field asked for at several
// times its distance from an airfoil should still hold the airfoil. Each offending chord's
// middle is capped at half its length, beside the caps so far (`caps`, which the curves'
// agreement starts from), and the boundary placed again, kChordRounds times at most; then the
// refusal stands (422, naming both curves).
Discretisation discretise_mending_chords(const Domain& domain, SizeField& rho, const BoundaryOptions& bopt,
                                         Observer* observer, SizeCaps& caps) {
    for (int round = 0;; ++round) {
        try {
            return discretise_boundary(domain, rho, bopt, observer);
        } catch (const CoarseChords& e) {
            if (round == kChordRounds) throw;
            caps.points.insert(caps.points.end(), e.finer().points.begin(), e.finer().points.end());
            caps.sizes.insert(caps.sizes.end(), e.finer().sizes.begin(), e.finer().sizes.end());
            rho.set_curve_cap(caps.points, caps.sizes, kAgreementCapRatio);
        }
    }
}

}  // namespace

MeshResult generate_mesh(const Domain& domain, const DensitySpec& density, const MeshOptions& asked,
                         Observer* observer) {
    // The stages' large arrays, once freed, serve the next stage's (kernel/memory.hpp).
    const detail::BlockReuse reuse;
    MeshOptions options = asked;
    if (options.max_points == 0 || options.max_points > kMaxPointsLimit) options.max_points = kMaxPointsLimit;
    MeshResult r;
    reset_predicate_counters();
    const auto t_start = Clock::now();

    // Admission: a mesh forecast above the limit is refused before any work that grows with it.
    auto t0 = Clock::now();
    {
        ForecastBudget budget;
        budget.curve_agreement = options.curve_agreement;
        const PointForecast forecast = forecast_points(domain, density, budget, observer);
        r.stats.forecast_points = forecast.total();
        if (forecast.total() > static_cast<double>(options.max_points))
            refuse_too_many(forecast.total(), options.max_points);
        if (observer) observer->on_forecast(forecast.total(), peak_bytes_for(forecast.total()));
    }

    // Each stage is announced as it begins, so that progress (and a stop) is seen in the
    // right stage (again, when the layers are grown again below).
    auto begin = [&](Stage stage) {
        if (observer) observer->on_progress(stage, 0.0);
    };

    // Everything from the boundary on is made again, a round or two at most, where the mesh
    // has sharp triangles of fixed points alone (cap_closing_triangles).
    std::optional<SizeField> field;
    std::optional<GrownLayers> layers;
    Mesh& m = r.mesh;
    SizeCaps closing;
    // The density made with: the request's, or with the jump gradation (below) once its field
    // was found to jump.
    DensitySpec graded = density;
    const bool may_grade = !density.gradation && options.jump_gradation > 1.0 && options.curve_agreement;
    for (int closing_round = 0;; ++closing_round) {
        const auto round_start = Clock::now();
        if (closing_round > 0) t0 = round_start;
        // Boundary.
        field.emplace(graded, domain);
        SizeField& rho = *field;
        BoundaryOptions bopt;
        bopt.spline_spacing = options.spline_spacing;
        bopt.max_points = options.max_points;
        Discretisation d = discretise_mending_chords(domain, rho, bopt, observer, closing);
        if (rho.interpolates()) set_interpolation_sources(rho, d);
        BoundaryTriangulation walls = triangulate_boundary(d);
        size_t gradation_bytes = 0;  // the gradation's sources, held beside the points' peak
        if (rho.gradation()) {
            // Limit the growth of the field sampled from the first boundary, then place the
            // boundary points again along the limited field (and interpolate from those).
            gradation_bytes = set_gradation_sources(rho, d, walls, options.max_points, observer, r.stats.forecast_points);
            d = discretise_mending_chords(domain, rho, bopt, observer, closing);
            if (rho.interpolates()) set_interpolation_sources(rho, d);
            walls = triangulate_boundary(d);
        }
        // Boundary layers' fans: the walls beside them and the field around them no coarser than
        // the fans' tops are apart (layers.hpp), growing gently away from them.
        LayerPlan plan;
        // The fans planned again on the walls placed since: a fan whose neighbours now stand
        // closer, or where the field is now smaller, may be cut shorter than planned, its tops
        // closer together than the walls were spaced for (a long slope of the outer edge down to
        // it), and a fan the earlier walls cut back entirely may stand on these. The walls are
        // placed again for those (narrow_fans), a few rounds at most.
        auto place_walls_for_plan = [&] {
            rho.set_cap(plan.caps(), kFanCapRatio);
            d = discretise_boundary(domain, rho, bopt, observer);
            if (rho.interpolates()) set_interpolation_sources(rho, d);
        };
        auto plan_fans_again = [&] {
            for (int round = 0; round < kReplanRounds; ++round) {
                if (!narrow_fans(plan, plan_layers(domain, d, rho, options.boundary_layers, options.max_points, observer)))
                    return;
                place_walls_for_plan();
            }
        };
        if (!options.boundary_layers.empty()) {
            if (options.order == 2)
                throw GeometryError(GeometryErrorKind::BadParameter,
                                    "second-order elements with boundary layers are not supported yet",
                                    {Subject::layers(0)});
            plan = plan_layers(domain, d, rho, options.boundary_layers, options.max_points, observer);
            if (!plan.fans.empty() || !plan.tops.empty()) {
                place_walls_for_plan();
                plan_fans_again();
                walls = triangulate_boundary(d);
            }
        }
        // Curves far coarser than the interior field beside them: spaced again to agree with it.
        if (options.curve_agreement) {
            r.stats.agreement = agree_with_interior(domain, rho, bopt, d, observer, plan.walls, closing);
            if (r.stats.agreement.rounds > 0) {
                // The agreement's caps (the interior capped beside fine curves, curves placed
                // again) cut fans back too: a fan planned 27,000 tall stood 760 on the agreed
                // walls, its tops 317 apart between wall tops 9,000 apart.
                if (!options.boundary_layers.empty()) plan_fans_again();
                walls = triangulate_boundary(d);
            }
        }
        // Refuse before the interior work when the mesh would clearly be too large. Not needed
        // when the forecast, which sees everything but the gradation and the interior's caps
        // at fine curves, is far below the limit and neither was applied.
        const bool forecast_decides = !rho.gradation() && r.stats.agreement.rounds == 0 &&
                                      4.0 * r.stats.forecast_points < static_cast<double>(options.max_points);
        // (Not in a closing round: its first mesh met the limit with room to spare, kClosingRoom.)
        if (asked.max_points && !forecast_decides && closing_round == 0) {
            const double limit = static_cast<double>(options.max_points);
            const double estimate = estimate_point_count(d, walls, rho, limit, observer);
            if (estimate > limit) refuse_too_many(estimate, options.max_points);
        }
        // Boundary layers: their outer edge takes the walls' place for the stages below.
        layers.reset();
        std::vector<LayerColumn> limits;  // columns held lower beside sharp triangles
        const auto curves_cap = rho.interior_cap();
        auto grow = [&] {
            rho.restore_interior_cap(curves_cap);  // a growth again sees the field the first saw
            layers = grow_layers(domain, d, rho, options.boundary_layers, options.max_points, observer, &plan, &limits);
            walls = triangulate_boundary(layers->front);
            if (options.curve_agreement) agree_interior_with_front(rho, layers->front);
        };
        auto lap = Clock::now();  // a layers' round, its growth included
        if (!options.boundary_layers.empty()) grow();
        r.timings.boundary_ms += ms_since(t0);

        bool as_first = false;  // the layers grown once more without limits: no round mended all
        bool jumped = false;    // the interior stage found the field jumping (FieldJumps)
        for (int round = 0;; ++round) {
            const Discretisation& fixed = layers ? layers->front : d;
            m = Mesh{};  // a round's mesh is let go before the next is made

            // Interior.
            begin(Stage::Interior);
            t0 = Clock::now();
            const double forecast = r.stats.forecast_points;
            InteriorBudget budget{options.max_points, forecast > 0.0 && forecast < static_cast<double>(options.max_points)
                                                          ? static_cast<size_t>(forecast)
                                                          : 0};
            if (may_grade && !graded.gradation) budget.jumps_to_stop = kJumpsToGrade;
            budget.extra_bytes = gradation_bytes;
            Array<Vec2> inner;
            try {
                inner = generate_interior_points(domain, fixed, walls, rho, options.interior, budget, observer,
                                                 &r.stats.interior);
            } catch (const FieldJumps&) {
                r.timings.interior_ms += ms_since(t0);
                jumped = true;
                break;
            }
            // Along a Hilbert curve: neighbours in the mesh become neighbours in memory, which
            // the triangle order (order_by_largest_corner) and every later sweep profit from.
            Array<std::uint32_t> order = detail::hilbert_order(inner);
            r.timings.interior_ms += ms_since(t0);

            // Triangulation: the fixed points, then the interior points in that order (copied
            // there once: a sorted copy of its own cost fresh pages as large).
            begin(Stage::Triangulation);
            t0 = Clock::now();
            {
                Array<Vec2> pts = std::move(walls.points);
                const size_t fixed_count = pts.size();
                detail::reserve_filled(pts, fixed_count + inner.size());
                for (const std::uint32_t i : order) pts.push_back(inner[i]);
                Array<Vec2>().swap(inner);
                Array<std::uint32_t>().swap(order);
                const std::vector<Constraint> cons = constraints_of(fixed);
                TriangulationResult tr = options.triangulator == Triangulator::Delaunay
                                             ? triangulate_delaunay(pts, cons, observer)
                                             : triangulate_advancing_front(pts, cons, observer);
                for (size_t i = 0; i < tr.alias.size(); ++i)
                    MESHD_INTERNAL_CHECK(tr.alias[i] == i, "two mesh points coincide");
                r.stats.triangulation = tr.stats;
                assemble(m, domain, fixed, layers ? layers->boundary : d,
                         std::span<const Vec2>(pts).subspan(fixed_count), std::move(tr.triangles));
            }  // the triangulation's points and aliases go before the smoothing (the peak's stage)
            r.timings.triangulation_ms += ms_since(t0);

            // Improvement.
            begin(Stage::Smoothing);
            t0 = Clock::now();
            if (options.smoothing_iterations > 0) {
                r.stats.smoothing_flips = 0;
                r.stats.smoothing_moves = smooth(m, options.smoothing_iterations, &domain, &r.stats.smoothing_flips, observer);
            }
            r.timings.smoothing_ms += ms_since(t0);

            // A triangle beside the layers still sharp after the smoothing's repair: the columns
            // at its corners are held lower and the layers grown again, and the stages above run
            // again on their new outer edge. Rare (a few domains in a thousand of the random
            // domains with layers), and each round costs a whole mesh. A lower round is kept
            // only if it has no sharp triangle left; else the layers are grown once more as at
            // first, and that mesh is made again (rather than kept aside: one mesh in memory).
            // (A first round without a sharp triangle beside the layers needs no other look.)
            if (!layers || options.smoothing_iterations == 0 || as_first || (round > 0 && !any_sharp(m))) break;
            // Nor where another round as long as this one would not fit in the time left before
            // the job's limit (Observer::seconds_left): the mesh made is kept, even a lowered
            // round's with a sharp triangle left, rather than lost to the limit.
            if (observer && observer->seconds_left() < 1e-3 * ms_since(lap)) break;
            if (round == kLayerRounds || !lower_columns_at_sharp_triangles(m, *layers, limits)) {
                if (round == 0) break;
                limits.clear();
                as_first = true;
            }
            t0 = lap = Clock::now();
            grow();
            r.timings.boundary_ms += ms_since(t0);
            ++r.stats.layer_rounds;
        }
        if (jumped) {
            // Everything again from the boundary, with the jump gradation; not a closing round.
            graded.gradation = options.jump_gradation;
            r.stats.gradation_applied = options.jump_gradation;
            t0 = Clock::now();  // the boundary's time from here
            --closing_round;
            continue;
        }
        // Not for a mesh near max_points: the finer curves add a few points, and a request
        // the first mesh met is not refused for them.
        // Nor where another round as long as this one would not fit in the time left.
        const bool room = static_cast<double>(m.point_count()) < kClosingRoom * static_cast<double>(options.max_points) &&
                          !(observer && observer->seconds_left() < 1e-3 * ms_since(round_start));
        if (closing_round == kClosingRounds || !options.curve_agreement || options.smoothing_iterations == 0 || !room ||
            !cap_closing_triangles(m, closing))
            break;
        ++r.stats.closing_rounds;
    }
    SizeField& rho = *field;

    // The defaults' last resort for 30 degrees: a mesh that the curves' agreement, the closing
    // rounds and the smoothing's repair left with a sharp triangle (sharp(): not at a corner
    // between two constrained edges) is refined to 30 degrees as min_angle_deg would, or to
    // the request's min_angle_deg where that is higher (a lower one does not take the defaults'
    // 30 away). Two meshes in 68,818 of the random domains' census with layers needed it (seed
    // 146694, a triangle of the isotropic part at 29.6 degrees; seed 145352, 25.3 degrees in a
    // gap between two holes' layers, mended by the refinement's point beside a sharp corner);
    // every other mesh is left as it was. Not with sharp_last_resort off (the request's
    // explicit min_angle_deg 0).
    // A mesh with no angle below 30 degrees has no sharp triangle: where nothing is added to
    // the mesh after this (no layers, first order), its figures are measured here, once, and
    // spare any_sharp's pass over every triangle on the meshes that need no last resort.
    std::optional<QualityMetrics> measured;
    bool last_resort = false;
    if (options.sharp_last_resort && options.curve_agreement && options.smoothing_iterations > 0 &&
        options.min_angle_deg < kSharpAngleDeg) {
        // (A density that fails at some edge's middle is left to the figures at the end: the
        // refinement may split that edge.)
        if (!layers && options.order == 1) {
            try {
                measured = measure_quality(m, rho);
            } catch (const GeometryError&) {
                measured.reset();
            }
        }
        // (The margin is far above the rounding of the smallest angle's arc tangent.)
        last_resort = !(measured && measured->angle_min >= kSharpAngleDeg + 1e-9) && any_sharp(m);
    }
    const double min_angle = std::max(options.min_angle_deg, last_resort ? kSharpAngleDeg : 0.0);
    if (min_angle > 0.0) {
        measured.reset();  // the refinement and its repair change the mesh
        t0 = Clock::now();
        const auto before_refinement = static_cast<VertexId>(m.point_count());
        r.stats.refinement_points = refine_min_angle(m, domain, rho, min_angle, options.max_points, observer);
        // The refinement's points were never smoothed: the angle repair once more for them
        // (without the smoothing, for them alone: the others stay where the front put them).
        if (r.stats.refinement_points > 0)
            r.stats.smoothing_moves += repair_angles(m, &domain, &r.stats.smoothing_flips, observer,
                                                     options.smoothing_iterations > 0 ? 0 : before_refinement);
        r.timings.smoothing_ms += ms_since(t0);
    }

    if (layers) add_layers(m, *layers);
    EdgeNodeCounts edge_nodes;
    if (options.order == 2) edge_nodes = add_edge_nodes(m, domain);

    begin(Stage::Quality);
    r.quality = measured ? std::move(*measured) : measure_quality(m, rho);
    if (layers) r.quality.boundary_layers = std::move(layers->figures);
    r.quality.curved_edges = edge_nodes.curved;
    r.quality.straightened_edges = edge_nodes.straightened;
    if (m.order() == 2)
        for (TriangleId t = 0; t < m.triangles.size(); ++t)
            r.quality.scaled_jacobian_min = std::min(r.quality.scaled_jacobian_min, min_scaled_jacobian(m, t));
    m.target_size.resize(m.point_count());
    {
        // In batches: a copy of every point would be fresh pages as large as the points.
        constexpr size_t kBatch = 1024;
        std::array<Vec2, kBatch> at;
        for (size_t v0 = 0; v0 < m.point_count(); v0 += kBatch) {
            const size_t n = std::min(kBatch, m.point_count() - v0);
            for (size_t i = 0; i < n; ++i) at[i] = m.point(static_cast<VertexId>(v0 + i));
            rho.interior(at.data(), n, m.target_size.data() + v0);
        }
    }
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
