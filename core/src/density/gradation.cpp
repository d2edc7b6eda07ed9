#include "density/gradation.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#if defined(__AVX__)
#include <immintrin.h>
#endif

#include "kernel/kdtree.hpp"
#include "kernel/spatial_order.hpp"
#include "meshd/core/errors.hpp"

namespace meshd::core {

// The envelope does not depend on the tree: a node is passed over only when its bound, which
// the rounding keeps at or below every cone inside it (the same operations on distances no
// longer than any of theirs), is at or above the least found, so the least cone is the same
// whatever the layout. Two layouts, by how the sources lie (Spread in gradation.hpp):
// - along curves, a k-d tree of median splits (detail::build_kd) over copies of the sources:
//   its boxes do not overlap;
// - over the domain, the sources along a Hilbert curve (a radix sort), kLeafSize to a leaf,
//   and a balanced binary tree over the leaves, each node's box and least size its
//   children's: the boxes overlap a little, but the build makes no comparisons to
//   mispredict. With median splits, the build was 28% of the NACA 0006 far field's run under
//   a gradation of 1.5 (2.8 million sources), and with this tree the run went from 2.3 to
//   1.7 s.
// Leaves of 32 rather than 8 (of 16 to 32 sources in the k-d tree rather than 4 to 8): a
// leaf's cones, four to an AVX step, cost less than the nodes a search passes through to
// reach fewer of them. Where the field's cones come below it (beside a refinement box's edge,
// a field that swings faster than the ratio allows) a search looks at every leaf about as
// far as the nearest fine source, and larger leaves are fewer of them: `bench/hard/sine_fast`
// 333.5 -> 316.4 M instructions, `channel_thin` 120.5 -> 112.4 M, no request more.
GradationField::GradationField(std::span<const Vec2> sources, std::span<const double> sizes, double ratio,
                               Spread spread)
    : slope_(ratio - 1.0), search_factor_(spread == Spread::Curves ? 4.0 : 1.0) {
    MESHD_INTERNAL_CHECK(sources.size() == sizes.size() && !sources.empty(), "gradation needs sources");
    const auto n = static_cast<std::uint32_t>(sources.size());
    detail::reserve_huge(x_, n + 3);
    detail::reserve_huge(y_, n + 3);
    detail::reserve_huge(h_, n + 3);
    if (spread == Spread::Domain) {
        for (const std::uint32_t i : detail::hilbert_order(sources)) {
            x_.push_back(sources[i].x);
            y_.push_back(sources[i].y);
            h_.push_back(sizes[i]);
        }
        const std::uint32_t leaves = (n + kLeafSize - 1) / kLeafSize;
        detail::reserve_huge(nodes_, 2 * static_cast<size_t>(leaves));
        build(0, leaves, n);
    } else {
        struct Source {
            Vec2 p;
            double h;
        };
        std::vector<Source> src(n);
        for (std::uint32_t i = 0; i < n; ++i) src[i] = {sources[i], sizes[i]};
        std::vector<detail::KdNode> tree;
        tree.reserve(2 * static_cast<size_t>(n) / kLeafSize + 2);
        detail::build_kd(tree, src.data(), 0, n, kLeafSize, [](const Source& q) { return q.p; },
                         [](const Source&, const Source&) { return false; });
        for (const Source& q : src) {
            x_.push_back(q.p.x);
            y_.push_back(q.p.y);
            h_.push_back(q.h);
        }
        // The nodes' least sizes from the leaves up: children come after their parent.
        nodes_.resize(tree.size());
        for (size_t k = tree.size(); k-- > 0;) {
            const detail::KdNode& t = tree[k];
            Node& nd = nodes_[k];
            nd = {t.box, HUGE_VAL, t.begin, t.end, t.left, t.right};
            if (t.left == 0)
                for (std::uint32_t i = t.begin; i < t.end; ++i) nd.hmin = std::fmin(nd.hmin, h_[i]);
            else
                nd.hmin = std::fmin(nodes_[t.left].hmin, nodes_[t.right].hmin);
        }
    }
    // Three more entries, never the least: a leaf's last step of four reads past its end.
    for (int k = 0; k < 3; ++k) {
        x_.push_back(0.0);
        y_.push_back(0.0);
        h_.push_back(HUGE_VAL);
    }
}

// The node over leaves [lb, le) and its subtree, depth first (each node before its children,
// the left subtree before the right; node 0 the root). Returns its index.
std::uint32_t GradationField::build(std::uint32_t lb, std::uint32_t le, std::uint32_t n) {
    const auto id = static_cast<std::uint32_t>(nodes_.size());
    nodes_.push_back({});
    Node nd{};
    nd.begin = lb * kLeafSize;
    nd.end = std::min(n, le * kLeafSize);
    nd.hmin = HUGE_VAL;
    if (le - lb == 1) {
        for (std::uint32_t i = nd.begin; i < nd.end; ++i) {
            nd.box.add(Vec2{x_[i], y_[i]});
            nd.hmin = std::fmin(nd.hmin, h_[i]);
        }
    } else {
        const std::uint32_t m = lb + (le - lb) / 2;
        nd.left = build(lb, m, n);
        nd.right = build(m, le, n);
        for (const std::uint32_t c : {nd.left, nd.right}) {
            nd.box.add(nodes_[c].box);
            nd.hmin = std::fmin(nd.hmin, nodes_[c].hmin);
        }
    }
    nodes_[id] = nd;
    return id;
}

double GradationField::capped(Vec2 x, double upper) const {
    // Below the envelope by the last search's bound (less a margin for the rounding of the
    // cones' sums): the answer is `upper`, to the bit.
    const double moved = slope_ * distance(x, last_at_);
    if (upper <= last_floor_ - moved - 1e-12 * (std::fabs(last_floor_) + moved)) return upper;
    // Along curves, searched up to four times `upper`: the cones above that are pruned as
    // early as those above `upper`, and the result is a bound that lasts for the next queries
    // (twice `upper` searched a third more often, for 0.8% more of Fig. 9's instructions;
    // eight times, no fewer). Over the domain, up to `upper`: there the envelope lies just
    // above the field nearly everywhere, a wider search found no bound to reuse and cost a
    // search for the nearest sources at every query (the NACA 0006 far field under a gradation:
    // 8.4 G instructions against 4.7 G; Fig. 9's caps searched so, in the same tree: 427 M
    // against 335 M).
    const double floor = search(x, search_factor_ * upper);
    last_at_ = x;
    last_floor_ = floor;
    return fmin_inline(upper, floor);
}

// The least of the cones at x of the sources [b, e) and of up to three after them: four a
// step where the processor has AVX (each cone by the same operations as one at a time, and the
// least of a set whatever the order). A cone past e is another source's, or an entry at
// infinity past the last: a value of the envelope's own cones, so the search still ends on
// the least of them.
#if defined(__AVX__)
double GradationField::least_cone(std::uint32_t b, std::uint32_t e, Vec2 x) const {
    const __m256d px = _mm256_set1_pd(x.x), py = _mm256_set1_pd(x.y), slope = _mm256_set1_pd(slope_);
    __m256d least = _mm256_set1_pd(HUGE_VAL);
    for (std::uint32_t i = b; i < e; i += 4) {
        const __m256d dx = _mm256_sub_pd(px, _mm256_loadu_pd(x_.data() + i));
        const __m256d dy = _mm256_sub_pd(py, _mm256_loadu_pd(y_.data() + i));
        const __m256d d = _mm256_sqrt_pd(_mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy)));
        least = _mm256_min_pd(least, _mm256_add_pd(_mm256_loadu_pd(h_.data() + i), _mm256_mul_pd(slope, d)));
    }
    const __m128d two = _mm_min_pd(_mm256_castpd256_pd128(least), _mm256_extractf128_pd(least, 1));
    return _mm_cvtsd_f64(_mm_min_sd(two, _mm_unpackhi_pd(two, two)));
}
#else
double GradationField::least_cone(std::uint32_t b, std::uint32_t e, Vec2 x) const {
    double least = HUGE_VAL;
    for (std::uint32_t i = b; i < e; ++i) least = fmin_inline(least, h_[i] + slope_ * distance(x, {x_[i], y_[i]}));
    return least;
}
#endif

// Depth first, each node's bound made where its parent is taken: a child whose bound is not
// below the least found is never stacked, and of two the one with the lower bound is taken
// first (its cones lower `best` sooner; the order never changes the least cone found). A
// stacked node is looked at again when taken, against the least found by then.
double GradationField::search(Vec2 x, double upper) const {
    double best = upper;
    auto bound = [&](const Node& n) {
        // At or above `best` already by its least size: no distance needed.
        return n.hmin >= best ? n.hmin : n.hmin + slope_ * std::sqrt(n.box.distance2(x));
    };
    struct Entry {
        std::uint32_t node;
        double bound;
    };
    Entry stack[128];  // at most one a level waits beside the path; the trees are far shallower
    int top = 0;
    const double root = bound(nodes_[0]);
    if (root >= best) return best;
    stack[top++] = {0, root};
    while (top > 0) {
        const Entry e = stack[--top];
        if (e.bound >= best) continue;
        const Node& n = nodes_[e.node];
        if (n.left == 0) {
            best = fmin_inline(best, least_cone(n.begin, n.end, x));
            continue;
        }
        const double bl = bound(nodes_[n.left]), br = bound(nodes_[n.right]);
        const bool left = bl < best, right = br < best;
        if (left && right) {
            if (bl <= br) {
                stack[top++] = {n.right, br};
                stack[top++] = {n.left, bl};
            } else {
                stack[top++] = {n.left, bl};
                stack[top++] = {n.right, br};
            }
        } else if (left) {
            stack[top++] = {n.left, bl};
        } else if (right) {
            stack[top++] = {n.right, br};
        }
    }
    return best;
}

}  // namespace meshd::core
