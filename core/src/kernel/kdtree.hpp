#pragma once
// A static 2-d tree of median splits, shared by the eq. 6.1 treecode
// (density/inverse_distance.cpp), the gradation field (density/gradation.cpp) and the
// advancing-front triangulator's candidate search (triangulation/advancing_front.cpp). The
// layout (the order of the points, the nodes' ranges and boxes) and the depth-first
// traversal live here; each user keeps its own per-node data and decides where to descend.

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <vector>

#include "meshd/core/vec2.hpp"

namespace meshd::core::detail {

struct KdNode {
    Box box;
    std::uint32_t begin, end;   // range in tree order
    std::uint32_t left, right;  // children; 0 for a leaf (node 0 is the root)
};

class KdLayout {
public:
    static constexpr std::uint32_t kLeafSize = 8;

    /// order[i]: index of the i-th point in tree order. Splits at the median of the wider
    /// side of each node's box, ties broken by index, so the layout is deterministic.
    explicit KdLayout(const std::vector<Vec2>& pts) : order(pts.size()), pts_(pts) {
        std::iota(order.begin(), order.end(), 0u);
        nodes.reserve(2 * pts.size() / kLeafSize + 2);
        if (!pts.empty()) build(0, static_cast<std::uint32_t>(pts.size()));
    }

    std::vector<std::uint32_t> order;
    std::vector<KdNode> nodes;

private:
    std::uint32_t build(std::uint32_t b, std::uint32_t e) {
        const auto id = static_cast<std::uint32_t>(nodes.size());
        nodes.push_back({});
        KdNode n{};
        n.begin = b;
        n.end = e;
        for (std::uint32_t i = b; i < e; ++i) n.box.add(pts_[order[i]]);
        if (e - b > kLeafSize) {
            const bool by_x = n.box.hi.x - n.box.lo.x >= n.box.hi.y - n.box.lo.y;
            const std::uint32_t m = b + (e - b) / 2;
            std::nth_element(order.begin() + b, order.begin() + m, order.begin() + e, [&](std::uint32_t i, std::uint32_t j) {
                const double pi = by_x ? pts_[i].x : pts_[i].y, pj = by_x ? pts_[j].x : pts_[j].y;
                return pi < pj || (pi == pj && i < j);
            });
            n.left = build(b, m);
            n.right = build(m, e);
        }
        nodes[id] = n;
        return id;
    }

    const std::vector<Vec2>& pts_;
};

/// What a depth-first traversal does after visiting a node: stop altogether, go no deeper
/// there (pruned, or a leaf already handled), or open its children, the named one first.
enum class Descend { Stop, No, LeftFirst, RightFirst };

/// Depth-first traversal from the root (node 0) of any node array with KdNode's `left` and
/// `right` (left == 0 for a leaf); visit(node) returns a Descend.
template <class Node, class Visit>
void depth_first(const std::vector<Node>& nodes, Visit&& visit) {
    if (nodes.empty()) return;
    std::uint32_t stack[128];  // two entries a level at most; the trees are far shallower
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const Node& n = nodes[stack[--top]];
        const Descend d = visit(n);
        if (d == Descend::Stop) return;
        if (d == Descend::No || n.left == 0) continue;
        if (d == Descend::LeftFirst) {
            stack[top++] = n.right;
            stack[top++] = n.left;
        } else {
            stack[top++] = n.left;
            stack[top++] = n.right;
        }
    }
}

}  // namespace meshd::core::detail
