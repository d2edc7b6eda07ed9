// Treecode for eq. (6.1); the error analysis is in inverse_distance.hpp.

#include "density/inverse_distance.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#if defined(__SSE2__)
#include <emmintrin.h>
#include <xmmintrin.h>
#endif
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define MESHD_AVX_SUM 1
#endif

#include "kernel/kdtree.hpp"
#include "meshd/core/errors.hpp"

namespace meshd::core {

namespace {

double delta_of(double theta) {
    return theta * theta * (1.0 + theta) / ((1.0 - theta) * (1.0 - theta) * (1.0 - theta));
}

// The cells' bound (inverse_distance.hpp): each far term within this share of its value.
double cell_delta_of(double phi) { return phi * phi * phi * phi * (1.0 + phi) / (1.0 - phi); }

// The largest x in (0, 0.5) with f(x) <= bound, f increasing.
template <class F>
double largest_within(F f, double bound) {
    double lo = 0.0, hi = 0.5;
    for (int i = 0; i < 60; ++i) {
        const double mid = 0.5 * (lo + hi);
        (f(mid) <= bound ? lo : hi) = mid;
    }
    return lo;
}

// A cubic's ten coefficients in a row, in the order of kTerms: (i, j) is the coefficient of
// dx^i dy^j. (As a 4 x 4 array, six of the sixteen were never used: a cell took 264 bytes,
// now 160, three cache lines.)
constexpr int kTerms[10][2] = {{0, 0}, {1, 0}, {0, 1}, {2, 0}, {1, 1}, {0, 2}, {3, 0}, {2, 1}, {1, 2}, {0, 3}};

// sum a(i, j) dx^i dy^j over i + j <= 3.
double cubic(const double (&a)[10], double dx, double dy) {
    const double x2 = dx * dx, y2 = dy * dy;
    return a[0] + a[1] * dx + a[2] * dy + a[3] * x2 + a[4] * dx * dy + a[5] * y2 + a[6] * x2 * dx + a[7] * x2 * dy +
           a[8] * dx * y2 + a[9] * y2 * dy;
}

// The same polynomial in (P - (C + d)) instead of (P - C).
void move_cubic(const double (&flat)[10], double dx, double dy, double (&moved)[10]) {
    double a[4][4] = {}, out[4][4];
    for (int t = 0; t < 10; ++t) a[kTerms[t][0]][kTerms[t][1]] = flat[t];
    static constexpr double kBinomial[4][4] = {{1, 0, 0, 0}, {1, 1, 0, 0}, {1, 2, 1, 0}, {1, 3, 3, 1}};
    const double px[4] = {1, dx, dx * dx, dx * dx * dx}, py[4] = {1, dy, dy * dy, dy * dy * dy};
    // Unrolled whole, the products by the binomials' and the powers' ones fall away (exactly:
    // x * 1 is x): a fifth of the instructions of the loops as written.
#pragma GCC unroll 4
    for (int k = 0; k < 4; ++k)
#pragma GCC unroll 4
        for (int l = 0; l < 4; ++l) {
            if (k + l >= 4) {
                out[k][l] = 0.0;
                continue;
            }
            double sum = 0.0;
#pragma GCC unroll 4
            for (int i = k; i < 4; ++i)
#pragma GCC unroll 4
                for (int j = l; j < 4; ++j)
                    if (i + j < 4) sum += a[i][j] * kBinomial[i][k] * kBinomial[j][l] * px[i - k] * py[j - l];
            out[k][l] = sum;
        }
    for (int t = 0; t < 10; ++t) moved[t] = out[kTerms[t][0]][kTerms[t][1]];
}

// Adds the terms of sources [b, e) at p in double, one at a time; the source's value when p is
// one of them (the formula's limit there), else null.
const double* add_terms(const double* x, const double* y, const double* r, size_t b, size_t e, Vec2 p, double& num,
                        double& den) {
    for (size_t i = b; i < e; ++i) {
        const double dx = p.x - x[i], dy = p.y - y[i];
        const double d2 = dx * dx + dy * dy;
        if (d2 == 0.0) return r + i;
        const double w = 1.0 / std::sqrt(d2);
        den += w;
        num += r[i] * w;
    }
    return nullptr;
}

#if defined(__SSE2__)
// The lanes of a last step of four that hold one of the `left` (1 to 3) sources left.
inline __m128 first_lanes(size_t left) {
    alignas(16) static constexpr std::int32_t kMasks[4][4] = {{0, 0, 0, 0}, {-1, 0, 0, 0}, {-1, -1, 0, 0}, {-1, -1, -1, 0}};
    return _mm_castsi128_ps(_mm_load_si128(reinterpret_cast<const __m128i*>(kMasks[left])));
}

// Sums of the weights of sources [b, e) at p in two pairs of lanes, four sources a step, the
// last step's lanes past e masked to zero (the cells' near sums: the arrays hold three entries
// past the last source; one code for every processor, as a cell sums a few short ranges,
// where a call per range and scalar tails cost more than the width). sums() is false when a
// squared distance left the floats' normal range.
struct NearSums {
    __m128d num0 = _mm_setzero_pd(), den0 = _mm_setzero_pd(), num1 = _mm_setzero_pd(), den1 = _mm_setzero_pd();
    __m128 out = _mm_setzero_ps();
    void add(const double* x, const double* y, const double* r, size_t b, size_t e, Vec2 p) {
        const __m128d px = _mm_set1_pd(p.x), py = _mm_set1_pd(p.y);
        const __m128 one = _mm_set1_ps(1.0f), low = _mm_set1_ps(std::numeric_limits<float>::min()),
                     high = _mm_set1_ps(std::numeric_limits<float>::max());
        // Four sources a step; the lanes past e of the last step (1 to 3 sources left) are
        // masked out.
        auto step = [&](size_t i, __m128 valid) {
            const __m128d dx0 = _mm_sub_pd(px, _mm_loadu_pd(x + i)), dy0 = _mm_sub_pd(py, _mm_loadu_pd(y + i));
            const __m128d dx1 = _mm_sub_pd(px, _mm_loadu_pd(x + i + 2)), dy1 = _mm_sub_pd(py, _mm_loadu_pd(y + i + 2));
            const __m128d d0 = _mm_add_pd(_mm_mul_pd(dx0, dx0), _mm_mul_pd(dy0, dy0));
            const __m128d d1 = _mm_add_pd(_mm_mul_pd(dx1, dx1), _mm_mul_pd(dy1, dy1));
            const __m128 d = _mm_movelh_ps(_mm_cvtpd_ps(d0), _mm_cvtpd_ps(d1));
            out = _mm_or_ps(out, _mm_and_ps(valid, _mm_or_ps(_mm_cmplt_ps(d, low), _mm_cmpgt_ps(d, high))));
            const __m128 w = _mm_and_ps(valid, _mm_div_ps(one, _mm_sqrt_ps(d)));
            const __m128d w0 = _mm_cvtps_pd(w), w1 = _mm_cvtps_pd(_mm_movehl_ps(w, w));
            den0 = _mm_add_pd(den0, w0);
            den1 = _mm_add_pd(den1, w1);
            num0 = _mm_add_pd(num0, _mm_mul_pd(_mm_loadu_pd(r + i), w0));
            num1 = _mm_add_pd(num1, _mm_mul_pd(_mm_loadu_pd(r + i + 2), w1));
        };
        const __m128 all = _mm_castsi128_ps(_mm_set1_epi32(-1));
        size_t i = b;
        for (; i + 4 <= e; i += 4) step(i, all);
        if (i < e) step(i, first_lanes(e - i));
    }
    bool sums(double& num, double& den) const {
        if (_mm_movemask_ps(out) != 0) return false;
        alignas(16) double lanes[2];
        _mm_store_pd(lanes, _mm_add_pd(num0, num1));
        num = lanes[0] + lanes[1];
        _mm_store_pd(lanes, _mm_add_pd(den0, den1));
        den = lanes[0] + lanes[1];
        return true;
    }
};

// Four sources per step: the squared distances (in double) become floats, whose square root
// and reciprocal take a quarter of the divider's time the doubles' take (the sum is bound by
// it); each weight 1/d is then within 3 float roundings (2e-7) of its exact value, so the
// ratio is within 4e-7, and the sums stay double. Sums the sources [0, 4 floor(n / 4));
// false when a squared distance left the floats' normal range (a query on a source, or
// absurdly far): the caller then sums in double.
bool sum_by_fours_sse2(const double* x, const double* y, const double* r, size_t n, Vec2 p, double& num,
                       double& den) {
    NearSums s;
    s.add(x, y, r, 0, n & ~size_t{3}, p);
    return s.sums(num, den);
}
#endif


#if defined(MESHD_AVX_SUM)
// NearSums on 256-bit registers (AVX): each step's four distances and weights as there, added
// to four double lanes at once instead of two pairs, lane k taking the same terms in the same
// order, and the lanes added in the same pairs at the end: the same sums to the bit.
struct WideSums {
    __m256d px, py, num4, den4;
    __m128 one, low, high, out;
    __m256 out8;
    __attribute__((target("avx"))) explicit WideSums(Vec2 p)
        : px(_mm256_set1_pd(p.x)), py(_mm256_set1_pd(p.y)), num4(_mm256_setzero_pd()), den4(_mm256_setzero_pd()),
          one(_mm_set1_ps(1.0f)), low(_mm_set1_ps(std::numeric_limits<float>::min())),
          high(_mm_set1_ps(std::numeric_limits<float>::max())), out(_mm_setzero_ps()), out8(_mm256_setzero_ps()) {}
    // The sources [i, i + 4) in the lanes of `valid`.
    __attribute__((target("avx"))) void step(const double* x, const double* y, const double* r, size_t i, __m128 valid) {
        const __m256d dx = _mm256_sub_pd(px, _mm256_loadu_pd(x + i)), dy = _mm256_sub_pd(py, _mm256_loadu_pd(y + i));
        const __m128 d = _mm256_cvtpd_ps(_mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy)));
        out = _mm_or_ps(out, _mm_and_ps(valid, _mm_or_ps(_mm_cmplt_ps(d, low), _mm_cmpgt_ps(d, high))));
        const __m256d w = _mm256_cvtps_pd(_mm_and_ps(valid, _mm_div_ps(one, _mm_sqrt_ps(d))));
        den4 = _mm256_add_pd(den4, w);
        num4 = _mm256_add_pd(num4, _mm256_mul_pd(_mm256_loadu_pd(r + i), w));
    }
    // The sources [b, e), four a step, the last one masked (1 to 3 sources left).
    __attribute__((target("avx"))) void add(const double* x, const double* y, const double* r, size_t b, size_t e) {
        size_t i = b;
        for (; i + 4 <= e; i += 4) step(x, y, r, i, _mm_castsi128_ps(_mm_set1_epi32(-1)));
        if (i < e) step(x, y, r, i, first_lanes(e - i));
    }
    // The same sums, eight sources a step while eight are left: their weights by one square
    // root and one division of eight floats, added four at a time as two steps of add() would
    // add them (lane k of each sum takes the sources b + k, b + k + 4, ... in order).
    __attribute__((target("avx"))) void add_by_eights(const double* x, const double* y, const double* r, size_t b,
                                                      size_t e) {
        const __m256 one8 = _mm256_set1_ps(1.0f), low8 = _mm256_set1_ps(std::numeric_limits<float>::min()),
                     high8 = _mm256_set1_ps(std::numeric_limits<float>::max());
        size_t i = b;
        for (; i + 8 <= e; i += 8) {
            const __m256d dx0 = _mm256_sub_pd(px, _mm256_loadu_pd(x + i)), dy0 = _mm256_sub_pd(py, _mm256_loadu_pd(y + i));
            const __m256d dx1 = _mm256_sub_pd(px, _mm256_loadu_pd(x + i + 4)), dy1 = _mm256_sub_pd(py, _mm256_loadu_pd(y + i + 4));
            const __m128 d0 = _mm256_cvtpd_ps(_mm256_add_pd(_mm256_mul_pd(dx0, dx0), _mm256_mul_pd(dy0, dy0)));
            const __m128 d1 = _mm256_cvtpd_ps(_mm256_add_pd(_mm256_mul_pd(dx1, dx1), _mm256_mul_pd(dy1, dy1)));
            const __m256 d = _mm256_insertf128_ps(_mm256_castps128_ps256(d0), d1, 1);
            out8 = _mm256_or_ps(out8, _mm256_or_ps(_mm256_cmp_ps(d, low8, _CMP_LT_OQ), _mm256_cmp_ps(d, high8, _CMP_GT_OQ)));
            const __m256 w = _mm256_div_ps(one8, _mm256_sqrt_ps(d));
            const __m256d w0 = _mm256_cvtps_pd(_mm256_castps256_ps128(w)), w1 = _mm256_cvtps_pd(_mm256_extractf128_ps(w, 1));
            den4 = _mm256_add_pd(den4, w0);
            num4 = _mm256_add_pd(num4, _mm256_mul_pd(_mm256_loadu_pd(r + i), w0));
            den4 = _mm256_add_pd(den4, w1);
            num4 = _mm256_add_pd(num4, _mm256_mul_pd(_mm256_loadu_pd(r + i + 4), w1));
        }
        add(x, y, r, i, e);
    }
    __attribute__((target("avx"))) bool sums(double& num, double& den) const {
        if (_mm_movemask_ps(out) != 0 || _mm256_movemask_ps(out8) != 0) return false;
        alignas(16) double lanes[2];
        _mm_store_pd(lanes, _mm_add_pd(_mm256_castpd256_pd128(num4), _mm256_extractf128_pd(num4, 1)));
        num = lanes[0] + lanes[1];
        _mm_store_pd(lanes, _mm_add_pd(_mm256_castpd256_pd128(den4), _mm256_extractf128_pd(den4, 1)));
        den = lanes[0] + lanes[1];
        return true;
    }
};

// sum_by_fours_sse2 on 256-bit registers where the processor has them (AVX), eight sources a
// step (WideSums::add_by_eights): lane k of each sum takes the sources k, k + 4, k + 8, ... in
// order, as the two 128-bit sums' lanes do, and the lanes are added in the same pairs: the
// same result to the bit, in about 0.53 ns a source instead of 1.28 (BM_InverseDistance<0>
// at 1,495 sources, 2026-12-03). Sums the sources [0, 4 floor(n / 4)); false when a squared
// distance left the floats' normal range.
__attribute__((target("avx"))) bool sum_by_fours_avx(const double* x, const double* y, const double* r, size_t n,
                                                      Vec2 p, double& num, double& den) {
    WideSums s(p);
    s.add_by_eights(x, y, r, 0, n & ~size_t{3});
    return s.sums(num, den);
}

// The near sums of a query cell on 256-bit registers: the ranges range(0 .. count - 1) of the
// sources, each as NearSums adds it.
template <class Range>
__attribute__((target("avx"))) bool near_sums_avx(const double* x, const double* y, const double* r, std::uint32_t count,
                                                   Range range, Vec2 p, double& num, double& den) {
    WideSums s(p);
    for (std::uint32_t j = 0; j < count; ++j) {
        const auto [b, e] = range(j);
        s.add_by_eights(x, y, r, b, e);
    }
    return s.sums(num, den);
}

// The far sources' terms of a new query cell (InverseDistanceField::add_far) on 256-bit
// registers: the terms of four sources at once (lanes = sources), each by add_far's operations
// in add_far's order, then turned (a 4 x 4 transpose) so that each coefficient takes the
// sources one after another as add_far adds them: the same polynomial to the bit, in about a
// third of the instructions. The coefficients sit in three groups, as a cell keeps them (kTerms):
// (0,0) (1,0) (0,1) (2,0), then (1,1) (0,2) (3,0) (2,1), then (1,2) (0,3).
struct WideFarSums {
    __m256d den0, den1, num0, num1;
    __m128d den2, num2;
    __attribute__((target("avx"))) WideFarSums(const double (&num)[10], const double (&den)[10])
        : den0(_mm256_loadu_pd(den)), den1(_mm256_loadu_pd(den + 4)), num0(_mm256_loadu_pd(num)),
          num1(_mm256_loadu_pd(num + 4)), den2(_mm_loadu_pd(den + 8)), num2(_mm_loadu_pd(num + 8)) {}
    __attribute__((target("avx"))) void store(double (&num)[10], double (&den)[10]) const {
        _mm256_storeu_pd(den, den0);
        _mm256_storeu_pd(den + 4, den1);
        _mm256_storeu_pd(num, num0);
        _mm256_storeu_pd(num + 4, num1);
        _mm_storeu_pd(den + 8, den2);
        _mm_storeu_pd(num + 8, num2);
    }
    // acc += the first m of the sources' vectors (a[k], b[k], c[k], d[k]), in order.
    __attribute__((target("avx"))) static void add_turned(__m256d& acc, __m256d a, __m256d b, __m256d c, __m256d d,
                                                          size_t m) {
        const __m256d ab0 = _mm256_unpacklo_pd(a, b), ab1 = _mm256_unpackhi_pd(a, b);
        const __m256d cd0 = _mm256_unpacklo_pd(c, d), cd1 = _mm256_unpackhi_pd(c, d);
        acc = _mm256_add_pd(acc, _mm256_permute2f128_pd(ab0, cd0, 0x20));
        if (m > 1) acc = _mm256_add_pd(acc, _mm256_permute2f128_pd(ab1, cd1, 0x20));
        if (m > 2) acc = _mm256_add_pd(acc, _mm256_permute2f128_pd(ab0, cd0, 0x31));
        if (m > 3) acc = _mm256_add_pd(acc, _mm256_permute2f128_pd(ab1, cd1, 0x31));
    }
    __attribute__((target("avx"))) static void add_turned(__m128d& acc, __m256d a, __m256d b, size_t m) {
        const __m256d ab0 = _mm256_unpacklo_pd(a, b), ab1 = _mm256_unpackhi_pd(a, b);
        acc = _mm_add_pd(acc, _mm256_castpd256_pd128(ab0));
        if (m > 1) acc = _mm_add_pd(acc, _mm256_castpd256_pd128(ab1));
        if (m > 2) acc = _mm_add_pd(acc, _mm256_extractf128_pd(ab0, 1));
        if (m > 3) acc = _mm_add_pd(acc, _mm256_extractf128_pd(ab1, 1));
    }
    // The sources [b, e) about the centre, four a step; the arrays hold three entries past the
    // last source (the last step's lanes past e are computed, not added).
    __attribute__((target("avx"))) void add(const double* x, const double* y, const double* r, size_t b, size_t e,
                                            Vec2 centre) {
        const __m256d cx = _mm256_set1_pd(centre.x), cy = _mm256_set1_pd(centre.y), one = _mm256_set1_pd(1.0),
                      half = _mm256_set1_pd(0.5), minus_half = _mm256_set1_pd(-0.5), three = _mm256_set1_pd(3.0),
                      five = _mm256_set1_pd(5.0), fifteen = _mm256_set1_pd(15.0), sign = _mm256_set1_pd(-0.0);
        for (size_t i = b; i < e; i += 4) {
            const __m256d ux = _mm256_sub_pd(cx, _mm256_loadu_pd(x + i)), uy = _mm256_sub_pd(cy, _mm256_loadu_pd(y + i));
            const __m256d r2 = _mm256_add_pd(_mm256_mul_pd(ux, ux), _mm256_mul_pd(uy, uy));
            const __m256d i1 = _mm256_div_pd(one, _mm256_sqrt_pd(r2));
            const __m256d q = _mm256_div_pd(one, r2);
            const __m256d i3 = _mm256_mul_pd(i1, q), i5 = _mm256_mul_pd(i3, q), i7 = _mm256_mul_pd(i5, q);
            const __m256d r2_3 = _mm256_mul_pd(three, r2);
            const __m256d ux3 = _mm256_mul_pd(three, ux), uy3 = _mm256_mul_pd(three, uy);
            const __m256d t10 = _mm256_mul_pd(_mm256_xor_pd(ux, sign), i3);
            const __m256d t01 = _mm256_mul_pd(_mm256_xor_pd(uy, sign), i3);
            const __m256d t20 = _mm256_mul_pd(_mm256_mul_pd(half, _mm256_sub_pd(_mm256_mul_pd(ux3, ux), r2)), i5);
            const __m256d t11 = _mm256_mul_pd(_mm256_mul_pd(ux3, uy), i5);
            const __m256d t02 = _mm256_mul_pd(_mm256_mul_pd(half, _mm256_sub_pd(_mm256_mul_pd(uy3, uy), r2)), i5);
            auto cubic_term = [&](__m256d lead, __m256d f1, __m256d f2, __m256d f3, __m256d last) {
                // -0.5 * (lead * f1 * f2 * f3 - 3 r2 * last) * i7, left to right as add_far writes it.
                const __m256d p = _mm256_mul_pd(_mm256_mul_pd(_mm256_mul_pd(lead, f1), f2), f3);
                return _mm256_mul_pd(_mm256_mul_pd(minus_half, _mm256_sub_pd(p, _mm256_mul_pd(r2_3, last))), i7);
            };
            const __m256d t30 = cubic_term(five, ux, ux, ux, ux), t21 = cubic_term(fifteen, ux, ux, uy, uy);
            const __m256d t12 = cubic_term(fifteen, ux, uy, uy, ux), t03 = cubic_term(five, uy, uy, uy, uy);
            const __m256d rho = _mm256_loadu_pd(r + i);
            const size_t m = std::min<size_t>(4, e - i);
            add_turned(den0, i1, t10, t01, t20, m);
            add_turned(num0, _mm256_mul_pd(rho, i1), _mm256_mul_pd(rho, t10), _mm256_mul_pd(rho, t01),
                       _mm256_mul_pd(rho, t20), m);
            add_turned(den1, t11, t02, t30, t21, m);
            add_turned(num1, _mm256_mul_pd(rho, t11), _mm256_mul_pd(rho, t02), _mm256_mul_pd(rho, t30),
                       _mm256_mul_pd(rho, t21), m);
            add_turned(den2, t12, t03, m);
            add_turned(num2, _mm256_mul_pd(rho, t12), _mm256_mul_pd(rho, t03), m);
        }
    }
};

// (A static initialiser may run before libgcc's own: __builtin_cpu_init first.)
bool has_avx() {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx");
}
const bool kHasAvx = has_avx();
std::atomic<bool> g_wide{kHasAvx};  // tests switch it (wide_sums) while no mesh is made
#endif

#if defined(__SSE2__)
bool sum_by_fours(const double* x, const double* y, const double* r, size_t n, Vec2 p, double& num, double& den) {
#if defined(MESHD_AVX_SUM)
    if (g_wide.load(std::memory_order_relaxed)) return sum_by_fours_avx(x, y, r, n, p, num, den);
#endif
    return sum_by_fours_sse2(x, y, r, n, p, num, den);
}
#endif

// num and den with the near sources' terms added, the ranges range(0 .. count - 1) of x, y, r,
// and their ratio; the value of a source when p is one (the formula's limit there).
template <class Range>
double near_value(const double* x, const double* y, const double* r, std::uint32_t count, Range range, Vec2 p,
                  double num, double den) {
#if defined(__SSE2__)
    double near_num, near_den;
#if defined(MESHD_AVX_SUM)
    if (g_wide.load(std::memory_order_relaxed)) {
        if (near_sums_avx(x, y, r, count, range, p, near_num, near_den)) return (num + near_num) / (den + near_den);
    } else
#endif
    {
        NearSums near;
        for (std::uint32_t j = 0; j < count; ++j) {
            const auto [b, e] = range(j);
            near.add(x, y, r, b, e, p);
        }
        if (near.sums(near_num, near_den)) return (num + near_num) / (den + near_den);
    }
#endif
    // In double, one term at a time (p on a source, or without SSE2).
    for (std::uint32_t j = 0; j < count; ++j) {
        const auto [b, e] = range(j);
        if (const double* at = add_terms(x, y, r, b, e, p, num, den)) return *at;
    }
    return num / den;
}

}  // namespace

bool detail::wide_sums(bool allow) {
#if defined(MESHD_AVX_SUM)
    g_wide.store(allow && kHasAvx, std::memory_order_relaxed);
    return allow && kHasAvx;
#else
    (void)allow;
    return false;
#endif
}

InverseDistanceField::InverseDistanceField(std::vector<Vec2> starts, std::vector<double> values,
                                           double tolerance, std::optional<size_t> packed_copies)
    : a_(std::move(starts)), rho_(std::move(values)) {
    MESHD_INTERNAL_CHECK(a_.size() == rho_.size() && !a_.empty(), "eq. 6.1 needs sources");
    MESHD_INTERNAL_CHECK(tolerance > 0.0 && tolerance < 1.0, "tolerance out of range");
    // The largest opening angles whose per-sum bounds keep the ratio within the tolerance.
    const double delta_max = tolerance / (2.0 + tolerance);
    theta_ = largest_within(delta_of, delta_max);
    phi_ = largest_within(cell_delta_of, delta_max);
    // The sources in tree order, and the treecode's sums over every node.
    const detail::KdLayout tree(a_);
    std::vector<Vec2> a;
    std::vector<double> r;
    a.reserve(a_.size());
    r.reserve(a_.size());
    for (auto i : tree.order) {
        a.push_back(a_[i]);
        r.push_back(rho_[i]);
    }
    a_ = std::move(a);
    rho_ = std::move(r);
    x_.reserve(a_.size() + 3);
    y_.reserve(a_.size() + 3);
    for (const Vec2& v : a_) {
        x_.push_back(v.x);
        y_.push_back(v.y);
    }
    // Three more entries: the cells' near sums read whole steps of four past a range's end
    // (the lanes past it masked).
    for (int k = 0; k < 3; ++k) {
        x_.push_back(0.0);
        y_.push_back(0.0);
        rho_.push_back(0.0);
    }
    nodes_.reserve(tree.nodes.size());
    for (const detail::KdNode& k : tree.nodes) {
        Node n{};
        n.begin = k.begin;
        n.end = k.end;
        n.left = k.left;
        n.right = k.right;
        n.count = static_cast<double>(k.end - k.begin);
        Vec2 c{0, 0}, cr{0, 0};
        double rs = 0.0;
        for (std::uint32_t i = k.begin; i < k.end; ++i) {
            c += a_[i];
            cr += rho_[i] * a_[i];
            rs += rho_[i];
        }
        n.c = c / n.count;
        n.c_rho = cr / rs;
        n.rho_sum = rs;
        for (std::uint32_t i = k.begin; i < k.end; ++i) {
            n.r = std::fmax(n.r, distance(n.c, a_[i]));
            n.r_rho = std::fmax(n.r_rho, distance(n.c_rho, a_[i]));
        }
        nodes_.push_back(n);
    }
    packing_budget_ = packed_copies ? *packed_copies : std::max(kPackedCopies, kPackedCopiesPerSource * a_.size());
    if (a_.size() > kCellSources) {
        // The root: the sources' box, every source near it (the tree's root node).
        Vec2 lo = a_.front(), hi = a_.front();
        for (const Vec2& v : a_) {
            lo = {std::fmin(lo.x, v.x), std::fmin(lo.y, v.y)};
            hi = {std::fmax(hi.x, v.x), std::fmax(hi.y, v.y)};
        }
        Place at{};
        at.centre = 0.5 * (lo + hi);
        at.half = 0.5 * std::fmax(hi.x - lo.x, hi.y - lo.y) * (1.0 + 1e-9);
        if (!(at.half > 0.0)) at.half = std::fmax(1e-300, std::fabs(at.centre.x) + std::fabs(at.centre.y));
        at.leaf = false;
        at.near_begin = 0;
        at.near_end = 1;
        places_.push_back(at);
        pad_near();
        near_nodes_.push_back(0);
        cells_.push_back(Cell{});
    }
}

void InverseDistanceField::pad_near() const {
    for (int k = 0; k < 3; ++k) {
        near_x_.push_back(0.0);
        near_y_.push_back(0.0);
        near_r_.push_back(0.0);
    }
}

double InverseDistanceField::direct(Vec2 p) const {
    const size_t n = a_.size();
    const double* x = x_.data();
    const double* y = y_.data();
    const double* r = rho_.data();
    double num = 0.0, den = 0.0;
    size_t i = 0;
#if defined(__SSE2__)
    if (!sum_by_fours(x, y, r, n, p, num, den)) return exact(p);
    i = n & ~size_t{3};
#endif
    if (const double* at = add_terms(x, y, r, i, n, p, num, den)) return *at;
    return num / den;
}

double InverseDistanceField::operator()(Vec2 p) const {
    return cells_.empty() ? summed(p) : through_cells(p);
}

double InverseDistanceField::summed(Vec2 p) const {
    return a_.size() <= kDirectSources ? direct(p) : treecode(p);
}

void InverseDistanceField::add_far(Cell& cell, Vec2 centre, double x, double y, double rho) const {
    // The Legendre series of 1/|P - A| about the centre to l = 3, in u = C - A and
    // d = P - C: 1/R - s/R^3 + (3 s^2 - R^2 q) / (2 R^5) - (5 s^3 - 3 R^2 s q) / (2 R^7),
    // s = u.d, q = d.d, written out in the monomials dx^i dy^j.
    const double ux = centre.x - x, uy = centre.y - y;
    const double r2 = ux * ux + uy * uy, r = std::sqrt(r2);
    // 1/R^(2l+1) by one more division and products: the divider is the far terms' cost.
    const double q = 1.0 / r2, i1 = 1.0 / r, i3 = i1 * q, i5 = i3 * q, i7 = i5 * q;
    double t[4][4] = {};
    t[0][0] = i1;
    t[1][0] = -ux * i3;
    t[0][1] = -uy * i3;
    t[2][0] = 0.5 * (3.0 * ux * ux - r2) * i5;
    t[1][1] = 3.0 * ux * uy * i5;
    t[0][2] = 0.5 * (3.0 * uy * uy - r2) * i5;
    t[3][0] = -0.5 * (5.0 * ux * ux * ux - 3.0 * r2 * ux) * i7;
    t[2][1] = -0.5 * (15.0 * ux * ux * uy - 3.0 * r2 * uy) * i7;
    t[1][2] = -0.5 * (15.0 * ux * uy * uy - 3.0 * r2 * ux) * i7;
    t[0][3] = -0.5 * (5.0 * uy * uy * uy - 3.0 * r2 * uy) * i7;
    for (int k = 0; k < 10; ++k) {
        const double term = t[kTerms[k][0]][kTerms[k][1]];
        cell.den[k] += term;
        cell.num[k] += rho * term;
    }
}

std::uint32_t InverseDistanceField::make_child(std::uint32_t parent, int quadrant) const {
    static_assert(sizeof(Cell) == 160 && sizeof(Place) <= 64, "a cell's sums in three lines, its place in one");
    Cell c{};
    Place at{};
    std::uint32_t from, to;
    {
        const Cell& p = cells_[parent];
        const Place& up = places_[parent];
        at.half = 0.5 * up.half;
        at.centre = {up.centre.x + ((quadrant & 1) ? at.half : -at.half),
                     up.centre.y + ((quadrant & 2) ? at.half : -at.half)};
        at.parent = parent;
        move_cubic(p.num, at.centre.x - up.centre.x, at.centre.y - up.centre.y, c.num);
        move_cubic(p.den, at.centre.x - up.centre.x, at.centre.y - up.centre.y, c.den);
        from = up.near_begin;
        to = up.near_end;
    }
    // Far: at least the half-diagonal / phi from the centre, so that |P - C| / R <= phi. The
    // parent's near nodes whole: all far, all near (kept), or opened (a leaf that straddles
    // stays near: summing a source term by term is never wrong).
    const double far = at.half * std::numbers::sqrt2 / phi_;
    at.near_begin = static_cast<std::uint32_t>(near_nodes_.size());
    size_t count = 0;
    std::vector<std::uint32_t>& open = open_;
    std::vector<std::pair<std::uint32_t, std::uint32_t>>& far_ranges = far_ranges_;
    far_ranges.clear();
    for (std::uint32_t k = from; k < to; ++k) {
        open.assign(1, near_nodes_[k]);
        while (!open.empty()) {
            const std::uint32_t id = open.back();
            open.pop_back();
            const Node& n = nodes_[id];
            const double d = distance(at.centre, n.c);
            if (d - n.r >= far) {
                far_ranges.emplace_back(n.begin, n.end);
            } else if (d + n.r < far || n.left == 0) {
                near_nodes_.push_back(id);
                count += n.end - n.begin;
            } else {
                open.push_back(n.right);
                open.push_back(n.left);
            }
        }
    }
    at.near_end = static_cast<std::uint32_t>(near_nodes_.size());
    // Sources that coincide cannot be parted: past 2^-40 of the root's width a cell is a leaf.
    at.leaf = count <= kCellNearSources || at.half < places_[0].half * 0x1p-40;
    at.packed = at.leaf && packed_sources() + count <= packing_budget_;
    if (at.packed) {
        // A leaf is never split: its near sources copied out in one range (one pass of eight
        // a step instead of a short pass per node), its node numbers let go.
        near_x_.resize(near_x_.size() - 3);
        near_y_.resize(near_y_.size() - 3);
        near_r_.resize(near_r_.size() - 3);
        // Grown by doubling, but never past the budget (and the last leaf's room).
        if (const size_t need = near_x_.size() + count + 3; need > near_x_.capacity()) {
            const size_t room = std::max(need, std::min(2 * near_x_.capacity(), packing_budget_ + 3));
            near_x_.reserve(room);
            near_y_.reserve(room);
            near_r_.reserve(room);
        }
        const auto packed = static_cast<std::uint32_t>(near_x_.size());
        for (std::uint32_t k = at.near_begin; k < at.near_end; ++k) {
            const Node& n = nodes_[near_nodes_[k]];
            near_x_.insert(near_x_.end(), x_.begin() + n.begin, x_.begin() + n.end);
            near_y_.insert(near_y_.end(), y_.begin() + n.begin, y_.begin() + n.end);
            near_r_.insert(near_r_.end(), rho_.begin() + n.begin, rho_.begin() + n.end);
        }
        near_nodes_.resize(at.near_begin);
        at.near_begin = packed;
        at.near_end = static_cast<std::uint32_t>(near_x_.size());
        pad_near();
    }
    // The far sources' terms, node by node in the order met.
#if defined(MESHD_AVX_SUM)
    if (g_wide.load(std::memory_order_relaxed)) {
        WideFarSums sums(c.num, c.den);
        for (const auto& [b, e] : far_ranges) sums.add(x_.data(), y_.data(), rho_.data(), b, e, at.centre);
        sums.store(c.num, c.den);
    } else
#endif
    {
        for (const auto& [b, e] : far_ranges)
            for (std::uint32_t i = b; i < e; ++i) add_far(c, at.centre, x_[i], y_[i], rho_[i]);
    }
    const auto id = static_cast<std::uint32_t>(cells_.size());
    cells_.push_back(c);
    places_.push_back(at);
    places_[parent].child[quadrant] = id;
    return id;
}

double InverseDistanceField::through_cells(Vec2 p) const {
    auto inside = [&](const Place& c) { return std::fabs(p.x - c.centre.x) <= c.half && std::fabs(p.y - c.centre.y) <= c.half; };
    // Outside the sources' box (not inside a domain they bound): summed.
    if (!inside(places_[0])) return summed(p);
    // Up from the last query's leaf to the first cell that holds p (queries come in runs:
    // neighbours share most of their way), then down to p's leaf.
    std::uint32_t k = last_leaf_;
    while (!inside(places_[k])) k = places_[k].parent;
    while (!places_[k].leaf) {
        const Place& at = places_[k];
        const int q = (p.x >= at.centre.x ? 1 : 0) + (p.y >= at.centre.y ? 2 : 0);
        k = at.child[q] != 0 ? at.child[q] : make_child(k, q);
    }
    last_leaf_ = k;
    const Place& at = places_[k];
    const Cell& c = cells_[k];
    const double dx = p.x - at.centre.x, dy = p.y - at.centre.y;
    const double num = cubic(c.num, dx, dy), den = cubic(c.den, dx, dy);
    if (at.packed) {
        const std::pair<std::uint32_t, std::uint32_t> all{at.near_begin, at.near_end};
        return near_value(near_x_.data(), near_y_.data(), near_r_.data(), 1, [&](std::uint32_t) { return all; }, p,
                          num, den);
    }
    return near_value(x_.data(), y_.data(), rho_.data(), at.near_end - at.near_begin,
                      [&](std::uint32_t j) {
                          const Node& n = nodes_[near_nodes_[at.near_begin + j]];
                          return std::pair<std::uint32_t, std::uint32_t>{n.begin, n.end};
                      },
                      p, num, den);
}

double InverseDistanceField::treecode(Vec2 p) const {
    double num = 0.0, den = 0.0;
    const double* at_source = nullptr;  // p is a source: rho there
    detail::depth_first(nodes_, [&](const Node& n) {
        const double d = distance(p, n.c);
        const double dr = distance(p, n.c_rho);
        if (n.r <= theta_ * d && n.r_rho <= theta_ * dr) {
            den += n.count / d;
            num += n.rho_sum / dr;
            return detail::Descend::No;
        }
        if (n.left == 0) {
            for (std::uint32_t i = n.begin; i < n.end; ++i) {
                const double di = distance(p, a_[i]);
                if (di == 0.0) {
                    at_source = &rho_[i];
                    return detail::Descend::Stop;
                }
                den += 1.0 / di;
                num += rho_[i] / di;
            }
            return detail::Descend::No;
        }
        return detail::Descend::RightFirst;
    });
    return at_source ? *at_source : num / den;
}

double InverseDistanceField::exact(Vec2 p) const {
    double num = 0.0, den = 0.0;
    for (size_t i = 0; i < a_.size(); ++i) {
        const double di = distance(p, a_[i]);
        if (di == 0.0) return rho_[i];
        den += 1.0 / di;
        num += rho_[i] / di;
    }
    return num / den;
}

}  // namespace meshd::core
