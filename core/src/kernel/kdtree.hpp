#pragma once
// A static 2-d tree of median splits, shared by the eq. 6.1 treecode
// (density/inverse_distance.cpp), the size field's caps (density/gradation.cpp, build_kd over
// copies of their sources; a gradation's samples take a tree over their Hilbert order there)
// and the advancing-front triangulator's candidate search
// (triangulation/advancing_front.cpp). The layout (the order of the points, the nodes' ranges
// and boxes) and the depth-first traversal live here; each user keeps its own per-node data
// and decides where to descend.

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <span>
#include <vector>

#include "meshd/core/vec2.hpp"

namespace meshd::core::detail {

struct KdNode {
    Box box;
    std::uint32_t begin, end;   // range in tree order
    std::uint32_t left, right;  // children; 0 for a leaf (node 0 is the root)
};

/// The median splits over records that carry their own positions, built in place: recs[b, e)
/// becomes the range of a node, split at the median of its box's wider side while it holds
/// more than `leaf`. pos(r) is a record's position; records equal on the split coordinate go
/// by before(r, s) (a strict order, or "never" when their order does not matter). Nodes are
/// numbered depth first, each before its children and the left subtree before the right; the
/// root is node 0. Records moved in place, rather than indices into the positions, keep the
/// selection's comparisons in cache (with millions of points, the indirect ones were most of
/// the build).
template <class Rec, class Pos, class Before>
std::uint32_t build_kd(std::vector<KdNode>& nodes, Rec* recs, std::uint32_t b, std::uint32_t e, std::uint32_t leaf,
                       const Pos& pos, const Before& before) {
    const auto id = static_cast<std::uint32_t>(nodes.size());
    nodes.push_back({});
    KdNode n{};
    n.begin = b;
    n.end = e;
    for (std::uint32_t i = b; i < e; ++i) n.box.add(pos(recs[i]));
    if (e - b > leaf) {
        const bool by_x = n.box.hi.x - n.box.lo.x >= n.box.hi.y - n.box.lo.y;
        const std::uint32_t m = b + (e - b) / 2;
        std::nth_element(recs + b, recs + m, recs + e, [&](const Rec& r, const Rec& s) {
            const Vec2 pr = pos(r), ps = pos(s);
            const double cr = by_x ? pr.x : pr.y, cs = by_x ? ps.x : ps.y;
            return cr < cs || (cr == cs && before(r, s));
        });
        n.left = build_kd(nodes, recs, b, m, leaf, pos, before);
        n.right = build_kd(nodes, recs, m, e, leaf, pos, before);
    }
    nodes[id] = n;
    return id;
}

class KdLayout {
public:
    static constexpr std::uint32_t kLeafSize = 8;

    /// order[i]: index of the i-th point in tree order. Splits at the median of the wider
    /// side of each node's box, ties broken by index, so the layout is deterministic.
    explicit KdLayout(std::span<const Vec2> pts) : order(pts.size()) {
        struct Indexed {
            Vec2 p;
            std::uint32_t index;
        };
        std::vector<Indexed> recs(pts.size());
        for (size_t i = 0; i < pts.size(); ++i) recs[i] = {pts[i], static_cast<std::uint32_t>(i)};
        nodes.reserve(2 * pts.size() / kLeafSize + 2);
        if (!pts.empty())
            build_kd(nodes, recs.data(), 0, static_cast<std::uint32_t>(pts.size()), kLeafSize,
                     [](const Indexed& r) { return r.p; },
                     [](const Indexed& r, const Indexed& s) { return r.index < s.index; });
        for (size_t i = 0; i < recs.size(); ++i) order[i] = recs[i].index;
    }

    std::vector<std::uint32_t> order;
    std::vector<KdNode> nodes;
};

/// What a depth-first traversal does after visiting a node: stop altogether, go no deeper
/// there (pruned, or a leaf already handled), or open its children, the named one first.
enum class Descend { Stop, No, LeftFirst, RightFirst };

/// Depth-first traversal from the root (node 0) of any node array with KdNode's `left` and
/// `right` (left == 0 for a leaf); visit(node) returns a Descend.
template <class Nodes, class Visit>
void depth_first(const Nodes& nodes, Visit&& visit) {
    using Node = typename Nodes::value_type;
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
