// Graded points on the curves of whole domains.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <set>
#include <algorithm>

#include "fixtures.hpp"
#include "boundary/boundary.hpp"
#include "geometry/curve.hpp"
#include "meshd/core/errors.hpp"
#include "meshd/core/mesher.hpp"

using namespace meshd::core;
using namespace meshd::test;

namespace {

double polygon_area(const Discretisation& d, const std::vector<VertexId>& cycle) {
    double a = 0;
    for (size_t i = 0; i < cycle.size(); ++i) a += cross(d.point(cycle[i]), d.point(cycle[(i + 1) % cycle.size()]));
    return a / 2;
}

// Every segment within `tol` of (rho(A) + rho(B)) / 2 on curves long against rho, with rho
// the curve's density (taken from the field, not from what the discretisation stored; the
// size cap for curved shapes does not bind on these domains).
void expect_spacing_law(const Domain& dom, const SizeField& rho, const Discretisation& d, double tol) {
    std::vector<double> worst(dom.curves().size(), 0.0);
    for (const BoundarySegment& s : d.segments) {
        const Vec2 a = d.point(s.a), b = d.point(s.b);
        const double ratio = distance(a, b) / (0.5 * (rho.on_curve(s.curve, a) + rho.on_curve(s.curve, b)));
        worst[s.curve] = std::fmax(worst[s.curve], std::fabs(ratio - 1.0));
    }
    for (CurveId c = 0; c < dom.curves().size(); ++c)
        EXPECT_LT(worst[c], tol) << dom.curves()[c].name;
}

}  // namespace

TEST(Boundary, SquareWithUniformDensity) {
    const Domain dom = build_domain(unit_square());
    DensitySpec spec;
    spec.size = 0.05;
    SizeField rho(spec, dom);
    const Discretisation d = discretise_boundary(dom, rho);
    EXPECT_EQ(d.size(), 80u);
    ASSERT_EQ(d.loops.size(), 1u);
    EXPECT_EQ(d.loops[0].size(), 80u);
    EXPECT_EQ(d.segments.size(), 80u);
    EXPECT_NEAR(polygon_area(d, d.loops[0]), 1.0, 1e-12);
    // Corners are exact points shared by two curves.
    for (const auto& p : dom.points()) {
        int found = 0;
        for (VertexId v = 0; v < d.size(); ++v) found += d.point(v) == p.position;
        EXPECT_EQ(found, 1);
    }
    // Consecutive segments chain, and every segment is as long as rho.
    for (size_t i = 0; i < d.segments.size(); ++i) {
        EXPECT_EQ(d.segments[i].b, d.segments[(i + 1) % d.segments.size()].a);
        EXPECT_NEAR(distance(d.point(d.segments[i].a), d.point(d.segments[i].b)), 0.05, 1e-12);
    }
}

TEST(Boundary, AirfoilInFarFieldFollowsRhoAndHasTheDomainOnTheLeft) {
    const Domain dom = build_domain(naca_in_circle("0012", 20.0));
    DensitySpec spec;
    spec.curves = {{"farfield", std::string("0.4*sqrt(x^2+y^2)+0.2")},
                   {"wing", std::string("0.005 + 0.05*sqrt((x+0.01)^2+y^2)")}};
    SizeField rho(spec, dom);
    const Discretisation d = discretise_boundary(dom, rho);
    ASSERT_EQ(d.loops.size(), 2u);
    EXPECT_GT(polygon_area(d, d.loops[0]), 0.0);  // outer counter-clockwise
    EXPECT_LT(polygon_area(d, d.loops[1]), 0.0);  // hole clockwise
    expect_spacing_law(dom, rho, d, 0.05);
    // The far-field points are on the circle, the wing's on the section.
    for (VertexId v : d.curve_vertices[*dom.find_curve("farfield")])
        EXPECT_NEAR(distance(d.point(v), {0.5, 0}), 20.0, 1e-12);
    // The trailing edge, a corner, is a point.
    bool te = false;
    for (VertexId v = 0; v < d.size(); ++v) te |= distance(d.point(v), {1, 0}) < 1e-15;
    EXPECT_TRUE(te);
}

TEST(Boundary, FiveDigitAirfoilAndSplineSpacingModes) {
    for (auto mode : {SplineSpacing::ArcLength, SplineSpacing::ControlPolygon}) {
        DomainSpec s = naca_in_circle("23012", 10.0);
        // Replace the analytic section by a spline through 161 of its points, as a .dat
        // airfoil would be.
        NacaSpec ns;
        ns.code = "23012";
        auto exact = make_naca(ns);
        std::vector<Vec2> pts;
        for (int i = 0; i <= 160; ++i) pts.push_back(exact->point(2.0 * i / 160.0));
        pts.back() = pts.front();
        s.curves[0].shape = SplineShape{pts};
        const Domain dom = build_domain(s);
        DensitySpec spec;
        spec.curves = {{"farfield", 1.0}, {"wall", std::string("0.004 + 0.04*sqrt((x-0.3)^2+y^2)")}};
        SizeField rho(spec, dom);
        BoundaryOptions opt;
        opt.spline_spacing = mode;
        const Discretisation d = discretise_boundary(dom, rho, opt);
        const SpacingReport r = spacing_report(dom, d);
        const auto& wing = r.per_curve[*dom.find_curve("wing")];
        EXPECT_GT(wing.segments, 50u);
        if (mode == SplineSpacing::ArcLength) EXPECT_LT(wing.max_abs_error, 0.05);
        else EXPECT_LT(wing.mean_abs_error, 0.5);  // measured, not guaranteed: see the README
    }
}

TEST(Boundary, EmbeddedCurvesShareTheirEnds) {
    DomainSpec s = unit_square();
    s.points.push_back({"M", {0.5, 0.5}});
    s.curves.push_back(line("wake", "C", "M", "wake"));
    s.embedded = {"wake"};
    const Domain dom = build_domain(s);
    DensitySpec spec;
    spec.size = 0.1;
    SizeField rho(spec, dom);
    const Discretisation d = discretise_boundary(dom, rho);
    ASSERT_EQ(d.embedded.size(), 1u);
    const auto& w = d.embedded[0];
    EXPECT_EQ(d.point(w.front()), (Vec2{1, 1}));
    EXPECT_EQ(d.point(w.back()), (Vec2{0.5, 0.5}));
    // C is one vertex for the loop and the wake.
    EXPECT_NE(std::find(d.loops[0].begin(), d.loops[0].end(), w.front()), d.loops[0].end());
    EXPECT_EQ(d.segments.size() - d.loop_segment_count, w.size() - 1);
}

TEST(Boundary, FullCircleHoleAndReversedCurves) {
    DomainSpec s = unit_square();
    s.loops = {loop({"-left", "-top", "-right", "-bottom"})};
    s.points.push_back({"P", {0.3, 0.5}});
    s.curves.push_back(arc("hole", "P", "P", {0.5, 0.5}, ArcDirection::Cw));
    s.loops.push_back(loop({"hole"}));
    const Domain dom = build_domain(s);
    DensitySpec spec;
    spec.size = std::string("0.02 + 0.05 * x");
    SizeField rho(spec, dom);
    const Discretisation d = discretise_boundary(dom, rho);
    EXPECT_NEAR(polygon_area(d, d.loops[0]), 1.0, 1e-12);
    EXPECT_LT(polygon_area(d, d.loops[1]), 0.0);
    expect_spacing_law(dom, rho, d, 0.05);
}

// A circular hole of radius 0.05 under a size of 1: the size along it is capped at
// kMaxSegmentTurn (90 degrees) times its radius, so each segment turns by at most about a
// quarter of the circle and the hole has four segments at least (a closed curve on its own
// gets three whatever its size). The cap is skipped only below 0.9 of that (least_radius).
TEST(Boundary, ASmallHoleUnderACoarseSizeIsSpacedByItsCurvature) {
    DomainSpec s = unit_square();
    s.loops = {loop({"-left", "-top", "-right", "-bottom"})};
    const double r = 0.05;
    s.points.push_back({"P", {0.5 + r, 0.5}});
    s.curves.push_back(arc("hole", "P", "P", {0.5, 0.5}, ArcDirection::Cw));
    s.loops.push_back(loop({"hole"}));
    const Domain dom = build_domain(s);
    // A size whose segments would turn by 120 degrees (below the 135 past which a step is
    // halved to keep the shape), and one far above the cap.
    for (const double size : {2.1 * r, 1.0}) {
        SCOPED_TRACE(size);
        DensitySpec spec;
        spec.size = size;
        SizeField rho(spec, dom);
        const Discretisation d = discretise_boundary(dom, rho);
        ASSERT_EQ(d.loops.size(), 2u);
        EXPECT_GE(d.loops[1].size(), 4u);
        for (const BoundarySegment& seg : d.segments) {
            if (dom.curves()[seg.curve].name != "hole") continue;
            // The turn of a chord of a circle is the angle it spans: 2 asin(l / 2r).
            const double l = distance(d.point(seg.a), d.point(seg.b));
            EXPECT_LE(2.0 * std::asin(std::fmin(1.0, l / (2.0 * r))), 0.5 * std::numbers::pi * 1.05);
        }
    }
    // An eighth of the circumference, below the cap: the cap is skipped, and the spacing law
    // holds on the circle as on the square's sides.
    DensitySpec fine;
    fine.size = 0.25 * std::numbers::pi * r;
    SizeField rho_fine(fine, dom);
    expect_spacing_law(dom, rho_fine, discretise_boundary(dom, rho_fine), 0.05);
}

// Chords that cross, and chords that cross nothing but break how the loops nest. The unit
// circle as four chords (a density twice its radius: the shape cap's quarter turns) is the
// square through (1, 0), (0, 1), (-1, 0), (0, -1), whose side x + y = 1 lies between the
// circle and anything at x + y > 1 near (0.8, 0.3).
namespace {

DomainSpec unit_circle_with(std::vector<std::pair<std::string, Vec2>> points, std::vector<CurveSpec> curves) {
    DomainSpec s;
    s.points = {{"P", {1.0, 0.0}}};
    s.points.insert(s.points.end(), points.begin(), points.end());
    s.curves = {arc("outer", "P", "P", {0, 0})};
    s.curves.insert(s.curves.end(), curves.begin(), curves.end());
    s.loops = {loop({"outer"})};
    return s;
}

// A narrow annulus: radii 1.02 and 1.0.
DomainSpec narrow_annulus() {
    DomainSpec s;
    s.points = {{"P", {1.02, 0}}, {"Q", {1.0, 0}}};
    s.curves = {arc("outer", "P", "P", {0, 0}), arc("inner", "Q", "Q", {0, 0})};
    s.loops = {loop({"outer"}), loop({"inner"})};
    return s;
}

// The kind and the two curves named of what discretise_boundary refuses, or "accepted".
std::string refusal(const Domain& dom, double size) {
    DensitySpec spec;
    spec.size = size;
    SizeField rho(spec, dom);
    try {
        discretise_boundary(dom, rho);
    } catch (const GeometryError& e) {
        std::string r = e.kind() == GeometryErrorKind::DiscretisationCrosses ? "crosses" : "other";
        for (const Subject& s : e.subjects()) r += " " + s.name;
        return r;
    }
    return "accepted";
}

}  // namespace

TEST(Boundary, CoarseDensityAcrossANarrowGapIsReported) {
    // Chords of the outer circle cut into the hole when rho is large.
    const Domain dom = build_domain(narrow_annulus());
    EXPECT_EQ(refusal(dom, 0.6), "crosses outer inner");
    EXPECT_EQ(refusal(dom, 0.005), "accepted");
}

TEST(Boundary, AChordThatLeavesAHoleOutsideTheDomainIsReported) {
    // A hole of radius 0.05 about (0.8, 0.3): x + y >= 1.1 - 0.05 sqrt 2 > 1 on it, inside the
    // circle (0.854 + 0.05 < 1).
    DomainSpec s = unit_circle_with({{"H", {0.85, 0.3}}}, {arc("hole", "H", "H", {0.8, 0.3})});
    s.loops.push_back(loop({"hole"}));
    const Domain dom = build_domain(s);
    EXPECT_EQ(refusal(dom, 2.0), "crosses outer hole");
    EXPECT_EQ(refusal(dom, 0.05), "accepted");
    // The chord to space finer is the square's side from (1, 0) to (0, 1): its middle, half
    // its length.
    DensitySpec coarse;
    coarse.size = 2.0;
    SizeField rho(coarse, dom);
    try {
        discretise_boundary(dom, rho);
        ADD_FAILURE() << "accepted";
    } catch (const CoarseChords& e) {
        ASSERT_EQ(e.finer().points.size(), 1u);
        EXPECT_NEAR(e.finer().points[0].x, 0.5, 1e-6);  // the arc length's quarters, to its tolerance
        EXPECT_NEAR(e.finer().points[0].y, 0.5, 1e-6);
        EXPECT_NEAR(e.finer().sizes[0], std::sqrt(0.5), 1e-6);
    }
}

TEST(Boundary, AChordThatLeavesAnEmbeddedCurveOutsideTheDomainIsReported) {
    // From (0.8, 0.3) to (0.8, 0.35): x + y > 1 all along, inside the circle.
    DomainSpec s = unit_circle_with({{"E0", {0.8, 0.3}}, {"E1", {0.8, 0.35}}}, {line("fin", "E0", "E1")});
    s.embedded = {"fin"};
    const Domain dom = build_domain(s);
    EXPECT_EQ(refusal(dom, 2.0), "crosses outer fin");
    EXPECT_EQ(refusal(dom, 0.05), "accepted");
}

TEST(Boundary, AConcaveChordThatTakesAHoleIntoAnotherIsReported) {
    // A hole: the rectangle [-0.5, 0.5] x [-0.2, 0.2] with its top bent down, an arc about
    // (0, 1.2) through (+-0.5, 0.2) that dips to y = 1.2 - sqrt(1.25) = 0.082. As one chord
    // (its 53 degrees are within the shape cap) the top is y = 0.2 again, and the small hole
    // about (0, 0.15), above the arc, falls inside the rectangle.
    DomainSpec s;
    s.points = {{"A", {-2, -2}}, {"B", {2, -2}}, {"C", {2, 2}}, {"D", {-2, 2}},
                {"E", {-0.5, -0.2}}, {"F", {0.5, -0.2}}, {"G", {0.5, 0.2}}, {"H", {-0.5, 0.2}}, {"K", {0.02, 0.15}}};
    s.curves = {line("s1", "A", "B"), line("s2", "B", "C"), line("s3", "C", "D"), line("s4", "D", "A"),
                line("base", "E", "F"), line("right", "F", "G"), arc("cap", "G", "H", {0, 1.2}, ArcDirection::Cw),
                line("left", "H", "E"), arc("dot", "K", "K", {0, 0.15})};
    s.loops = {loop({"s1", "s2", "s3", "s4"}), loop({"base", "right", "cap", "left"}), loop({"dot"})};
    const Domain dom = build_domain(s);
    EXPECT_EQ(refusal(dom, 2.0), "crosses cap dot");
    EXPECT_EQ(refusal(dom, 0.02), "accepted");
}

namespace {

// V - E + F of a mesh, E counted from the triangles (every inner edge twice, the others once).
long euler_characteristic(const Mesh& m) {
    size_t open = 0;
    for (const Triangle& t : m.triangles)
        for (const TriangleId n : t.n) open += n == kNoTriangle ? 1 : 0;
    const size_t edges = (3 * m.triangles.size() + open) / 2;
    return static_cast<long>(m.point_count()) - static_cast<long>(edges) + static_cast<long>(m.triangles.size());
}

// Every segment of the boundary is an edge of a triangle of the mesh.
bool boundary_segments_are_edges(const Mesh& m) {
    std::set<std::pair<VertexId, VertexId>> edges;
    for (const Triangle& t : m.triangles)
        for (int i = 0; i < 3; ++i) edges.insert(std::minmax(t.v[i], t.v[(i + 1) % 3]));
    return std::all_of(m.edges.begin(), m.edges.end(), [&](const MeshEdge& e) { return edges.count(std::minmax(e.a, e.b)) > 0; });
}

}  // namespace

// Found by fuzz/fuzz_request (crash 83a027ff): the far field of this request in four chords
// (a circle of radius 9.2 about (0.5, 7), 7.0 from the wing, whose chords are 6.5 from the
// centre) passed below the wing and left it outside the domain, and the triangulation's flood
// fill stopped on an internal check (a 500). The mesher spaces the far field finer where its
// chord passed and meshes the domain asked for: one hole, the wing's segments edges of it.
TEST(Boundary, AFarFieldWhoseChordsWouldCutTheWingOffIsSpacedFinerThere) {
    DomainSpec s = naca_in_circle("0006");
    s.points = {{"F", {6.5, 0.0}}};
    s.curves[1] = arc("farfield", "F", "F", {0.5, 7.0}, ArcDirection::Ccw, "farfield");
    const Domain dom = build_domain(s);
    DensitySpec spec;
    spec.curves = {{"farfield", std::string("2.4*sqrt(x^2+y^2)+0.2")}, {"wing", std::string("0.05*sqrt((x+1.01)^2+y^2)")}};
    spec.interior = InteriorMode::Interpolate;
    SizeField rho(spec, dom);
    EXPECT_THROW(discretise_boundary(dom, rho), CoarseChords);
    const MeshResult r = generate_mesh(dom, spec, MeshOptions{});
    EXPECT_TRUE(check_mesh(r.mesh).empty());
    EXPECT_EQ(euler_characteristic(r.mesh), 0);  // 1 - holes
    EXPECT_TRUE(boundary_segments_are_edges(r.mesh));
    EXPECT_GE(r.quality.angle_min, 30.0);
}

// The narrow annulus of CoarseDensityAcrossANarrowGapIsReported, through the mesher: the
// crossing chords are spaced finer (every crossing pair at once) until none crosses.
TEST(Boundary, ChordsThatWouldCrossAcrossANarrowGapAreSpacedFinerThere) {
    const MeshResult r = generate_mesh(build_domain(narrow_annulus()), density_of("0.6"), MeshOptions{});
    EXPECT_TRUE(check_mesh(r.mesh).empty());
    EXPECT_EQ(euler_characteristic(r.mesh), 0);
    EXPECT_TRUE(boundary_segments_are_edges(r.mesh));
    EXPECT_GE(r.quality.angle_min, 30.0);
}

TEST(Boundary, PointLimitAndCancellation) {
    const Domain dom = build_domain(unit_square());
    DensitySpec spec;
    spec.size = 0.001;
    SizeField rho(spec, dom);
    BoundaryOptions opt;
    opt.max_points = 1000;
    EXPECT_THROW(discretise_boundary(dom, rho, opt), GeometryError);
    struct Stop : Observer {
        bool should_stop() override { return true; }
    } stop;
    EXPECT_THROW(discretise_boundary(dom, rho, {}, &stop), Cancelled);
}

TEST(Boundary, DeterministicVertexOrder) {
    const Domain dom = build_domain(naca_in_circle());
    DensitySpec spec;
    spec.size = std::string("0.01 + 0.1*sqrt(x^2+y^2)");
    SizeField rho(spec, dom);
    const Discretisation a = discretise_boundary(dom, rho);
    const Discretisation b = discretise_boundary(dom, rho);
    EXPECT_EQ(a.x, b.x);
    EXPECT_EQ(a.y, b.y);
}

// Found by fuzz/fuzz_request (crash edc7f61b): a NACA section asked for a size 30 times its
// chord (capped at the domain's extent, still beyond its length) became one point: the
// shape cap is sampled where the density is, and every sample missed the leading edge, so
// the closed contour got no point but its start and the mesh an edge from a point to itself.
// A step over which the tangent turns by more than 135 degrees is now halved until none does.
TEST(Boundary, AClosedCurveFarCoarserThanItselfKeepsItsShape) {
    DomainSpec s = naca_in_circle("0516", 2.0);
    DensitySpec spec;
    spec.curves = {{"farfield", std::string("0.4*sqrt(x^2+y^2)+0.2")}, {"wing", std::string("0.05*sqrt((x+601)^2+y^2)")}};
    spec.interior = InteriorMode::Interpolate;
    spec.min = 0.002;
    const Domain dom = build_domain(s);
    SizeField rho(spec, dom);
    const Discretisation d = discretise_boundary(dom, rho);
    ASSERT_EQ(d.loops.size(), 2u);
    // Between its sharp trailing edge (where the tangent turns by 180 degrees less the wedge
    // angle) and itself, the contour's smooth part turns by more than 180 degrees: three
    // segments or more, enclosing area.
    EXPECT_GE(d.loops[1].size(), 3u);
    EXPECT_LT(polygon_area(d, d.loops[1]), 0.0);  // a hole: clockwise
    for (const BoundarySegment& seg : d.segments) EXPECT_NE(seg.a, seg.b);
}

// Found by fuzz/fuzz_request (crash c8a20a23): a density that jumps from about 200 at the main
// wing's trailing edge to 1.4 near its leading edge made the march step from the trailing
// edge over the whole upper surface and the leading edge: the wing became a sliver along its
// lower surface that ran the wrong way, and the triangulation failed (a 500). Along every curve,
// the tangent now turns by at most 135 degrees (kMaxStepTurn) between two consecutive points.
TEST(Boundary, ADensityJumpingOverALeadingEdgeKeepsTheShape) {
    DomainSpec s;
    s.points = {{"F", {449, 0}}};
    NacaSpec main_wing, flap;
    main_wing.code = "4412";
    main_wing.placement.chord = 80;
    flap.code = "0012";
    flap.placement = {30, {81, -12}, 30};
    s.curves.push_back({"main", main_wing, std::nullopt, std::nullopt, std::string("wall")});
    s.curves.push_back({"flap", flap, std::nullopt, std::nullopt, std::string("flap")});
    s.curves.push_back(arc("farfield", "F", "F", {25, 0}, ArcDirection::Ccw, "farfield"));
    s.loops = {loop({"farfield"}), loop({"main"}), loop({"flap"})};
    DensitySpec spec;
    spec.size = std::string(
        "x < 50 ? 0.2*sqrt(x^2+y^2)+1.4 : (x < 78 ? 0.2*sqrt((x-73)^2+(y+13)^2)+1.1 : "
        "(x < 100 ? 9.2*sqrt((x-88)^2+(y+20)^2)+6.1 : 0.2*sqrt((x-111)^2+(y+36)^2)+1.1))");
    const Domain dom = build_domain(s);
    SizeField rho(spec, dom);
    const Discretisation d = discretise_boundary(dom, rho);
    for (size_t l = 0; l < d.loops.size(); ++l) EXPECT_EQ(polygon_area(d, d.loops[l]) < 0.0, dom.loops()[l].hole);
    for (CurveId c = 0; c < dom.curves().size(); ++c) {
        const Curve& g = *dom.curves()[c].geometry;
        const std::vector<VertexId>& on = d.curve_vertices[c];
        auto param = [&](size_t i) { return i == 0 ? g.t_begin() : i + 1 == on.size() ? g.t_end() : d.param[on[i]]; };
        for (size_t i = 0; i + 1 < on.size(); ++i) {
            // The turn of the tangent between the two points, sampled finely (corners excluded:
            // these curves have none inside).
            const double t0 = param(i), t1 = param(i + 1), inset = 1e-9 * (t1 - t0);
            double turn = 0.0;
            Vec2 prev = g.derivative(t0 + inset);
            for (int k = 1; k <= 256; ++k) {
                const Vec2 next = g.derivative(k == 256 ? t1 - inset : t0 + (t1 - t0) * k / 256.0);
                turn += std::atan2(std::fabs(cross(prev, next)), dot(prev, next));
                prev = next;
            }
            EXPECT_LE(turn, 0.75 * std::numbers::pi * 1.05) << dom.curves()[c].name << " segment " << i;
        }
    }
}
