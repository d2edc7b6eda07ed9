#pragma once
// Finding crossing segments among many, without the quadratic all-pairs scan.
//
// Segments are sorted into the size classes of size_grid.hpp (powers of two of their longest
// box side); in the grid of its own class a segment touches at most 2 x 2 cells. A pair is tested when the smaller segment is looked up in
// the grids of classes no smaller than its own: O(classes) cells per segment, so the scan
// is linear in the number of segments for a bounded ratio of lengths per cell.
// Segments that share an end (by point index) are neighbours and are not tested.

#include <array>
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "meshd/core/vec2.hpp"

namespace meshd::core::detail {

struct SegmentSoup {
    std::vector<Vec2> points;
    std::vector<std::array<std::uint32_t, 2>> segments;  // point indices
};

/// The crossing pair (i, j), i < j, with the smallest i (then j), if any.
std::optional<std::pair<std::uint32_t, std::uint32_t>> find_crossing(const SegmentSoup& soup);

}  // namespace meshd::core::detail
