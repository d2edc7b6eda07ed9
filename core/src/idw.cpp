// Treecode for eq. (6.1); the error analysis is in idw.hpp.

#include "meshd/core/idw.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "meshd/core/errors.hpp"

namespace meshd::core {

namespace {

constexpr std::uint32_t kLeafSize = 8;

double delta_of(double theta) {
    return theta * theta * (1.0 + theta) / ((1.0 - theta) * (1.0 - theta) * (1.0 - theta));
}

}  // namespace

InverseDistanceField::InverseDistanceField(std::vector<Vec2> starts, std::vector<double> values,
                                           double tolerance)
    : a_(std::move(starts)), rho_(std::move(values)), tolerance_(tolerance) {
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
    // Sort the sources into tree order (permute both arrays together).
    std::vector<std::uint32_t> idx(a_.size());
    std::iota(idx.begin(), idx.end(), 0u);
    nodes_.reserve(2 * a_.size() / kLeafSize + 2);
    // Build on an index array, then apply the permutation.
    std::vector<Vec2> a = a_;
    std::vector<double> r = rho_;
    a_.clear();
    rho_.clear();
    // Recursive median split on indices.
    auto split = [&](auto&& self, std::uint32_t b, std::uint32_t e) -> void {
        if (e - b <= kLeafSize) return;
        Box box;
        for (std::uint32_t i = b; i < e; ++i) box.add(a[idx[i]]);
        const bool by_x = box.hi.x - box.lo.x >= box.hi.y - box.lo.y;
        const std::uint32_t m = b + (e - b) / 2;
        std::nth_element(idx.begin() + b, idx.begin() + m, idx.begin() + e, [&](auto i, auto j) {
            const Vec2 p = a[i], q = a[j];
            return by_x ? (p.x < q.x || (p.x == q.x && i < j)) : (p.y < q.y || (p.y == q.y && i < j));
        });
        self(self, b, m);
        self(self, m, e);
    };
    split(split, 0, static_cast<std::uint32_t>(idx.size()));
    for (auto i : idx) {
        a_.push_back(a[i]);
        rho_.push_back(r[i]);
    }
    build(0, static_cast<std::uint32_t>(a_.size()));
}

std::uint32_t InverseDistanceField::build(std::uint32_t begin, std::uint32_t end) {
    const auto id = static_cast<std::uint32_t>(nodes_.size());
    nodes_.push_back({});
    Node n{};
    n.begin = begin;
    n.end = end;
    n.count = static_cast<double>(end - begin);
    Vec2 c{0, 0}, cr{0, 0};
    double rs = 0.0;
    for (std::uint32_t i = begin; i < end; ++i) {
        c += a_[i];
        cr += rho_[i] * a_[i];
        rs += rho_[i];
    }
    n.c = c / n.count;
    n.c_rho = cr / rs;
    n.rho_sum = rs;
    for (std::uint32_t i = begin; i < end; ++i) {
        n.r = std::fmax(n.r, distance(n.c, a_[i]));
        n.r_rho = std::fmax(n.r_rho, distance(n.c_rho, a_[i]));
    }
    if (end - begin > kLeafSize) {
        // Same split point as the sort above.
        const std::uint32_t m = begin + (end - begin) / 2;
        n.left = build(begin, m);
        n.right = build(m, end);
    }
    nodes_[id] = n;
    return id;
}

double InverseDistanceField::operator()(Vec2 p) const {
    double num = 0.0, den = 0.0;
    std::uint32_t stack[128];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const Node& n = nodes_[stack[--top]];
        const double d = distance(p, n.c);
        const double dr = distance(p, n.c_rho);
        if (n.r <= theta_ * d && n.r_rho <= theta_ * dr) {
            den += n.count / d;
            num += n.rho_sum / dr;
            continue;
        }
        if (n.left == 0) {
            for (std::uint32_t i = n.begin; i < n.end; ++i) {
                const double di = distance(p, a_[i]);
                if (di == 0.0) return rho_[i];
                den += 1.0 / di;
                num += rho_[i] / di;
            }
            continue;
        }
        stack[top++] = n.left;
        stack[top++] = n.right;
    }
    return num / den;
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
