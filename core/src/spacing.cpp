#include "meshd/core/spacing.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "meshd/core/errors.hpp"
#include "meshd/core/tolerances.hpp"

namespace meshd::core {

DensityProfile sample_density(double length, const std::function<double(double)>& rho,
                              double min_size, size_t max_stations) {
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
        const double hmin = std::fmin(ha, hb);
        bool split = len > 0.5 * hmin;
        double sm = 0.5 * (sa + sb), hm = 0.0;
        if (len > floor_len && len > 1e-15 * length) {
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
                                    " samples along one curve");
    }
    return out;
}

std::vector<double> graded_stations(const DensityProfile& prof) {
    const auto& s = prof.s;
    const auto& h = prof.h;
    const size_t m = s.size() - 1;
    const double total = s.back();
    std::vector<double> x{0.0};
    double a = 0.0, ha = h[0];
    size_t i = 0;  // station interval [s_i, s_{i+1}] holding a
    for (;;) {
        // F(B) = B - a - (ha + h(B)) / 2 is -ha < 0 at B = a and linear on each interval.
        double left = a, f_left = -ha;
        bool found = false;
        double b = 0.0;
        size_t j = i;
        for (; j < m; ++j) {
            const double right = s[j + 1];
            const double f_right = right - a - 0.5 * (ha + h[j + 1]);
            if (f_right >= 0.0) {
                b = left + (right - left) * (-f_left) / (f_right - f_left);
                found = true;
                break;
            }
            left = right;
            f_left = f_right;
        }
        if (!found) break;
        // h(b) on interval j
        const double w = s[j + 1] > s[j] ? (b - s[j]) / (s[j + 1] - s[j]) : 1.0;
        const double hb = h[j] + w * (h[j + 1] - h[j]);
        if (!(b > a)) b = std::nextafter(a, total);  // guards a degenerate profile
        x.push_back(b);
        a = b;
        ha = hb;
        i = j;
    }
    // The last point x_k < M: either stretch so that x_k lands on M, or add the point the
    // march would have placed next (beyond M) and shrink so that it lands on M.
    const double last = x.back();
    const double next = last + 0.5 * (ha + h[m]);
    double scale;
    if (x.size() == 1) {
        x.push_back(next);
        scale = total / next;
    } else {
        const double stretch = total / last;  // >= 1
        const double shrink = total / next;   // < 1
        if (std::fabs(std::log(shrink)) < std::fabs(std::log(stretch))) {
            x.push_back(next);
            scale = shrink;
        } else {
            scale = stretch;
        }
    }
    for (double& v : x) v *= scale;
    x.back() = total;
    return x;
}

}  // namespace meshd::core
