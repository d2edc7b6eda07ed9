#include "density/gradation.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "kernel/kdtree.hpp"
#include "meshd/core/errors.hpp"

namespace meshd::core {

GradationField::GradationField(std::vector<Vec2> sources, std::vector<double> sizes, double ratio)
    : slope_(ratio - 1.0) {
    MESHD_INTERNAL_CHECK(sources.size() == sizes.size() && !sources.empty(), "gradation needs sources");
    const detail::KdLayout tree(sources);
    pts_.reserve(sources.size());
    h_.reserve(sources.size());
    for (auto i : tree.order) {
        pts_.push_back(sources[i]);
        h_.push_back(sizes[i]);
    }
    nodes_.reserve(tree.nodes.size());
    for (const detail::KdNode& k : tree.nodes) {
        Node n{k.box, HUGE_VAL, k.begin, k.end, k.left, k.right};
        for (std::uint32_t i = k.begin; i < k.end; ++i) n.hmin = std::fmin(n.hmin, h_[i]);
        nodes_.push_back(n);
    }
}

double GradationField::capped(Vec2 x, double upper) const {
    // Below the envelope by the last search's bound (less a margin for the rounding of the
    // cones' sums): the answer is `upper`, to the bit.
    const double moved = slope_ * distance(x, last_at_);
    if (upper <= last_floor_ - moved - 1e-12 * (std::fabs(last_floor_) + moved)) return upper;
    // Searched up to twice `upper`: the cones above that are pruned as early as those above
    // `upper`, and the result is a bound that lasts for the next queries.
    const double floor = search(x, 2.0 * upper);
    last_at_ = x;
    last_floor_ = floor;
    return std::fmin(upper, floor);
}

double GradationField::search(Vec2 x, double upper) const {
    double best = upper;
    detail::depth_first(nodes_, [&](const Node& n) {
        if (n.hmin + slope_ * std::sqrt(n.box.distance2(x)) >= best) return detail::Descend::No;
        if (n.left == 0) {
            for (std::uint32_t i = n.begin; i < n.end; ++i) {
                const double h = h_[i] + slope_ * distance(x, pts_[i]);
                if (h < best) best = h;
            }
            return detail::Descend::No;
        }
        // The nearer child first: its cones lower `best` sooner. (Squared distances: the
        // order only changes how soon `best` falls, never the least cone found.)
        const Node& l = nodes_[n.left];
        const Node& r = nodes_[n.right];
        const double dl = norm2(x - 0.5 * (l.box.lo + l.box.hi));
        const double dr = norm2(x - 0.5 * (r.box.lo + r.box.hi));
        return dl < dr ? detail::Descend::LeftFirst : detail::Descend::RightFirst;
    });
    return best;
}

}  // namespace meshd::core
