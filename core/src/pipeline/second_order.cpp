#include "pipeline/second_order.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "geometry/curve.hpp"

namespace meshd::core {

namespace {

/// A curved triangle whose scaled Jacobian falls below this at a node is straightened: it
/// would be folded (below 0) or so distorted that a finite element on it is useless.
constexpr double kMinScaledJacobian = 0.1;

std::uint64_t edge_key(VertexId a, VertexId b) {
    if (a > b) std::swap(a, b);
    return (static_cast<std::uint64_t>(a) << 32) | b;
}

Vec2 chord_middle(const Mesh& m, VertexId a, VertexId b) { return {(m.x[a] + m.x[b]) / 2, (m.y[a] + m.y[b]) / 2}; }

// The parameter of vertex v on curve c: its own when it lies on c, else that of the curve's
// end it is (for a closed curve, the end nearer `near`); nothing when v is not on c.
std::optional<double> param_on(const Mesh& m, const Curve& g, CurveId c, VertexId v, std::optional<double> near) {
    if (m.curve[v] == c) return m.param[v];
    if (c >= m.curve_ends.size()) return std::nullopt;
    const auto& ends = m.curve_ends[c];
    if (ends[0] == v && ends[1] == v) {
        if (!near) return std::nullopt;
        return std::abs(*near - g.t_begin()) <= std::abs(*near - g.t_end()) ? g.t_begin() : g.t_end();
    }
    if (ends[0] == v) return g.t_begin();
    if (ends[1] == v) return g.t_end();
    return std::nullopt;
}

// The six nodes of triangle t in the order of the shape functions: corners, then the nodes
// on (v0, v1), (v1, v2), (v2, v0).
std::array<Vec2, 6> nodes_of(const Mesh& m, TriangleId t) {
    const Triangle& tri = m.triangles[t];
    const auto& e = m.edge_node[t];
    return {m.point(tri.v[0]), m.point(tri.v[1]), m.point(tri.v[2]), m.edge_nodes[e[2]], m.edge_nodes[e[0]],
            m.edge_nodes[e[1]]};
}

}  // namespace

double min_scaled_jacobian(const Mesh& m, TriangleId t) {
    const std::array<Vec2, 6> p = nodes_of(m, t);
    const double twice_area = (p[1].x - p[0].x) * (p[2].y - p[0].y) - (p[2].x - p[0].x) * (p[1].y - p[0].y);
    // The reference nodes (xi, eta); the quadratic shape functions' derivatives there.
    static constexpr double kAt[6][2] = {{0, 0}, {1, 0}, {0, 1}, {0.5, 0}, {0.5, 0.5}, {0, 0.5}};
    double lowest = INFINITY;
    for (const auto& at : kAt) {
        const double l1 = at[0], l2 = at[1], l0 = 1 - l1 - l2;
        const double dxi[6] = {-(4 * l0 - 1), 4 * l1 - 1, 0, 4 * (l0 - l1), 4 * l2, -4 * l2};
        const double deta[6] = {-(4 * l0 - 1), 0, 4 * l2 - 1, -4 * l1, 4 * l1, 4 * (l0 - l2)};
        double x_xi = 0, y_xi = 0, x_eta = 0, y_eta = 0;
        for (size_t i = 0; i < 6; ++i) {
            x_xi += dxi[i] * p[i].x;
            y_xi += dxi[i] * p[i].y;
            x_eta += deta[i] * p[i].x;
            y_eta += deta[i] * p[i].y;
        }
        lowest = std::min(lowest, (x_xi * y_eta - x_eta * y_xi) / twice_area);
    }
    return lowest;
}

EdgeNodeCounts add_edge_nodes(Mesh& m, const Domain& domain) {
    std::unordered_map<std::uint64_t, std::uint32_t> curve_edge;  // constrained edge -> index in m.edges
    curve_edge.reserve(m.edges.size() * 2);
    for (std::uint32_t k = 0; k < m.edges.size(); ++k) curve_edge.emplace(edge_key(m.edges[k].a, m.edges[k].b), k);

    m.edge_nodes.clear();
    m.edge_nodes.reserve(m.point_count() + m.triangles.size());
    m.edge_node.assign(m.triangles.size(), {0, 0, 0});
    m.edge_node_of_edge.assign(m.edges.size(), 0);
    std::vector<std::uint8_t> curved;  // per edge node: it lies on a curve, off its chord
    for (TriangleId t = 0; t < m.triangles.size(); ++t) {
        const Triangle& tri = m.triangles[t];
        for (std::uint32_t i = 0; i < 3; ++i) {
            const TriangleId n = tri.n[i];
            if (n != kNoTriangle && n < t) {
                // Made by the neighbour: the same node.
                const Triangle& other = m.triangles[n];
                for (std::uint32_t j = 0; j < 3; ++j)
                    if (other.n[j] == t) m.edge_node[t][i] = m.edge_node[n][j];
                continue;
            }
            const VertexId a = tri.v[(i + 1) % 3], b = tri.v[(i + 2) % 3];
            Vec2 node = chord_middle(m, a, b);
            bool on_curve = false;
            if (edge_bit(tri.constrained, i)) {
                auto it = curve_edge.find(edge_key(a, b));
                if (it != curve_edge.end()) {
                    const CurveId c = m.edges[it->second].curve;
                    const Curve& g = *domain.curves()[c].geometry;
                    std::optional<double> ta = param_on(m, g, c, a, std::nullopt);
                    std::optional<double> tb = param_on(m, g, c, b, ta);
                    if (!ta) ta = param_on(m, g, c, a, tb);
                    if (ta && tb) {
                        node = g.point((*ta + *tb) / 2);
                        on_curve = true;
                    }
                    m.edge_node_of_edge[it->second] = static_cast<std::uint32_t>(m.edge_nodes.size());
                }
            }
            m.edge_node[t][i] = static_cast<std::uint32_t>(m.edge_nodes.size());
            m.edge_nodes.push_back(node);
            curved.push_back(on_curve ? 1 : 0);
        }
    }

    // Curved triangles that the curve would fold (a thin layer by a strongly curved wall):
    // their curve nodes go back to the chords.
    EdgeNodeCounts counts;
    for (TriangleId t = 0; t < m.triangles.size(); ++t) {
        const auto& e = m.edge_node[t];
        if (!curved[e[0]] && !curved[e[1]] && !curved[e[2]]) continue;
        if (min_scaled_jacobian(m, t) >= kMinScaledJacobian) continue;
        const Triangle& tri = m.triangles[t];
        for (std::uint32_t i = 0; i < 3; ++i) {
            if (!curved[e[i]]) continue;
            m.edge_nodes[e[i]] = chord_middle(m, tri.v[(i + 1) % 3], tri.v[(i + 2) % 3]);
            curved[e[i]] = 0;
            ++counts.straightened;
        }
    }
    for (std::uint8_t c : curved) counts.curved += c;
    return counts;
}

}  // namespace meshd::core
