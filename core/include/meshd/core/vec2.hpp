#pragma once
/// Plane vectors and points. A plain aggregate: cheap to copy, no invariants.

#include <cmath>

namespace meshd::core {

struct Vec2 {
    double x = 0.0;
    double y = 0.0;

    friend constexpr Vec2 operator+(Vec2 a, Vec2 b) { return {a.x + b.x, a.y + b.y}; }
    friend constexpr Vec2 operator-(Vec2 a, Vec2 b) { return {a.x - b.x, a.y - b.y}; }
    friend constexpr Vec2 operator-(Vec2 a) { return {-a.x, -a.y}; }
    friend constexpr Vec2 operator*(double s, Vec2 a) { return {s * a.x, s * a.y}; }
    friend constexpr Vec2 operator*(Vec2 a, double s) { return {s * a.x, s * a.y}; }
    friend constexpr Vec2 operator/(Vec2 a, double s) { return {a.x / s, a.y / s}; }
    constexpr Vec2& operator+=(Vec2 b) { x += b.x; y += b.y; return *this; }
    constexpr Vec2& operator-=(Vec2 b) { x -= b.x; y -= b.y; return *this; }
    friend constexpr bool operator==(Vec2 a, Vec2 b) = default;
};

constexpr double dot(Vec2 a, Vec2 b) { return a.x * b.x + a.y * b.y; }
/// z component of the 3D cross product: positive when b is counter-clockwise of a.
constexpr double cross(Vec2 a, Vec2 b) { return a.x * b.y - a.y * b.x; }
/// Plain square root of the sum of squares: coordinates are bounded (tolerances.hpp,
/// kMaxCoordinate), so no overflow guard (std::hypot is several times slower).
inline double norm(Vec2 a) { return std::sqrt(a.x * a.x + a.y * a.y); }
constexpr double norm2(Vec2 a) { return dot(a, a); }
inline double distance(Vec2 a, Vec2 b) { return norm(b - a); }
/// a rotated by +90 degrees (the left normal direction of a).
constexpr Vec2 perp(Vec2 a) { return {-a.y, a.x}; }
inline bool is_finite(Vec2 a) { return std::isfinite(a.x) && std::isfinite(a.y); }
constexpr Vec2 lerp(Vec2 a, Vec2 b, double t) { return {a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)}; }

/// std::fmax's and std::fmin's values, bit for bit (the number when the other is a NaN, as
/// a NaN a fails both comparisons; of two equal values, zeros of either sign included, the
/// second, as glibc's maxsd and minsd give), without their call into the maths library: on
/// the load run's square the front's 32,000 calls were 1% of its instructions.
constexpr double fmax_inline(double a, double b) { return b != b || a > b ? a : b; }
constexpr double fmin_inline(double a, double b) { return b != b || a < b ? a : b; }

/// Axis-aligned bounding box; empty until the first point is added.
struct Box {
    Vec2 lo{HUGE_VAL, HUGE_VAL};
    Vec2 hi{-HUGE_VAL, -HUGE_VAL};

    /// (A NaN coordinate leaves the box as it was, as std::fmin would; the comparisons below
    /// compile to two instructions where fmin is a call into the maths library.)
    void add(Vec2 p) {
        lo = {p.x < lo.x ? p.x : lo.x, p.y < lo.y ? p.y : lo.y};
        hi = {p.x > hi.x ? p.x : hi.x, p.y > hi.y ? p.y : hi.y};
    }
    void add(const Box& b) {
        if (!b.empty()) { add(b.lo); add(b.hi); }
    }
    bool empty() const { return lo.x > hi.x; }
    /// p in the box, its sides included.
    bool contains(Vec2 p) const { return p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y; }
    double diagonal() const { return empty() ? 0.0 : distance(lo, hi); }
    /// The squared distance from p to the box (0 inside). (Comparisons, not fmax: this is
    /// on the k-d trees' search paths.)
    double distance2(Vec2 p) const {
        const double ex = lo.x - p.x > p.x - hi.x ? lo.x - p.x : p.x - hi.x;
        const double ey = lo.y - p.y > p.y - hi.y ? lo.y - p.y : p.y - hi.y;
        const double dx = ex > 0.0 ? ex : 0.0, dy = ey > 0.0 ? ey : 0.0;
        return dx * dx + dy * dy;
    }
};

}  // namespace meshd::core
