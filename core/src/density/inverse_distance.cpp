// Treecode for eq. (6.1); the error analysis is in inverse_distance.hpp.

#include "density/inverse_distance.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
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

#if defined(__SSE2__)
// Four sources per step: the squared distances (in double) become floats, whose square root
// and reciprocal take a quarter of the divider's time the doubles' take (the sum is bound by
// it); each weight 1/d is then within 3 float roundings (2e-7) of its exact value, so the
// ratio is within 4e-7, and the sums stay double. Sums the sources [0, 4 floor(n / 4));
// false when a squared distance left the floats' normal range (a query on a source, or
// absurdly far): the caller then sums in double.
bool sum_by_fours_sse2(const double* x, const double* y, const double* r, size_t n, Vec2 p, double& num,
                       double& den) {
    const __m128d px = _mm_set1_pd(p.x), py = _mm_set1_pd(p.y);
    const __m128 one = _mm_set1_ps(1.0f), low = _mm_set1_ps(std::numeric_limits<float>::min()),
                 high = _mm_set1_ps(std::numeric_limits<float>::max());
    __m128d num0 = _mm_setzero_pd(), den0 = _mm_setzero_pd(), num1 = _mm_setzero_pd(), den1 = _mm_setzero_pd();
    __m128 out = _mm_setzero_ps();
    for (size_t i = 0; i + 4 <= n; i += 4) {
        const __m128d dx0 = _mm_sub_pd(px, _mm_loadu_pd(x + i)), dy0 = _mm_sub_pd(py, _mm_loadu_pd(y + i));
        const __m128d dx1 = _mm_sub_pd(px, _mm_loadu_pd(x + i + 2)), dy1 = _mm_sub_pd(py, _mm_loadu_pd(y + i + 2));
        const __m128d d0 = _mm_add_pd(_mm_mul_pd(dx0, dx0), _mm_mul_pd(dy0, dy0));
        const __m128d d1 = _mm_add_pd(_mm_mul_pd(dx1, dx1), _mm_mul_pd(dy1, dy1));
        const __m128 d = _mm_movelh_ps(_mm_cvtpd_ps(d0), _mm_cvtpd_ps(d1));
        out = _mm_or_ps(out, _mm_or_ps(_mm_cmplt_ps(d, low), _mm_cmpgt_ps(d, high)));
        const __m128 w = _mm_div_ps(one, _mm_sqrt_ps(d));
        const __m128d w0 = _mm_cvtps_pd(w), w1 = _mm_cvtps_pd(_mm_movehl_ps(w, w));
        den0 = _mm_add_pd(den0, w0);
        den1 = _mm_add_pd(den1, w1);
        num0 = _mm_add_pd(num0, _mm_mul_pd(_mm_loadu_pd(r + i), w0));
        num1 = _mm_add_pd(num1, _mm_mul_pd(_mm_loadu_pd(r + i + 2), w1));
    }
    if (_mm_movemask_ps(out) != 0) return false;
    alignas(16) double lanes[2];
    _mm_store_pd(lanes, _mm_add_pd(num0, num1));
    num = lanes[0] + lanes[1];
    _mm_store_pd(lanes, _mm_add_pd(den0, den1));
    den = lanes[0] + lanes[1];
    return true;
}
#endif

#if defined(MESHD_AVX_SUM)
// sum_by_fours_sse2 on 256-bit registers where the processor has them (AVX): eight sources a
// step, their weights by one square root and one division of eight floats, added four at a
// time to the same sums, so that lane k of each sum takes the sources k, k + 4, k + 8, ... in
// order, as the two 128-bit sums' lanes do, and the lanes are added in the same pairs: the
// same result to the bit, in about 0.53 ns a source instead of 1.28 (BM_InverseDistance<0>
// at 1,495 sources, 2026-12-03). Sums the sources [0, 4 floor(n / 4)); false when a squared
// distance left the floats' normal range.
__attribute__((target("avx"))) bool sum_by_fours_avx(const double* x, const double* y, const double* r, size_t n,
                                                      Vec2 p, double& num, double& den) {
    const __m256d px = _mm256_set1_pd(p.x), py = _mm256_set1_pd(p.y);
    const __m128 one = _mm_set1_ps(1.0f), low = _mm_set1_ps(std::numeric_limits<float>::min()),
                 high = _mm_set1_ps(std::numeric_limits<float>::max());
    __m256d num4 = _mm256_setzero_pd(), den4 = _mm256_setzero_pd();
    __m128 out = _mm_setzero_ps();
    size_t i = 0;
    const __m256 one8 = _mm256_set1_ps(1.0f), low8 = _mm256_set1_ps(std::numeric_limits<float>::min()),
                 high8 = _mm256_set1_ps(std::numeric_limits<float>::max());
    __m256 out8 = _mm256_setzero_ps();
    for (; i + 8 <= n; i += 8) {
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
    for (; i + 4 <= n; i += 4) {
        const __m256d dx = _mm256_sub_pd(px, _mm256_loadu_pd(x + i)), dy = _mm256_sub_pd(py, _mm256_loadu_pd(y + i));
        const __m128 d = _mm256_cvtpd_ps(_mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy)));
        out = _mm_or_ps(out, _mm_or_ps(_mm_cmplt_ps(d, low), _mm_cmpgt_ps(d, high)));
        const __m256d w = _mm256_cvtps_pd(_mm_div_ps(one, _mm_sqrt_ps(d)));
        den4 = _mm256_add_pd(den4, w);
        num4 = _mm256_add_pd(num4, _mm256_mul_pd(_mm256_loadu_pd(r + i), w));
    }
    if (_mm256_movemask_ps(out8) != 0 || _mm_movemask_ps(out) != 0) return false;
    alignas(16) double lanes[2];
    _mm_store_pd(lanes, _mm_add_pd(_mm256_castpd256_pd128(num4), _mm256_extractf128_pd(num4, 1)));
    num = lanes[0] + lanes[1];
    _mm_store_pd(lanes, _mm_add_pd(_mm256_castpd256_pd128(den4), _mm256_extractf128_pd(den4, 1)));
    den = lanes[0] + lanes[1];
    return true;
}

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
                                           double tolerance)
    : a_(std::move(starts)), rho_(std::move(values)) {
    MESHD_INTERNAL_CHECK(a_.size() == rho_.size() && !a_.empty(), "eq. 6.1 needs sources");
    MESHD_INTERNAL_CHECK(tolerance > 0.0 && tolerance < 1.0, "tolerance out of range");
    // Largest theta whose per-sum bound keeps the ratio within the tolerance.
    const double delta_max = tolerance / (2.0 + tolerance);
    double lo = 0.0, hi = 0.5;
    for (int i = 0; i < 60; ++i) {
        const double mid = 0.5 * (lo + hi);
        (delta_of(mid) <= delta_max ? lo : hi) = mid;
    }
    theta_ = lo;
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
    if (a_.size() <= kDirectSources) {
        x_.reserve(a_.size());
        y_.reserve(a_.size());
        for (const Vec2& v : a_) {
            x_.push_back(v.x);
            y_.push_back(v.y);
        }
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
}

double InverseDistanceField::direct(Vec2 p) const {
    const size_t n = x_.size();
    const double* x = x_.data();
    const double* y = y_.data();
    const double* r = rho_.data();
    double num = 0.0, den = 0.0;
    size_t i = 0;
#if defined(__SSE2__)
    if (!sum_by_fours(x, y, r, n, p, num, den)) return exact(p);
    i = n & ~size_t{3};
#endif
    for (; i < n; ++i) {
        const double dx = p.x - x[i], dy = p.y - y[i];
        const double d2 = dx * dx + dy * dy;
        if (d2 == 0.0) return r[i];
        const double w = 1.0 / std::sqrt(d2);
        den += w;
        num += r[i] * w;
    }
    return num / den;
}

double InverseDistanceField::operator()(Vec2 p) const {
    return a_.size() <= kDirectSources ? direct(p) : treecode(p);
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
