#pragma once
// Second-order meshes: a node on every edge, on the curve for the edges that lie on one.

#include <cstdint>

#include "meshd/core/domain.hpp"
#include "meshd/core/mesh.hpp"

namespace meshd::core {

struct EdgeNodeCounts {
    std::uint64_t curved = 0;        ///< curve edges whose middle node lies on their curve
    std::uint64_t straightened = 0;  ///< curve edges left straight: the curve would fold a triangle
};

/// Fills mesh.edge_nodes, edge_node and edge_node_of_edge. A curve edge whose curved node
/// would fold its triangle (or either triangle, inside the domain) is left straight.
EdgeNodeCounts add_edge_nodes(Mesh& mesh, const Domain& domain);

/// The Jacobian determinant of the 6-node triangle t's map from the reference triangle, at
/// its three corners and three edge nodes, over twice the straight triangle's area (1 for a
/// straight triangle); the smallest of the six.
double min_scaled_jacobian(const Mesh& mesh, TriangleId t);

}  // namespace meshd::core
