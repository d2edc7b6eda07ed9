#include "boundary/spacing.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "meshd/core/errors.hpp"
#include "kernel/tolerances.hpp"

namespace meshd::core {

DensityProfile sample_density(double length, const std::function<double(double)>& rho,
                              double min_size, size_t max_stations, double floor) {
    DensityProfile out;
    // Start from a coarse uniform sampling, then refine each interval depth first.
    const int initial = 8;
    std::vector<std::pair<double, double>> stack;  // (s, h) pending right ends, reversed
    out.s.push_back(0.0);
    out.h.push_back(rho(0.0));
    for (int i = initial; i >= 1; --i) {
        const double s = i == initial ? length : length * i / initial;
        stack.emplace_back(s, rho(s));
    }
    const double floor_len = 0.05 * min_size;
    while (!stack.empty()) {
        const double sa = out.s.back(), ha = out.h.back();
        const auto [sb, hb] = stack.back();
        const double len = sb - sa;
        const double hmin = fmin_inline(ha, hb);
        bool split = len > 0.5 * hmin;
        double sm = 0.5 * (sa + sb), hm = 0.0;
        if (len > floor_len && len > floor * hmin && len > 1e-15 * length) {
            hm = rho(sm);
            if (!split) split = std::fabs(hm - 0.5 * (ha + hb)) > tol::kDensityInterpolation * hmin;
        } else {
            split = false;
        }
        if (split && sm > sa && sm < sb) {
            stack.emplace_back(sm, hm);
            continue;
        }
        out.s.push_back(sb);
        out.h.push_back(hb);
        stack.pop_back();
        if (out.s.size() > max_stations)
            throw GeometryError(GeometryErrorKind::TooManyPoints,
                                "the density asks for more than " + std::to_string(max_stations) +
                                    " samples along the curves");
    }
    return out;
}

namespace {

// Lo's march with the target scaled by lambda: from x_0 = 0, x_{k+1} solves
// x_{k+1} - x_k = lambda (h(x_k) + h(x_{k+1})) / 2 on the piecewise-linear h (extended as a
// constant beyond the last station). Stops after `steps` points, or, when steps == 0, at the
// last point before M. Appends the points (x_0 included) to `out` when given; returns the
// number of points made after x_0 and leaves the next point the march would make in `next`.
size_t march(const DensityProfile& prof, double lambda, size_t steps, std::vector<double>* out,
             double& last, double& next) {
    const auto& s = prof.s;
    const auto& h = prof.h;
    const size_t m = s.size() - 1;
    const double total = s.back();
    if (out) out->push_back(0.0);
    double a = 0.0, ha = h[0];
    size_t i = 0;  // station interval [s_i, s_{i+1}] holding a
    size_t made = 0;
    for (;;) {
        // F(B) = B - a - lambda (ha + h(B)) / 2 is -lambda ha < 0 at B = a, linear on each
        // interval: the first interval whose right end has F >= 0 holds the root.
        double left = a, f_left = -lambda * ha;
        double b = 0.0, hb = h[m];
        bool found = false;
        size_t j = i;
        for (; j < m; ++j) {
            const double right = s[j + 1];
            const double f_right = right - a - 0.5 * lambda * (ha + h[j + 1]);
            if (f_right >= 0.0) {
                b = left + (right - left) * (-f_left) / (f_right - f_left);
                const double w = s[j + 1] > s[j] ? (b - s[j]) / (s[j + 1] - s[j]) : 1.0;
                hb = h[j] + std::clamp(w, 0.0, 1.0) * (h[j + 1] - h[j]);
                found = true;
                break;
            }
            left = right;
            f_left = f_right;
        }
        if (!found) {
            // Beyond M, h is the constant h[m]: B - a = lambda (ha + h[m]) / 2.
            j = m;
            b = a + 0.5 * lambda * (ha + h[m]);
            hb = h[m];
        }
        if (!(b > a)) b = std::nextafter(a, HUGE_VAL);  // a degenerate profile
        if (steps == 0 ? b >= total : made == steps) {
            last = a;
            next = b;
            return made;
        }
        if (out) out->push_back(b);
        ++made;
        a = b;
        ha = hb;
        i = std::min(j, m - 1);
    }
}

}  // namespace

std::vector<double> graded_stations(const DensityProfile& prof, size_t max_segments) {
    const double total = prof.s.back();
    // Unscaled march: the last point x_k before M and the next one beyond it.
    double last = 0.0, next = 0.0;
    const size_t k = march(prof, 1.0, 0, nullptr, last, next);
    if (k > max_segments)
        throw GeometryError(GeometryErrorKind::TooManyPoints,
                            "the density asks for more than " + std::to_string(max_segments) +
                                " points along one curve");
    // n segments: k when stretching x_k onto M is the smaller change, k + 1 when shrinking
    // the next point onto M is (3.21-3.22 distribute the leftover this way).
    size_t n = k + 1;
    if (k > 0 && std::fabs(std::log(total / last)) <= std::fabs(std::log(next / total))) n = k;
    if (n == 1) return {0.0, total};
    // The paper spreads the leftover over all segments in proportion to their lengths, which
    // shifts every point; where rho is small far from the start that shift is many local
    // sizes. Instead scale the target itself by a factor lambda, found so that the n-th
    // point of the march lands on M: every segment keeps the same ratio to its target at its
    // own place. The end of the march grows monotonically with lambda; regula falsi
    // (Illinois) on a bracket finds it in a few marches.
    std::vector<double> x, best;
    double best_err = HUGE_VAL;
    auto end_at = [&](double lambda) {
        x.clear();
        double l = 0.0, nx = 0.0;
        march(prof, lambda, n, &x, l, nx);
        const double f = l - total;  // position of the n-th point, relative to M
        if (std::fabs(f) < best_err) {
            best_err = std::fabs(f);
            best.swap(x);
        }
        return f;
    };
    // Accurate far beyond what the rounding of a long march allows, and far below the last
    // segment (about h at M), which absorbs the remainder.
    const double accept = std::fmax(1e-6 * prof.h.back(),
                                    8.0 * static_cast<double>(n) * 0x1p-52 * total);
    // The unscaled march already says where the n-th point falls: for a uniform rho,
    // M / x_n is the answer; start there and bracket around it.
    const double guess = total / (n == k ? last : next);
    const double f_guess = end_at(guess);
    if (std::fabs(f_guess) > accept) {
        double lo = guess, hi = guess, f_lo = f_guess, f_hi = f_guess;
        // x_n grows about in proportion to lambda: a step of twice the relative miss brackets.
        double step = std::fmin(0.5, 2.0 * std::fabs(f_guess) / total);
        if (f_guess > 0.0) {
            do { hi = lo; f_hi = f_lo; lo *= 1.0 - step; f_lo = end_at(lo); step *= 2; } while (f_lo > 0.0);
        } else {
            do { lo = hi; f_lo = f_hi; hi *= 1.0 + step; f_hi = end_at(hi); step *= 2; } while (f_hi < 0.0);
        }
        int side = 0;
        for (int iter = 0; iter < 100 && best_err > accept && hi - lo > 1e-15 * hi; ++iter) {
            const double lambda = (lo * f_hi - hi * f_lo) / (f_hi - f_lo);
            const double f = end_at(lambda);
            if (f < 0.0) {
                lo = lambda; f_lo = f;
                if (side == -1) f_hi *= 0.5;  // Illinois: keep the stale end from stalling
                side = -1;
            } else {
                hi = lambda; f_hi = f;
                if (side == 1) f_lo *= 0.5;
                side = 1;
            }
        }
    }
    // Rounding: points strictly increasing and the end exactly at M.
    best.back() = total;
    for (size_t i = best.size() - 1; i-- > 1;) best[i] = std::min(best[i], std::nextafter(best[i + 1], 0.0));
    return best;
}

}  // namespace meshd::core
