#pragma once
// The compass search both the smoothing and the refinement place points with: from p, the
// eight compass directions at step h; the best of them that beats `best` is taken, else the
// step halves; until the step is down to `stop` or `iterations` steps are done. No
// derivatives: the scores (smallest angles, worst shapes) are minima over triangles, flat or
// kinked where two triangles tie.

#include <array>
#include <numbers>

#include "meshd/core/vec2.hpp"

namespace meshd::core::detail {

/// Returns the best point found; `best` holds its score (unchanged when none beat it).
/// score(q, bound) may stop early and return anything not above `bound` when q cannot beat it.
template <class Score>
Vec2 pattern_search(Vec2 p, double h, double stop, int iterations, double& best, Score&& score) {
    constexpr double r = 0.5 * std::numbers::sqrt2;
    static constexpr std::array<Vec2, 8> kCompass{Vec2{1, 0},  Vec2{r, r},   Vec2{0, 1},  Vec2{-r, r},
                                                  Vec2{-1, 0}, Vec2{-r, -r}, Vec2{0, -1}, Vec2{r, -r}};
    for (int iter = 0; iter < iterations && h > stop; ++iter) {
        Vec2 next = p;
        for (const Vec2& d : kCompass) {
            const Vec2 q = p + h * d;
            const double f = score(q, best);
            if (f > best) {
                best = f;
                next = q;
            }
        }
        if (next == p) h *= 0.5;
        p = next;
    }
    return p;
}

}  // namespace meshd::core::detail
