// Points among a domain's loops; see nesting.hpp.

#include "geometry/nesting.hpp"

#include <algorithm>
#include <cmath>

#include "kernel/predicates.hpp"

namespace meshd::core::detail {

RingIndex::RingIndex(const std::vector<Vec2>& ring) : ring_(ring) {
    const size_t n = ring.size();
    lo_ = HUGE_VAL;
    hi_ = -HUGE_VAL;
    for (Vec2 p : ring) lo_ = std::fmin(lo_, p.y), hi_ = std::fmax(hi_, p.y);
    size_t bands = std::max<size_t>(1, n / 4);
    for (;; bands = std::max<size_t>(1, bands / 2)) {
        inv_ = hi_ > lo_ ? static_cast<double>(bands) / (hi_ - lo_) : 0.0;
        bands_ = bands;
        size_t entries = 0;
        for (size_t i = 0; i < n; ++i) {
            const auto [b0, b1] = span(ring[i].y, ring[(i + 1) % n].y);
            entries += b1 - b0 + 1;
        }
        if (entries <= 16 * n + 16 || bands == 1) break;
    }
    start_.assign(bands_ + 1, 0);
    for (size_t i = 0; i < n; ++i) {
        const auto [b0, b1] = span(ring[i].y, ring[(i + 1) % n].y);
        for (size_t b = b0; b <= b1; ++b) ++start_[b + 1];
    }
    for (size_t b = 0; b < bands_; ++b) start_[b + 1] += start_[b];
    edges_.resize(start_.back());
    std::vector<size_t> fill(start_.begin(), start_.end() - 1);
    for (size_t i = 0; i < n; ++i) {
        const auto [b0, b1] = span(ring[i].y, ring[(i + 1) % n].y);
        for (size_t b = b0; b <= b1; ++b) edges_[fill[b]++] = static_cast<std::uint32_t>(i);
    }
}

int RingIndex::winding(Vec2 p) const {
    if (!(p.y >= lo_ && p.y <= hi_)) return 0;  // above or below every edge
    const size_t b = band(p.y);
    int w = 0;
    const size_t n = ring_.size();
    for (size_t k = start_[b]; k < start_[b + 1]; ++k) {
        const Vec2 a = ring_[edges_[k]], c = ring_[(edges_[k] + 1) % n];
        if (a.y <= p.y) {
            if (c.y > p.y && orient2d(a, c, p) == Orientation::Left) ++w;
        } else if (c.y <= p.y && orient2d(a, c, p) == Orientation::Right) {
            --w;
        }
    }
    return w;
}

size_t RingIndex::band(double y) const {
    const double f = std::floor((y - lo_) * inv_);
    if (!(f > 0.0)) return 0;
    return std::min(static_cast<size_t>(std::fmin(f, 1e18)), bands_ - 1);
}

std::pair<size_t, size_t> RingIndex::span(double y0, double y1) const {
    return {band(std::fmin(y0, y1)), band(std::fmax(y0, y1))};
}

LoopNesting::LoopNesting(const std::vector<std::vector<Vec2>>& rings, size_t outer)
    : rings_(rings), outer_(outer), boxes_(rings.size()), index_(rings.size()) {
    for (size_t r = 0; r < rings.size(); ++r)
        for (Vec2 p : rings[r]) boxes_[r].add(p);
    for (size_t r = 0; r < rings.size(); ++r) {
        if (r == outer) continue;
        const auto k = static_cast<std::uint32_t>(box_soup_.points.size());
        box_soup_.points.push_back(boxes_[r].lo);
        box_soup_.points.push_back(boxes_[r].hi);
        box_soup_.segments.push_back({k, k + 1});
        holes_.push_back(r);
    }
    box_grid_ = std::make_unique<SegmentGrid>(box_soup_, 0.0);
}

LoopNesting::~LoopNesting() = default;

int LoopNesting::winding(size_t ring, Vec2 p) {
    if (!index_[ring]) index_[ring] = std::make_unique<RingIndex>(rings_[ring]);
    return index_[ring]->winding(p);
}

bool LoopNesting::inside_outer(Vec2 p) { return boxes_[outer_].contains(p) && winding(outer_, p) != 0; }

std::optional<size_t> LoopNesting::hole_holding(Vec2 p, size_t except) {
    std::optional<size_t> found;
    box_grid_->near(p, [&](std::uint32_t i) {
        const size_t h = holes_[i];
        if (!found && h != except && boxes_[h].contains(p) && winding(h, p) != 0) found = h;
    });
    return found;
}

}  // namespace meshd::core::detail
