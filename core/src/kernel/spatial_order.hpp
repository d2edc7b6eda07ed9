#pragma once
// Orders of points along a Hilbert curve, for memory locality and short walks.

#include <cstdint>
#include <span>
#include <vector>

#include "meshd/core/vec2.hpp"
#include "kernel/memory.hpp"

namespace meshd::core::detail {

/// Indices of `pts` along a Hilbert curve over their bounding box (2^12 cells a side;
/// points in one cell keep their index order). Deterministic, O(n).
Array<std::uint32_t> hilbert_order(std::span<const Vec2> pts);

/// Biased randomised insertion order (Amenta, Choi and Rote): each point joins a round by a
/// hash of its index (the last round holds 7/8 of the points, each earlier round 1/8 of the
/// next, the first about 64), and each round follows the Hilbert curve. Deterministic, O(n).
Array<std::uint32_t> brio_order(std::span<const Vec2> pts);

}  // namespace meshd::core::detail
