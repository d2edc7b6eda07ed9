// Every curve type against closed forms.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "geometry/bspline.hpp"
#include "geometry/curve.hpp"
#include "meshd/core/errors.hpp"

using namespace meshd::core;

namespace {

constexpr double kPi = std::numbers::pi;

double polyline_length(const Curve& c, int n) {
    double len = 0.0;
    Vec2 prev = c.point(c.t_begin());
    for (int i = 1; i <= n; ++i) {
        const Vec2 p = c.point(c.t_begin() + (c.t_end() - c.t_begin()) * i / n);
        len += distance(prev, p);
        prev = p;
    }
    return len;
}

void expect_derivative_matches_difference(const Curve& c, double tol) {
    const double span = c.t_end() - c.t_begin();
    for (int i = 1; i < 50; ++i) {
        const double t = c.t_begin() + span * (i + 0.37) / 51.0;
        const double h = 1e-6 * span;
        const Vec2 fd = (c.point(t + h) - c.point(t - h)) / (2 * h);
        const Vec2 d = c.derivative(t);
        EXPECT_NEAR(d.x, fd.x, tol * (1 + norm(d))) << "t=" << t;
        EXPECT_NEAR(d.y, fd.y, tol * (1 + norm(d))) << "t=" << t;
    }
}

GeometryErrorKind kind_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const GeometryError& e) {
        return e.kind();
    }
    ADD_FAILURE() << "no GeometryError thrown";
    return GeometryErrorKind::BadParameter;
}

}  // namespace

TEST(Line, EndsAndLength) {
    auto l = make_line({1, 2}, {4, 6});
    EXPECT_EQ(l->start(), (Vec2{1, 2}));
    EXPECT_EQ(l->end(), (Vec2{4, 6}));
    EXPECT_DOUBLE_EQ(curve_length(*l), 5.0);
    auto p = make_arc_length(*l);
    EXPECT_NEAR(distance(l->point(p->param_at(2.5)), {2.5, 4}), 0.0, 1e-14);
}

TEST(Line, ZeroLengthIsRefused) {
    EXPECT_EQ(kind_of([] { make_line({1, 1}, {1, 1}); }), GeometryErrorKind::ZeroLength);
    EXPECT_EQ(kind_of([] { make_line({NAN, 1}, {1, 1}); }), GeometryErrorKind::NonFinite);
}

TEST(Arc, PointsAreOnTheCircle) {
    const Vec2 c{0.5, -0.25};
    const double r = 3.0;
    const Vec2 a = c + Vec2{r * std::cos(0.3), r * std::sin(0.3)};
    const Vec2 b = c + Vec2{r * std::cos(2.1), r * std::sin(2.1)};
    for (auto dir : {ArcDirection::Ccw, ArcDirection::Cw}) {
        auto arc = make_arc(a, b, c, dir, false);
        for (int i = 0; i <= 100; ++i) {
            const double t = arc->t_end() * i / 100.0;
            EXPECT_NEAR(distance(arc->point(t), c), r, 1e-12 * r);
        }
        const double sweep = dir == ArcDirection::Ccw ? 1.8 : 2 * kPi - 1.8;
        EXPECT_NEAR(curve_length(*arc), r * sweep, 1e-12);
        EXPECT_EQ(arc->end(), b);
        expect_derivative_matches_difference(*arc, 1e-6);
    }
    // ccw passes through the top of the circle between 0.3 and 2.1 rad; cw through the bottom.
    EXPECT_GT(make_arc(a, b, c, ArcDirection::Ccw, false)->point(0.9).y, c.y);
    EXPECT_LT(make_arc(a, b, c, ArcDirection::Cw, false)->point(0.9).y, c.y);
}

TEST(Arc, FullCircle) {
    auto arc = make_arc({20.5, 0}, {20.5, 0}, {0.5, 0}, ArcDirection::Ccw, true);
    EXPECT_NEAR(curve_length(*arc), 2 * kPi * 20, 1e-10);
    EXPECT_EQ(arc->start(), arc->end());
    EXPECT_FALSE(arc->corner_at_ends());
}

// least_radius() is a lower bound of the radius of curvature |C'|^3 / |C' x C''| (C'' by
// central differences of the derivative) at every sampled parameter: the boundary skips the
// curvature cap below it. A line's is infinite; a curve without a known bound says 0.
TEST(Curve, LeastRadiusBoundsTheRadiusOfCurvature) {
    auto radius_at = [](const Curve& g, double t) {
        const double h = 1e-5 * (g.t_end() - g.t_begin());
        const Vec2 d = g.derivative(t), dd = (g.derivative(t + h) - g.derivative(t - h)) / (2.0 * h);
        const double k = std::fabs(cross(d, dd));
        return k > 0.0 ? std::pow(norm(d), 3.0) / k : HUGE_VAL;
    };
    std::vector<std::shared_ptr<const Curve>> curves;
    const Vec2 c{0.5, -0.25};
    for (const double r : {0.01, 3.0, 250.0})
        for (auto dir : {ArcDirection::Ccw, ArcDirection::Cw})
            curves.push_back(make_arc(c + Vec2{r * std::cos(0.3), r * std::sin(0.3)},
                                      c + Vec2{r * std::cos(2.1), r * std::sin(2.1)}, c, dir, false));
    curves.push_back(make_arc({20.5, 0}, {20.5, 0}, {0.5, 0}, ArcDirection::Cw, true));
    curves.push_back(make_part(curves.back(), 1.0, 2.5));
    curves.push_back(make_line({0, 0}, {3, 1}));
    for (const auto& g : curves) {
        const double bound = g->least_radius();
        ASSERT_GT(bound, 0.0);
        for (int i = 1; i < 100; ++i) {
            const double t = g->t_begin() + (g->t_end() - g->t_begin()) * i / 100.0;
            const double r = radius_at(*g, t);
            EXPECT_LE(bound, r * (1.0 + 1e-6)) << "at t = " << t;
            if (std::isfinite(r)) {
                EXPECT_GT(bound, 0.999 * r) << "an arc's bound is its radius";
            }
        }
    }
    EXPECT_EQ(make_line({0, 0}, {1, 1})->least_radius(), HUGE_VAL);
    NacaSpec naca;
    naca.code = "0012";
    EXPECT_EQ(make_naca(naca)->least_radius(), 0.0);  // not known: the cap is always measured
}

TEST(Arc, EndsOffTheCircleAreRefused) {
    EXPECT_EQ(kind_of([] { make_arc({1, 0}, {0, 1.001}, {0, 0}, ArcDirection::Ccw, false); }),
              GeometryErrorKind::ArcEndsOffCircle);
    // Within the relative tolerance 1e-9 is accepted.
    EXPECT_NO_THROW(make_arc({1, 0}, {0, 1 + 1e-11}, {0, 0}, ArcDirection::Ccw, false));
    EXPECT_EQ(kind_of([] { make_arc({0, 0}, {0, 0}, {0, 0}, ArcDirection::Ccw, true); }),
              GeometryErrorKind::ZeroLength);
}

TEST(BSpline, CubicBezierMatchesBernsteinForm) {
    const std::vector<Vec2> v{{0, 0}, {1, 2}, {3, 3}, {4, 0}};
    auto c = make_bspline(v, 3, std::vector<double>{0, 0, 0, 0, 1, 1, 1, 1});
    for (int i = 0; i <= 20; ++i) {
        const double t = i / 20.0, s = 1 - t;
        const Vec2 want = s * s * s * v[0] + 3 * s * s * t * v[1] + 3 * s * t * t * v[2] + t * t * t * v[3];
        EXPECT_NEAR(distance(c->point(t), want), 0.0, 1e-14);
        const Vec2 dwant = 3 * s * s * (v[1] - v[0]) + 6 * s * t * (v[2] - v[1]) + 3 * t * t * (v[3] - v[2]);
        EXPECT_NEAR(distance(c->derivative(t), dwant), 0.0, 1e-13);
    }
}

TEST(BSpline, PaperKnotsFromControlPolygon) {
    // Degree 1: the knots are the control polygon lengths K(V_i) (eq. 3.35), the curve is
    // the polygon itself and its parameter is the polygon length.
    const std::vector<Vec2> v{{0, 0}, {3, 0}, {3, 4}, {0, 4}};
    const auto knots = BSplineCurve::paper_knots(v, 1);
    EXPECT_EQ(knots, (std::vector<double>{0, 0, 3, 7, 10, 10}));
    auto c = make_bspline(v, 1, std::nullopt);
    EXPECT_NEAR(distance(c->point(5.0), {3, 2}), 0.0, 1e-14);
    // Degree 3: clamped on [0, M], interior knots inside and increasing.
    const std::vector<Vec2> w{{0, 0}, {1, 1}, {2, -1}, {3, 1}, {4, -1}, {5, 0}};
    const auto k3 = BSplineCurve::paper_knots(w, 3);
    ASSERT_EQ(k3.size(), w.size() + 4);
    for (size_t i = 1; i < k3.size(); ++i) EXPECT_LE(k3[i - 1], k3[i]);
    double m = 0;
    for (size_t i = 1; i < w.size(); ++i) m += distance(w[i - 1], w[i]);
    EXPECT_DOUBLE_EQ(k3.back(), m);
    auto c3 = make_bspline(w, 3, std::nullopt);
    EXPECT_EQ(c3->start(), w.front());
    EXPECT_EQ(c3->end(), w.back());
    expect_derivative_matches_difference(*c3, 1e-6);
}

TEST(BSpline, CornerAtRepeatedKnot) {
    // Two Bezier pieces meeting at (2, 0) with a kink.
    const std::vector<Vec2> v{{0, 0}, {1, 1}, {1.5, 1}, {2, 0}, {2.5, 1}, {3, 1}, {4, 0}};
    auto c = make_bspline(v, 3, std::vector<double>{0, 0, 0, 0, 1, 1, 1, 2, 2, 2, 2});
    ASSERT_EQ(c->corners().size(), 1u);
    EXPECT_DOUBLE_EQ(c->corners()[0], 1.0);
    EXPECT_EQ(c->point(1.0), (Vec2{2, 0}));
}

TEST(BSpline, ValidationErrors) {
    EXPECT_EQ(kind_of([] { make_bspline({{0, 0}, {1, 1}}, 3, std::nullopt); }),
              GeometryErrorKind::TooFewControlPoints);
    EXPECT_EQ(kind_of([] { make_bspline({{0, 0}, {1, 1}}, 0, std::nullopt); }), GeometryErrorKind::BadDegree);
    EXPECT_EQ(kind_of([] { make_bspline({{0, 0}, {1, 1}, {2, 0}}, 2, std::vector<double>{0, 0, 0, 1, 1}); }),
              GeometryErrorKind::BadKnots);
    EXPECT_EQ(kind_of([] { make_bspline({{0, 0}, {1, 1}, {2, 0}}, 2, std::vector<double>{0, 0, 0.5, 1, 1, 1}); }),
              GeometryErrorKind::BadKnots);
    EXPECT_EQ(kind_of([] { make_bspline({{0, 0}, {1, 1}, {2, 0}}, 2, std::vector<double>{0, 0, 0, 2, 1, 1}); }),
              GeometryErrorKind::BadKnots);
    EXPECT_EQ(kind_of([] { make_bspline({{0, 0}, {NAN, 1}, {2, 0}}, 2, std::nullopt); }),
              GeometryErrorKind::NonFinite);
    try {
        make_bspline({{0, 0}, {1, 1}, {2, INFINITY}}, 2, std::nullopt);
        FAIL() << "no error";
    } catch (const GeometryError& e) {
        EXPECT_EQ(e.kind(), GeometryErrorKind::NonFinite);
        ASSERT_EQ(e.subjects().size(), 1u);
        EXPECT_EQ(e.subjects()[0].field, (std::vector<std::string>{"control_points", "2"}));
    }
}

TEST(Spline, PassesThroughItsPoints) {
    std::vector<Vec2> pts;
    for (int i = 0; i <= 12; ++i) pts.push_back({i * 0.5, std::sin(i * 0.5)});
    auto c = make_spline_through(pts);
    const auto* b = c->as_bspline();
    ASSERT_NE(b, nullptr);
    // Node k sits at the knot of multiplicity 3 number k: check every given point is on it.
    std::vector<double> nodes{0.0};
    for (size_t k = 1; k < pts.size(); ++k) nodes.push_back(nodes.back() + distance(pts[k - 1], pts[k]));
    for (size_t k = 0; k < pts.size(); ++k) EXPECT_NEAR(distance(c->point(nodes[k]), pts[k]), 0.0, 1e-12);
    // Between the nodes it follows the sine closely.
    for (int i = 0; i < 60; ++i) {
        const Vec2 p = c->point(c->t_end() * (i + 0.5) / 60);
        EXPECT_NEAR(p.y, std::sin(p.x), 5e-3);
    }
    // C2: second differences of the derivative match across an interior node.
    const double t = nodes[5], h = 1e-5;
    const Vec2 d2l = (c->derivative(t - h) - c->derivative(t - 2 * h)) / h;
    const Vec2 d2r = (c->derivative(t + 2 * h) - c->derivative(t + h)) / h;
    EXPECT_NEAR(d2l.y, d2r.y, 1e-3);
    expect_derivative_matches_difference(*c, 1e-5);
}

TEST(Spline, ClosedWhenEndsCoincideAndSmoothThere) {
    std::vector<Vec2> pts;
    const int n = 24;
    for (int i = 0; i <= n; ++i) {
        const double a = 2 * kPi * i / n;
        pts.push_back({2 * std::cos(a), std::sin(a)});
    }
    pts.back() = pts.front();
    auto c = make_spline_through(pts);
    EXPECT_EQ(c->start(), c->end());
    EXPECT_FALSE(c->corner_at_ends());  // periodic: the tangent is continuous at the join
    const Vec2 d0 = c->derivative(c->t_begin()), d1 = c->derivative(c->t_end());
    EXPECT_NEAR(distance(d0, d1), 0.0, 1e-9);
    // Close to the ellipse everywhere.
    for (int i = 0; i < 200; ++i) {
        const Vec2 p = c->point(c->t_end() * i / 200.0);
        EXPECT_NEAR(p.x * p.x / 4 + p.y * p.y, 1.0, 2e-3);
    }
}

TEST(Spline, TooFewPoints) {
    EXPECT_EQ(kind_of([] { make_spline_through({{0, 0}}); }), GeometryErrorKind::TooFewControlPoints);
    EXPECT_EQ(kind_of([] { make_spline_through({{0, 0}, {0, 0}}); }), GeometryErrorKind::TooFewControlPoints);
}

TEST(ArcLength, InverseIsConsistent) {
    const std::vector<Vec2> w{{0, 0}, {1, 2}, {2, -1}, {3, 1}, {4, -1}, {5, 0}};
    auto c = make_bspline(w, 3, std::nullopt);
    auto p = make_arc_length(*c);
    EXPECT_NEAR(p->length(), polyline_length(*c, 200000), 1e-6);
    for (int i = 0; i <= 40; ++i) {
        const double s = p->length() * i / 40.0;
        EXPECT_NEAR(p->spacing_at(p->param_at(s)), s, 1e-10);
    }
}

TEST(ArcLength, ControlPolygonParametrisationIsMonotone) {
    const std::vector<Vec2> w{{0, 0}, {1, 2}, {2, -1}, {3, 1}, {4, -1}, {5, 0}};
    auto c = make_bspline(w, 3, std::nullopt);
    auto p = make_parametrisation(*c, SplineSpacing::ControlPolygon);
    double m = 0;
    for (size_t i = 1; i < w.size(); ++i) m += distance(w[i - 1], w[i]);
    EXPECT_DOUBLE_EQ(p->length(), m);
    double prev = -1;
    for (int i = 0; i <= 100; ++i) {
        const double t = p->param_at(m * i / 100.0);
        EXPECT_GE(t, prev);
        prev = t;
    }
    EXPECT_DOUBLE_EQ(p->param_at(m), c->t_end());
}

// ---------------------------------------------------------------------------------------
// NACA sections

namespace {

double naca4_thickness(double t, double x, double a4) {
    return 5 * t * (0.2969 * std::sqrt(x) - 0.1260 * x - 0.3516 * x * x + 0.2843 * x * x * x - a4 * x * x * x * x);
}

// Upper-surface parameter of the closed contour where the chordwise station is x.
double upper_param(double x) { return 1.0 - std::acos(1.0 - 2.0 * x) / kPi; }

}  // namespace

TEST(Naca, SymmetricThicknessMatchesFormula) {
    NacaSpec spec{"0012", {}, TrailingEdge::Closed, AirfoilSurface::Both};
    auto c = make_naca(spec);
    const Vec2 p = c->point(upper_param(0.3));
    EXPECT_NEAR(p.x, 0.3, 1e-14);
    EXPECT_NEAR(p.y, naca4_thickness(0.12, 0.3, 0.1036), 1e-14);
    // Lower surface mirrors it.
    const Vec2 q = c->point(2.0 - upper_param(0.3));
    EXPECT_NEAR(q.x, 0.3, 1e-14);
    EXPECT_NEAR(q.y, -p.y, 1e-14);
    EXPECT_NEAR(naca_section(spec, 0.3).thickness, naca4_thickness(0.12, 0.3, 0.1036), 1e-15);
    // Closed trailing edge: one point at (1, 0); leading edge at the origin.
    EXPECT_EQ(c->start(), c->end());
    EXPECT_NEAR(distance(c->start(), {1, 0}), 0.0, 1e-15);
    EXPECT_NEAR(distance(c->point(1.0), {0, 0}), 0.0, 1e-15);
    expect_derivative_matches_difference(*c, 1e-5);
}

TEST(Naca, OpenTrailingEdgeHasABase) {
    NacaSpec spec{"0012", {}, TrailingEdge::Open, AirfoilSurface::Both};
    auto c = make_naca(spec);
    const double gap = 2 * naca4_thickness(0.12, 1.0, 0.1015);
    EXPECT_GT(gap, 0.002);
    const Vec2 upper_te = c->start();
    EXPECT_NEAR(upper_te.y, gap / 2, 1e-14);
    EXPECT_EQ(c->start(), c->end());           // still a closed curve
    ASSERT_EQ(c->corners().size(), 1u);        // the lower trailing-edge corner
    EXPECT_NEAR(c->point(c->corners()[0]).y, -gap / 2, 1e-14);
    EXPECT_NEAR(curve_length(*c), polyline_length(*c, 400000), 1e-6);
}

TEST(Naca, PlacementChordLeadingEdgeAngle) {
    NacaSpec spec{"0012", {2.0, 1.0, 10.0}, TrailingEdge::Closed, AirfoilSurface::Both};
    spec.placement = {2.0, {3.0, -1.0}, 10.0};
    auto c = make_naca(spec);
    const double a = 10.0 * kPi / 180;
    // Nose up: the trailing edge is below the leading edge.
    const Vec2 te = c->start();
    EXPECT_NEAR(te.x, 3.0 + 2.0 * std::cos(a), 1e-14);
    EXPECT_NEAR(te.y, -1.0 - 2.0 * std::sin(a), 1e-14);
    const Vec2 p = c->point(upper_param(0.3));
    const Vec2 local{0.3 * 2.0, naca4_thickness(0.12, 0.3, 0.1036) * 2.0};
    EXPECT_NEAR(p.x, 3.0 + std::cos(a) * local.x + std::sin(a) * local.y, 1e-13);
    EXPECT_NEAR(p.y, -1.0 - std::sin(a) * local.x + std::cos(a) * local.y, 1e-13);
}

TEST(Naca, CamberedFourDigit) {
    NacaSpec spec{"2412", {}, TrailingEdge::Closed, AirfoilSurface::Both};
    const auto s = naca_section(spec, 0.4);
    EXPECT_NEAR(s.camber, 0.02, 1e-15);  // maximum camber m at p
    EXPECT_NEAR(s.slope, 0.0, 1e-15);
    EXPECT_NEAR(naca_section(spec, 0.2).camber, 0.02 / 0.16 * (0.8 * 0.2 - 0.04), 1e-15);
    auto c = make_naca(spec);
    // Thickness is laid off normal to the camber line: the midpoint of the upper and lower
    // surface points at the same beta lies on the camber line.
    const double u = upper_param(0.2);
    const Vec2 mid = 0.5 * (c->point(u) + c->point(2.0 - u));
    EXPECT_NEAR(mid.x, 0.2, 1e-14);
    EXPECT_NEAR(mid.y, naca_section(spec, 0.2).camber, 1e-14);
    expect_derivative_matches_difference(*c, 1e-5);
}

TEST(Naca, FiveDigitCamberPeaksAtItsDesignPosition) {
    for (const char* code : {"21012", "22012", "23012", "24012", "25012"}) {
        NacaSpec spec{code, {}, TrailingEdge::Closed, AirfoilSurface::Both};
        const double p = (code[1] - '0') / 20.0;
        // The maximum of the (non-reflexed) camber line is at p = P/20.
        double best_x = 0, best = -1;
        for (int i = 1; i < 20000; ++i) {
            const double x = i / 20000.0;
            const double yc = naca_section(spec, x).camber;
            if (yc > best) { best = yc; best_x = x; }
        }
        EXPECT_NEAR(best_x, p, 0.01) << code;
        // The camber line ends at the trailing edge.
        EXPECT_NEAR(naca_section(spec, 1.0).camber, 0.0, 1e-3) << code;
        // Slope is the derivative of the camber.
        for (double x : {0.05, 0.1, 0.3, 0.7}) {
            const double h = 1e-6;
            const double fd = (naca_section(spec, x + h).camber - naca_section(spec, x - h).camber) / (2 * h);
            EXPECT_NEAR(naca_section(spec, x).slope, fd, 1e-6) << code << " x=" << x;
        }
        auto c = make_naca(spec);
        expect_derivative_matches_difference(*c, 1e-5);
    }
    // 23012: design lift 0.3, camber line 230 (r = 0.2025, k1 = 15.957): y_c at r.
    NacaSpec s23{"23012", {}, TrailingEdge::Closed, AirfoilSurface::Both};
    const double r = 0.2025, k1 = 15.957;
    EXPECT_NEAR(naca_section(s23, r).camber, k1 * r * r * r * (1 - r) / 6, 1e-12);
}

TEST(Naca, SingleSurfaceForSymmetryPlanes) {
    NacaSpec spec{"0012", {}, TrailingEdge::Closed, AirfoilSurface::Upper};
    auto c = make_naca(spec);
    EXPECT_NEAR(distance(c->start(), {1, 0}), 0.0, 1e-15);
    EXPECT_EQ(c->end(), (Vec2{0, 0}));
    for (int i = 1; i < 20; ++i) EXPECT_GT(c->point(i / 20.0).y, 0.0);
    spec.surface = AirfoilSurface::Lower;
    auto l = make_naca(spec);
    for (int i = 1; i < 20; ++i) EXPECT_LT(l->point(i / 20.0).y, 0.0);
}

TEST(Naca, BadCodes) {
    for (const char* code : {"", "12", "001", "0a12", "2012", "0000", "26012", "21112", "23212"}) {
        NacaSpec spec{code, {}, TrailingEdge::Closed, AirfoilSurface::Both};
        EXPECT_EQ(kind_of([&] { make_naca(spec); }), GeometryErrorKind::BadNaca) << code;
    }
    NacaSpec spec{"0012", {}, TrailingEdge::Closed, AirfoilSurface::Both};
    spec.placement.chord = 0;
    EXPECT_EQ(kind_of([&] { make_naca(spec); }), GeometryErrorKind::BadParameter);
    spec.placement.chord = 1;
    spec.placement.angle_deg = NAN;
    EXPECT_EQ(kind_of([&] { make_naca(spec); }), GeometryErrorKind::NonFinite);
}

// A curve whose speed is not finite somewhere (what a point at 1e300 made of a spline) must
// be refused, not refined without end: the arc-length model has a budget of pieces.
TEST(ArcLength, ACurveWithoutAFiniteSpeedIsRefusedNotRefinedForever) {
    class Wild final : public Curve {
    public:
        CurveType type() const override { return CurveType::Spline; }
        double t_begin() const override { return 0.0; }
        double t_end() const override { return 1.0; }
        Vec2 point(double t) const override { return {t, 0.0}; }
        Vec2 derivative(double t) const override { return {t > 0.3 && t < 0.4 ? HUGE_VAL : 1.0, 0.0}; }
    } wild;
    try {
        curve_length(wild);
        FAIL() << "no error";
    } catch (const GeometryError& e) {
        EXPECT_EQ(e.kind(), GeometryErrorKind::BadParameter);
    }
}
