// The whole pipeline on many domains: mesh invariants, both triangulators giving the same
// triangles, smoothing never inverting, spacing against rho, determinism, cancellation.

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <numbers>
#include <random>

#include "fixtures.hpp"

#include "boundary/boundary.hpp"
#include "density/size_field.hpp"
#include "improve/smooth.hpp"
#include "kernel/memory.hpp"
#include "meshd/core/errors.hpp"
#include "meshd/core/mesher.hpp"
#include "pipeline/agreement.hpp"
#include "pipeline/estimate.hpp"
#include "random/random_domains.hpp"

using namespace meshd::core;
using namespace meshd::test;

namespace {

struct Case {
    std::string name;
    DomainSpec domain;
    DensitySpec density;
    double min_within_sqrt2;  // measured, with a margin: a regression guard
    // The smallest angle with the defaults: 30 degrees (issue 15's target).
    double min_angle = 30.0;
};

Case square() { return {"square", unit_square(), density_of("0.03"), 0.95}; }

Case annulus() {
    DomainSpec s;
    s.points = {{"P", {1, 0}}, {"Q", {0.3, 0}}};
    s.curves = {arc("outer", "P", "P", {0, 0}), arc("inner", "Q", "Q", {0, 0})};
    s.loops = {loop({"outer"}), loop({"inner"})};
    return {"annulus", s, density_of("0.01 + 0.05 * sqrt(x^2 + y^2)"), 0.95};
}

Case naca(const std::string& code) {
    DensitySpec d;
    d.curves = {{"farfield", std::string("0.4*sqrt(x^2+y^2)+0.2")},
                {"wing", std::string("0.003 + 0.05*sqrt((x+0.01)^2+y^2)")}};
    return {"naca" + code, naca_in_circle(code, 10.0), d, 0.95};
}

Case three_element() {
    return {"three-element", three_element_wing({1.03, -0.05}), density_of("0.004 + 0.08*sqrt((x-0.5)^2+y^2)"), 0.95};
}

Case plate_with_holes() {
    DomainSpec s = unit_square();
    for (auto& p : s.points) p.second = 10.0 * p.second;
    std::mt19937_64 rng(2024);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<std::pair<Vec2, double>> holes;
    while (holes.size() < 50) {
        const Vec2 c{0.6 + 8.8 * u(rng), 0.6 + 8.8 * u(rng)};
        const double r = 0.15 + 0.25 * u(rng);
        bool ok = true;
        for (const auto& [c2, r2] : holes) ok &= distance(c, c2) > r + r2 + 0.2;
        if (ok) holes.push_back({c, r});
    }
    for (size_t i = 0; i < holes.size(); ++i) {
        const std::string n = "h" + std::to_string(i);
        s.points.push_back({n, holes[i].first + Vec2{holes[i].second, 0.0}});
        s.curves.push_back(arc(n, n, n, holes[i].first, ArcDirection::Ccw, "hole"));
        s.loops.push_back(loop({n.c_str()}));
    }
    return {"plate-with-holes", s, density_of("0.1"), 0.95};
}

Case embedded_touching() {
    // The bottom side is split at M, where a wake line starts; a second embedded line runs
    // from the corner C into the domain.
    DomainSpec s;
    s.points = {{"A", {0, 0}}, {"M", {0.5, 0}}, {"B", {1, 0}}, {"C", {1, 1}}, {"D", {0, 1}},
                {"W", {0.5, 0.6}}, {"X", {0.7, 0.7}}};
    s.curves = {line("b1", "A", "M", "wall"), line("b2", "M", "B", "wall"), line("right", "B", "C"),
                line("top", "C", "D"), line("left", "D", "A"), line("wake", "M", "W", "wake"),
                line("cut", "C", "X", "cut")};
    s.loops = {loop({"b1", "b2", "right", "top", "left"})};
    s.embedded = {"wake", "cut"};
    // The cut leaves the corner C at 45 degrees: its first point and two points of the right
    // side made a triangle of 29.7 degrees until points on curves could slide along them.
    return {"embedded", s, density_of("0.02 + 0.05*sqrt((x-0.5)^2+(y-0.3)^2)"), 0.95};
}

std::vector<Case> cases() {
    return {square(), annulus(), naca("0012"), naca("23012"), three_element(), plate_with_holes(),
            embedded_touching()};
}


void expect_valid(const Mesh& m, const std::string& name) {
    const auto v = check_mesh(m);
    for (size_t i = 0; i < v.size() && i < 10; ++i) ADD_FAILURE() << name << ": " << v[i];
}

}  // namespace

class MesherCase : public ::testing::TestWithParam<int> {};

TEST_P(MesherCase, ValidMeshBothTriangulatorsAgreeSmoothingKeepsItValid) {
    const Case c = cases()[static_cast<size_t>(GetParam())];
    SCOPED_TRACE(c.name);
    const Domain dom = build_domain(c.domain);
    MeshOptions raw;
    raw.smoothing_iterations = 0;
    const MeshResult a = generate_mesh(dom, c.density, raw);
    expect_valid(a.mesh, c.name + " (delaunay)");
    EXPECT_GT(a.mesh.triangles.size(), 100u);
    raw.triangulator = Triangulator::AdvancingFront;
    const MeshResult b = generate_mesh(dom, c.density, raw);
    expect_valid(b.mesh, c.name + " (advancing front)");
    EXPECT_EQ(canonical(a.mesh.triangles), canonical(b.mesh.triangles));
    const MeshResult s = generate_mesh(dom, c.density);  // defaults: smoothing on
    expect_valid(s.mesh, c.name + " (smoothed)");
    EXPECT_GT(s.stats.smoothing_moves, 0u);
    // Corners never move; points on curves only along them.
    for (const std::string& e : fixed_points_kept(dom, s.mesh, a.mesh)) ADD_FAILURE() << c.name << ": " << e;
    // Spacing against rho, and quality, as figures with a floor.
    EXPECT_GE(s.quality.size_ratio_within_sqrt2, c.min_within_sqrt2);
    EXPECT_GE(s.quality.angle_min, c.min_angle);
    EXPECT_GT(s.quality.quality_mean, 0.95);
    EXPECT_GE(s.quality.quality_mean, a.quality.quality_mean - 1e-12);
    EXPECT_EQ(s.quality.triangles, s.mesh.triangles.size());
    EXPECT_EQ(s.quality.points, s.quality.boundary_points + s.quality.interior_points);
    std::printf("[ %s ] %zu points, %zu triangles, min angle %.1f, quality mean %.3f, within sqrt2 %.3f\n",
                c.name.c_str(), s.quality.points, s.quality.triangles, s.quality.angle_min, s.quality.quality_mean,
                s.quality.size_ratio_within_sqrt2);
}

INSTANTIATE_TEST_SUITE_P(Domains, MesherCase, ::testing::Range(0, 7));

// The Core II benchmark case (bench/naca_driver.cpp) at s = 1, with the default options. Of
// the targets (docs/benchmarks.md), those that hold at every scale are checked here: the
// smallest angle at least 30 degrees (the angle repair's bound) and 97% of the edges within
// sqrt 2 of rho. The mean radius ratio target is for s = 0.1 and is measured by bench/.
TEST(Mesher, BenchmarkCaseMeetsTheQualityTargetsWithDefaults) {
    const Domain dom = build_domain(naca_in_circle("0012", 20.0));
    DensitySpec d;
    d.size = "x < 0.5 ? 0.1*sqrt(x^2+y^2)+0.007 : 0.1*sqrt((x-1.008930411365)^2+y^2)+0.006";
    const MeshResult r = generate_mesh(dom, d);
    expect_valid(r.mesh, "benchmark");
    EXPECT_GE(r.quality.angle_min, 30.0);
    EXPECT_GE(r.quality.size_ratio_within_sqrt2, 0.97);
    // Without smoothing (and so without the repair) the smallest angle is lower.
    MeshOptions raw;
    raw.smoothing_iterations = 0;
    const MeshResult r0 = generate_mesh(dom, d, raw);
    EXPECT_LT(r0.quality.angle_min, r.quality.angle_min);
    std::printf("[ benchmark s=1 ] %zu triangles, min angle %.1f (unsmoothed %.1f), quality mean %.4f, within sqrt2 %.4f\n",
                r.quality.triangles, r.quality.angle_min, r0.quality.angle_min, r.quality.quality_mean,
                r.quality.size_ratio_within_sqrt2);
}

TEST(Mesher, DeterministicBitForBit) {
    const Case c = three_element();
    const Domain dom = build_domain(c.domain);
    const MeshResult a = generate_mesh(dom, c.density);
    const MeshResult b = generate_mesh(dom, c.density);
    EXPECT_EQ(a.mesh.x, b.mesh.x);
    EXPECT_EQ(a.mesh.y, b.mesh.y);
    ASSERT_EQ(a.mesh.triangles.size(), b.mesh.triangles.size());
    for (size_t t = 0; t < a.mesh.triangles.size(); ++t) EXPECT_EQ(a.mesh.triangles[t].v, b.mesh.triangles[t].v);
}

// The stages of one mesh hand their large blocks on (kernel/memory.hpp): the triangulation
// and the smoothing take the interior's pages instead of fresh ones, and the mesher keeps
// nothing once it returns; the mesh it returns is whole.
TEST(Mesher, TheStagesReuseEachOthersLargeBlocksAndKeepNoneAfterwards) {
    const Domain dom = build_domain(unit_square());
    const auto before = detail::block_counters();
    // Equilateral triangles of side h hold 2 / (sqrt(3) h^2) points a unit of area: 72,000.
    const MeshResult r = generate_mesh(dom, density_of("0.004"));
    const auto after = detail::block_counters();
    expect_valid(r.mesh, "square");
    EXPECT_GT(r.mesh.point_count(), 60000u);
    EXPECT_GT(after.reused_bytes - before.reused_bytes, std::size_t{16} << 20);
    EXPECT_EQ(after.kept_bytes, 0u);
}

TEST(Mesher, PaperInterpolatedDensityInside) {
    // Fig. 9: densities on the loops only, eq. 6.1 inside.
    const Case c = naca("0012");
    const Domain dom = build_domain(c.domain);
    ASSERT_FALSE(c.density.size.has_value());  // eq. 6.1 inside
    const MeshResult r = generate_mesh(dom, c.density);
    expect_valid(r.mesh, "fig9");
    EXPECT_GT(r.quality.size_ratio_within_sqrt2, 0.95);
}

TEST(Mesher, PointLimitRefusesBeforeTheWorkIsDone) {
    const Domain dom = build_domain(unit_square());
    DensitySpec d;
    d.size = 0.001;
    MeshOptions o;
    o.max_points = 10000;
    EXPECT_THROW(generate_mesh(dom, d, o), GeometryError);
}

TEST(Mesher, GradationLimitsHowFastSizesGrow) {
    // A density that jumps from 0.005 to 0.2 across x = 0.5.
    const Domain dom = build_domain(unit_square());
    DensitySpec spec;
    spec.size = std::string("x < 0.5 ? 0.005 : 0.2");
    const double g = 1.2;
    auto lipschitz_excess = [&](const SizeField& rho) {
        // Largest |h(x) - h(y)| - (g - 1)|x - y| over random nearby pairs.
        std::mt19937_64 rng(5);
        std::uniform_real_distribution<double> u(0.0, 1.0);
        double worst = -HUGE_VAL;
        for (int i = 0; i < 4000; ++i) {
            const Vec2 x{u(rng), u(rng)};
            const Vec2 y{std::clamp(x.x + 0.1 * (u(rng) - 0.5), 0.0, 1.0), std::clamp(x.y + 0.1 * (u(rng) - 0.5), 0.0, 1.0)};
            worst = std::fmax(worst, std::fabs(rho.interior(x) - rho.interior(y)) - (g - 1) * distance(x, y));
        }
        return worst;
    };
    SizeField raw(spec, dom);
    EXPECT_GT(lipschitz_excess(raw), 0.1);  // the raw field jumps

    spec.gradation = g;
    SizeField graded(spec, dom);
    const Discretisation d = discretise_boundary(dom, graded);
    set_gradation_sources(graded, d, triangulate_boundary(d), kMaxPointsLimit);
    ASSERT_TRUE(graded.graded());
    // Up to the sampling of the field (samples about one local size apart).
    EXPECT_LT(lipschitz_excess(graded), 0.01);
    // Never above the asked size.
    for (double x : {0.1, 0.4, 0.6, 0.9}) EXPECT_LE(graded.interior({x, 0.5}), raw.interior({x, 0.5}));

    const MeshResult r = generate_mesh(dom, spec);
    expect_valid(r.mesh, "graded");
    spec.gradation.reset();
    MeshOptions raw_jump;
    raw_jump.jump_gradation = 0.0;  // the field as asked (by default, its jump gets a gradation)
    const MeshResult q = generate_mesh(dom, spec, raw_jump);
    EXPECT_GT(r.quality.quality_min, q.quality.quality_min);
    std::printf("[ gradation ] %zu points (without: %zu), worst radius ratio %.3f (without: %.3f)\n",
                r.mesh.point_count(), q.mesh.point_count(), r.quality.quality_min, q.quality.quality_min);
}

// A gradation samples the interior on square cells no larger than the local size and more
// than half of it: one to four samples in a square of the local size, wherever the triangles
// of the boundary's triangulation lie. In a far field they are slivers from the airfoil to the
// circle, whose bisection down to the local size gave about 20 samples a mesh point. The count
// is read from the bytes set_gradation_sources reports, 96 a sample (estimate.cpp), less the
// boundary's points, which are samples too.
TEST(Mesher, AGradationsSamplesAreOneToFourInASquareOfTheLocalSize) {
    const double radius = 5.0, h = 0.05;
    const Domain dom = build_domain(naca_in_circle("0006", radius));
    DensitySpec spec = density_of("0.05");
    spec.gradation = 1.5;
    SizeField rho(spec, dom);
    const Discretisation d = discretise_boundary(dom, rho);
    const size_t bytes = set_gradation_sources(rho, d, triangulate_boundary(d), kMaxPointsLimit);
    ASSERT_EQ(bytes % 96, 0u);
    const double interior = static_cast<double>(bytes / kGradationBytesPerSource - d.size());
    // The airfoil's area is below 0.05 (a NACA 00xx encloses about 0.685 t c^2).
    const double area_hi = std::numbers::pi * radius * radius, area_lo = area_hi - 0.05;
    EXPECT_GE(interior, area_lo / (h * h));
    // Four a size squared, and the cells the circle cuts whose centres are inside.
    EXPECT_LE(interior, 4.0 * area_hi / (h * h) + 4.0 * (2.0 * std::numbers::pi * radius) / h);
}

// Each triangle of the boundary's triangulation has the samples a walk of its own cells finds
// (estimate.cpp), though the triangles share one walk of the lattice: in a far field, where
// slivers from the airfoil to the circle cross the same cells, with a refinement box whose
// jump the gradation spreads and a size at the trailing edge far below the size a little away
// from it (so a cell holding that point is split further for the triangles of that point
// alone). Counted from the bytes
// reported: the whole triangulation at once, and each of its triangles alone (each with a size field of its own, as the samples
// become the field's gradation).
TEST(Mesher, AGradationsSamplesAreEachTrianglesOwn) {
    const Domain dom = build_domain(naca_in_circle("0012", 5.0));
    DensitySpec spec =
        density_of("min(x > -0.2 && x < 3 && abs(y) < 0.4 ? 0.02 : 0.3, 0.001 + 10 * sqrt((x - 1)^2 + y^2))");
    spec.gradation = 1.5;
    SizeField rho(spec, dom);
    const Discretisation d = discretise_boundary(dom, rho);
    const BoundaryTriangulation walls = triangulate_boundary(d);
    auto samples = [&](const BoundaryTriangulation& w) {
        SizeField own(spec, dom);
        return set_gradation_sources(own, d, w, kMaxPointsLimit) / kGradationBytesPerSource - d.size();
    };
    const size_t together = samples(walls);
    size_t alone = 0;
    BoundaryTriangulation one;
    one.points = walls.points;
    for (const Triangle& t : walls.triangles) {
        one.triangles.assign(1, t);
        alone += samples(one);
    }
    EXPECT_EQ(together, alone);
    // At least one a square of the box's size (its area 3.2 x 0.8, the airfoil's under 0.1).
    EXPECT_GE(static_cast<double>(together), (3.2 * 0.8 - 0.1) / (0.02 * 0.02));
}

// The cells reach past the domain, but a field finer beyond it than in it does not split them
// down to its size: on the unit square under 0.1, with 10^-6 beyond its right side, the
// sampling visits a few hundred cells, fewer than the 65,536 between two polls of the
// observer (the cells along that side were split to 10^-6 before: millions of visits, 340 ms
// to sample for a mesh of 125 points), and the samples are as on the square alone.
TEST(Mesher, AGradationsSamplesIgnoreTheFieldBeyondTheDomain) {
    const Domain dom = build_domain(unit_square());
    DensitySpec spec = density_of("x > 1 ? 0.000001 : 0.1");
    spec.gradation = 1.5;
    SizeField rho(spec, dom);
    const Discretisation d = discretise_boundary(dom, rho);
    struct Polls : Observer {
        int polls = 0;
        bool should_stop() override {
            ++polls;
            return false;
        }
    } polls;
    const size_t bytes = set_gradation_sources(rho, d, triangulate_boundary(d), kMaxPointsLimit, &polls);
    EXPECT_EQ(polls.polls, 0);
    const double interior = static_cast<double>(bytes / kGradationBytesPerSource - d.size());
    EXPECT_GE(interior, 1.0 / (0.1 * 0.1));
    EXPECT_LE(interior, 4.0 / (0.1 * 0.1) + 4.0 * 4.0 / 0.1);  // four a size squared, and the sides' cells
}

TEST(Mesher, MinAngleRefinementGuaranteesTheBoundAwayFromInputCorners) {
    for (const Case& c : {square(), annulus(), plate_with_holes(), naca("0012"), three_element()}) {
        const Domain dom = build_domain(c.domain);
        SizeField rho(c.density, dom);
        MeshOptions o;
        o.min_angle_deg = 32.0;
        const MeshResult r = generate_mesh(dom, c.density, o);
        expect_valid(r.mesh, c.name + " refined");
        // Every angle at least the bound, except an angle between two constrained edges.
        size_t corners = 0;
        for (const Triangle& t : r.mesh.triangles) {
            for (std::uint32_t k = 0; k < 3; ++k) {
                const Vec2 p = r.mesh.point(t.v[k]);
                const Vec2 u = r.mesh.point(t.v[(k + 1) % 3]) - p, w = r.mesh.point(t.v[(k + 2) % 3]) - p;
                const double ang = std::atan2(std::fabs(cross(u, w)), dot(u, w)) * 180.0 / std::numbers::pi;
                if (ang >= 32.0 - 1e-9) continue;
                const bool input = edge_bit(t.constrained, (k + 1) % 3) && edge_bit(t.constrained, (k + 2) % 3);
                if (input) {
                    ++corners;
                    continue;
                }
                // Refinement stops at a tenth of the local size: such triangles are tiny.
                const double shortest = std::min({norm(u), norm(w), distance(p + u, p + w)});
                EXPECT_LT(shortest, 0.1 * rho.interior(p)) << c.name << ": angle " << ang;
            }
        }
        std::printf("[ %s ] refined: %zu points (+%lu), min angle %.1f, %zu input corners below the bound\n",
                    c.name.c_str(), r.mesh.point_count(), r.stats.refinement_points, r.quality.angle_min, corners);
        // The edges list follows the split segments: every edge is still a mesh edge (checked
        // above) and the loops still chain.
        EXPECT_GT(r.mesh.edges.size(), 0u);
    }
}

// Above 30 degrees a triangle's circumradius is shorter than its shortest edge, and the
// triangles around a new centre are often below the bound themselves: on this polygon with a
// line from a corner (a request of fuzz/general_requests.py), asked for 34 degrees, the
// centres went on and on, 408 points becoming 16,232 at 18.2 degrees without the smoothing
// and 14,063 at 34 with it. Past 30 degrees centres are now kept only where they reach the
// bound within a budget, else points that leave their cavity better than the triangle they
// mend: here the bound with a few points either way.
TEST(Mesher, ABoundAbove30DegreesDoesNotSetOffACascadeOfCentres) {
    DomainSpec s;
    s.points = {{"P0", {0.7165, 0.4127}},  {"P1", {0.512, 0.8576}},   {"P2", {0.241, 0.8166}},
                {"P3", {-0.6422, 0.2815}}, {"P4", {-0.7535, 0.3163}}, {"P5", {-0.9179, -0.0571}},
                {"P6", {-0.1033, -0.772}}, {"P7", {0.3407, -0.5847}}, {"E", {0.4681, 0.2696}}};
    for (int i = 0; i < 8; ++i) {
        const std::string a = "P" + std::to_string(i), b = "P" + std::to_string((i + 1) % 8);
        s.curves.push_back(line(("o" + std::to_string(i)).c_str(), a.c_str(), b.c_str(), "side"));
    }
    s.curves.push_back(line("emb", "P0", "E", "interface"));
    s.loops = {loop({"o0", "o1", "o2", "o3", "o4", "o5", "o6", "o7"})};
    s.embedded = {"emb"};
    const Domain dom = build_domain(s);
    const DensitySpec d = density_of("0.0356563 + 0.0657346*sqrt(x^2+y^2)");
    for (const int smoothing : {0, 5}) {
        SCOPED_TRACE(smoothing);
        MeshOptions o;
        o.smoothing_iterations = smoothing;
        const size_t plain = generate_mesh(dom, d, o).mesh.point_count();
        o.min_angle_deg = 34.0;
        const MeshResult r = generate_mesh(dom, d, o);
        expect_valid(r.mesh, "34 degrees asked");
        EXPECT_GE(smallest_free_angle(r.mesh).first, 34.0 - 1e-9);
        EXPECT_LE(static_cast<double>(r.mesh.point_count()), 1.25 * static_cast<double>(plain));
    }
}

// Without the smoothing (smoothing_iterations 0: the front's points stay where it put them)
// the angle repair after the refinement moves the refinement's own points only. On half
// domains over a NACA 0006 upper surface (requests of fuzz/general_requests.py) asked for 34
// degrees, the refinement alone ended at 30.2, 31.2 and 31.7 degrees; with its points
// repaired it reaches 34, and every point the front made is where it was, to the bit.
// (On 370 such requests, 71% met 34 degrees instead of 57%.)
TEST(Mesher, WithoutTheSmoothingTheRefinementsOwnPointsAreRepaired) {
    const struct {
        double far;
        const char* size;
    } cases[] = {{2.8543, "0.0844158 + 0.286186*sqrt((x-0.5)^2+y^2)"},
                 {2.0217, "0.0302488 + 0.353696*sqrt((x-0.5)^2+y^2)"},
                 {5.3977, "0.0484075 + 0.369888*sqrt((x-0.5)^2+y^2)"}};
    for (const auto& c : cases) {
        SCOPED_TRACE(c.size);
        DomainSpec s;
        s.points = {{"TE", {1.0, 0.0}}, {"LE", {0.0, 0.0}}, {"A", {0.5 - c.far, 0.0}}, {"B", {0.5 + c.far, 0.0}}};
        NacaSpec upper;
        upper.code = "0006";
        upper.surface = AirfoilSurface::Upper;
        s.curves.push_back({"upper", upper, std::string("TE"), std::string("LE"), std::string("wall")});
        s.curves.push_back(line("front", "LE", "A", "symmetry"));
        s.curves.push_back(arc("far", "B", "A", {0.5, 0.0}, ArcDirection::Ccw, "farfield"));
        s.curves.push_back(line("back", "B", "TE", "symmetry"));
        s.loops = {loop({"upper", "front", "-far", "back"})};
        const Domain dom = build_domain(s);
        MeshOptions o;
        o.smoothing_iterations = 0;
        const MeshResult plain = generate_mesh(dom, density_of(c.size), o);
        o.min_angle_deg = 34.0;
        const MeshResult r = generate_mesh(dom, density_of(c.size), o);
        expect_valid(r.mesh, "34 degrees without the smoothing");
        EXPECT_GE(smallest_free_angle(r.mesh).first, 34.0 - 1e-9);
        ASSERT_GT(r.mesh.point_count(), plain.mesh.point_count());
        for (VertexId v = 0; v < plain.mesh.point_count(); ++v) {
            ASSERT_EQ(r.mesh.x[v], plain.mesh.x[v]) << v;
            ASSERT_EQ(r.mesh.y[v], plain.mesh.y[v]) << v;
        }
    }
}

namespace {

// The annulus's circles at 0.6 and 0.2, far coarser than the constant 0.04 inside.
DensitySpec coarse_circles_fine_inside() {
    DensitySpec d;
    d.curves = {{"outer", 0.6}, {"inner", 0.2}};
    d.interior = InteriorMode::Expression;
    d.interior_expression = "0.04";
    return d;
}

}  // namespace

// Curves far coarser than the interior field beside them leave slivers no interior point
// avoids; the pipeline spaces them again (pipeline/agreement.hpp). Coarse circles (0.6, 0.2)
// around a constant interior of 0.04: every segment ends at most 1.5 times 0.04 long, the
// smallest angle reaches 30 degrees, and the admission forecast counts the extra points.
TEST(Mesher, CurvesFarCoarserThanTheInteriorAreSpacedAgainToAgreeWithIt) {
    const Domain dom = build_domain(annulus().domain);  // circles r = 1 and r = 0.3 about 0
    const DensitySpec d = coarse_circles_fine_inside();
    auto longest = [](const Mesh& m) {
        double l = 0.0;
        for (const MeshEdge& e : m.edges) l = std::max(l, distance(m.point(e.a), m.point(e.b)));
        return l;
    };
    MeshOptions off;
    off.curve_agreement = false;
    const MeshResult own = generate_mesh(dom, d, off);
    EXPECT_GT(longest(own.mesh), 0.5);  // the outer circle's own 0.6 (a test that can fail)
    EXPECT_LT(own.quality.angle_min, 30.0);
    EXPECT_EQ(own.stats.agreement.rounds, 0);

    const MeshResult r = generate_mesh(dom, d);
    expect_valid(r.mesh, "annulus, curves agreeing");
    EXPECT_GT(r.stats.agreement.rounds, 0);
    EXPECT_LE(longest(r.mesh), 1.5 * 0.04);
    EXPECT_GE(r.quality.angle_min, 30.0);
    EXPECT_GE(r.quality.size_ratio_within_sqrt2, own.quality.size_ratio_within_sqrt2);
    const double points = static_cast<double>(r.mesh.point_count());
    EXPECT_NEAR(r.stats.forecast_points / points, 1.0, 0.1);
    std::printf("[ annulus 0.6/0.2 around 0.04 ] %zu points, %d rounds, min angle %.1f (own spacing: %zu points, %.1f)\n",
                r.mesh.point_count(), r.stats.agreement.rounds, r.quality.angle_min, own.mesh.point_count(),
                own.quality.angle_min);
}

// Curves spaced finer than the size inside (0.02 on the square's sides, 1.25 to 4 times that
// inside). The advancing front's first row then takes only every other place over a side, and
// before the front closed on the points its candidates came too close to, every candidate
// after that first row fell into a place not taken: 96 to 172 inner points and 24 to 26
// degrees for every ratio from 1.25 up (the agreement caps the inside beside the sides from
// 1.5 on, growing by 1.5, which is as coarse next to them). The inside is meshed at the field (the mesh's own
// edges against rho at their middles), with 30 degrees.
TEST(Mesher, CurvesFinerThanTheInsideStillGetTheInsideFilledAtItsSize) {
    const Domain dom = build_domain(unit_square());
    for (const double ratio : {1.25, 1.3, 1.4, 2.0, 4.0}) {
        DensitySpec d;
        for (const char* side : {"bottom", "right", "top", "left"}) d.curves.push_back({side, 0.02});
        d.interior = InteriorMode::Expression;
        d.interior_expression = std::to_string(0.02 * ratio);
        const MeshResult r = generate_mesh(dom, d);
        expect_valid(r.mesh, "square, curves finer than the inside");
        EXPECT_GE(r.quality.size_ratio_within_sqrt2, 0.95) << ratio;
        EXPECT_GE(r.quality.angle_min, 30.0) << ratio;
        // At least 80% of the points of a mesh at the inside's size (equilateral triangles of
        // side rho, two to a point: 2 / (sqrt 3 rho^2) on the unit square), the finer band
        // along the sides only adding to them.
        const double rho = 0.02 * ratio;
        EXPECT_GT(static_cast<double>(r.quality.interior_points), 0.8 * 2.0 / (std::sqrt(3.0) * rho * rho)) << ratio;
    }
}

// A blunt trailing edge far finer than density.min: a NACA 0006 section of chord 0.15 has an
// open trailing edge whose base is 1.9e-4 long, one segment of its own, in a unit circle where
// the size asked is 0.01 and min is 0.03 (so 0.03 everywhere). The agreement grades the field
// and the surfaces down to the base, growing by 1.5 an element (density.min clamps the sizes
// given, not those the geometry forces). Held at min, the sizes jumped 150-fold at the base and
// its triangles fell to 21-27 degrees (found by fuzz/general_requests.py; 27.1 here). Away
// from the section the mesh keeps to min.
TEST(Mesher, ABaseFinerThanTheMinimumSizeIsGradedDownTo) {
    for (const double angle : {0.0, 20.0}) {
        SCOPED_TRACE(angle);
        DomainSpec s;
        s.points = {{"F", {1.0, 0.0}}};
        NacaSpec wing;
        wing.code = "0006";
        wing.trailing_edge = TrailingEdge::Open;
        wing.placement = {0.15, {-0.075, 0.0}, angle};
        s.curves.push_back({"wing", wing, std::nullopt, std::nullopt, std::string("wall")});
        s.curves.push_back(arc("farfield", "F", "F", {0.0, 0.0}, ArcDirection::Ccw, "farfield"));
        s.loops = {loop({"farfield"}), loop({"wing"})};
        DensitySpec d;
        d.size = 0.01;
        d.min = 0.03;
        const MeshResult r = generate_mesh(build_domain(s), d);
        expect_valid(r.mesh, "a base finer than min");
        const auto [free_angle, at] = smallest_free_angle(r.mesh);
        EXPECT_GE(free_angle, 30.0) << "at " << at.x << ", " << at.y;
        // The trailing edge is within 0.15 of the origin; beyond 0.5 the field is min's: no
        // edge there is near the 0.01 asked (a mesh's edges lie within 0.7 to 1.4 of the field
        // but for a few in a thousand).
        double shortest_far = HUGE_VAL, shortest_near = HUGE_VAL;
        for (const Triangle& t : r.mesh.triangles)
            for (std::uint32_t i = 0; i < 3; ++i) {
                const Vec2 a = r.mesh.point(t.v[i]), b = r.mesh.point(t.v[(i + 1) % 3]);
                const double l = distance(a, b);
                double& shortest = norm(0.5 * (a + b)) > 0.5 ? shortest_far : shortest_near;
                shortest = std::min(shortest, l);
            }
        EXPECT_GE(shortest_far, 0.6 * 0.03);
        EXPECT_LT(shortest_near, 1e-3);  // the base and the graded sizes about it
    }
}

// The paper's eq. 6.1 inside a far field of 0.4 r + 0.2 (segments of 4 at r = 10) around a
// wing of small segments: the interior beside the far field takes the wing's sizes, and the far
// field is spaced again to match; beside the leading edge, where eq. 6.1 averages in the
// coarser segments further along the chord, the field is capped at the curve's spacing growing
// by 1.5. Both NACA sections reach 30 degrees; the forecast follows the mesh.
TEST(Mesher, AFarFieldCoarserThanEq61BesideItIsSpacedAgain) {
    for (const char* code : {"0012", "23012"}) {
        const Case c = naca(code);
        SCOPED_TRACE(c.name);
        const Domain dom = build_domain(c.domain);
        MeshOptions off;
        off.curve_agreement = false;
        const MeshResult own = generate_mesh(dom, c.density, off);
        EXPECT_LT(own.quality.angle_min, 30.0);
        const MeshResult r = generate_mesh(dom, c.density);
        expect_valid(r.mesh, "eq. 6.1, curves agreeing");
        EXPECT_GT(r.stats.agreement.rounds, 0);
        EXPECT_GE(r.quality.angle_min, 30.0);
        EXPECT_GT(r.quality.size_ratio_within_sqrt2, own.quality.size_ratio_within_sqrt2);
        EXPECT_NEAR(r.stats.forecast_points / static_cast<double>(r.mesh.point_count()), 1.0, 0.1);
        EXPECT_NEAR(own.stats.forecast_points / static_cast<double>(own.mesh.point_count()), 1.0, 0.1);
    }
}

// The agreement places the curves again each round, but a curve no new cap reaches keeps its
// points (pipeline/agreement.cpp). Whatever it kept, the curves it ends with must be those
// that placing every curve from scratch gives for the field it ends with, point for point.
TEST(Mesher, TheAgreedCurvesAreThoseTheFinalFieldPlaces) {
    struct Sample {
        std::string name;
        DomainSpec domain;
        DensitySpec density;
    };
    std::vector<Sample> samples;
    samples.push_back({"naca0012", naca("0012").domain, naca("0012").density});
    {
        DensitySpec d;
        d.curves = {{"farfield", std::string("0.4*sqrt(x^2+y^2)+0.2")}, {"wall", std::string("0.002 + 0.03*sqrt(x^2+y^2)")}};
        samples.push_back({"three elements", three_element_wing({1.01, -0.04}), d});
    }
    {
        DensitySpec d;
        d.curves = {{"farfield", std::string("0.4*sqrt(x^2+y^2)+0.2")}, {"wing", std::string("0.05*sqrt((x+0.01)^2+y^2)")}};
        d.min = 0.002;
        samples.push_back({"Fig. 9", naca_in_circle("0012", 5.0), d});
    }
    size_t kept = 0;
    for (const Sample& s : samples) {
        SCOPED_TRACE(s.name);
        const Domain dom = build_domain(s.domain);
        SizeField rho(s.density, dom);
        ASSERT_TRUE(rho.interpolates());
        Discretisation d = discretise_boundary(dom, rho);
        set_interpolation_sources(rho, d);
        const AgreementStats stats = agree_with_interior(dom, rho, {}, d, nullptr);
        EXPECT_GT(stats.rounds, 0);
        kept += stats.curves_kept;
        const Discretisation fresh = discretise_boundary(dom, rho);
        ASSERT_EQ(fresh.size(), d.size());
        for (VertexId v = 0; v < d.size(); ++v) {
            ASSERT_EQ(fresh.point(v), d.point(v)) << "point " << v;
            ASSERT_EQ(fresh.rho[v], d.rho[v]) << "point " << v;
            ASSERT_EQ(fresh.curve[v], d.curve[v]) << "point " << v;
        }
        ASSERT_EQ(fresh.segments.size(), d.segments.size());
        for (size_t i = 0; i < d.segments.size(); ++i) {
            EXPECT_EQ(fresh.segments[i].a, d.segments[i].a);
            EXPECT_EQ(fresh.segments[i].b, d.segments[i].b);
        }
    }
    EXPECT_GT(kept, 0u);  // the airfoils, which the far field's caps do not reach
}

// Refinement splits boundary segments whose diametral circle holds a circumcentre; on a
// curved wall the new point must lie on the curve, not on the chord (the chord of a coarse
// arc is far inside the circle). Coarse arcs around a fine interior force such splits (with
// the curves left at their own density: the pipeline would otherwise space them again).
TEST(Mesher, MinAngleRefinementPutsNewBoundaryPointsOnTheirCurves) {
    const Domain dom = build_domain(annulus().domain);  // circles r = 1 and r = 0.3 about 0
    const DensitySpec d = coarse_circles_fine_inside();
    MeshOptions o;
    o.curve_agreement = false;
    const MeshResult plain = generate_mesh(dom, d, o);
    o.min_angle_deg = 30.0;
    const MeshResult r = generate_mesh(dom, d, o);
    expect_valid(r.mesh, "annulus refined");
    auto on_walls = [](const Mesh& m) {
        return std::count_if(m.kind.begin(), m.kind.end(), [](PointKind k) { return k == PointKind::Boundary; });
    };
    ASSERT_GT(on_walls(r.mesh), on_walls(plain.mesh));  // segments were split
    const CurveId outer = *dom.find_curve("outer"), inner = *dom.find_curve("inner");
    for (VertexId v = 0; v < r.mesh.point_count(); ++v) {
        if (r.mesh.kind[v] != PointKind::Boundary) continue;
        const double radius = r.mesh.curve[v] == outer ? 1.0 : 0.3;
        EXPECT_TRUE(r.mesh.curve[v] == outer || r.mesh.curve[v] == inner);
        EXPECT_NEAR(norm(r.mesh.point(v)), radius, 1e-12) << "point " << v;
    }
}

// A size far larger than the domain on one curve must not cut the curve into too few
// segments to keep its loop (it gave "the outside reached the domain", a 500): the size is
// capped at 90 degrees of turn per segment, so the circle keeps at least four.
TEST(Mesher, AHugeSizeOnACurveStillKeepsItsLoop) {
    const Domain dom = build_domain(annulus().domain);  // circles r = 1 and r = 0.3 about 0
    DensitySpec d;
    d.curves = {{"outer", 2147483648.0}, {"inner", 0.05}};  // eq. 6.1 inside
    const MeshResult r = generate_mesh(dom, d);
    expect_valid(r.mesh, "huge outer size");
    const CurveId outer = *dom.find_curve("outer");
    size_t outer_edges = 0;
    for (const MeshEdge& e : r.mesh.edges) outer_edges += e.curve == outer;
    EXPECT_GE(outer_edges, 4u);
}

// With a gradation, the field is sampled at about the local size before the point estimate;
// a tiny size must be refused as soon as the sampling shows the mesh too large, not after
// sampling the whole domain (more than 10^7 samples here; the boundary's 13,000 points are
// within the limit). The sampler polls the observer every 2^16 steps: it refuses after about
// 60 polls; the whole domain takes well over a thousand, where this observer stops it.
TEST(Mesher, AGradedFieldOverTheLimitIsRefusedDuringSampling) {
    struct Polls : Observer {
        int n = 0;
        bool should_stop() override { return ++n > 1000; }
    } polls;
    const Domain dom = build_domain(unit_square());
    DensitySpec d;
    d.size = 3e-4;
    d.gradation = 1.2;
    MeshOptions o;
    o.max_points = 30000;
    try {
        generate_mesh(dom, d, o, &polls);
        FAIL() << "no error";
    } catch (const GeometryError& e) {
        EXPECT_EQ(e.kind(), GeometryErrorKind::TooManyPoints);
    }
    EXPECT_LT(polls.n, 1000);
}

// A gradation grades away from a fine region narrower than the boundary's triangles. Sizes of
// 0.001 in a strip 0.01 wide along the left wall of a unit square and 0.2 beyond, graded at
// 1.5 (a slope of 0.5): the field's samples came from the centroids of the boundary's
// triangles, slivers from wall to wall, none of them in the strip, so the graded field rose
// from the wall's own points and stood at six times the graded bound at the strip's edge (508
// of the 742 points beyond the strip above twice that bound; 0.897 of the edges within sqrt 2
// of the field). The slivers along the fine wall are now split along their length.
TEST(Mesher, AGradationGradesAwayFromAFineStripAlongAWall) {
    const Domain dom = build_domain(unit_square());
    const double w = 0.01, h = 0.001, g = 1.5;
    DensitySpec d;
    d.size = std::string("x < 0.01 ? 0.001 : 0.2");
    d.gradation = g;
    const MeshResult r = generate_mesh(dom, d);
    expect_valid(r.mesh, "strip");
    // The bound the gradation promises beyond the strip: h + (g - 1) * the distance from it.
    // Its samples are at about the local size, so a point may see the strip's nearest sample
    // some sizes inside it: twice the bound is well beyond that.
    size_t beyond = 0, above = 0;
    for (VertexId v = 0; v < r.mesh.point_count(); ++v) {
        const Vec2 p = r.mesh.point(v);
        if (p.x <= w) continue;
        ++beyond;
        above += r.mesh.target_size[v] > 2.0 * (h + (g - 1.0) * (p.x - w)) ? 1 : 0;
    }
    ASSERT_GT(beyond, 100u);
    EXPECT_LT(static_cast<double>(above), 0.02 * static_cast<double>(beyond)) << above << " of " << beyond;
    EXPECT_GE(r.quality.size_ratio_within_sqrt2, 0.95);
    EXPECT_GE(r.quality.angle_min, 30.0);
}

// The memory of a run is reserved by its forecast (Observer::on_forecast). A fine region
// narrower than the forecast's samples (0.001 within 0.01 of a wall, 0.2 beyond) holds about
// ten times the points forecast, so the interior stage tells the observer again each time its
// count passes twice the forecast, four times it, and so on: the count then, and the memory a
// run of that size needs.
TEST(Mesher, TheObserverHearsOfAMeshOutgrowingItsForecast) {
    const Domain dom = build_domain(unit_square());
    DensitySpec d;
    d.size = std::string("x < 0.01 ? 0.001 : 0.2");
    struct Forecasts : Observer {
        std::vector<std::pair<double, size_t>> heard;
        void on_forecast(double points, size_t bytes) override { heard.emplace_back(points, bytes); }
    } obs;
    MeshOptions o;
    o.curve_agreement = false;  // no closing round: one interior stage, one run of reports
    o.jump_gradation = 0.0;     // nor a mesh made again with a gradation
    const MeshResult r = generate_mesh(dom, d, o, &obs);
    ASSERT_EQ(r.stats.closing_rounds, 0u);
    ASSERT_FALSE(obs.heard.empty());
    const double forecast = std::floor(obs.heard[0].first);
    const double made = static_cast<double>(r.mesh.point_count());
    ASSERT_GT(made, 4.0 * forecast) << "not the case this test is for";
    // One report for each doubling of the forecast the mesh passed, at the first point past it.
    std::vector<double> expected;
    for (double at = 2.0 * forecast; at < made; at *= 2.0) expected.push_back(at + 1.0);
    ASSERT_EQ(obs.heard.size(), expected.size() + 1);
    for (size_t k = 0; k < expected.size(); ++k) {
        EXPECT_EQ(obs.heard[k + 1].first, expected[k]);
        EXPECT_EQ(obs.heard[k + 1].second, peak_bytes_for(expected[k]));
    }
}

// The interior stage's reports (above) carry a gradation's sources too: they stay with the
// field to the end of the run, beside the points' own peak, and the gradation reported them
// with the forecast's peak (96 bytes a source, from 2^16 sources). So every report of the
// interior is the points' peak plus the same bytes as the gradation's last report beyond the
// forecast's peak. The case: a strip of 0.0005 along a wall graded at 1.5, which the forecast
// cannot see, wide enough for more than 2^16 sources (about one a point of the strip).
TEST(Mesher, TheInteriorsReportsCarryTheGradationsSources) {
    const Domain dom = build_domain(unit_square());
    DensitySpec d;
    d.size = std::string("x < 0.02 ? 0.0005 : 0.2");
    d.gradation = 1.5;
    struct Forecasts : Observer {
        std::vector<std::pair<double, size_t>> heard;
        void on_forecast(double points, size_t bytes) override { heard.emplace_back(points, bytes); }
    } obs;
    MeshOptions o;
    o.curve_agreement = false;
    const MeshResult r = generate_mesh(dom, d, o, &obs);
    ASSERT_GE(obs.heard.size(), 3u);
    const double forecast = obs.heard[0].first;
    size_t sources_bytes = 0, interior_reports = 0;
    for (size_t k = 1; k < obs.heard.size(); ++k) {
        const auto [points, bytes] = obs.heard[k];
        if (points == forecast) {  // the gradation's
            ASSERT_EQ(interior_reports, 0u);
            sources_bytes = bytes - peak_bytes_for(forecast);
        } else {
            ++interior_reports;
            EXPECT_EQ(bytes, peak_bytes_for(points) + sources_bytes) << points;
        }
    }
    EXPECT_GE(sources_bytes, 96u << 16) << "not the case this test is for";
    EXPECT_GE(interior_reports, 1u) << "not the case this test is for";
    EXPECT_GT(static_cast<double>(r.mesh.point_count()), 2.0 * forecast);
}

// A size field that jumps faster than one element can follow (a strip of 0.001 along a wall,
// 0.2 beyond; a refinement box tenfold finer across a line) left triangles below 30 degrees
// that no smoothing lifts (27.3 and 30.1 here, after a closing round). Where the request gives
// no gradation, the interior stage now counts the candidates more than three times off both
// ends of their segment, and past a few the mesh is made again with a gradation of 1.5.
TEST(Mesher, AFieldThatJumpsIsMadeAgainWithAGradation) {
    const Domain dom = build_domain(unit_square());
    for (const char* size : {"x < 0.02 ? 0.001 : 0.2", "x < 0.5 ? 0.01 : 0.1"}) {
        DensitySpec d;
        d.size = std::string(size);
        const MeshResult r = generate_mesh(dom, d);
        expect_valid(r.mesh, size);
        EXPECT_EQ(r.stats.gradation_applied, 1.5) << size;
        EXPECT_GE(r.quality.angle_min, 30.0) << size;
        // The same as asking for that gradation: the first, jumping, mesh is not kept.
        DensitySpec asked = d;
        asked.gradation = 1.5;
        const MeshResult same = generate_mesh(dom, asked);
        EXPECT_EQ(same.stats.gradation_applied, 0.0) << size;
        EXPECT_EQ(same.mesh.x, r.mesh.x) << size;
        EXPECT_EQ(same.mesh.y, r.mesh.y) << size;
    }
    // A gradation the request gives is kept, jumps or not, and so is a field with none when
    // the jump gradation is off.
    DensitySpec own;
    own.size = std::string("x < 0.5 ? 0.01 : 0.1");
    own.gradation = 4.0;
    EXPECT_EQ(generate_mesh(dom, own).stats.gradation_applied, 0.0);
    MeshOptions off;
    off.jump_gradation = 0.0;
    DensitySpec raw;
    raw.size = own.size;
    const MeshResult r = generate_mesh(dom, raw, off);
    EXPECT_EQ(r.stats.gradation_applied, 0.0);
    EXPECT_GT(r.stats.interior.jumps, 16u);
    // A field that changes gently never jumps.
    DensitySpec gentle;
    gentle.size = std::string("0.01 + 0.1 * x");
    const MeshResult g = generate_mesh(dom, gentle);
    EXPECT_EQ(g.stats.interior.jumps, 0u);
    EXPECT_EQ(g.stats.gradation_applied, 0.0);
}

// Every stage honours the observer: stopping as soon as a stage has reported progress ends
// the run with Cancelled inside that stage (the boundary, the interior, the triangulation
// and the smoothing each poll on their own; the pipeline announces each stage as it begins,
// so a stage that never polled would be caught by the next one, which fails here).
TEST(Mesher, CancellationIsHonouredInEveryStage) {
    const Domain dom = build_domain(unit_square());
    DensitySpec d;
    d.size = 0.005;  // about 46,000 points: every stage polls more than once
    for (const Stage target : {Stage::Boundary, Stage::Interior, Stage::Triangulation, Stage::Smoothing}) {
        struct StopIn : Observer {
            Stage target = Stage::Boundary, last = Stage::Quality;
            bool reached = false;
            void on_progress(Stage s, double) override {
                last = s;
                reached = reached || s == target;
            }
            bool should_stop() override { return reached; }
        } obs;
        obs.target = target;
        EXPECT_THROW(generate_mesh(dom, d, {}, &obs), Cancelled) << to_string(target);
        EXPECT_EQ(obs.last, target) << to_string(target);
    }
}

// The smoothing's angle repair polls too. Where the field changes faster than the mesh can
// follow (here its size goes from 0.005 to 0.055 and back every 0.1 along x, across one or
// two elements), it works on thousands of triangles for eight rounds: on a domain twenty
// times this one, 3.6 s in which a job's cancellation and time limit went unheard (a server
// job with a 1 s limit answered after 4.4 s). The mesh is made unsmoothed, then smoothed
// with an observer that asks to stop as soon as the sweeps report their end (0.9), which is
// where the repair begins: the repair must stop, where it used to run to its end and return.
TEST(Mesher, CancellationIsHonouredInTheAngleRepair) {
    const Domain dom = build_domain(unit_square());
    DensitySpec d;
    d.size = std::string("0.03 + 0.025*sin(60*x)");
    MeshOptions o;
    o.smoothing_iterations = 0;
    Mesh m = generate_mesh(dom, d, o).mesh;
    struct StopInRepair : Observer {
        bool reached = false;
        void on_progress(Stage s, double fraction) override {
            reached = reached || (s == Stage::Smoothing && fraction >= 0.9);
        }
        bool should_stop() override { return reached; }
    } obs;
    EXPECT_THROW(smooth(m, 5, &dom, nullptr, &obs), Cancelled);
    EXPECT_TRUE(obs.reached);
    // The same with the repair alone (after min_angle_deg's refinement), asked to stop at once.
    struct StopNow : Observer {
        bool should_stop() override { return true; }
    } now;
    EXPECT_THROW(repair_angles(m, &dom, nullptr, &now), Cancelled);
}

// Found by fuzz/fuzz_request (crash 41b88212): sizes from 0.007 at the wing to the extent in
// part of the far field made the interior's candidate points, where two neighbouring radii
// differ by orders of magnitude, land far outside the domain, and the size-class grid
// converted their cell numbers from doubles out of the range of a 64-bit integer (undefined
// behaviour: the sanitizer build, with float-cast-overflow, stops on it). Candidates outside
// the domain's box are rejected before any search; cell numbers saturate.
TEST(Mesher, FuzzCandidatesFarOutsideTheDomain) {
    DomainSpec s = naca_in_circle("0012", 16.0);
    for (auto& p : s.points) p.second = p.second + Vec2{4.0, 0.0};
    std::get<ArcShape>(s.curves[1].shape).center = {4.5, 0.0};
    DensitySpec d;
    d.size = std::string("x < 0.5 ? (x^2+y^2)+0.007 : 0.1*sqrt((x-1.008930411365)^2+y^2)+0.006");
    const Domain dom = build_domain(s);
    const MeshResult r = generate_mesh(dom, d);
    expect_valid(r.mesh, "candidates far outside");
    for (VertexId v = 0; v < r.mesh.point_count(); ++v) {
        const Vec2 p = r.mesh.point(v);
        ASSERT_TRUE(p.x >= dom.box().lo.x && p.x <= dom.box().hi.x && p.y >= dom.box().lo.y && p.y <= dom.box().hi.y);
    }
}

namespace {

// The unit square at a constant size of 0.1 with a hole [0.3, 0.7] x [y0, y1] (lines, corners
// named H0..H3).
DomainSpec square_with_box_hole(double y0, double y1) {
    DomainSpec s = unit_square();
    s.points.insert(s.points.end(), {{"H0", {0.3, y0}}, {"H1", {0.3, y1}}, {"H2", {0.7, y1}}, {"H3", {0.7, y0}}});
    s.curves.insert(s.curves.end(), {line("h0", "H0", "H1", "hole"), line("h1", "H1", "H2", "hole"),
                                     line("h2", "H2", "H3", "hole"), line("h3", "H3", "H0", "hole")});
    s.loops.push_back(loop({"h0", "h1", "h2", "h3"}));
    return s;
}

// The length of an embedded edge ending at `end` (0 if none does).
double embedded_edge_at(const Mesh& m, Vec2 end) {
    double length = 0.0;
    for (const MeshEdge& e : m.edges)
        if (e.embedded && (m.point(e.a) == end || m.point(e.b) == end)) length = distance(m.point(e.a), m.point(e.b));
    return length;
}

// The longest boundary edge with both ends in the box [x0, x1] x [y0, y1].
double longest_edge_within(const Mesh& m, double x0, double x1, double y0, double y1) {
    const auto inside = [&](Vec2 p) { return p.x >= x0 && p.x <= x1 && p.y >= y0 && p.y <= y1; };
    double l = 0.0;
    for (const MeshEdge& e : m.edges)
        if (inside(m.point(e.a)) && inside(m.point(e.b))) l = std::max(l, distance(m.point(e.a), m.point(e.b)));
    return l;
}

}  // namespace

// A hole 0.02 above the square's bottom side, everything sized 0.1: the two sides of the gap
// face each other across the domain, and only sides spaced at about the gap's width give
// triangles across it fair angles (20 degrees on a random domain where a hole almost touched
// its outer polygon). The agreement caps both at the gap's width; a plate as thin as the gap
// (its own two sides face each other across the hole, not the domain) keeps the size asked.
TEST(Mesher, BoundariesFacingAcrossANarrowGapAreSpacedAtItsWidth) {
    const double gap = 0.02;
    const Domain dom = build_domain(square_with_box_hole(gap, 0.3));
    MeshOptions off;
    off.curve_agreement = false;
    const MeshResult own = generate_mesh(dom, density_of("0.1"), off);
    EXPECT_LT(own.quality.angle_min, 30.0);  // slivers across the gap (a test that can fail)
    EXPECT_GT(longest_edge_within(own.mesh, 0.3, 0.7, -0.01, gap + 0.01), 0.08);

    const MeshResult r = generate_mesh(dom, density_of("0.1"));
    expect_valid(r.mesh, "a hole close to a side");
    EXPECT_GE(r.quality.angle_min, 30.0);
    // Both sides of the gap, its middle part (the caps grow away from where it is narrowest,
    // and the placement rounds to whole segments).
    EXPECT_LE(longest_edge_within(r.mesh, 0.35, 0.65, -0.01, gap + 0.01), 2.0 * gap);

    const Domain plate = build_domain(square_with_box_hole(0.5, 0.5 + gap));
    const MeshResult p = generate_mesh(plate, density_of("0.1"));
    expect_valid(p.mesh, "a thin plate");
    EXPECT_GT(longest_edge_within(p.mesh, 0.3, 0.7, 0.49, 0.51 + gap), 0.08);
}

// An embedded line from the square's corner ending 0.02 short of a hole's side, everything
// sized 0.1: the line's free end and that side face each other across a gap as narrow as two
// sides would (a spoke reaching across the gap between two holes ended a third of the local
// size from the other hole: 11.3 degrees on a random domain with layers). Both are spaced at
// the gap's width there, as two sides are.
TEST(Mesher, AnEmbeddedCurvesFreeEndNearAWallIsAGapAsNarrow) {
    const double gap = 0.02;
    const Vec2 end{0.3 - gap, 0.3};
    DomainSpec s = square_with_box_hole(0.1, 0.5);
    s.points.push_back({"E", end});
    s.curves.push_back(line("spoke", "A", "E", "cut"));
    s.embedded = {"spoke"};
    const MeshResult r = generate_mesh(build_domain(s), density_of("0.1"));
    expect_valid(r.mesh, "a line ending beside a hole");
    EXPECT_GE(r.quality.angle_min, 30.0);
    // The hole's side beside the end, and the line's last segment.
    EXPECT_LE(longest_edge_within(r.mesh, 0.29, 0.31, 0.25, 0.35), 2.0 * gap);
    const double last = embedded_edge_at(r.mesh, end);
    EXPECT_GT(last, 0.0);
    EXPECT_LE(last, 2.0 * gap);
}

// Two embedded lines along y = 0.5 whose ends face each other 0.02 apart, everything sized
// 0.1: two free ends close together are a gap as narrow as two sides (seed 24033 of the random
// domains with layers: ends 0.55 of the field apart, a triangle of the two and an interior
// point at 27.9 degrees). Both lines are spaced at the gap's width at those ends.
TEST(Mesher, TwoFreeEndsCloseTogetherAreAGapAsNarrow) {
    const double gap = 0.02;
    const Vec2 e1{0.5 - gap / 2, 0.5}, e2{0.5 + gap / 2, 0.5};
    DomainSpec s = unit_square();
    s.points.push_back({"L1", {0.2, 0.5}});
    s.points.push_back({"E1", e1});
    s.points.push_back({"E2", e2});
    s.points.push_back({"L2", {0.8, 0.5}});
    s.curves.push_back(line("west", "L1", "E1", "cut"));
    s.curves.push_back(line("east", "E2", "L2", "cut"));
    s.embedded = {"west", "east"};
    const MeshResult r = generate_mesh(build_domain(s), density_of("0.1"));
    expect_valid(r.mesh, "two lines ending close together");
    EXPECT_GE(r.quality.angle_min, 30.0);
    for (const Vec2 end : {e1, e2}) {
        const double last = embedded_edge_at(r.mesh, end);
        EXPECT_GT(last, 0.0);
        EXPECT_LE(last, 2.0 * gap);
    }
}
