#pragma once
// Finding crossing segments among many, and the segments near a point, without the quadratic
// all-pairs scan.
//
// Segments are sorted into the size classes of size_grid.hpp (powers of two of their longest
// box side); in the grid of its own class a segment touches at most 2 x 2 cells. A pair is
// tested when the smaller segment is looked up in the grids of classes no smaller than its
// own: O(classes) cells per segment, so the scan is linear in the number of segments for a
// bounded ratio of lengths per cell. Segments that share an end (by point index) are
// neighbours and are not tested.

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "kernel/size_grid.hpp"
#include "meshd/core/vec2.hpp"

namespace meshd::core::detail {

struct SegmentSoup {
    std::vector<Vec2> points;
    std::vector<std::array<std::uint32_t, 2>> segments;  // point indices
};

/// The segments of a soup by size class, each with its box grown by `margin` on every side.
class SegmentGrid {
public:
    struct Cells {
        std::int64_t x0, x1, y0, y1;
    };

    SegmentGrid(const SegmentSoup& soup, double margin);
    /// The segments first to last - 1 only, in the size classes of `frame` (grids made with
    /// one frame have the same classes, so that their segments' sizes compare).
    SegmentGrid(const SegmentSoup& soup, double margin, const Box& frame, std::uint32_t first, std::uint32_t last);

    bool empty() const { return cls_.empty(); }
    int size_class(std::uint32_t segment) const { return cls_[segment - first_]; }
    bool class_used(int k) const { return used_[static_cast<size_t>(k)]; }
    /// The cells of class k that the segment's grown box covers.
    Cells cells(std::uint32_t segment, int k) const;

    template <class F>
    void in_cell(int k, std::int64_t x, std::int64_t y, F&& visit) const {
        for (auto e = grid_.head(k, x, y); e != CellMap::kNone; e = grid_.next(e)) visit(grid_.item(e));
    }
    /// Every segment whose grown box may hold p (a superset: callers test), some more than once.
    template <class F>
    void near(Vec2 p, F&& visit) const {
        if (empty()) return;
        for (int k = 1; k <= SizeClasses::kMax; ++k)
            if (class_used(k)) in_cell(k, classes_.ix(p.x, k), classes_.iy(p.y, k), visit);
    }

private:
    const SegmentSoup& soup_;
    double margin_;
    std::uint32_t first_ = 0;
    SizeClasses classes_;
    std::vector<int> cls_;
    std::array<bool, SizeClasses::kMax + 1> used_{};
    CellMap grid_;
};

/// Calls visit(i, j), i < j, for every pair of segments that share a point (segments with a
/// common end only when they overlap), each pair once.
void for_each_crossing(const SegmentSoup& soup, const std::function<void(std::uint32_t, std::uint32_t)>& visit);

/// A run of a soup's segments, first to last - 1.
struct SegmentRange {
    std::uint32_t first, last;
};

/// for_each_crossing among the segments of one run only.
void for_each_crossing(const SegmentSoup& soup, SegmentRange run, const std::function<void(std::uint32_t, std::uint32_t)>& visit);

/// Calls visit(i, j) for every i of run a and j of run b (two runs that do not overlap) that
/// share a point, as for_each_crossing tells them, each pair once (i always a's). Segments of
/// the same run are never looked at together: where a run's own segments crowd its grid's
/// cells (dozens of thin layers' rungs over one column), only the other run's segments pay
/// for the crowd.
void for_each_crossing_between(const SegmentSoup& soup, SegmentRange a, SegmentRange b,
                               const std::function<void(std::uint32_t, std::uint32_t)>& visit);

/// Calls visit(i, j), i < j, for every pair of segments whose bounding boxes (the boxes with
/// the segment as their diagonal) overlap or touch, each pair once.
void for_each_box_overlap(const SegmentSoup& soup, const std::function<void(std::uint32_t, std::uint32_t)>& visit);

/// True when the convex hulls of the point sets a and b are more than `margin` apart along
/// a direction at right angles to, or along, the line through two points of one set (each
/// pair of a set is tried: a hull's edges are among them). A cheap test that may say false
/// of sets that are apart, never true of sets that meet: with a margin far above the
/// rounding of the projections (1e-9 of the coordinates' size, say), it serves as proof.
bool hulls_apart(std::span<const Vec2> a, std::span<const Vec2> b, double margin);

/// Runs of one soup, tested two at a time (for_each_crossing_between) with each run's grid
/// made once, when first asked for, in a frame common to all runs: a strip of thin layers that
/// faces a dozen others is put in a grid once rather than a dozen times.
class RunCrossings {
public:
    RunCrossings(const SegmentSoup& soup, std::vector<SegmentRange> runs);
    ~RunCrossings();
    RunCrossings(const RunCrossings&) = delete;
    RunCrossings& operator=(const RunCrossings&) = delete;

    /// for_each_crossing_between(soup, runs[r], runs[s], visit).
    void between(size_t r, size_t s, const std::function<void(std::uint32_t, std::uint32_t)>& visit);

private:
    const SegmentGrid& grid(size_t r);

    const SegmentSoup& soup_;
    std::vector<SegmentRange> runs_;
    std::vector<Box> boxes_;
    Box frame_;
    std::vector<std::unique_ptr<SegmentGrid>> grids_;
};

/// The crossing pair (i, j), i < j, with the smallest i (then j), if any.
std::optional<std::pair<std::uint32_t, std::uint32_t>> find_crossing(const SegmentSoup& soup);

}  // namespace meshd::core::detail
