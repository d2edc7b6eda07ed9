// Adaptive exact predicates after Shewchuk (1997): a floating-point filter with a proven
// error bound, then exact expansion arithmetic.
//
// Expansions: a value is held as a sum of doubles of increasing magnitude that do not
// overlap; two_sum and two_product give the exact rounding error of one operation, so sums
// and products of doubles can be carried out without loss.

#include "meshd/core/predicates.hpp"

#include <cmath>
#include <cstddef>

namespace meshd::core {

namespace {

thread_local PredicateCounters counters;

constexpr double kEpsilon = 0x1p-53;  // half an ulp of 1
// Bound on the error of the filtered orient2d determinant relative to its magnitude sum.
constexpr double kOrientBound = (3.0 + 16.0 * kEpsilon) * kEpsilon;

// x + y = s + e exactly.
inline void two_sum(double x, double y, double& s, double& e) {
    s = x + y;
    const double bv = s - x;
    const double av = s - bv;
    e = (x - av) + (y - bv);
}

// x * y = p + e exactly (fused multiply-add computes the rounding error exactly; we do not
// rely on contraction elsewhere, see -ffp-contract=off).
inline void two_product(double x, double y, double& p, double& e) {
    p = x * y;
    e = std::fma(x, y, -p);
}

// Adds a double to an expansion in place (Shewchuk's Grow-Expansion with zero elimination).
// e has n components; returns the new count. The output buffer must hold n + 1.
size_t grow(double* e, size_t n, double b) {
    double q = b;
    size_t out = 0;
    for (size_t i = 0; i < n; ++i) {
        double s, err;
        two_sum(q, e[i], s, err);
        q = s;
        if (err != 0.0) e[out++] = err;
    }
    if (q != 0.0 || out == 0) e[out++] = q;
    return out;
}

int sign_of(double v) { return (v > 0.0) - (v < 0.0); }

int orient_exact(Vec2 a, Vec2 b, Vec2 c) {
    // det = ax*by - ax*cy - ay*bx + ay*cx + bx*cy - by*cx, every product exact.
    const double terms[6][2] = {{a.x, b.y}, {-a.x, c.y}, {-a.y, b.x},
                                {a.y, c.x}, {b.x, c.y},  {-b.y, c.x}};
    double e[13];
    size_t n = 0;
    for (const auto& t : terms) {
        double p, err;
        two_product(t[0], t[1], p, err);
        n = grow(e, n, err);
        n = grow(e, n, p);
    }
    // The largest component carries the sign of a non-overlapping expansion.
    return sign_of(e[n - 1]);
}

}  // namespace

Orientation orient2d(Vec2 a, Vec2 b, Vec2 c) {
    ++counters.orient_calls;
    const double left = (a.x - c.x) * (b.y - c.y);
    const double right = (a.y - c.y) * (b.x - c.x);
    const double det = left - right;
    const double sum = std::fabs(left) + std::fabs(right);
    if (std::fabs(det) > kOrientBound * sum) return static_cast<Orientation>(sign_of(det));
    ++counters.orient_exact;
    return static_cast<Orientation>(orient_exact(a, b, c));
}

PredicateCounters predicate_counters() { return counters; }
void reset_predicate_counters() { counters = {}; }

bool segments_intersect(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
    const int o1 = static_cast<int>(orient2d(a, b, c));
    const int o2 = static_cast<int>(orient2d(a, b, d));
    const int o3 = static_cast<int>(orient2d(c, d, a));
    const int o4 = static_cast<int>(orient2d(c, d, b));
    if (o1 * o2 < 0 && o3 * o4 < 0) return true;
    auto on_segment = [](Vec2 p, Vec2 q, Vec2 r) {  // r collinear with pq: within its box?
        return std::fmin(p.x, q.x) <= r.x && r.x <= std::fmax(p.x, q.x) &&
               std::fmin(p.y, q.y) <= r.y && r.y <= std::fmax(p.y, q.y);
    };
    if (o1 == 0 && on_segment(a, b, c)) return true;
    if (o2 == 0 && on_segment(a, b, d)) return true;
    if (o3 == 0 && on_segment(c, d, a)) return true;
    if (o4 == 0 && on_segment(c, d, b)) return true;
    return false;
}

}  // namespace meshd::core
