#pragma once
// Geometric constructions: points computed in doubles (inexact, unlike the predicates'
// signs); their use is then decided by exact predicates.

#include <cmath>

#include "meshd/core/vec2.hpp"

namespace meshd::core {

/// Centre of the circle through a, b and c; not finite when they are collinear.
inline Vec2 circumcentre(Vec2 a, Vec2 b, Vec2 c) {
    const Vec2 ab = b - a, ac = c - a;
    const double d = 2.0 * cross(ab, ac);
    return a + Vec2{(ac.y * norm2(ab) - ab.y * norm2(ac)) / d,
                    (ab.x * norm2(ac) - ac.x * norm2(ab)) / d};
}

/// Where fixed points make a corner that a triangle of its two sides alone will close (no
/// interior point fits between them: a short spoke leaving a curve, the free part of a line a
/// layer column slid up), the mesher spaces them so that the triangle has no angle below this
/// (degrees): the 30 the defaults promise, and a margin. Only corners of kMinClosingDeg to
/// kMaxClosingDeg: narrower ones close below it whatever their sides, and the interior front
/// places a point in wider ones.
inline constexpr double kClosingAngleDeg = 31.0, kMinClosingDeg = 33.0, kMaxClosingDeg = 116.0;

/// The point of segment ab nearest to p (a itself when the segment has no length).
inline Vec2 nearest_on(Vec2 a, Vec2 b, Vec2 p) {
    const Vec2 ab = b - a;
    const double l2 = dot(ab, ab);
    if (!(l2 > 0.0)) return a;
    const double t = dot(p - a, ab) / l2;
    return a + (t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t) * ab;
}

/// The angle between u and w (radians, 0 to pi).
inline double angle_between(Vec2 u, Vec2 w) { return std::atan2(std::fabs(cross(u, w)), dot(u, w)); }

/// The shortest side that, meeting a side of length b at angle theta (0 < theta < pi - angle),
/// leaves an angle of at least `angle` at b's far end: b sin(angle) / sin(theta + angle).
inline double shortest_side_for_angle(double b, double theta, double angle) {
    return b * std::sin(angle) / std::sin(theta + angle);
}

}  // namespace meshd::core
