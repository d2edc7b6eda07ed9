#include "kernel/crossings.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "kernel/predicates.hpp"
#include "kernel/size_grid.hpp"

namespace meshd::core::detail {

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
    const double extent = std::fmax(box.hi.x - box.lo.x, box.hi.y - box.lo.y);
    if (!(extent > 0.0)) return std::nullopt;

    // Each segment in the grid whose cells (2 c_k) are one to two times its longest box side:
    // its box spans at most 2 x 2 cells there.
    const SizeClasses classes(box.lo, extent);
    std::vector<int> cls(n);
    std::array<bool, SizeClasses::kMax + 1> used{};
    auto side = [&](size_t i) {
        const Vec2 a = pts[segs[i][0]], b = pts[segs[i][1]];
        return std::fmax(std::fabs(a.x - b.x), std::fabs(a.y - b.y));
    };
    struct Range { std::int64_t x0, x1, y0, y1; };
    auto cell_range = [&](size_t i, int k) {
        const Vec2 a = pts[segs[i][0]], b = pts[segs[i][1]];
        return Range{classes.ix(std::fmin(a.x, b.x), k), classes.ix(std::fmax(a.x, b.x), k),
                     classes.iy(std::fmin(a.y, b.y), k), classes.iy(std::fmax(a.y, b.y), k)};
    };
    CellMap grid;
    for (size_t i = 0; i < n; ++i) {
        cls[i] = classes.class_of(0.5 * side(i));
        used[static_cast<size_t>(cls[i])] = true;
        const Range r = cell_range(i, cls[i]);
        for (auto x = r.x0; x <= r.x1; ++x)
            for (auto y = r.y0; y <= r.y1; ++y) grid.push(SizeClasses::key(cls[i], x, y), static_cast<std::uint32_t>(i));
    }

    std::optional<std::pair<std::uint32_t, std::uint32_t>> best;
    std::vector<std::uint32_t> candidates;
    for (size_t i = 0; i < n; ++i) {
        candidates.clear();
        for (int k = 1; k <= cls[i]; ++k) {  // classes of segments no smaller than this one
            if (!used[static_cast<size_t>(k)]) continue;
            const Range r = cell_range(i, k);
            for (auto x = r.x0; x <= r.x1; ++x)
                for (auto y = r.y0; y <= r.y1; ++y)
                    for (auto e = grid.head(SizeClasses::key(k, x, y)); e != CellMap::kNone; e = grid.next(e)) {
                        const std::uint32_t j = grid.item(e);
                        if (j == i || (cls[j] == cls[i] && j < i)) continue;  // same class: test once
                        candidates.push_back(j);
                    }
        }
        if (candidates.empty()) continue;
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
                if (so != to && (orient2d(pts[shared], pts[so], pts[to]) != Orientation::Collinear ||
                                 dot(pts[so] - pts[shared], pts[to] - pts[shared]) < 0.0))
                    continue;
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
