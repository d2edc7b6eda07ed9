// Adaptive exact predicates after Shewchuk (1997): a floating-point filter with a proven
// error bound, then exact expansion arithmetic.
//
// Expansions: a value is held as a sum of doubles of increasing magnitude that do not
// overlap; two_sum and two_product give the exact rounding error of one operation, so sums
// and products of doubles can be carried out without loss.

#include "kernel/predicates.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>

namespace meshd::core {

namespace {

thread_local PredicateCounters counters;


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

// ---------------------------------------------------------------------------------------
// Expansions in fixed buffers, for the exact stage of incircle. That stage is not rare: four
// points of one circle (a hole's or a cylinder's outline) are cocircular to within rounding,
// so every filter between them fails. With a heap-allocated vector for each step it took a
// third of the plate-with-holes example's instructions (malloc and free most of them).
//
// Expansion<N> holds at most N components; each operation's bound follows from its inputs'
// (a sum, the sum of theirs; a product by a double, twice; a product of expansions, twice
// their product), so the compiler checks that every result fits. The determinant's bound is
// 1,536 components (12 KB on the stack); zero elimination keeps the real counts far lower.

template <size_t N>
struct Expansion {
    std::array<double, N> v;  // increasing magnitude, non-overlapping; never read past n
    size_t n = 0;
};

// Sum of two non-overlapping expansions: merge by magnitude, then accumulate with two_sum
// (Shewchuk's Fast-Expansion-Sum, with zero elimination). h has room for ne + nf.
size_t add_into(const double* e, size_t ne, const double* f, size_t nf, double* h) {
    if (ne + nf == 0) return 0;
    // The merge goes to h itself: at step m the accumulation below reads g[m] before it
    // writes h[out], out < m, so it never overwrites what it has yet to read.
    double* g = h;
    size_t i = 0, j = 0, k = 0;
    while (i < ne && j < nf) g[k++] = std::fabs(f[j]) < std::fabs(e[i]) ? f[j++] : e[i++];
    while (i < ne) g[k++] = e[i++];
    while (j < nf) g[k++] = f[j++];
    const size_t total = k;
    double q = g[0];
    size_t out = 0;
    for (size_t m = 1; m < total; ++m) {
        double sum, err;
        two_sum(q, g[m], sum, err);
        if (err != 0.0) h[out++] = err;
        q = sum;
    }
    if (q != 0.0 || out == 0) h[out++] = q;
    return out;
}

template <size_t A, size_t B>
Expansion<A + B> operator+(const Expansion<A>& e, const Expansion<B>& f) {
    Expansion<A + B> h;
    h.n = add_into(e.v.data(), e.n, f.v.data(), f.n, h.v.data());
    return h;
}

template <size_t A>
Expansion<A> operator-(Expansion<A> e) {
    for (size_t i = 0; i < e.n; ++i) e.v[i] = -e.v[i];
    return e;
}

// e * b for a double b (Scale-Expansion with zero elimination); h has room for 2 ne.
size_t scale_into(const double* e, size_t ne, double b, double* h) {
    double q, err;
    two_product(e[0], b, q, err);
    size_t out = 0;
    if (err != 0.0) h[out++] = err;
    for (size_t i = 1; i < ne; ++i) {
        double p1, p0, sum;
        two_product(e[i], b, p1, p0);
        two_sum(q, p0, sum, err);
        if (err != 0.0) h[out++] = err;
        two_sum(p1, sum, q, err);
        if (err != 0.0) h[out++] = err;
    }
    if (q != 0.0 || out == 0) h[out++] = q;
    return out;
}

// e * f: the sum of e scaled by each component of f, in two buffers that take turns.
template <size_t A, size_t B>
Expansion<2 * A * B> operator*(const Expansion<A>& e, const Expansion<B>& f) {
    Expansion<2 * A * B> h;
    std::array<double, 2 * A * B> spare;
    std::array<double, 2 * A> part;
    double* acc = h.v.data();
    double* next = spare.data();
    size_t n = scale_into(e.v.data(), e.n, f.v[0], acc);
    for (size_t j = 1; j < f.n; ++j) {
        const size_t np = scale_into(e.v.data(), e.n, f.v[j], part.data());
        n = add_into(acc, n, part.data(), np, next);
        std::swap(acc, next);
    }
    if (acc != h.v.data()) std::copy_n(acc, n, h.v.data());
    h.n = n;
    return h;
}

// a - b exactly, one or two components.
Expansion<2> diff(double a, double b) {
    Expansion<2> d;
    double s, err;
    two_sum(a, -b, s, err);
    if (err != 0.0) d.v[d.n++] = err;
    d.v[d.n++] = s;
    return d;
}

// The determinant's sign from the six differences to d.
template <size_t D>
int incircle_sign(const Expansion<D>& adx, const Expansion<D>& ady, const Expansion<D>& bdx, const Expansion<D>& bdy,
                  const Expansion<D>& cdx, const Expansion<D>& cdy) {
    const auto alift = adx * adx + ady * ady;
    const auto blift = bdx * bdx + bdy * bdy;
    const auto clift = cdx * cdx + cdy * cdy;
    const auto bc = bdx * cdy + -(cdx * bdy);
    const auto ca = cdx * ady + -(adx * cdy);
    const auto ab = adx * bdy + -(bdx * ady);
    const auto det = alift * bc + blift * ca + clift * ab;
    return sign_of(det.v[det.n - 1]);
}

int incircle_expansion(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
    const std::array<Expansion<2>, 6> t{diff(a.x, d.x), diff(a.y, d.y), diff(b.x, d.x),
                                        diff(b.y, d.y), diff(c.x, d.x), diff(c.y, d.y)};
    // Nearby points (within a factor of two in each coordinate) have exact differences:
    // then the bounds, and the buffers, are 16 times smaller (96 components).
    if (std::all_of(t.begin(), t.end(), [](const Expansion<2>& e) { return e.n == 1; })) {
        std::array<Expansion<1>, 6> u;
        for (size_t i = 0; i < 6; ++i) u[i] = {{t[i].v[0]}, 1};
        return incircle_sign(u[0], u[1], u[2], u[3], u[4], u[5]);
    }
    return incircle_sign(t[0], t[1], t[2], t[3], t[4], t[5]);
}

int orient_expansion(Vec2 a, Vec2 b, Vec2 c) {
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

namespace detail {

Orientation orient2d_exact(Vec2 a, Vec2 b, Vec2 c) {
    ++counters.orient_exact;
    // When the four differences are exact (points on a line parallel to an axis, on a common
    // grid: most of the filter's failures, on a domain's straight sides), the determinant is
    // the difference of two products that two_product makes exact: their rounded values
    // order them (rounding is monotone), and where those tie, their rounding errors do.
    // Differences of 0, or between 2^-450 and 2^500 in magnitude, keep the errors exact.
    double acx, acy, bcx, bcy, tail;
    bool exact = true;
    auto difference = [&](double x, double y, double& d) {
        two_sum(x, -y, d, tail);
        const double m = std::fabs(d);
        exact = exact && tail == 0.0 && (m == 0.0 || (m >= 0x1p-450 && m <= 0x1p500));
    };
    difference(a.x, c.x, acx);
    difference(a.y, c.y, acy);
    difference(b.x, c.x, bcx);
    difference(b.y, c.y, bcy);
    if (exact) {
        double p1, e1, p2, e2;
        two_product(acx, bcy, p1, e1);
        two_product(acy, bcx, p2, e2);
        if (p1 != p2) return p1 > p2 ? Orientation::Left : Orientation::Right;
        return e1 > e2 ? Orientation::Left : (e1 < e2 ? Orientation::Right : Orientation::Collinear);
    }
    return static_cast<Orientation>(orient_expansion(a, b, c));
}

int incircle_exact(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
    ++counters.incircle_exact;
    return incircle_expansion(a, b, c, d);
}

int incircle_tie(Vec2 a, Vec2 b, Vec2 c, Vec2 d, std::uint32_t ra, std::uint32_t rb, std::uint32_t rc,
                 std::uint32_t rd) {
    // The determinant with rows (x, y, x^2 + y^2, 1) is linear in each lifted height; raising
    // the height of row i by eps^rank adds eps^rank times its cofactor, (-1)^i times the
    // orientation of the other three rows in order. The highest-weighted (lowest rank) point
    // whose cofactor is non-zero decides.
    const std::array<Vec2, 4> p{a, b, c, d};
    std::array<std::uint32_t, 4> rank{ra, rb, rc, rd};
    std::array<int, 4> order{0, 1, 2, 3};
    std::sort(order.begin(), order.end(), [&](int i, int j) { return rank[static_cast<size_t>(i)] < rank[static_cast<size_t>(j)]; });
    for (int i : order) {
        std::array<Vec2, 3> rest;
        size_t k = 0;
        for (int j = 0; j < 4; ++j)
            if (j != i) rest[k++] = p[static_cast<size_t>(j)];
        const int o = static_cast<int>(orient2d(rest[0], rest[1], rest[2]));
        if (o != 0) return (i % 2 == 0) ? o : -o;
    }
    return 0;
}

}  // namespace detail

PredicateCounters predicate_counters() { return counters; }
void reset_predicate_counters() { counters = {}; }

namespace {
// r collinear with pq: within its box, so on the closed segment?
bool in_box(Vec2 p, Vec2 q, Vec2 r) {
    return fmin_inline(p.x, q.x) <= r.x && r.x <= fmax_inline(p.x, q.x) && fmin_inline(p.y, q.y) <= r.y &&
           r.y <= fmax_inline(p.y, q.y);
}
}  // namespace

bool segments_intersect(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
    const int o1 = static_cast<int>(orient2d(a, b, c));
    const int o2 = static_cast<int>(orient2d(a, b, d));
    const int o3 = static_cast<int>(orient2d(c, d, a));
    const int o4 = static_cast<int>(orient2d(c, d, b));
    if (o1 * o2 < 0 && o3 * o4 < 0) return true;
    if (o1 == 0 && in_box(a, b, c)) return true;
    if (o2 == 0 && in_box(a, b, d)) return true;
    if (o3 == 0 && in_box(c, d, a)) return true;
    if (o4 == 0 && in_box(c, d, b)) return true;
    return false;
}

bool inside_segment(Vec2 a, Vec2 b, Vec2 p) {
    return p != a && p != b && orient2d(a, b, p) == Orientation::Collinear && in_box(a, b, p);
}

}  // namespace meshd::core
