// Boundary layers on airfoils, a high-lift configuration, a half airfoil on a symmetry line,
// a cylinder and holes close together: the hybrid mesh is valid (every cell positive and
// convex, conforming, Euler), the layers keep the asked first height and growth where they
// stand on a wall, cut-backs are reported, both triangulators agree, runs repeat exactly.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <map>
#include <set>

#include "fixtures.hpp"

#include "meshd/core/errors.hpp"
#include "meshd/core/mesher.hpp"

using namespace meshd::core;
using namespace meshd::test;

namespace {

struct LayerCase {
    std::string name;
    DomainSpec domain;
    DensitySpec density;
    std::vector<BoundaryLayerSpec> layers;
    bool narrow;  // the layers must be cut back somewhere
    // The isotropic triangles with the defaults: issue 15's 30 degrees, and the layers' outer
    // edge without a jump in spacing (neighbouring segments within a factor 2), but where
    // said otherwise.
    double min_angle = 30.0;
    double outer_ratio = 2.0;
};

// gtest names a failing case by this, not by its bytes.
void PrintTo(const LayerCase& c, std::ostream* os) { *os << c.name; }

BoundaryLayerSpec spec(std::vector<std::string> curves, double first, double growth, int layers, double thickness = 0) {
    BoundaryLayerSpec s;
    s.curves = std::move(curves);
    s.first_height = first;
    s.growth = growth;
    s.layers = layers;
    s.thickness = thickness;
    return s;
}

LayerCase naca(const std::string& code, double growth, int layers) {
    DensitySpec d;
    d.curves = {{"farfield", std::string("0.4*sqrt(x^2+y^2)+0.2")},
                {"wing", std::string("0.003 + 0.05*sqrt((x+0.01)^2+y^2)")}};
    return {"naca" + code, naca_in_circle(code, 10.0), d, {spec({"wing"}, 1e-5, growth, layers)}, false};
}

// Its density is far coarser than the slot between slat and main element (a segment of 0.04
// at the main element's leading edge, the slot 0.02 wide): the fans at the slat's trailing
// edge and the main element's leading edge are cut back in the slot on the first spacing of
// the walls, which the fan caps are made from, and stand fuller on the final one. The
// isotropic triangles reach 26 degrees there (7 before the fan caps and the outer edge's
// slope limit).
LayerCase three_element() {
    LayerCase c{"three-element", three_element_wing({1.01, -0.04}), density_of("0.004 + 0.08*sqrt((x-0.5)^2+y^2)"), {spec({"wall"}, 1e-5, 1.2, 40)}, true};
    // The flap's columns under the main element's trailing edge are cut back unevenly (a
    // column at a time): the outer edge there changes its spacing by up to 2.3 (12 at the
    // slat's trailing-edge fan before the final fans were held to the planned height).
    c.outer_ratio = 2.5;
    return c;
}

LayerCase half_airfoil() {
    DomainSpec s;
    s.points = {{"LE", {0, 0}}, {"TE", {1, 0}}, {"F1", {6.5, 0}}, {"F2", {-5.5, 0}}};
    NacaSpec upper{"0012", {}, TrailingEdge::Closed, AirfoilSurface::Upper};
    s.curves.push_back({"wing", upper, std::string("TE"), std::string("LE"), std::string("wall")});
    s.curves.push_back(line("wake_side", "TE", "F1", "symmetry"));
    s.curves.push_back(arc("farfield", "F1", "F2", {0.5, 0.0}));
    s.curves.push_back(line("front_side", "F2", "LE", "symmetry"));
    s.loops = {loop({"wake_side", "farfield", "front_side", "-wing"})};
    return {"half-airfoil", s, density_of("0.004 + 0.08*sqrt((x-0.5)^2+y^2)"), {spec({"wing"}, 1e-4, 1.2, 20)}, false};
}

LayerCase cylinder() {
    DomainSpec s;
    s.points = {{"A", {0, 0}}, {"B", {10, 0}}, {"C", {10, 10}}, {"D", {0, 10}}, {"P", {5.5, 5}}};
    s.curves = {line("bottom", "A", "B", "wall"), line("right", "B", "C", "outlet"), line("top", "C", "D", "wall"),
                line("left", "D", "A", "inlet"), arc("cylinder", "P", "P", {5, 5}, ArcDirection::Ccw, "cylinder")};
    s.loops = {loop({"bottom", "right", "top", "left"}), loop({"cylinder"})};
    return {"cylinder", s, density_of("0.03 + 0.05*sqrt((x-5)^2+(y-5)^2)"), {spec({"cylinder"}, 1e-3, 1.2, 0, 0.1)}, false};
}

// Three holes 0.02 apart, layers up to 0.05 thick on each: they must give way to each other.
LayerCase holes_close_together() {
    DomainSpec s;
    s.points = {{"A", {0, 0}}, {"B", {4, 0}}, {"C", {4, 2}}, {"D", {0, 2}}};
    s.curves = {line("bottom", "A", "B"), line("right", "B", "C"), line("top", "C", "D"), line("left", "D", "A")};
    s.loops = {loop({"bottom", "right", "top", "left"})};
    for (int i = 0; i < 3; ++i) {
        const std::string n = "h" + std::to_string(i);
        const Vec2 c{1.38 + 0.62 * i, 1.0};
        s.points.push_back({n, c + Vec2{0.3, 0.0}});
        s.curves.push_back(arc(n, n, n, c, ArcDirection::Ccw, "hole"));
        s.loops.push_back(loop({n.c_str()}));
    }
    return {"holes-close-together", s, density_of("0.02"), {spec({"hole"}, 1e-3, 1.1, 0, 0.05)}, true};
}

// A blunt trailing edge: the base's two corners turn by about 90 degrees each and get fans.
LayerCase blunt_trailing_edge() {
    DomainSpec s;
    s.points = {{"F", {10.5, 0.0}}};
    NacaSpec wing{"0012", {}, TrailingEdge::Open, AirfoilSurface::Both};
    s.curves.push_back({"wing", wing, std::nullopt, std::nullopt, std::string("wall")});
    s.curves.push_back(arc("farfield", "F", "F", {0.5, 0.0}));
    s.loops = {loop({"farfield"}), loop({"wing"})};
    return {"blunt-trailing-edge", s, density_of("0.002 + 0.08*sqrt((x-0.5)^2+y^2)"), {spec({"wing"}, 1e-5, 1.2, 30)}, false};
}

// A wake line leaves the trailing edge: the fan's middle column slides along it, and the
// layers go on on both of its sides.
LayerCase wake_line() {
    LayerCase c = naca("0012", 1.15, 25);
    c.domain.points.push_back({"TE", {1.0, 0.0}});
    c.domain.points.push_back({"W", {3.0, 0.0}});
    for (auto& cs : c.domain.curves)
        if (cs.name == "wing") cs.from = cs.to = "TE";
    c.domain.curves.push_back(line("wake", "TE", "W", "wake"));
    c.domain.embedded = {"wake"};
    c.density.curves.push_back({"wake", std::string("0.003 + 0.05*sqrt((x+0.01)^2+y^2)")});
    c.name = "wake-line";
    c.layers[0].first_height = 1e-4;
    return c;
}

// A wall that ends on arcs: its end columns slide along the arcs (points on the circles).
LayerCase wall_between_arcs() {
    DomainSpec s;
    s.points = {{"A", {0, 0}}, {"B", {2, 0}}, {"C", {2, 1}}, {"D", {0, 1}}};
    s.curves = {line("bottom", "A", "B", "wall"), arc("right", "B", "C", {1.5, 0.5}, ArcDirection::Ccw, "outlet"),
                line("top", "C", "D"), arc("left", "D", "A", {0.5, 0.5}, ArcDirection::Ccw, "inlet")};
    s.loops = {loop({"bottom", "right", "top", "left"})};
    return {"wall-between-arcs", s, density_of("0.05"), {spec({"bottom"}, 1e-3, 1.2, 10)}, false};
}

std::vector<LayerCase> cases() {
    return {naca("0012", 1.15, 30), naca("4412", 1.25, 20), three_element(), half_airfoil(),
            cylinder(),             holes_close_together(), blunt_trailing_edge(), wake_line(),
            wall_between_arcs()};
}

MeshResult mesh(const LayerCase& c, Triangulator tr = Triangulator::Delaunay) {
    MeshOptions o;
    o.boundary_layers = c.layers;
    o.triangulator = tr;
    return generate_mesh(c.domain, c.density, o);
}

// The wall's layer stacks, read from the mesh alone: for each wall edge with a quad on it,
// the heights of the levels above it (the distance of each quad top's middle from the wall
// edge's line).
std::vector<std::vector<double>> stacks(const Mesh& m, const std::set<std::string>& wall_tags) {
    std::map<std::pair<VertexId, VertexId>, size_t> by_bottom;
    for (size_t q = 0; q < m.quads.size(); ++q) by_bottom[{m.quads[q][0], m.quads[q][1]}] = q;
    std::vector<std::vector<double>> out;
    for (const MeshEdge& e : m.edges) {
        if (!wall_tags.count(m.tags[e.tag])) continue;
        auto it = by_bottom.find({e.a, e.b});
        if (it == by_bottom.end()) continue;
        const Vec2 a = m.point(e.a), b = m.point(e.b);
        std::vector<double> heights;
        while (it != by_bottom.end()) {
            const auto& Q = m.quads[it->second];
            const Vec2 mid = 0.5 * (m.point(Q[2]) + m.point(Q[3]));
            heights.push_back(std::fabs(cross(b - a, mid - a)) / distance(a, b));
            it = by_bottom.find({Q[3], Q[2]});
        }
        out.push_back(std::move(heights));
    }
    return out;
}

// The layers' outer edge read from the mesh: the edges that an isotropic triangle shares with
// a layer cell (a quad, a fan's or a step's triangle), by vertex.
std::map<VertexId, std::vector<double>> outer_edge_lengths(const Mesh& m) {
    auto key = [](VertexId a, VertexId b) { return std::pair{std::min(a, b), std::max(a, b)}; };
    std::set<std::pair<VertexId, VertexId>> layer_edges;
    for (const auto& q : m.quads)
        for (size_t i = 0; i < 4; ++i) layer_edges.insert(key(q[i], q[(i + 1) % 4]));
    for (const Triangle& t : m.triangles)
        if (t.layer)
            for (size_t i = 0; i < 3; ++i) layer_edges.insert(key(t.v[i], t.v[(i + 1) % 3]));
    std::map<VertexId, std::vector<double>> at;
    for (const Triangle& t : m.triangles) {
        if (t.layer) continue;
        for (size_t i = 0; i < 3; ++i) {
            const VertexId a = t.v[i], b = t.v[(i + 1) % 3];
            if (!layer_edges.count(key(a, b))) continue;
            const double len = distance(m.point(a), m.point(b));
            at[a].push_back(len);
            at[b].push_back(len);
        }
    }
    return at;
}

class Layers : public ::testing::TestWithParam<LayerCase> {};

TEST_P(Layers, TheHybridMeshIsValidAndTheLayersKeepTheirHeights) {
    const LayerCase& c = GetParam();
    const MeshResult r = mesh(c);
    const Mesh& m = r.mesh;
    const auto problems = check_mesh(m);
    EXPECT_TRUE(problems.empty()) << c.name << ": " << (problems.empty() ? "" : problems.front());
    EXPECT_FALSE(m.quads.empty()) << c.name;
    ASSERT_EQ(r.quality.boundary_layers.size(), c.layers.size());
    const BoundaryLayerSpec& s = c.layers[0];
    const auto& fig = r.quality.boundary_layers[0];

    std::set<std::string> walls;
    for (const std::string& name : s.curves) walls.insert(name);
    for (const auto& cs : c.domain.curves)
        if (walls.count(cs.name) && cs.tag) walls.insert(*cs.tag);
    const auto st = stacks(m, walls);
    ASSERT_FALSE(st.empty()) << c.name;
    size_t levels = 0;
    for (const auto& h : st) {
        // First height and growth, from the geometry: s_1 = first, s_(k+1) - s_k = growth (s_k - s_(k-1)).
        EXPECT_NEAR(h[0], s.first_height, 0.01 * s.first_height) << c.name;
        for (size_t k = 1; k < h.size(); ++k) {
            const double below = k == 1 ? h[0] : h[k - 1] - h[k - 2];
            EXPECT_NEAR((h[k] - h[k - 1]) / below, s.growth, 0.01 * s.growth) << c.name << " level " << k;
        }
        if (s.layers) {
            EXPECT_LE(h.size(), static_cast<size_t>(s.layers)) << c.name;
        }
        if (s.thickness > 0) {
            EXPECT_LE(h.back(), s.thickness * (1 + 1e-9)) << c.name;
        }
        levels += h.size();
    }
    EXPECT_GT(levels, 3 * st.size()) << c.name << ": the walls hold layers";
    EXPECT_NEAR(fig.first_height_min, s.first_height, 0.01 * s.first_height) << c.name;
    EXPECT_NEAR(fig.first_height_max, s.first_height, 0.01 * s.first_height) << c.name;
    EXPECT_GT(fig.scaled_jacobian_min, 0.0) << c.name;
    // The corner farthest from a right angle has the smallest sine: the two figures agree.
    EXPECT_GE(fig.skew_max, 0.0);
    EXPECT_LT(fig.skew_max, 1.0);
    EXPECT_NEAR(fig.scaled_jacobian_min, std::cos(fig.skew_max * std::numbers::pi / 2), 1e-9) << c.name;
    EXPECT_GE(fig.aspect_ratio_max, 1.0) << c.name;
    if (c.narrow) {
        EXPECT_GT(fig.cut_back, 0u) << c.name;
        EXPECT_FALSE(fig.cut_back_at.empty()) << c.name;
    }
    EXPECT_LE(fig.cut_back_at.size(), 16u);
    EXPECT_EQ(r.quality.quads, m.quads.size());
}

// Where the layers fan round a corner the walls and the field are spaced for the fan's tops,
// and the interior field is capped at the outer edge's own spacing: the isotropic triangles
// meet the layers at fair angles, with no jump along the outer edge (before: neighbouring
// segments 25 times apart at a NACA trailing edge, 11 degrees).
TEST_P(Layers, TheIsotropicTrianglesMeetTheLayersWithoutAJumpInSize) {
    const LayerCase& c = GetParam();
    const MeshResult r = mesh(c);
    EXPECT_GE(r.quality.angle_min, c.min_angle) << c.name;
    const auto outer = outer_edge_lengths(r.mesh);
    ASSERT_FALSE(outer.empty()) << c.name;
    double worst = 1.0;
    for (const auto& [v, lengths] : outer)
        if (lengths.size() == 2) worst = std::max(worst, std::max(lengths[0], lengths[1]) / std::min(lengths[0], lengths[1]));
    EXPECT_LE(worst, c.outer_ratio) << c.name;
}

TEST_P(Layers, BothTriangulatorsGiveTheSameMeshAndRunsRepeat) {
    const LayerCase& c = GetParam();
    MeshOptions raw;  // no smoothing: the triangulations themselves are compared
    raw.boundary_layers = c.layers;
    raw.smoothing_iterations = 0;
    const MeshResult a = generate_mesh(c.domain, c.density, raw);
    raw.triangulator = Triangulator::AdvancingFront;
    const MeshResult b = generate_mesh(c.domain, c.density, raw);
    EXPECT_TRUE(check_mesh(b.mesh).empty()) << c.name;
    EXPECT_EQ(a.mesh.x, b.mesh.x);
    EXPECT_EQ(a.mesh.y, b.mesh.y);
    EXPECT_EQ(canonical(a.mesh.triangles), canonical(b.mesh.triangles)) << c.name;
    EXPECT_EQ(a.mesh.quads, b.mesh.quads);
    // Smoothing moves interior points, and points on curves along them: the layers stay put.
    const MeshResult s = mesh(c), again = mesh(c);
    ASSERT_EQ(s.mesh.point_count(), a.mesh.point_count());
    for (const std::string& e : fixed_points_kept(build_domain(c.domain), s.mesh, a.mesh))
        ADD_FAILURE() << c.name << ": " << e;
    EXPECT_EQ(s.mesh.quads, a.mesh.quads);
    EXPECT_EQ(s.mesh.x, again.mesh.x);
    EXPECT_EQ(s.mesh.y, again.mesh.y);
    EXPECT_EQ(canonical(s.mesh.triangles), canonical(again.mesh.triangles));
    EXPECT_EQ(s.mesh.quads, again.mesh.quads);
}

INSTANTIATE_TEST_SUITE_P(Domains, Layers, ::testing::ValuesIn(cases()),
                         [](const ::testing::TestParamInfo<LayerCase>& p) {
                             std::string n = p.param.name;
                             for (char& ch : n)
                                 if (ch == '-') ch = '_';
                             return n;
                         });

// The wake line keeps its edges through the layers (each edge of it shared by two cells) and
// the layers around the trailing edge are not cut back.
TEST(LayersAlongAWake, TheFanSlidesOnTheLineAndNothingIsCutBack) {
    const MeshResult r = mesh(wake_line());
    EXPECT_TRUE(check_mesh(r.mesh).empty());
    EXPECT_EQ(r.quality.boundary_layers[0].cut_back, 0u);
    size_t wake_points_in_layers = 0;
    for (VertexId v = 0; v < r.mesh.point_count(); ++v)
        if (r.mesh.kind[v] == PointKind::Embedded && r.mesh.x[v] < 1.01) ++wake_points_in_layers;
    EXPECT_GE(wake_points_in_layers, 10u) << "the column on the wake holds the layers' points";
}

// The end columns of a wall that ends on arcs lie on the arcs: points of those curves, on
// their circles.
TEST(LayersSlide, AlongCurvedBoundaries) {
    const MeshResult r = mesh(wall_between_arcs());
    EXPECT_TRUE(check_mesh(r.mesh).empty());
    const Mesh& m = r.mesh;
    size_t on_arcs_near_the_wall = 0;
    for (VertexId v = 0; v < m.point_count(); ++v) {
        if (m.kind[v] != PointKind::Boundary || m.y[v] > 0.05) continue;
        for (const Vec2 c : {Vec2{1.5, 0.5}, Vec2{0.5, 0.5}})
            if (std::fabs(distance(m.point(v), c) - std::sqrt(0.5)) < 1e-12 && m.y[v] > 1e-9) ++on_arcs_near_the_wall;
    }
    EXPECT_GE(on_arcs_near_the_wall, 10u) << "the end columns' points lie on the arcs";
    EXPECT_EQ(r.quality.boundary_layers[0].cut_back, 0u);
}

// cells "triangles": every quad split along its shorter diagonal, the rest unchanged.
TEST(LayersAsTriangles, EachQuadBecomesTwoTrianglesAlongItsShorterDiagonal) {
    LayerCase c = naca("0012", 1.2, 20);
    const MeshResult quads = mesh(c);
    c.layers[0].quads = false;
    const MeshResult tris = mesh(c);
    EXPECT_TRUE(check_mesh(tris.mesh).empty());
    EXPECT_TRUE(tris.mesh.quads.empty());
    EXPECT_EQ(tris.mesh.triangles.size(), quads.mesh.triangles.size() + 2 * quads.mesh.quads.size());
    EXPECT_EQ(tris.mesh.x, quads.mesh.x);
    // Every quad's two triangles share its shorter diagonal.
    std::set<std::pair<VertexId, VertexId>> edges;
    for (const Triangle& t : tris.mesh.triangles)
        for (int i = 0; i < 3; ++i) edges.insert(std::minmax(t.v[i], t.v[(i + 1) % 3]));
    for (const auto& q : quads.mesh.quads) {
        const double d02 = distance(quads.mesh.point(q[0]), quads.mesh.point(q[2]));
        const double d13 = distance(quads.mesh.point(q[1]), quads.mesh.point(q[3]));
        const auto diag = d02 <= d13 ? std::minmax(q[0], q[2]) : std::minmax(q[1], q[3]);
        EXPECT_TRUE(edges.count(diag));
    }
}

// The layers stop before a cell taller than rho: with a coarse rho they are few.
TEST(LayersStop, BeforeACellTallerThanRho) {
    LayerCase c = cylinder();
    c.layers[0].thickness = 0;
    c.layers[0].layers = 200;
    const MeshResult r = mesh(c);
    EXPECT_TRUE(check_mesh(r.mesh).empty());
    const auto st = stacks(r.mesh, {"cylinder"});
    ASSERT_FALSE(st.empty());
    for (const auto& h : st) {
        ASSERT_GE(h.size(), 2u);
        // rho on the cylinder is 0.03 + 0.05 * 0.5 = 0.055 and grows outwards: the last
        // layer is no taller than rho there, one more would be (growth 1.2).
        const double last = h.back() - h[h.size() - 2];
        EXPECT_LE(last, 0.055 + 0.05 * (h.back() + 1e-9) + 1e-12);
        EXPECT_GT(last * 1.2, (0.055 + 0.05 * h.back()) * 0.999);
    }
}

TEST(LayersRefused, ANameThatIsNoLoopCurveOrTag) {
    LayerCase c = cylinder();
    c.layers[0].curves = {"nothing"};
    try {
        mesh(c);
        FAIL() << "no error";
    } catch (const GeometryError& e) {
        EXPECT_EQ(e.kind(), GeometryErrorKind::UnknownCurve);
        ASSERT_FALSE(e.subjects().empty());
        EXPECT_EQ(e.subjects()[0].kind, Subject::Kind::Layers);
    }
}

TEST(LayersRefused, MoreLayerPointsThanTheLimit) {
    LayerCase c = naca("0012", 1.01, 200);
    MeshOptions o;
    o.boundary_layers = c.layers;
    o.max_points = 5000;
    EXPECT_THROW(generate_mesh(c.domain, c.density, o), GeometryError);
}

}  // namespace

// A free end where the field is coarse stands for a large cross; where its arm reaches the
// wall the field is fine, and a crossing there is no reason to cut the wall's layers back:
// nothing is cut (before the crossing had to lie within the local size of the end, a column
// under the arm lost all its layers).
TEST(LayersBesideAFreeEnd, AreNotCutWhereTheEndsCrossReachesIntoAFinerField) {
    DomainSpec s;
    s.points = {{"A", {0, 0}}, {"B", {3, 0}}, {"C", {3, 1.5}}, {"D", {0, 1.5}}, {"P", {1, 0.3}}, {"Q", {1.3, 0.6}}};
    s.curves = {line("bottom", "A", "B", "wall"), line("right", "B", "C"), line("top", "C", "D"), line("left", "D", "A"),
                line("cut", "P", "Q")};
    s.loops = {loop({"bottom", "right", "top", "left"})};
    s.embedded = {"cut"};
    MeshOptions o;
    o.boundary_layers = {spec({"bottom"}, 1e-4, 1.2, 12)};
    const MeshResult r = generate_mesh(s, density_of("0.01 + 1.5*y"), o);
    EXPECT_TRUE(check_mesh(r.mesh, false).empty());
    EXPECT_EQ(r.quality.boundary_layers[0].cut_back, 0u);
    EXPECT_EQ(r.quality.boundary_layers[0].layers_min, 12);
}

// Found by fuzz/fuzz_request (crash 7e6d2a1c): the bottom wall's layers are cut back to none
// at B, where the right side leans away, and stand two layers high at A on the left side. The
// layers' outer edge then runs from the column's top on the left side straight to the corner
// B, and the smoothing took B for an end of the left side: it let the top slide along the
// side down past the column's first point, and a layer triangle turned over. The points the
// columns leave on the sides stay at whole multiples of the first height (growth 1) from the
// walls.
TEST(LayersOnASide, TheColumnsPointsStayWhereTheLayersPutThem) {
    DomainSpec s;
    s.points = {{"A", {0, 0}}, {"B", {1, 0}}, {"C", {2, 1}}, {"D", {0, 1}}};
    s.curves = {line("bottom", "A", "B", "wall"), line("right", "B", "C"), line("top", "C", "D", "wall"),
                line("left", "D", "A")};
    s.loops = {loop({"bottom", "right", "top", "left"})};
    MeshOptions o;
    o.boundary_layers = {spec({"wall"}, 0.1, 1.0, 200)};
    const MeshResult r = generate_mesh(s, density_of("2.1"), o);
    EXPECT_TRUE(check_mesh(r.mesh, false).empty());
    size_t on_left = 0;
    for (VertexId v = 0; v < r.mesh.point_count(); ++v) {
        if (r.mesh.x[v] != 0.0) continue;
        ++on_left;
        const double tenths = r.mesh.y[v] / 0.1;
        EXPECT_NEAR(tenths, std::round(tenths), 1e-9) << "point " << v << " at y = " << r.mesh.y[v];
    }
    EXPECT_GE(on_left, 4u) << "A, D and a layer point from each wall";
}

// Found by a run of generated layered requests through fuzz/fuzz_request: an embedded line
// leaves the wall's corner P0 at 9 degrees to the wall and ends 0.072 from it, inside the
// first layer (0.114 thick). The line crosses no edge of the layers (it shares the cell's
// corner), so the crossing test let the cell stand over the line's end, which was then in no
// cell. A boundary point strictly inside a cell now takes the cell's top corners away.
TEST(LayersOverAnEmbeddedLine, AreCutBackWhereTheLinesEndLiesInACell) {
    DomainSpec s;
    s.points = {{"P0", {0.5357, 0.3005}}, {"P1", {-0.7038, 0.1226}}, {"P2", {-0.7435, -0.6409}},
                {"E", {0.08863171434957523, 0.061337465972738814}}};
    s.curves = {line("e0", "P0", "P1"), line("e1", "P1", "P2", "wall"), line("e2", "P2", "P0", "wall"),
                line("emb", "P0", "E")};
    s.loops = {loop({"e0", "e1", "e2"})};
    s.embedded = {"emb"};
    for (const double min_angle : {0.0, 25.0}) {
        MeshOptions o;
        o.boundary_layers = {spec({"wall"}, 0.11393115320406842, 1.05, 1)};
        o.min_angle_deg = min_angle;
        const MeshResult r = generate_mesh(s, density_of("0.828676660909711"), o);
        EXPECT_TRUE(check_mesh(r.mesh, false).empty()) << min_angle;
        EXPECT_GT(r.quality.boundary_layers[0].cut_back, 0u) << min_angle;
        // E is a corner of triangles only: no quad holds it.
        VertexId e = kNoVertex;
        for (VertexId v = 0; v < r.mesh.point_count(); ++v)
            if (r.mesh.x[v] == 0.08863171434957523 && r.mesh.y[v] == 0.061337465972738814) e = v;
        ASSERT_NE(e, kNoVertex);
        for (const auto& q : r.mesh.quads) {
            bool inside = true;
            for (int i = 0; i < 4; ++i) {
                const Vec2 a = r.mesh.point(q[i]), b = r.mesh.point(q[(i + 1) % 4]);
                inside = inside && cross(b - a, r.mesh.point(e) - a) > 0.0;
            }
            EXPECT_FALSE(inside) << "a quad over E";
        }
    }
}
