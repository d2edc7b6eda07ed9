#pragma once
// Geometric constructions: points computed in doubles (inexact, unlike the predicates'
// signs); their use is then decided by exact predicates.

#include "meshd/core/vec2.hpp"

namespace meshd::core {

/// Centre of the circle through a, b and c; not finite when they are collinear.
inline Vec2 circumcentre(Vec2 a, Vec2 b, Vec2 c) {
    const Vec2 ab = b - a, ac = c - a;
    const double d = 2.0 * cross(ab, ac);
    return a + Vec2{(ac.y * norm2(ab) - ab.y * norm2(ac)) / d,
                    (ab.x * norm2(ac) - ac.x * norm2(ab)) / d};
}

}  // namespace meshd::core
