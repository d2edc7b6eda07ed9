#include "crossings.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "meshd/core/predicates.hpp"

namespace meshd::core::detail {

namespace {

std::uint64_t cell_key(std::int64_t ix, std::int64_t iy) {
    return (static_cast<std::uint64_t>(ix) << 32) ^ (static_cast<std::uint64_t>(iy) & 0xffffffffu);
}

}  // namespace

std::optional<std::pair<std::uint32_t, std::uint32_t>> find_crossing(const SegmentSoup& soup) {
    const auto& pts = soup.points;
    const auto& segs = soup.segments;
    const size_t n = segs.size();
    if (n < 2) return std::nullopt;

    Box box;
    for (const auto& s : segs) {
        box.add(pts[s[0]]);
        box.add(pts[s[1]]);
    }
    const Vec2 origin = box.lo;
    const double extent = std::fmax(box.hi.x - box.lo.x, box.hi.y - box.lo.y);
    if (!(extent > 0.0)) return std::nullopt;

    // Size class k: cell size extent * 2^-k, the largest k with cell >= segment box side.
    constexpr int kMaxClass = 40;
    std::vector<int> cls(n);
    for (size_t i = 0; i < n; ++i) {
        const Vec2 a = pts[segs[i][0]], b = pts[segs[i][1]];
        const double side = std::fmax(std::fabs(a.x - b.x), std::fabs(a.y - b.y));
        int k = side > 0.0 ? static_cast<int>(std::floor(std::log2(extent / side))) : kMaxClass;
        cls[i] = std::clamp(k, 0, kMaxClass);
    }
    std::vector<std::unordered_map<std::uint64_t, std::vector<std::uint32_t>>> grids(kMaxClass + 1);
    auto cell_range = [&](size_t i, int k, std::int64_t& x0, std::int64_t& x1, std::int64_t& y0,
                          std::int64_t& y1) {
        const double cell = std::ldexp(extent, -k);
        const Vec2 a = pts[segs[i][0]], b = pts[segs[i][1]];
        x0 = static_cast<std::int64_t>(std::floor((std::fmin(a.x, b.x) - origin.x) / cell));
        x1 = static_cast<std::int64_t>(std::floor((std::fmax(a.x, b.x) - origin.x) / cell));
        y0 = static_cast<std::int64_t>(std::floor((std::fmin(a.y, b.y) - origin.y) / cell));
        y1 = static_cast<std::int64_t>(std::floor((std::fmax(a.y, b.y) - origin.y) / cell));
    };
    for (size_t i = 0; i < n; ++i) {
        std::int64_t x0, x1, y0, y1;
        cell_range(i, cls[i], x0, x1, y0, y1);
        for (auto x = x0; x <= x1; ++x)
            for (auto y = y0; y <= y1; ++y)
                grids[static_cast<size_t>(cls[i])][cell_key(x, y)].push_back(static_cast<std::uint32_t>(i));
    }
    std::vector<int> used_classes;
    for (int k = 0; k <= kMaxClass; ++k)
        if (!grids[static_cast<size_t>(k)].empty()) used_classes.push_back(k);

    std::optional<std::pair<std::uint32_t, std::uint32_t>> best;
    std::vector<std::uint32_t> candidates;
    for (size_t i = 0; i < n; ++i) {
        candidates.clear();
        for (int k : used_classes) {
            if (k > cls[i]) continue;  // smaller segments look this one up themselves
            std::int64_t x0, x1, y0, y1;
            cell_range(i, k, x0, x1, y0, y1);
            const auto& grid = grids[static_cast<size_t>(k)];
            for (auto x = x0; x <= x1; ++x)
                for (auto y = y0; y <= y1; ++y) {
                    auto it = grid.find(cell_key(x, y));
                    if (it == grid.end()) continue;
                    for (std::uint32_t j : it->second) {
                        if (j == i) continue;
                        if (cls[j] == cls[i] && j < i) continue;  // same class: test once
                        candidates.push_back(j);
                    }
                }
        }
        std::sort(candidates.begin(), candidates.end());
        candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
        const auto& s = segs[i];
        for (std::uint32_t j : candidates) {
            const auto& t = segs[j];
            if (s[0] == t[0] || s[0] == t[1] || s[1] == t[0] || s[1] == t[1]) {
                // Neighbours: only a collinear overlap (folding back) is a crossing.
                const std::uint32_t shared = (s[0] == t[0] || s[0] == t[1]) ? s[0] : s[1];
                const std::uint32_t so = s[0] == shared ? s[1] : s[0];
                const std::uint32_t to = t[0] == shared ? t[1] : t[0];
                if (so == to) {
                    // the same segment twice
                } else if (orient2d(pts[shared], pts[so], pts[to]) != Orientation::Collinear ||
                           dot(pts[so] - pts[shared], pts[to] - pts[shared]) < 0.0) {
                    continue;
                }
            } else if (!segments_intersect(pts[s[0]], pts[s[1]], pts[t[0]], pts[t[1]])) {
                continue;
            }
            const auto ii = static_cast<std::uint32_t>(i);
            const std::pair<std::uint32_t, std::uint32_t> pair{std::min(ii, j), std::max(ii, j)};
            if (!best || pair < *best) best = pair;
        }
    }
    return best;
}

}  // namespace meshd::core::detail
