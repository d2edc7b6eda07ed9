#pragma once
/// Exact geometric predicates (adaptive precision).
///
/// Each predicate first evaluates its determinant in double precision and compares it with
/// a forward error bound (Shewchuk, "Adaptive precision floating-point arithmetic and fast
/// robust geometric predicates", 1997). Only when the bound does not settle the sign is the
/// determinant recomputed exactly as a floating-point expansion (a sum of non-overlapping
/// doubles), from which the sign is read. Inputs must be finite.

#include <cmath>
#include <cstdint>

#include "meshd/core/vec2.hpp"

namespace meshd::core {

enum class Orientation : int { Right = -1, Collinear = 0, Left = 1 };

namespace detail {
// The exact stages, for the rare calls the floating-point filter cannot settle.
Orientation orient2d_exact(Vec2 a, Vec2 b, Vec2 c);
int incircle_exact(Vec2 a, Vec2 b, Vec2 c, Vec2 d);
int incircle_tie(Vec2 a, Vec2 b, Vec2 c, Vec2 d, std::uint32_t ra, std::uint32_t rb, std::uint32_t rc,
                 std::uint32_t rd);
// Error bounds of the filters relative to the magnitude sums (Shewchuk's ccwerrboundA and
// iccerrboundA for round-to-nearest doubles).
inline constexpr double kEpsilon = 0x1p-53;
inline constexpr double kOrientBound = (3.0 + 16.0 * kEpsilon) * kEpsilon;
inline constexpr double kIncircleBound = (10.0 + 96.0 * kEpsilon) * kEpsilon;
}  // namespace detail

/// Side of c with respect to the directed line a -> b: Left when a, b, c turn
/// counter-clockwise. (The filter is inline: the triangulators call it in their inner loops.)
inline Orientation orient2d(Vec2 a, Vec2 b, Vec2 c) {
    const double left = (a.x - c.x) * (b.y - c.y);
    const double right = (a.y - c.y) * (b.x - c.x);
    const double det = left - right;
    // std::fabs clears the sign bit without a branch; a comparison here compiled to one
    // branch per term, mispredicted half the time (the signs of coordinate differences).
    const double sum = std::fabs(left) + std::fabs(right);
    if (det > detail::kOrientBound * sum) return Orientation::Left;
    if (-det > detail::kOrientBound * sum) return Orientation::Right;
    return detail::orient2d_exact(a, b, c);
}

/// Position of d with respect to the circle through a, b, c (a, b, c counter-clockwise):
/// > 0 inside, < 0 outside, 0 on the circle. For a, b, c clockwise the sign flips.
/// (Always inline: with more than a few callers the compiler stopped inlining it, and the
/// Delaunay flips' tests, out of line, cost more than the calls they had saved.)
[[gnu::always_inline]] inline int incircle(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
    const double adx = a.x - d.x, ady = a.y - d.y;
    const double bdx = b.x - d.x, bdy = b.y - d.y;
    const double cdx = c.x - d.x, cdy = c.y - d.y;
    const double bdxcdy = bdx * cdy, cdxbdy = cdx * bdy;
    const double alift = adx * adx + ady * ady;
    const double cdxady = cdx * ady, adxcdy = adx * cdy;
    const double blift = bdx * bdx + bdy * bdy;
    const double adxbdy = adx * bdy, bdxady = bdx * ady;
    const double clift = cdx * cdx + cdy * cdy;
    const double det = alift * (bdxcdy - cdxbdy) + blift * (cdxady - adxcdy) + clift * (adxbdy - bdxady);
    auto mag = [](double v) { return std::fabs(v); };  // no branch (see orient2d)
    const double permanent = (mag(bdxcdy) + mag(cdxbdy)) * alift + (mag(cdxady) + mag(adxcdy)) * blift +
                             (mag(adxbdy) + mag(bdxady)) * clift;
    const double bound = detail::kIncircleBound * permanent;
    if (det > bound) return 1;
    if (-det > bound) return -1;
    return detail::incircle_exact(a, b, c, d);
}

/// incircle() under a symbolic perturbation that removes every tie: each point p_i is
/// lifted to x^2 + y^2 + eps^(rank_i) with eps infinitesimal, a smaller rank weighing more
/// (callers rank by vertex index). The result is never 0 unless all four points are
/// collinear. Every decision of the Delaunay code goes through it, so that any two
/// algorithms building the (constrained) Delaunay triangulation of the same points build
/// the same one, cocircular points included.
inline int incircle_perturbed(Vec2 a, Vec2 b, Vec2 c, Vec2 d, std::uint32_t ra, std::uint32_t rb,
                              std::uint32_t rc, std::uint32_t rd) {
    const int s = incircle(a, b, c, d);
    return s != 0 ? s : detail::incircle_tie(a, b, c, d, ra, rb, rc, rd);
}

/// How many predicate calls of this thread needed the exact stage, for statistics.
struct PredicateCounters {
    std::uint64_t orient_exact = 0;
    std::uint64_t incircle_exact = 0;
};
/// Counters of the calling thread since it started (or since reset).
PredicateCounters predicate_counters();
void reset_predicate_counters();

/// True when the closed segments ab and cd have at least one point in common.
bool segments_intersect(Vec2 a, Vec2 b, Vec2 c, Vec2 d);

/// True when p lies on the segment ab and is neither end, exactly: collinear, and within
/// the segment's box by comparisons (a length along ab in floating point cannot tell a
/// point one unit in the last place short of b from b).
bool inside_segment(Vec2 a, Vec2 b, Vec2 p);

}  // namespace meshd::core
