#include "kernel/crossings.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>

#include "kernel/predicates.hpp"

namespace meshd::core::detail {

namespace {

Box grown_box(const SegmentSoup& soup, double margin) {
    Box box;
    for (const auto& s : soup.segments) {
        box.add(soup.points[s[0]]);
        box.add(soup.points[s[1]]);
    }
    if (!soup.segments.empty()) {
        box.lo = box.lo - Vec2{margin, margin};
        box.hi = box.hi + Vec2{margin, margin};
    }
    return box;
}

double longest_side(const Box& b) { return fmax_inline(b.hi.x - b.lo.x, b.hi.y - b.lo.y); }

}  // namespace

SegmentGrid::SegmentGrid(const SegmentSoup& soup, double margin)
    : SegmentGrid(soup, margin, grown_box(soup, margin)) {}

SegmentGrid::SegmentGrid(const SegmentSoup& soup, double margin, const Box& box)
    : soup_(soup), margin_(margin), classes_(box.lo, longest_side(box)) {
    const size_t n = soup.segments.size();
    if (n == 0 || !(longest_side(box) > 0.0)) return;
    // Each segment in the grid whose cells (2 c_k) are one to two times its grown box's
    // longest side: the box spans at most 2 x 2 cells there.
    cls_.resize(n);
    for (std::uint32_t i = 0; i < n; ++i) {
        const Vec2 a = soup.points[soup.segments[i][0]], b = soup.points[soup.segments[i][1]];
        const double side = fmax_inline(std::fabs(a.x - b.x), std::fabs(a.y - b.y)) + 2.0 * margin;
        cls_[i] = classes_.class_of(0.5 * side);
        used_[static_cast<size_t>(cls_[i])] = true;
        const Cells r = cells(i, cls_[i]);
        for (auto x = r.x0; x <= r.x1; ++x)
            for (auto y = r.y0; y <= r.y1; ++y) grid_.push(cls_[i], x, y, i);
    }
}

SegmentGrid::Cells SegmentGrid::cells(std::uint32_t segment, int k) const {
    const Vec2 a = soup_.points[soup_.segments[segment][0]], b = soup_.points[soup_.segments[segment][1]];
    return Cells{classes_.ix(fmin_inline(a.x, b.x) - margin_, k), classes_.ix(fmax_inline(a.x, b.x) + margin_, k),
                 classes_.iy(fmin_inline(a.y, b.y) - margin_, k), classes_.iy(fmax_inline(a.y, b.y) + margin_, k)};
}

namespace {

// Calls visit(i, j) for every pair of segments whose boxes (the boxes with the segments as
// their diagonals; the grid's margin is 0) overlap or touch, each pair once, from the smaller
// segment, j in increasing order for each i.
template <class F>
void for_each_candidate(const SegmentSoup& soup, const SegmentGrid& grid, F&& visit) {
    auto box = [&](std::uint32_t i) {
        Box b;
        b.add(soup.points[soup.segments[i][0]]);
        b.add(soup.points[soup.segments[i][1]]);
        return b;
    };
    std::vector<std::uint32_t> candidates;
    // The segment whose candidates last took each segment: a segment met again in another
    // cell is not taken twice (thin layers put dozens of levels in one cell of their longer
    // edges, each met from up to four cells).
    std::vector<std::uint32_t> taken_by(soup.segments.size(), UINT32_MAX);
    for (std::uint32_t i = 0; i < soup.segments.size(); ++i) {
        candidates.clear();
        const int own = grid.size_class(i);
        const Box bi = box(i);
        for (int k = 1; k <= own; ++k) {  // classes of segments no smaller than this one
            if (!grid.class_used(k)) continue;
            const SegmentGrid::Cells r = grid.cells(i, k);
            for (auto x = r.x0; x <= r.x1; ++x)
                for (auto y = r.y0; y <= r.y1; ++y)
                    grid.in_cell(k, x, y, [&](std::uint32_t j) {
                        if (j == i || (grid.size_class(j) == own && j < i)) return;  // same class: test once
                        if (taken_by[j] == i) return;
                        taken_by[j] = i;
                        const Box bj = box(j);
                        if (bi.lo.x <= bj.hi.x && bj.lo.x <= bi.hi.x && bi.lo.y <= bj.hi.y && bj.lo.y <= bi.hi.y)
                            candidates.push_back(j);
                    });
        }
        if (candidates.empty()) continue;
        std::sort(candidates.begin(), candidates.end());  // the callers' order: by segment
        for (const std::uint32_t j : candidates) visit(i, j);
    }
}

}  // namespace

void for_each_crossing(const SegmentSoup& soup, const std::function<void(std::uint32_t, std::uint32_t)>& visit) {
    const auto& pts = soup.points;
    const auto& segs = soup.segments;
    if (segs.size() < 2) return;
    const SegmentGrid grid(soup, 0.0);
    if (grid.empty()) return;
    for_each_candidate(soup, grid, [&](std::uint32_t i, std::uint32_t j) {
        const auto& s = segs[i];
        const auto& t = segs[j];
        if (s[0] == t[0] || s[0] == t[1] || s[1] == t[0] || s[1] == t[1]) {
            // Neighbours: only a collinear overlap (folding back) is a crossing.
            const std::uint32_t shared = (s[0] == t[0] || s[0] == t[1]) ? s[0] : s[1];
            const std::uint32_t so = s[0] == shared ? s[1] : s[0];
            const std::uint32_t to = t[0] == shared ? t[1] : t[0];
            if (so != to && (orient2d(pts[shared], pts[so], pts[to]) != Orientation::Collinear ||
                             dot(pts[so] - pts[shared], pts[to] - pts[shared]) < 0.0))
                return;
        } else if (!segments_intersect(pts[s[0]], pts[s[1]], pts[t[0]], pts[t[1]])) {
            return;
        }
        visit(std::min(i, j), std::max(i, j));
    });
}

void for_each_box_overlap(const SegmentSoup& soup, const std::function<void(std::uint32_t, std::uint32_t)>& visit) {
    if (soup.segments.size() < 2) return;
    const SegmentGrid grid(soup, 0.0);
    if (grid.empty()) return;
    for_each_candidate(soup, grid, [&](std::uint32_t i, std::uint32_t j) { visit(std::min(i, j), std::max(i, j)); });
}

bool hulls_apart(std::span<const Vec2> a, std::span<const Vec2> b, double margin) {
    // The two sets' extents along n, and whether a gap of more than margin |n| lies between.
    auto parted_along = [&](Vec2 n) {
        const double len = norm(n);
        if (!(len > 0.0)) return false;
        double a_lo = HUGE_VAL, a_hi = -HUGE_VAL, b_lo = HUGE_VAL, b_hi = -HUGE_VAL;
        for (const Vec2& p : a) {
            const double d = dot(n, p);
            a_lo = fmin_inline(a_lo, d);
            a_hi = fmax_inline(a_hi, d);
        }
        for (const Vec2& p : b) {
            const double d = dot(n, p);
            b_lo = fmin_inline(b_lo, d);
            b_hi = fmax_inline(b_hi, d);
        }
        const double gap = margin * len;
        return a_lo - b_hi > gap || b_lo - a_hi > gap;
    };
    for (const std::span<const Vec2> s : {a, b})
        for (size_t i = 0; i < s.size(); ++i)
            for (size_t j = i + 1; j < s.size(); ++j) {
                const Vec2 d = s[j] - s[i];
                if (parted_along(perp(d)) || parted_along(d)) return true;
            }
    return false;
}

std::optional<std::pair<std::uint32_t, std::uint32_t>> find_crossing(const SegmentSoup& soup) {
    std::optional<std::pair<std::uint32_t, std::uint32_t>> best;
    for_each_crossing(soup, [&](std::uint32_t i, std::uint32_t j) {
        if (!best || std::pair{i, j} < *best) best = std::pair{i, j};
    });
    return best;
}

}  // namespace meshd::core::detail
