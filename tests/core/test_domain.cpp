// The domain model: construction, orientation and every validation error.

#include <gtest/gtest.h>

#include <numbers>

#include "fixtures.hpp"
#include "meshd/core/errors.hpp"
#include "meshd/core/mesher.hpp"

using namespace meshd::core;
using namespace meshd::test;

namespace {

GeometryError error_of(const DomainSpec& spec) {
    try {
        build_domain(spec);
    } catch (const GeometryError& e) {
        return e;
    }
    ADD_FAILURE() << "domain accepted";
    return GeometryError(GeometryErrorKind::BadParameter, "none");
}

bool names_curve(const GeometryError& e, const std::string& name) {
    for (const auto& s : e.subjects())
        if (s.kind == Subject::Kind::Curve && s.name == name) return true;
    return false;
}

}  // namespace

TEST(Domain, SquareIsBuiltCounterClockwise) {
    const Domain d = build_domain(unit_square());
    ASSERT_EQ(d.loops().size(), 1u);
    EXPECT_FALSE(d.loops()[0].hole);
    EXPECT_NEAR(d.loops()[0].area, 1.0, 1e-12);
    EXPECT_EQ(d.tags(), (std::vector<std::string>{"wall", "outlet", "inlet"}));
    EXPECT_EQ(d.curves()[0].tag, d.curves()[2].tag);
    EXPECT_NEAR(d.extent(), std::sqrt(2.0), 1e-12);
}

TEST(Domain, ClockwiseOuterLoopIsReversed) {
    DomainSpec s = unit_square();
    s.loops = {loop({"-left", "-top", "-right", "-bottom"})};
    const Domain d = build_domain(s);
    EXPECT_GT(d.loops()[0].area, 0.0);
    // After reversal the first item is traversed forwards again.
    for (const auto& u : d.loops()[0].items) EXPECT_FALSE(u.reversed);
}

TEST(Domain, AirfoilInFarFieldHasACcwOuterLoopAndAClockwiseHole) {
    const Domain d = build_domain(naca_in_circle());
    ASSERT_EQ(d.loops().size(), 2u);
    EXPECT_FALSE(d.loops()[0].hole);
    EXPECT_TRUE(d.loops()[1].hole);
    EXPECT_GT(d.loops()[0].area, 0.0);
    EXPECT_LT(d.loops()[1].area, 0.0);
    EXPECT_EQ(d.loops()[0].spec_index, 0);
    EXPECT_NEAR(d.loops()[0].area, std::numbers::pi * 400.0, 0.1);
    // The NACA contour is given counter-clockwise, so as a hole it is traversed backwards.
    EXPECT_TRUE(d.loops()[1].items[0].reversed);
    EXPECT_EQ(d.hole_count(), 1u);
}

TEST(Domain, LoopOrderDoesNotMatterForTheOuterLoop) {
    DomainSpec s = naca_in_circle();
    s.loops = {loop({"wing"}), loop({"farfield"})};
    const Domain d = build_domain(s);
    EXPECT_EQ(d.loops()[0].spec_index, 1);
    EXPECT_TRUE(d.loops()[1].hole);
}

TEST(Domain, EmbeddedCurveTouchingTheBoundaryAtSharedPoints) {
    DomainSpec s = unit_square();
    s.points.push_back({"M", {0.5, 0.5}});
    s.curves.push_back(line("wake", "C", "M"));
    s.embedded = {"wake"};
    const Domain d = build_domain(s);
    ASSERT_EQ(d.embedded().size(), 1u);
    EXPECT_EQ(d.curves()[d.embedded()[0]].name, "wake");
}

TEST(DomainErrors, UnknownPointAndCurve) {
    DomainSpec s = unit_square();
    s.curves[1].to = "Z";
    auto e = error_of(s);
    EXPECT_EQ(e.kind(), GeometryErrorKind::UnknownPoint);
    ASSERT_FALSE(e.subjects().empty());
    EXPECT_EQ(e.subjects()[0].name, "right");
    EXPECT_EQ(e.subjects()[0].field, (std::vector<std::string>{"to"}));

    s = unit_square();
    s.loops[0][2].curve = "roof";
    e = error_of(s);
    EXPECT_EQ(e.kind(), GeometryErrorKind::UnknownCurve);
    EXPECT_EQ(e.subjects()[0].kind, Subject::Kind::Loop);
    EXPECT_EQ(e.subjects()[0].index, 0);
    EXPECT_EQ(e.subjects()[0].field, (std::vector<std::string>{"2"}));
}

TEST(DomainErrors, LoopThatDoesNotClose) {
    DomainSpec s = unit_square();
    s.loops = {loop({"bottom", "top", "right", "left"})};
    auto e = error_of(s);
    EXPECT_EQ(e.kind(), GeometryErrorKind::LoopNotClosed);
    EXPECT_TRUE(names_curve(e, "bottom"));
    EXPECT_TRUE(names_curve(e, "top"));
    s.loops = {loop({"bottom", "right", "top"})};
    EXPECT_EQ(error_of(s).kind(), GeometryErrorKind::LoopNotClosed);
    s.loops = {{}};
    EXPECT_EQ(error_of(s).kind(), GeometryErrorKind::EmptyLoop);
    s.loops = {};
    EXPECT_EQ(error_of(s).kind(), GeometryErrorKind::NoOuterLoop);
}

TEST(DomainErrors, CurveUsedTwice) {
    DomainSpec s = unit_square();
    s.embedded = {"top"};
    EXPECT_EQ(error_of(s).kind(), GeometryErrorKind::CurveReused);
}

TEST(DomainErrors, CrossingCurves) {
    // A bow tie: the diagonals cross.
    DomainSpec s;
    s.points = {{"A", {0, 0}}, {"B", {1, 0}}, {"C", {1, 1}}, {"D", {0, 1}}};
    s.curves = {line("ac", "A", "C"), line("cb", "C", "B"), line("bd", "B", "D"), line("da", "D", "A")};
    s.loops = {loop({"ac", "cb", "bd", "da"})};
    auto e = error_of(s);
    EXPECT_EQ(e.kind(), GeometryErrorKind::CurvesCross);
    EXPECT_TRUE(names_curve(e, "ac"));
    EXPECT_TRUE(names_curve(e, "bd"));
}

TEST(DomainErrors, CurveCrossingItself) {
    DomainSpec s;
    s.points = {{"A", {0, 0}}, {"B", {4, 0}}};
    s.curves = {{"loopy", BSplineShape{{{0, 0}, {6, 3}, {-2, 3}, {4, 0}}, 3, std::nullopt}, "A", "B", {}},
                line("base", "B", "A")};
    s.loops = {loop({"loopy", "base"})};
    auto e = error_of(s);
    EXPECT_EQ(e.kind(), GeometryErrorKind::SelfIntersection);
    EXPECT_TRUE(names_curve(e, "loopy"));
}

TEST(DomainErrors, HoleOutsideAndHolesOverlapping) {
    DomainSpec s = unit_square();
    s.points.push_back({"P", {2.0, 0.5}});
    s.curves.push_back(arc("c1", "P", "P", {2.2, 0.5}));
    s.loops.push_back(loop({"c1"}));
    auto e = error_of(s);
    EXPECT_EQ(e.kind(), GeometryErrorKind::HoleOutside);
    EXPECT_EQ(e.subjects()[0].index, 1);

    s = unit_square();
    s.points.push_back({"P", {0.2, 0.5}});
    s.points.push_back({"Q", {0.4, 0.5}});
    s.curves.push_back(arc("big", "P", "P", {0.5, 0.5}));
    s.curves.push_back(arc("small", "Q", "Q", {0.5, 0.5}));
    s.loops.push_back(loop({"big"}));
    s.loops.push_back(loop({"small"}));
    e = error_of(s);
    EXPECT_EQ(e.kind(), GeometryErrorKind::HolesOverlap);

    // Overlapping circles cross.
    s = unit_square();
    s.points.push_back({"P", {0.2, 0.5}});
    s.points.push_back({"Q", {0.4, 0.5}});
    s.curves.push_back(arc("h1", "P", "P", {0.35, 0.5}));
    s.curves.push_back(arc("h2", "Q", "Q", {0.55, 0.5}));
    s.loops.push_back(loop({"h1"}));
    s.loops.push_back(loop({"h2"}));
    EXPECT_EQ(error_of(s).kind(), GeometryErrorKind::CurvesCross);
}

TEST(DomainErrors, EmbeddedOutside) {
    DomainSpec s = unit_square();
    s.points.push_back({"P", {2, 2}});
    s.points.push_back({"Q", {3, 2}});
    s.curves.push_back(line("stray", "P", "Q"));
    s.embedded = {"stray"};
    EXPECT_EQ(error_of(s).kind(), GeometryErrorKind::EmbeddedOutside);
}

TEST(DomainErrors, ZeroLengthNonFiniteCoincident) {
    DomainSpec s = unit_square();
    s.points[1].second = {0, 0};  // B on A
    auto e = error_of(s);
    EXPECT_TRUE(e.kind() == GeometryErrorKind::ZeroLength || e.kind() == GeometryErrorKind::CoincidentPoints);

    s = unit_square();
    s.points[2].second = {NAN, 1};
    e = error_of(s);
    EXPECT_EQ(e.kind(), GeometryErrorKind::NonFinite);
    EXPECT_EQ(e.subjects()[0].kind, Subject::Kind::Point);
    EXPECT_EQ(e.subjects()[0].name, "C");

    s = unit_square();
    s.points[2].second = {1e308, 1};
    EXPECT_NE(error_of(s).kind(), GeometryErrorKind::BadParameter);  // refused, not crashed

    s = unit_square();
    s.points.push_back({"E", {1, 1}});  // a second name for C
    s.curves[2].from = "E";
    e = error_of(s);
    EXPECT_EQ(e.kind(), GeometryErrorKind::CoincidentPoints);
}

TEST(DomainErrors, ArcEndsOffCircleNamesTheCurve) {
    DomainSpec s = unit_square();
    s.curves[1] = arc("right", "B", "C", {1.2, 0.5});
    s.curves[1].shape = ArcShape{{1.0, 0.4}, ArcDirection::Ccw};
    auto e = error_of(s);
    EXPECT_EQ(e.kind(), GeometryErrorKind::ArcEndsOffCircle);
    EXPECT_TRUE(names_curve(e, "right"));
}

TEST(DomainErrors, BSplineEndsMustMatchNamedPoints) {
    DomainSpec s = unit_square();
    s.curves[2] = {"top", BSplineShape{{{1, 1}, {0.5, 1.2}, {0.1, 1}}, 2, std::nullopt}, "C", "D", {}};
    auto e = error_of(s);
    EXPECT_EQ(e.kind(), GeometryErrorKind::EndsMismatch);
    EXPECT_EQ(e.subjects()[0].field, (std::vector<std::string>{"to"}));
}

TEST(DomainErrors, TooFewControlPointsNamesTheField) {
    DomainSpec s = unit_square();
    s.curves[2] = {"top", BSplineShape{{{1, 1}, {0, 1}}, 3, std::nullopt}, "C", "D", {}};
    auto e = error_of(s);
    EXPECT_EQ(e.kind(), GeometryErrorKind::TooFewControlPoints);
    EXPECT_EQ(e.subjects()[0].name, "top");
    EXPECT_EQ(e.subjects()[0].field, (std::vector<std::string>{"control_points"}));
}

TEST(Domain, BSplineWithoutNamedEndsJoinsNamedPointsAtItsEnds) {
    DomainSpec s = unit_square();
    s.curves[2] = {"top", BSplineShape{{{1, 1}, {0.5, 1.2}, {0, 1}}, 2, std::nullopt}, {}, {}, {}};
    const Domain d = build_domain(s);
    EXPECT_EQ(d.points()[d.curves()[2].from].name, "C");
    EXPECT_EQ(d.points()[d.curves()[2].to].name, "D");
}

// Found while fuzzing the triangulation with subnormal coordinates: the exact predicates
// assume their products do not underflow, and the in-circle test multiplies four coordinate
// differences. A square 1e-160 wide hung the pipeline; domains under 1e-30 across are refused
// (422), while one 1e-29 across still meshes.
TEST(Domain, TooSmallToComputeWithIsRefused) {
    auto square = [](double side) {
        DomainSpec s = unit_square();
        for (auto& p : s.points) p.second = side * p.second;
        return s;
    };
    try {
        build_domain(square(1e-160));
        FAIL() << "no error";
    } catch (const GeometryError& e) {
        EXPECT_EQ(e.kind(), GeometryErrorKind::ZeroLength);
        EXPECT_NE(std::string(e.what()).find("below 1e-30"), std::string::npos) << e.what();
    }
    DensitySpec d;
    d.size = 1e-30;
    const MeshResult r = generate_mesh(square(1e-29), d);
    for (const auto& v : check_mesh(r.mesh)) ADD_FAILURE() << v;
    EXPECT_GT(r.mesh.point_count(), 4u);
}

// Many holes against an outer loop of many edges: each hole is asked about once, against an
// index of the outer loop's edges by horizontal bands (a plain scan cost holes x edges). The
// answers must be those of the definition: a hole moved outside, or into another, is named.
TEST(Domain, ManyHolesInsideALongOuterLoopOneOutsideOneInAnother) {
    DomainSpec s;
    SplineShape outer;
    for (int i = 0; i <= 2000; ++i) {
        const double t = 2.0 * std::numbers::pi * (i % 2000) / 2000.0;
        const double r = 10.0 + 0.3 * std::sin(7.0 * t);  // a wavy circle
        outer.through.push_back({r * std::cos(t), r * std::sin(t)});
    }
    s.curves.push_back({"outer", outer, std::nullopt, std::nullopt, std::string("far")});
    s.loops.push_back(loop({"outer"}));
    int n = 0;
    for (int i = -12; i <= 12; ++i)
        for (int j = -12; j <= 12; ++j) {
            if (i * i + j * j > 12 * 12) continue;
            const std::string h = "h" + std::to_string(n++);
            const Vec2 c{0.6 * i, 0.6 * j};
            s.points.push_back({h, c + Vec2{0.1, 0.0}});
            s.curves.push_back(arc(h, h, h, c));
            s.loops.push_back(loop({h.c_str()}));
        }
    ASSERT_GT(n, 400);
    const DomainSpec base = s;
    const Domain d = build_domain(s);
    EXPECT_EQ(d.hole_count(), static_cast<size_t>(n));
    // Hole 200 (point 200, curve and loop 201) moved beyond the outer loop.
    const Vec2 away{11.0, 0.0};
    s.points[200].second = away + Vec2{0.1, 0.0};
    std::get<ArcShape>(s.curves[201].shape).center = away;
    GeometryError e = error_of(s);
    EXPECT_EQ(e.kind(), GeometryErrorKind::HoleOutside);
    ASSERT_FALSE(e.subjects().empty());
    EXPECT_EQ(e.subjects()[0].index, 201);
    // Hole 300 shrunk into hole 100: named as inside it.
    s = base;
    const Vec2 c100 = std::get<ArcShape>(s.curves[101].shape).center;
    s.points[300].second = c100 + Vec2{0.05, 0.0};
    std::get<ArcShape>(s.curves[301].shape).center = c100;
    e = error_of(s);
    EXPECT_EQ(e.kind(), GeometryErrorKind::HolesOverlap);
    ASSERT_EQ(e.subjects().size(), 2u);
    EXPECT_EQ(e.subjects()[0].index, 301);
    EXPECT_EQ(e.subjects()[1].index, 101);
}
