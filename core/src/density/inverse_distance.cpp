// Treecode for eq. (6.1); the error analysis is in inverse_distance.hpp.

#include "density/inverse_distance.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "kernel/kdtree.hpp"
#include "meshd/core/errors.hpp"

namespace meshd::core {

namespace {

double delta_of(double theta) {
    return theta * theta * (1.0 + theta) / ((1.0 - theta) * (1.0 - theta) * (1.0 - theta));
}

}  // namespace

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
    // Two sources per instruction, two independent pairs of sums (the compiler may not
    // reorder the scalar sums, nor call sqrt without its errno check).
    const __m128d px = _mm_set1_pd(p.x), py = _mm_set1_pd(p.y), one = _mm_set1_pd(1.0);
    __m128d num0 = _mm_setzero_pd(), den0 = _mm_setzero_pd(), num1 = _mm_setzero_pd(), den1 = _mm_setzero_pd();
    const __m128d zero = _mm_setzero_pd();
    __m128d hit = _mm_setzero_pd();
    for (; i + 4 <= n; i += 4) {
        const __m128d dx0 = _mm_sub_pd(px, _mm_loadu_pd(x + i)), dy0 = _mm_sub_pd(py, _mm_loadu_pd(y + i));
        const __m128d dx1 = _mm_sub_pd(px, _mm_loadu_pd(x + i + 2)), dy1 = _mm_sub_pd(py, _mm_loadu_pd(y + i + 2));
        const __m128d d0 = _mm_add_pd(_mm_mul_pd(dx0, dx0), _mm_mul_pd(dy0, dy0));
        const __m128d d1 = _mm_add_pd(_mm_mul_pd(dx1, dx1), _mm_mul_pd(dy1, dy1));
        hit = _mm_or_pd(hit, _mm_or_pd(_mm_cmpeq_pd(d0, zero), _mm_cmpeq_pd(d1, zero)));
        const __m128d w0 = _mm_div_pd(one, _mm_sqrt_pd(d0)), w1 = _mm_div_pd(one, _mm_sqrt_pd(d1));
        den0 = _mm_add_pd(den0, w0);
        den1 = _mm_add_pd(den1, w1);
        num0 = _mm_add_pd(num0, _mm_mul_pd(_mm_loadu_pd(r + i), w0));
        num1 = _mm_add_pd(num1, _mm_mul_pd(_mm_loadu_pd(r + i + 2), w1));
    }
    if (_mm_movemask_pd(hit) != 0) {
        for (size_t k = 0; k < i; ++k)
            if (x[k] == p.x && y[k] == p.y) return r[k];
    }
    alignas(16) double lanes[2];
    _mm_store_pd(lanes, _mm_add_pd(num0, num1));
    num = lanes[0] + lanes[1];
    _mm_store_pd(lanes, _mm_add_pd(den0, den1));
    den = lanes[0] + lanes[1];
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
