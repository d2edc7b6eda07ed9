// Embedded curves that end on another curve away from its ends: the touched curve is split
// there and the touch point is a boundary point of both, on every curve type; real crossings
// are still refused.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <set>

#include "fixtures.hpp"
#include "geometry/curve.hpp"
#include "meshd/core/errors.hpp"
#include "meshd/core/mesher.hpp"

using namespace meshd::core;
using namespace meshd::test;

namespace {

// The box [-2, 3] x [-2, 2] as the outer loop.
DomainSpec box() {
    DomainSpec s;
    s.points = {{"A", {-2, -2}}, {"B", {3, -2}}, {"C", {3, 2}}, {"D", {-2, 2}}};
    s.curves = {line("bottom", "A", "B", "wall"), line("right", "B", "C", "far"), line("top", "C", "D", "far"),
                line("left", "D", "A", "far")};
    s.loops = {loop({"bottom", "right", "top", "left"})};
    return s;
}

struct TouchCase {
    std::string name;
    DomainSpec domain;  // with the embedded curve "cut" from T into the domain
    std::string touched;
    Vec2 t;
};

// The box, a hole given by `hole` (empty for none) and the cut from T to Q.
TouchCase with_cut(std::string name, std::optional<CurveSpec> hole, std::string touched, Vec2 t, Vec2 q) {
    DomainSpec s = box();
    if (hole) {
        s.curves.push_back(*hole);
        s.loops.push_back(loop({"hole"}));
    }
    s.points.push_back({"T", t});
    s.points.push_back({"Q", q});
    s.curves.push_back(line("cut", "T", "Q", "cut"));
    s.embedded = {"cut"};
    return {std::move(name), std::move(s), std::move(touched), t};
}

// A closed section y = +-0.3 sqrt(x) (1 - x) as a Selig file, cosine-spaced; point n/2 of the
// upper surface is at x = 0.5.
std::string selig_section(int n) {
    std::string text = "test section\n";
    char line_buf[96];
    auto add = [&](double x, double y) {
        std::snprintf(line_buf, sizeof line_buf, "%.17g %.17g\n", x, y);
        text += line_buf;
    };
    auto x_of = [&](int i) { return 0.5 * (1.0 - std::cos(std::numbers::pi * i / n)); };
    auto y_of = [](double x) { return 0.3 * std::sqrt(x) * (1.0 - x); };
    for (int i = n; i >= 0; --i) add(x_of(i), y_of(x_of(i)));
    for (int i = 1; i <= n; ++i) add(x_of(i), -y_of(x_of(i)));
    return text;
}

std::vector<TouchCase> touch_cases() {
    std::vector<TouchCase> out;
    // A straight side of the outer loop.
    out.push_back(with_cut("line", std::nullopt, "bottom", {0.5, -2.0}, {0.5, -1.0}));
    // A circle (a hole): at 60 degrees.
    {
        const double c60 = 0.5, s60 = std::sqrt(3.0) / 2.0;
        CurveSpec hole = arc("hole", "H", "H", {0.5, 0.0}, ArcDirection::Ccw, "hole");
        TouchCase tc = with_cut("arc", hole, "hole", {0.5 + 0.5 * c60, 0.5 * s60}, {0.5 + 1.2 * c60, 1.2 * s60});
        tc.domain.points.push_back({"H", {1.0, 0.0}});
        out.push_back(std::move(tc));
    }
    // A closed quadratic B-spline with uniform knots: at the knot 1/4 it passes through the
    // midpoint of its second control leg, (P1 + P2) / 2 = (0.5, -0.5).
    {
        BSplineShape b{{{0, 0}, {0, -0.5}, {1, -0.5}, {1, 0.5}, {0, 0.5}, {0, 0}}, 2,
                       std::vector<double>{0, 0, 0, 0.25, 0.5, 0.75, 1, 1, 1}};
        out.push_back(with_cut("bspline", CurveSpec{"hole", b, std::nullopt, std::nullopt, std::string("hole")}, "hole",
                               {0.5, -0.5}, {0.5, -1.5}));
    }
    // A periodic spline through points: at one of them.
    {
        SplineShape sp{{{0, 0.5}, {-0.5, 0}, {0, -0.5}, {0.5, 0}, {0, 0.5}}};
        out.push_back(with_cut("spline", CurveSpec{"hole", sp, std::nullopt, std::nullopt, std::string("hole")}, "hole",
                               {0.5, 0.0}, {1.5, 0.0}));
    }
    // NACA 0012 with its closed trailing edge: the upper surface at x = 0.5, from the
    // section's formula.
    {
        NacaSpec naca;
        naca.code = "0012";
        const double x = 0.5;
        const double yt = 0.6 * (0.2969 * std::sqrt(x) - 0.1260 * x - 0.3516 * x * x + 0.2843 * x * x * x -
                                 0.1036 * x * x * x * x);
        out.push_back(with_cut("naca", CurveSpec{"hole", naca, std::nullopt, std::nullopt, std::string("hole")}, "hole",
                               {x, yt}, {x, 1.0}));
    }
    // An airfoil file: at one of its points (the curve interpolates them; the file's chord
    // frame is already the placement's).
    {
        AirfoilSpec af;
        af.coordinates = selig_section(40);
        const double x = 0.5;
        out.push_back(with_cut("airfoil", CurveSpec{"hole", af, std::nullopt, std::nullopt, std::string("hole")}, "hole",
                               {x, 0.3 * std::sqrt(x) * (1.0 - x)}, {x, 1.0}));
    }
    return out;
}

double angle_at(Vec2 apex, Vec2 a, Vec2 b) {
    return std::atan2(std::fabs(cross(a - apex, b - apex)), dot(a - apex, b - apex)) * 180.0 / std::numbers::pi;
}

DensitySpec constant(double h) {
    DensitySpec d;
    d.size = h;
    return d;
}

}  // namespace

class TouchingEveryCurveType : public ::testing::TestWithParam<int> {};

TEST_P(TouchingEveryCurveType, TheTouchedCurveIsSplitAndTheMeshFollowsBoth) {
    const TouchCase c = touch_cases()[static_cast<size_t>(GetParam())];
    SCOPED_TRACE(c.name);
    const Domain d = build_domain(c.domain);

    // Two parts with the curve's name and tag, joined at T.
    const std::vector<CurveId>& parts = d.curve_parts(c.touched);
    ASSERT_EQ(parts.size(), 2u);
    const DomainCurve& first = d.curves()[parts[0]];
    const DomainCurve& second = d.curves()[parts[1]];
    EXPECT_EQ(first.name, c.touched);
    EXPECT_EQ(second.name, c.touched);
    EXPECT_EQ(first.tag, second.tag);
    ASSERT_EQ(first.to, second.from);
    EXPECT_EQ(d.points()[first.to].position, c.t);
    const CurveId cut = *d.find_curve("cut");
    EXPECT_TRUE(d.curves()[cut].from == first.to || d.curves()[cut].to == first.to);
    // Each part is the curve between its ends, from the curve's start through T to its end.
    EXPECT_LE(distance(first.geometry->end(), c.t), 1e-9 * d.extent());
    EXPECT_LE(distance(second.geometry->start(), c.t), 1e-9 * d.extent());
    // The parts follow each other in their loop.
    bool consecutive = false;
    for (const DomainLoop& l : d.loops())
        for (size_t i = 0; i < l.items.size(); ++i) {
            const CurveUse& u = l.items[i];
            const CurveUse& v = l.items[(i + 1) % l.items.size()];
            consecutive |= (u.curve == parts[0] && v.curve == parts[1] && !u.reversed && !v.reversed) ||
                           (u.curve == parts[1] && v.curve == parts[0] && u.reversed && v.reversed);
        }
    EXPECT_TRUE(consecutive);

    for (const Triangulator tri : {Triangulator::Delaunay, Triangulator::AdvancingFront}) {
        MeshOptions opt;
        opt.triangulator = tri;
        const MeshResult r = generate_mesh(d, constant(0.08), opt);
        const Mesh& m = r.mesh;
        for (const std::string& v : check_mesh(m)) ADD_FAILURE() << v;
        // T is a mesh point where the cut and both parts of the touched curve meet.
        VertexId at = UINT32_MAX;
        for (VertexId v = 0; v < m.point_count(); ++v)
            if (m.point(v) == c.t) at = v;
        ASSERT_NE(at, UINT32_MAX);
        std::multiset<CurveId> meeting;
        for (const MeshEdge& e : m.edges)
            if (e.a == at || e.b == at) meeting.insert(e.curve);
        EXPECT_EQ(meeting, (std::multiset<CurveId>{parts[0], parts[1], cut}));
        // No sliver there: the curves meet at right angles, so the triangles around T are
        // far from flat (the unsplit arc gave angles of 1.5 degrees).
        for (const Triangle& t : m.triangles) {
            for (int k = 0; k < 3; ++k) {
                if (t.v[static_cast<size_t>(k)] != at) continue;
                const Vec2 p0 = m.point(t.v[0]), p1 = m.point(t.v[1]), p2 = m.point(t.v[2]);
                EXPECT_GT(angle_at(p0, p1, p2), 15.0);
                EXPECT_GT(angle_at(p1, p2, p0), 15.0);
                EXPECT_GT(angle_at(p2, p0, p1), 15.0);
            }
        }
    }
}

INSTANTIATE_TEST_SUITE_P(AllTypes, TouchingEveryCurveType, ::testing::Range(0, 6),
                         [](const ::testing::TestParamInfo<int>& param) {
                             return touch_cases()[static_cast<size_t>(param.param)].name;
                         });

TEST(Touching, ACutThroughAHoleIsStillRefused) {
    TouchCase c = touch_cases()[1];  // the arc
    // From outside the circle on one side to outside on the other: through the hole.
    c.domain.points[c.domain.points.size() - 2].second = {-0.5, 0.0};
    try {
        build_domain(c.domain);
        FAIL() << "accepted";
    } catch (const GeometryError& e) {
        EXPECT_EQ(e.kind(), GeometryErrorKind::CurvesCross);
        std::set<std::string> names;
        for (const Subject& s : e.subjects()) names.insert(s.name);
        EXPECT_TRUE(names.count("cut"));
        EXPECT_TRUE(names.count("hole"));
    }
}

TEST(Touching, AnEndNearButNotOnACurveIsNotATouch) {
    // 1e-6 of the extent off the bottom side: a gap, not a touch (the tolerance is 1e-9).
    TouchCase c = touch_cases()[0];
    c.domain.points[c.domain.points.size() - 2].second = {0.5, -2.0 + 1e-6 * std::sqrt(41.0)};
    const Domain d = build_domain(c.domain);
    EXPECT_EQ(d.curve_parts("bottom").size(), 1u);
}

TEST(Touching, TwoCutsFromOnePointSplitTheCurveOnce) {
    TouchCase c = touch_cases()[0];
    c.domain.points.push_back({"R", {1.5, -1.0}});
    c.domain.curves.push_back(line("cut2", "T", "R", "cut"));
    c.domain.embedded.push_back("cut2");
    const Domain d = build_domain(c.domain);
    EXPECT_EQ(d.curve_parts("bottom").size(), 2u);
    const MeshResult r = generate_mesh(d, constant(0.1));
    for (const std::string& v : check_mesh(r.mesh)) ADD_FAILURE() << v;
}

TEST(Touching, AnEmbeddedCurveEndingOnAnotherSplitsItAndKeepsItsPlace) {
    // A T junction: "stem" ends in the middle of the embedded "bar".
    DomainSpec s = box();
    s.points.push_back({"L", {-1, 0}});
    s.points.push_back({"R", {2, 0}});
    s.points.push_back({"S", {0.5, 1.5}});
    s.points.push_back({"J", {0.5, 0}});
    s.curves.push_back(line("bar", "L", "R", "bar"));
    s.curves.push_back(line("stem", "S", "J", "stem"));
    s.embedded = {"bar", "stem"};
    const Domain d = build_domain(s);
    ASSERT_EQ(d.curve_parts("bar").size(), 2u);
    EXPECT_EQ(d.embedded().size(), 3u);
    const MeshResult r = generate_mesh(d, constant(0.1));
    for (const std::string& v : check_mesh(r.mesh)) ADD_FAILURE() << v;

    // An error about a later embedded curve still names its own place in the list (2), though
    // the bar before it is now two curves.
    s.points.push_back({"H", {2.5, 1.5}});
    s.curves.push_back(arc("hole", "H", "H", {2.5, 1.2}));
    s.loops.push_back(loop({"hole"}));
    s.points.push_back({"U", {2.45, 1.2}});
    s.points.push_back({"V", {2.55, 1.2}});
    s.curves.push_back(line("lost", "U", "V"));
    s.embedded.push_back("lost");
    try {
        build_domain(s);
        FAIL() << "accepted";
    } catch (const GeometryError& e) {
        EXPECT_EQ(e.kind(), GeometryErrorKind::EmbeddedOutside);
        bool indexed = false;
        for (const Subject& sub : e.subjects())
            if (sub.kind == Subject::Kind::Embedded) indexed = sub.index == 2;
        EXPECT_TRUE(indexed);
    }
}

TEST(Touching, ADensityGivenByTheCurvesNameHoldsOnEveryPart) {
    TouchCase c = touch_cases()[0];
    DensitySpec rho = constant(0.1);
    rho.curves = {{"bottom", 0.01}};
    const Domain d = build_domain(c.domain);
    const MeshResult r = generate_mesh(d, rho);
    size_t on_bottom = 0;
    const std::vector<CurveId>& parts = d.curve_parts("bottom");
    for (const MeshEdge& e : r.mesh.edges)
        on_bottom += std::find(parts.begin(), parts.end(), e.curve) != parts.end();
    // 5 units at 0.01: 500 edges (each part of 2.5 gets 250).
    EXPECT_NEAR(static_cast<double>(on_bottom), 500.0, 5.0);
}
