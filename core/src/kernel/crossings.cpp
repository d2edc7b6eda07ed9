#include "kernel/crossings.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>

#include "kernel/predicates.hpp"

namespace meshd::core::detail {

namespace {

Box grown_box(const SegmentSoup& soup, double margin, SegmentRange run) {
    Box box;
    for (std::uint32_t i = run.first; i < run.last; ++i) {
        box.add(soup.points[soup.segments[i][0]]);
        box.add(soup.points[soup.segments[i][1]]);
    }
    if (run.last > run.first) {
        box.lo = box.lo - Vec2{margin, margin};
        box.hi = box.hi + Vec2{margin, margin};
    }
    return box;
}

double longest_side(const Box& b) { return fmax_inline(b.hi.x - b.lo.x, b.hi.y - b.lo.y); }

SegmentRange all_of(const SegmentSoup& soup) { return {0, static_cast<std::uint32_t>(soup.segments.size())}; }

// Up to this many pairs, for_each_crossing_between tests each (the shorter run then holds at
// most 64 segments).
constexpr std::uint64_t kBetweenEveryPair = 4096;

}  // namespace

SegmentGrid::SegmentGrid(const SegmentSoup& soup, double margin)
    : SegmentGrid(soup, margin, grown_box(soup, margin, all_of(soup)), 0, static_cast<std::uint32_t>(soup.segments.size())) {}

SegmentGrid::SegmentGrid(const SegmentSoup& soup, double margin, const Box& frame, std::uint32_t first,
                         std::uint32_t last)
    : soup_(soup), margin_(margin), first_(first), classes_(frame.lo, longest_side(frame)) {
    if (last <= first || !(longest_side(frame) > 0.0)) return;
    // Each segment in the grid whose cells (2 c_k) are one to two times its grown box's
    // longest side: the box spans at most 2 x 2 cells there.
    cls_.resize(last - first);
    for (std::uint32_t i = first; i < last; ++i) {
        const Vec2 a = soup.points[soup.segments[i][0]], b = soup.points[soup.segments[i][1]];
        const double side = fmax_inline(std::fabs(a.x - b.x), std::fabs(a.y - b.y)) + 2.0 * margin;
        const int k = classes_.class_of(0.5 * side);
        cls_[i - first] = k;
        used_[static_cast<size_t>(k)] = true;
        const Cells r = cells(i, k);
        for (auto x = r.x0; x <= r.x1; ++x)
            for (auto y = r.y0; y <= r.y1; ++y) grid_.push(k, x, y, i);
    }
}

SegmentGrid::Cells SegmentGrid::cells(std::uint32_t segment, int k) const {
    const Vec2 a = soup_.points[soup_.segments[segment][0]], b = soup_.points[soup_.segments[segment][1]];
    return Cells{classes_.ix(fmin_inline(a.x, b.x) - margin_, k), classes_.ix(fmax_inline(a.x, b.x) + margin_, k),
                 classes_.iy(fmin_inline(a.y, b.y) - margin_, k), classes_.iy(fmax_inline(a.y, b.y) + margin_, k)};
}

namespace {

Box segment_box(const SegmentSoup& soup, std::uint32_t i) {
    Box b;
    b.add(soup.points[soup.segments[i][0]]);
    b.add(soup.points[soup.segments[i][1]]);
    return b;
}

bool boxes_meet(const Box& a, const Box& b) {
    return a.lo.x <= b.hi.x && b.lo.x <= a.hi.x && a.lo.y <= b.hi.y && b.lo.y <= a.hi.y;
}

// Calls visit(i, j) for every j in `grid` of a class from 1 to `upto` whose box (the box with
// the segment as its diagonal; the grid's margin is 0) overlaps or touches i's, and that
// `take(j)` lets through, in increasing order of j. `taken_by` (indexed by j - base) holds
// the query whose candidates last took each segment: a segment met again in another cell is
// not taken twice (thin layers put dozens of levels in one cell of their longer edges, each
// met from up to four cells).
template <class Take, class F>
void candidates_of(const SegmentSoup& soup, std::uint32_t i, const SegmentGrid& grid, int upto, Take&& take,
                   std::vector<std::uint32_t>& taken_by, std::uint32_t base, std::vector<std::uint32_t>& candidates,
                   F&& visit) {
    candidates.clear();
    const Box bi = segment_box(soup, i);
    for (int k = 1; k <= upto; ++k) {
        if (!grid.class_used(k)) continue;
        const SegmentGrid::Cells r = grid.cells(i, k);
        for (auto x = r.x0; x <= r.x1; ++x)
            for (auto y = r.y0; y <= r.y1; ++y)
                grid.in_cell(k, x, y, [&](std::uint32_t j) {
                    if (!take(j) || taken_by[j - base] == i) return;
                    taken_by[j - base] = i;
                    if (boxes_meet(bi, segment_box(soup, j))) candidates.push_back(j);
                });
    }
    std::sort(candidates.begin(), candidates.end());  // the callers' order: by segment
    for (const std::uint32_t j : candidates) visit(i, j);
}

// Calls visit(i, j) for every pair of segments of the run whose boxes overlap or touch, each
// pair once, from the smaller segment, j in increasing order for each i.
template <class F>
void for_each_candidate(const SegmentSoup& soup, const SegmentGrid& grid, SegmentRange run, F&& visit) {
    std::vector<std::uint32_t> candidates;
    std::vector<std::uint32_t> taken_by(run.last - run.first, UINT32_MAX);
    for (std::uint32_t i = run.first; i < run.last; ++i) {
        const int own = grid.size_class(i);
        // Classes of segments no smaller than this one; within its own class, each pair once.
        candidates_of(
            soup, i, grid, own, [&](std::uint32_t j) { return j != i && (grid.size_class(j) != own || j > i); },
            taken_by, run.first, candidates, visit);
    }
}

// Whether segments i and j share a point; neighbours (a common end) only where they overlap.
bool segments_cross(const SegmentSoup& soup, std::uint32_t i, std::uint32_t j) {
    const auto& pts = soup.points;
    const auto& s = soup.segments[i];
    const auto& t = soup.segments[j];
    if (s[0] == t[0] || s[0] == t[1] || s[1] == t[0] || s[1] == t[1]) {
        // Neighbours: only a collinear overlap (folding back) is a crossing.
        const std::uint32_t shared = (s[0] == t[0] || s[0] == t[1]) ? s[0] : s[1];
        const std::uint32_t so = s[0] == shared ? s[1] : s[0];
        const std::uint32_t to = t[0] == shared ? t[1] : t[0];
        return so == to || (orient2d(pts[shared], pts[so], pts[to]) == Orientation::Collinear &&
                            dot(pts[so] - pts[shared], pts[to] - pts[shared]) >= 0.0);
    }
    return segments_intersect(pts[s[0]], pts[s[1]], pts[t[0]], pts[t[1]]);
}

}  // namespace

void for_each_crossing(const SegmentSoup& soup, SegmentRange run, const std::function<void(std::uint32_t, std::uint32_t)>& visit) {
    if (run.last < run.first + 2) return;
    const SegmentGrid grid(soup, 0.0, grown_box(soup, 0.0, run), run.first, run.last);
    if (grid.empty()) return;
    for_each_candidate(soup, grid, run, [&](std::uint32_t i, std::uint32_t j) {
        if (segments_cross(soup, i, j)) visit(std::min(i, j), std::max(i, j));
    });
}

void for_each_crossing(const SegmentSoup& soup, const std::function<void(std::uint32_t, std::uint32_t)>& visit) {
    for_each_crossing(soup, all_of(soup), visit);
}

namespace {

// True (and each pair visited) when the runs are short enough to test every pair: rather than
// two grids made (their hash tables' fixed cost is some 50,000 instructions; a pair's boxes
// take about ten).
bool every_pair_between(const SegmentSoup& soup, SegmentRange a, SegmentRange b,
                        const std::function<void(std::uint32_t, std::uint32_t)>& visit) {
    if (static_cast<std::uint64_t>(a.last - a.first) * (b.last - b.first) > kBetweenEveryPair) return false;
    // The shorter run's boxes made once (it holds at most 64 segments).
    const bool a_shorter = a.last - a.first <= b.last - b.first;
    const SegmentRange shorter = a_shorter ? a : b, longer = a_shorter ? b : a;
    std::array<Box, 64> boxes;
    for (std::uint32_t i = shorter.first; i < shorter.last; ++i) boxes[i - shorter.first] = segment_box(soup, i);
    for (std::uint32_t j = longer.first; j < longer.last; ++j) {
        const Box bj = segment_box(soup, j);
        for (std::uint32_t i = shorter.first; i < shorter.last; ++i)
            if (boxes_meet(boxes[i - shorter.first], bj) && segments_cross(soup, i, j)) {
                if (a_shorter) visit(i, j);
                else visit(j, i);
            }
    }
    return true;
}

// for_each_crossing_between with the runs' grids (made in one frame, so that their classes
// compare) and boxes given.
void grids_between(const SegmentSoup& soup, const SegmentGrid& grid_a, SegmentRange a, const Box& box_a,
                   const SegmentGrid& grid_b, SegmentRange b, const Box& box_b,
                   const std::function<void(std::uint32_t, std::uint32_t)>& visit) {
    if (grid_a.empty() || grid_b.empty()) return;
    std::vector<std::uint32_t> candidates;
    auto cross = [&](std::uint32_t i, std::uint32_t j) {
        if (segments_cross(soup, i, j)) visit(i, j);
    };
    // Each pair from its smaller segment: a's in b's classes no smaller than their own, b's in
    // a's classes strictly larger; a segment clear of the other run's box asks nothing (two
    // strips that face each other meet over a part of each).
    std::vector<std::uint32_t> taken_b(b.last - b.first, UINT32_MAX);
    for (std::uint32_t i = a.first; i < a.last; ++i)
        if (boxes_meet(segment_box(soup, i), box_b))
            candidates_of(soup, i, grid_b, grid_a.size_class(i), [](std::uint32_t) { return true; }, taken_b, b.first,
                          candidates, cross);
    std::vector<std::uint32_t> taken_a(a.last - a.first, UINT32_MAX);
    for (std::uint32_t j = b.first; j < b.last; ++j)
        if (boxes_meet(segment_box(soup, j), box_a))
            candidates_of(soup, j, grid_a, grid_b.size_class(j) - 1, [](std::uint32_t) { return true; }, taken_a,
                          a.first, candidates, [&](std::uint32_t jj, std::uint32_t i) { cross(i, jj); });
}

}  // namespace

void for_each_crossing_between(const SegmentSoup& soup, SegmentRange a, SegmentRange b,
                               const std::function<void(std::uint32_t, std::uint32_t)>& visit) {
    RunCrossings(soup, {a, b}).between(0, 1, visit);
}

RunCrossings::RunCrossings(const SegmentSoup& soup, std::vector<SegmentRange> runs)
    : soup_(soup), runs_(std::move(runs)), grids_(runs_.size()) {
    boxes_.reserve(runs_.size());
    for (const SegmentRange& r : runs_) {
        boxes_.push_back(grown_box(soup, 0.0, r));
        frame_.add(boxes_.back());
    }
}

RunCrossings::~RunCrossings() = default;

const SegmentGrid& RunCrossings::grid(size_t r) {
    if (!grids_[r]) grids_[r] = std::make_unique<SegmentGrid>(soup_, 0.0, frame_, runs_[r].first, runs_[r].last);
    return *grids_[r];
}

void RunCrossings::between(size_t r, size_t s, const std::function<void(std::uint32_t, std::uint32_t)>& visit) {
    const SegmentRange a = runs_[r], b = runs_[s];
    if (a.last <= a.first || b.last <= b.first || !boxes_meet(boxes_[r], boxes_[s]) ||
        every_pair_between(soup_, a, b, visit))
        return;
    grids_between(soup_, grid(r), a, boxes_[r], grid(s), b, boxes_[s], visit);
}

void for_each_box_overlap(const SegmentSoup& soup, const std::function<void(std::uint32_t, std::uint32_t)>& visit) {
    if (soup.segments.size() < 2) return;
    const SegmentGrid grid(soup, 0.0);
    if (grid.empty()) return;
    for_each_candidate(soup, grid, all_of(soup), [&](std::uint32_t i, std::uint32_t j) { visit(std::min(i, j), std::max(i, j)); });
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
