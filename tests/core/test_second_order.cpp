// Second-order meshes (MeshOptions::order 2): a node on every edge, on the curve for the edges
// that lie on one, and no curved triangle folded.

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>

#include "fixtures.hpp"
#include "meshd/core/mesher.hpp"
#include "pipeline/second_order.hpp"

using namespace meshd::core;
using namespace meshd::test;

namespace {

// The square [-1, 1]^2 with a circular hole of radius r at the origin.
DomainSpec square_with_hole(double r) {
    DomainSpec s;
    s.points = {{"A", {-1, -1}}, {"B", {1, -1}}, {"C", {1, 1}}, {"D", {-1, 1}}, {"H", {r, 0}}};
    s.curves = {line("bottom", "A", "B", "wall"), line("right", "B", "C", "wall"), line("top", "C", "D", "wall"),
                line("left", "D", "A", "wall"), arc("hole", "H", "H", {0, 0}, ArcDirection::Ccw, "hole")};
    s.loops = {loop({"bottom", "right", "top", "left"}), loop({"hole"})};
    return s;
}

MeshResult mesh2(const DomainSpec& s, double size, bool curve_agreement = true) {
    DensitySpec d;
    d.size = size;
    MeshOptions o;
    o.order = 2;
    o.curve_agreement = curve_agreement;
    return generate_mesh(s, d, o);
}

// Every edge of the mesh (as a sorted vertex pair) with the edge nodes the triangles on it
// name: exactly one node per edge, shared by the two triangles of an inner edge.
void expect_one_node_per_edge(const Mesh& m) {
    std::map<std::pair<VertexId, VertexId>, std::set<std::uint32_t>> nodes;
    for (TriangleId t = 0; t < m.triangles.size(); ++t)
        for (std::uint32_t i = 0; i < 3; ++i) {
            VertexId a = m.triangles[t].v[(i + 1) % 3], b = m.triangles[t].v[(i + 2) % 3];
            nodes[{std::min(a, b), std::max(a, b)}].insert(m.edge_node[t][i]);
        }
    // Euler: V - E + F = 1 - holes.
    EXPECT_EQ(nodes.size(), m.point_count() + m.triangles.size() - 1 + m.holes);
    EXPECT_EQ(m.edge_nodes.size(), nodes.size());
    std::set<std::uint32_t> all;
    for (const auto& [edge, ids] : nodes) {
        EXPECT_EQ(ids.size(), 1u);
        all.insert(*ids.begin());
    }
    EXPECT_EQ(all.size(), nodes.size());  // no node on two edges
}

}  // namespace

TEST(SecondOrder, CurveEdgesGetNodesOnTheCurveAndInnerEdgesTheChordMiddle) {
    const double r = 0.4;
    const MeshResult res = mesh2(square_with_hole(r), 0.08);
    const Mesh& m = res.mesh;
    ASSERT_EQ(m.order(), 2);
    EXPECT_TRUE(check_mesh(m).empty());
    expect_one_node_per_edge(m);
    ASSERT_EQ(m.edge_node_of_edge.size(), m.edges.size());
    EXPECT_EQ(res.quality.straightened_edges, 0u);
    // Every boundary edge lies on a curve (a line is one too); the hole's curved triangles
    // are the only ones whose Jacobian varies, so the smallest is below 1 but not below 0.1.
    EXPECT_EQ(res.quality.curved_edges, m.edges.size());
    EXPECT_LT(res.quality.scaled_jacobian_min, 1.0 - 1e-6);
    EXPECT_GE(res.quality.scaled_jacobian_min, 0.1);
    std::set<std::uint32_t> on_curves;
    for (size_t k = 0; k < m.edges.size(); ++k) {
        const MeshEdge& e = m.edges[k];
        const Vec2 p = m.edge_nodes[m.edge_node_of_edge[k]];
        on_curves.insert(m.edge_node_of_edge[k]);
        if (m.tags[e.tag] == "hole") {
            // On the circle, between the edge's ends (the shorter arc), not on the chord.
            EXPECT_NEAR(std::hypot(p.x, p.y), r, 1e-12) << "edge " << k;
            const Vec2 a = m.point(e.a), b = m.point(e.b);
            const double mid_angle = std::atan2(a.y + b.y, a.x + b.x);
            EXPECT_NEAR(std::remainder(std::atan2(p.y, p.x) - mid_angle, 2 * M_PI), 0.0, 1e-9) << "edge " << k;
        } else {
            // A straight side: the chord's middle.
            EXPECT_NEAR(p.x, (m.x[e.a] + m.x[e.b]) / 2, 1e-15);
            EXPECT_NEAR(p.y, (m.y[e.a] + m.y[e.b]) / 2, 1e-15);
        }
    }
    for (TriangleId t = 0; t < m.triangles.size(); ++t) {
        bool straight = true;
        for (std::uint32_t i = 0; i < 3; ++i) straight = straight && !on_curves.count(m.edge_node[t][i]);
        // A straight 6-node triangle maps the reference triangle affinely: J / 2A = 1 everywhere.
        if (straight) {
            EXPECT_NEAR(min_scaled_jacobian(m, t), 1.0, 1e-9) << "triangle " << t;
        }
        for (std::uint32_t i = 0; i < 3; ++i) {
            if (on_curves.count(m.edge_node[t][i])) continue;
            const VertexId a = m.triangles[t].v[(i + 1) % 3], b = m.triangles[t].v[(i + 2) % 3];
            EXPECT_EQ(m.edge_nodes[m.edge_node[t][i]].x, (m.x[a] + m.x[b]) / 2);
            EXPECT_EQ(m.edge_nodes[m.edge_node[t][i]].y, (m.y[a] + m.y[b]) / 2);
        }
        EXPECT_GE(min_scaled_jacobian(m, t), 0.1) << "triangle " << t;
    }
}

// A coarse hole close to the walls: its arcs bulge more than the gap between it and the
// square is wide. Curved, the thin triangles there would fold; those edges stay straight and
// every triangle keeps a positive Jacobian. With the curves' own spacing: the agreement spaces
// both sides of a gap narrower than their segments at its width, and nothing folds then.
TEST(SecondOrder, EdgesThatWouldFoldATriangleStayStraight) {
    const double r = 0.9;
    DomainSpec s = square_with_hole(r);
    const MeshResult res = mesh2(s, 0.9, false);
    const Mesh& m = res.mesh;
    EXPECT_TRUE(check_mesh(m).empty());
    expect_one_node_per_edge(m);
    std::uint64_t straight_hole_edges = 0;
    for (size_t k = 0; k < m.edges.size(); ++k) {
        if (m.tags[m.edges[k].tag] != "hole") continue;
        const Vec2 p = m.edge_nodes[m.edge_node_of_edge[k]];
        const double d = std::hypot(p.x, p.y);
        if (std::abs(d - r) > 1e-12) {
            ++straight_hole_edges;  // then it is the chord's middle
            EXPECT_NEAR(p.x, (m.x[m.edges[k].a] + m.x[m.edges[k].b]) / 2, 1e-15);
        }
    }
    EXPECT_EQ(straight_hole_edges, res.quality.straightened_edges);
    EXPECT_GT(res.quality.straightened_edges, 0u) << "the case no longer folds: make it coarser";
    EXPECT_EQ(res.quality.curved_edges + res.quality.straightened_edges, m.edges.size());
    double lowest = 1.0;
    for (TriangleId t = 0; t < m.triangles.size(); ++t) {
        EXPECT_GE(min_scaled_jacobian(m, t), 0.1) << "triangle " << t;
        lowest = std::min(lowest, min_scaled_jacobian(m, t));
    }
    EXPECT_EQ(res.quality.scaled_jacobian_min, lowest);
}

TEST(SecondOrder, OrderOneHasNoEdgeNodes) {
    DensitySpec d;
    d.size = 0.2;
    const MeshResult res = generate_mesh(square_with_hole(0.4), d);
    EXPECT_EQ(res.mesh.order(), 1);
    EXPECT_TRUE(res.mesh.edge_nodes.empty());
}

// Order 2 after the min_angle_deg refinement (its new boundary points on their curves): the
// edge nodes are made from the refined mesh.
TEST(SecondOrder, AfterMinAngleRefinement) {
    DensitySpec d;
    d.size = 0.15;
    MeshOptions o;
    o.order = 2;
    o.min_angle_deg = 30;
    const MeshResult res = generate_mesh(square_with_hole(0.4), d, o);
    const Mesh& m = res.mesh;
    EXPECT_TRUE(check_mesh(m).empty());
    expect_one_node_per_edge(m);
    for (size_t k = 0; k < m.edges.size(); ++k)
        if (m.tags[m.edges[k].tag] == "hole") {
            const Vec2 p = m.edge_nodes[m.edge_node_of_edge[k]];
            EXPECT_NEAR(std::hypot(p.x, p.y), 0.4, 1e-12) << "edge " << k;
        }
    for (TriangleId t = 0; t < m.triangles.size(); ++t) EXPECT_GE(min_scaled_jacobian(m, t), 0.1) << "triangle " << t;
}
