#include "meshd/core/gradation.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "meshd/core/errors.hpp"

namespace meshd::core {

GradationField::GradationField(std::vector<Vec2> sources, std::vector<double> sizes, double ratio)
    : slope_(ratio - 1.0) {
    MESHD_INTERNAL_CHECK(sources.size() == sizes.size() && !sources.empty(), "gradation needs sources");
    std::vector<std::uint32_t> idx(sources.size());
    std::iota(idx.begin(), idx.end(), 0u);
    // Order the sources as the tree will: median splits, recursively.
    auto split = [&](auto&& self, std::uint32_t b, std::uint32_t e) -> void {
        if (e - b <= 8) return;
        Box box;
        for (std::uint32_t i = b; i < e; ++i) box.add(sources[idx[i]]);
        const bool by_x = box.hi.x - box.lo.x >= box.hi.y - box.lo.y;
        const std::uint32_t m = b + (e - b) / 2;
        std::nth_element(idx.begin() + b, idx.begin() + m, idx.begin() + e, [&](std::uint32_t i, std::uint32_t j) {
            const double pi = by_x ? sources[i].x : sources[i].y, pj = by_x ? sources[j].x : sources[j].y;
            return pi < pj || (pi == pj && i < j);
        });
        self(self, b, m);
        self(self, m, e);
    };
    split(split, 0, static_cast<std::uint32_t>(idx.size()));
    pts_.reserve(idx.size());
    h_.reserve(idx.size());
    for (auto i : idx) {
        pts_.push_back(sources[i]);
        h_.push_back(sizes[i]);
    }
    build(0, static_cast<std::uint32_t>(pts_.size()));
}

std::uint32_t GradationField::build(std::uint32_t begin, std::uint32_t end) {
    const auto id = static_cast<std::uint32_t>(nodes_.size());
    nodes_.push_back({});
    Node n{};
    n.begin = begin;
    n.end = end;
    n.hmin = HUGE_VAL;
    for (std::uint32_t i = begin; i < end; ++i) {
        n.box.add(pts_[i]);
        n.hmin = std::fmin(n.hmin, h_[i]);
    }
    if (end - begin > 8) {
        const std::uint32_t m = begin + (end - begin) / 2;
        n.left = build(begin, m);
        n.right = build(m, end);
    }
    nodes_[id] = n;
    return id;
}

double GradationField::operator()(Vec2 x) const {
    double best = HUGE_VAL;
    std::uint32_t stack[128];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const Node& n = nodes_[stack[--top]];
        const double dx = std::fmax(0.0, std::fmax(n.box.lo.x - x.x, x.x - n.box.hi.x));
        const double dy = std::fmax(0.0, std::fmax(n.box.lo.y - x.y, x.y - n.box.hi.y));
        if (n.hmin + slope_ * std::sqrt(dx * dx + dy * dy) >= best) continue;
        if (n.left == 0) {
            for (std::uint32_t i = n.begin; i < n.end; ++i) best = std::fmin(best, h_[i] + slope_ * distance(x, pts_[i]));
            continue;
        }
        // Nearer child last, so it is taken first.
        const Node& l = nodes_[n.left];
        const Node& r = nodes_[n.right];
        const double dl = distance(x, 0.5 * (l.box.lo + l.box.hi));
        const double dr = distance(x, 0.5 * (r.box.lo + r.box.hi));
        if (dl < dr) {
            stack[top++] = n.right;
            stack[top++] = n.left;
        } else {
            stack[top++] = n.left;
            stack[top++] = n.right;
        }
    }
    return best;
}

}  // namespace meshd::core
