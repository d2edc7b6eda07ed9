// Airfoil coordinate files: both layouts, either order, duplicated leading edge, blunt
// trailing edges, and text that is not an airfoil.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <sstream>

#include "geometry/curve.hpp"
#include "meshd/core/errors.hpp"

using namespace meshd::core;

namespace {

// NACA 0012 points from the formula: a4 chooses a closed (0.1036) or blunt (0.1015) edge.
std::vector<Vec2> naca_surface(bool upper, int n, double a4) {
    std::vector<Vec2> pts;
    for (int i = 0; i <= n; ++i) {
        const double b = std::numbers::pi * i / n;
        const double x = 0.5 * (1 - std::cos(b));
        const double yt = 0.6 * (0.2969 * std::sqrt(x) - 0.1260 * x - 0.3516 * x * x +
                                 0.2843 * x * x * x - a4 * x * x * x * x);
        pts.push_back({x, upper ? yt : -yt});
    }
    return pts;  // leading edge to trailing edge
}

std::string selig(double a4, bool lower_first = false) {
    std::ostringstream os;
    os.precision(10);
    os << "NACA 0012 test section\n";
    auto up = naca_surface(!lower_first, 60, a4), lo = naca_surface(lower_first, 60, a4);
    for (auto it = up.rbegin(); it != up.rend(); ++it) os << "  " << it->x << "  " << it->y << "\n";
    for (size_t i = 1; i < lo.size(); ++i) os << "  " << lo[i].x << "  " << lo[i].y << "\n";
    return os.str();
}

std::string lednicer(double a4) {
    std::ostringstream os;
    os.precision(10);
    os << "NACA 0012 LEDNICER\n       61.       61.\n\n";
    for (auto p : naca_surface(true, 60, a4)) os << " " << p.x << " " << p.y << "\n";
    os << "\n";
    for (auto p : naca_surface(false, 60, a4)) os << " " << p.x << " " << p.y << "\n";
    return os.str();
}

double max_distance_to_formula(const Curve& c, double a4) {
    double worst = 0;
    for (int i = 1; i < 400; ++i) {
        const Vec2 p = c.point(c.t_begin() + (c.t_end() - c.t_begin()) * i / 400.0);
        if (p.x <= 0.0 || p.x > 1.0) continue;
        const double x = p.x;
        const double yt = 0.6 * (0.2969 * std::sqrt(x) - 0.1260 * x - 0.3516 * x * x +
                                 0.2843 * x * x * x - a4 * x * x * x * x);
        worst = std::fmax(worst, std::fabs(std::fabs(p.y) - yt));
    }
    return worst;
}

GeometryErrorKind kind_of(const std::string& text) {
    try {
        parse_airfoil_dat(text);
    } catch (const GeometryError& e) {
        return e.kind();
    }
    ADD_FAILURE() << "accepted:\n" << text;
    return GeometryErrorKind::BadParameter;
}

}  // namespace

TEST(AirfoilDat, SeligIsParsedAndFollowsTheSection) {
    const auto parsed = parse_airfoil_dat(selig(0.1036));
    EXPECT_EQ(parsed.name, "NACA 0012 test section");
    EXPECT_FALSE(parsed.lednicer);
    EXPECT_EQ(parsed.points.size(), 121u);
    auto c = make_airfoil({selig(0.1036), {}, TrailingEdge::Open});
    EXPECT_EQ(c->start(), c->end());
    EXPECT_LT(max_distance_to_formula(*c, 0.1036), 2e-4);
}

TEST(AirfoilDat, LednicerGivesTheSameContourWithOneLeadingEdgePoint) {
    const auto s = parse_airfoil_dat(selig(0.1036));
    const auto l = parse_airfoil_dat(lednicer(0.1036));
    EXPECT_TRUE(l.lednicer);
    ASSERT_EQ(l.points.size(), s.points.size());  // the leading edge appears once
    for (size_t i = 0; i < s.points.size(); ++i) EXPECT_NEAR(distance(l.points[i], s.points[i]), 0.0, 1e-9);
}

TEST(AirfoilDat, EitherOrderIsAccepted) {
    auto a = make_airfoil({selig(0.1036, true), {}, TrailingEdge::Open});
    EXPECT_LT(max_distance_to_formula(*a, 0.1036), 2e-4);
}

TEST(AirfoilDat, BluntTrailingEdgeKeptOrClosed) {
    const std::string text = selig(0.1015);
    auto open = make_airfoil({text, {}, TrailingEdge::Open});
    EXPECT_EQ(open->start(), open->end());
    ASSERT_EQ(open->corners().size(), 1u);  // the base line starts at the lower edge
    const Vec2 lower_te = open->point(open->corners()[0]);
    EXPECT_NEAR(distance(open->start(), lower_te), 2 * 0.6 * (0.2969 - 0.1260 - 0.3516 + 0.2843 - 0.1015), 1e-9);
    auto closed = make_airfoil({text, {}, TrailingEdge::Closed});
    EXPECT_EQ(closed->start(), closed->end());
    EXPECT_TRUE(closed->corners().empty());
    EXPECT_NEAR(distance(closed->start(), {1, 0}), 0.0, 1e-12);
}

TEST(AirfoilDat, PlacementScalesRotatesAndMoves) {
    auto c = make_airfoil({selig(0.1036), {2.0, {1.0, 1.0}, 90.0}, TrailingEdge::Open});
    // Nose up by 90 degrees: the trailing edge is straight below the leading edge.
    EXPECT_NEAR(distance(c->start(), {1.0, -1.0}), 0.0, 1e-12);
}

TEST(AirfoilDat, HeaderFormatsAndFortranNumbers) {
    std::string text = "# comment line\nMy foil\n";
    for (auto p : naca_surface(true, 20, 0.1036)) (void)p;
    auto up = naca_surface(true, 20, 0.1036), lo = naca_surface(false, 20, 0.1036);
    std::ostringstream os;
    os.precision(12);
    for (auto it = up.rbegin(); it != up.rend(); ++it) os << it->x << "D0, " << it->y << "\r\n";
    for (size_t i = 0; i < lo.size(); ++i) os << lo[i].x << "\t" << lo[i].y << "\n";  // LE repeated
    const auto parsed = parse_airfoil_dat(text + os.str());
    EXPECT_EQ(parsed.name, "# comment line");
    EXPECT_EQ(parsed.points.size(), 41u);
}

TEST(AirfoilDat, TextThatIsNotAnAirfoilIsRefused) {
    EXPECT_EQ(kind_of(""), GeometryErrorKind::BadAirfoil);
    EXPECT_EQ(kind_of("hello world\nthis is not a list of points\n"), GeometryErrorKind::BadAirfoil);
    EXPECT_EQ(kind_of("foil\n1 0\n0.5 0.1\n0 0\n0.5 -0.1\n1 0\n"), GeometryErrorKind::BadAirfoil);  // too few
    // Three columns.
    EXPECT_EQ(kind_of("foil\n1 0 0\n0.5 0.1 0\n0 0 0\n0.5 -0.1 0\n1 0 0\n0.7 0.1 0\n0.2 0 1\n"),
              GeometryErrorKind::BadAirfoil);
    // Text inside the data.
    std::string broken = selig(0.1036);
    broken.insert(broken.find("\n", 200) + 1, "oops\n");
    EXPECT_EQ(kind_of(broken), GeometryErrorKind::BadAirfoil);
    // A straight run of points: the leading edge is an end.
    std::ostringstream line;
    for (int i = 0; i <= 20; ++i) line << i / 20.0 << " " << 0.0 << "\n";
    EXPECT_EQ(kind_of(line.str()), GeometryErrorKind::BadAirfoil);
    // A figure of eight crosses itself.
    std::ostringstream eight;
    for (int i = 0; i <= 40; ++i) {
        const double t = 2 * std::numbers::pi * i / 40;
        eight << 0.5 + 0.5 * std::cos(t) << " " << 0.1 * std::sin(2 * t) << "\n";
    }
    EXPECT_EQ(kind_of(eight.str()), GeometryErrorKind::BadAirfoil);
    // Lednicer counts that do not match.
    std::string led = lednicer(0.1036);
    led.replace(led.find("61."), 3, "62.");
    EXPECT_EQ(kind_of(led), GeometryErrorKind::BadAirfoil);
    // Not finite.
    std::string nan = selig(0.1036);
    nan.replace(nan.find("\n", 100) + 1, 0, "nan 0.1\n");
    EXPECT_EQ(kind_of(nan), GeometryErrorKind::BadAirfoil);
}
