#pragma once
/// Exact geometric predicates (adaptive precision).
///
/// Each predicate first evaluates its determinant in double precision and compares it with
/// a forward error bound (Shewchuk, "Adaptive precision floating-point arithmetic and fast
/// robust geometric predicates", 1997). Only when the bound does not settle the sign is the
/// determinant recomputed exactly as a floating-point expansion (a sum of non-overlapping
/// doubles), from which the sign is read. Inputs must be finite.

#include <atomic>
#include <cstdint>

#include "meshd/core/vec2.hpp"

namespace meshd::core {

enum class Orientation : int { Right = -1, Collinear = 0, Left = 1 };

/// Side of c with respect to the directed line a -> b: Left when a, b, c turn
/// counter-clockwise.
Orientation orient2d(Vec2 a, Vec2 b, Vec2 c);

/// Position of d with respect to the circle through a, b, c (a, b, c counter-clockwise):
/// > 0 inside, < 0 outside, 0 on the circle. For a, b, c clockwise the sign flips.
int incircle(Vec2 a, Vec2 b, Vec2 c, Vec2 d);

/// incircle() under a symbolic perturbation that removes every tie: each point p_i is
/// lifted to x^2 + y^2 + eps^(rank_i) with eps infinitesimal, a smaller rank weighing more
/// (callers rank by vertex index). The result is never 0 unless all four points are
/// collinear. Every decision of the Delaunay code goes through it, so that any two
/// algorithms building the (constrained) Delaunay triangulation of the same points build
/// the same one, cocircular points included.
int incircle_perturbed(Vec2 a, Vec2 b, Vec2 c, Vec2 d, std::uint32_t ra, std::uint32_t rb,
                       std::uint32_t rc, std::uint32_t rd);

/// Calls of the predicates and how many needed the exact stage, for statistics.
struct PredicateCounters {
    std::uint64_t orient_calls = 0;
    std::uint64_t orient_exact = 0;
    std::uint64_t incircle_calls = 0;
    std::uint64_t incircle_exact = 0;
};
/// Counters of the calling thread since it started (or since reset).
PredicateCounters predicate_counters();
void reset_predicate_counters();

/// True when the closed segments ab and cd have at least one point in common.
bool segments_intersect(Vec2 a, Vec2 b, Vec2 c, Vec2 d);

}  // namespace meshd::core
