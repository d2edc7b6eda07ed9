#include "kernel/crossings.hpp"

#include <algorithm>
#include <cmath>

#include "kernel/predicates.hpp"

namespace meshd::core::detail {

namespace {

constexpr int kMaxClass = 40;

// Grid cells of all classes in one sorted array: key = class (6 bits) | x (29) | y (29).
std::uint64_t cell_key(int k, std::int64_t ix, std::int64_t iy) {
    constexpr std::uint64_t mask = (std::uint64_t{1} << 29) - 1;
    return (static_cast<std::uint64_t>(k) << 58) | ((static_cast<std::uint64_t>(ix) & mask) << 29) |
           (static_cast<std::uint64_t>(iy) & mask);
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
    std::vector<int> cls(n);
    std::vector<bool> used(kMaxClass + 1, false);
    for (size_t i = 0; i < n; ++i) {
        const Vec2 a = pts[segs[i][0]], b = pts[segs[i][1]];
        const double side = std::fmax(std::fabs(a.x - b.x), std::fabs(a.y - b.y));
        const int k = side > 0.0 ? static_cast<int>(std::floor(std::log2(extent / side))) : kMaxClass;
        cls[i] = std::clamp(k, 0, kMaxClass);
        used[static_cast<size_t>(cls[i])] = true;
    }
    struct Range { std::int64_t x0, x1, y0, y1; };
    auto cell_range = [&](size_t i, int k) {
        const double cell = std::ldexp(extent, -k);
        const Vec2 a = pts[segs[i][0]], b = pts[segs[i][1]];
        return Range{static_cast<std::int64_t>(std::floor((std::fmin(a.x, b.x) - origin.x) / cell)),
                     static_cast<std::int64_t>(std::floor((std::fmax(a.x, b.x) - origin.x) / cell)),
                     static_cast<std::int64_t>(std::floor((std::fmin(a.y, b.y) - origin.y) / cell)),
                     static_cast<std::int64_t>(std::floor((std::fmax(a.y, b.y) - origin.y) / cell))};
    };
    // Hash of cells (open addressing) whose slots head chains of the segments in the cell.
    std::vector<std::uint32_t> next_entry;  // chain of entries in one cell
    std::vector<std::uint32_t> entry_seg;
    next_entry.reserve(2 * n);
    entry_seg.reserve(2 * n);
    size_t table_size = 16;
    while (table_size < 8 * n) table_size <<= 1;  // at most 4 cells a segment: load <= 1/2
    const std::uint64_t mask = table_size - 1;
    constexpr std::uint32_t kEmpty = UINT32_MAX;
    std::vector<std::uint64_t> slot_key(table_size, 0);
    std::vector<std::uint32_t> slot_head(table_size, kEmpty);
    auto slot_of = [&](std::uint64_t key) {
        std::uint64_t h = (key * 0x9E3779B97F4A7C15ull) >> 20;
        for (;; ++h) {
            const size_t i = static_cast<size_t>(h & mask);
            if (slot_head[i] == kEmpty || slot_key[i] == key) return i;
        }
    };
    for (size_t i = 0; i < n; ++i) {
        const Range r = cell_range(i, cls[i]);
        for (auto x = r.x0; x <= r.x1; ++x)
            for (auto y = r.y0; y <= r.y1; ++y) {
                const std::uint64_t key = cell_key(cls[i], x, y);
                const size_t slot = slot_of(key);
                slot_key[slot] = key;
                next_entry.push_back(slot_head[slot]);
                entry_seg.push_back(static_cast<std::uint32_t>(i));
                slot_head[slot] = static_cast<std::uint32_t>(entry_seg.size() - 1);
            }
    }

    std::optional<std::pair<std::uint32_t, std::uint32_t>> best;
    std::vector<std::uint32_t> candidates;
    for (size_t i = 0; i < n; ++i) {
        candidates.clear();
        for (int k = 0; k <= cls[i]; ++k) {  // classes of segments no smaller than this one
            if (!used[static_cast<size_t>(k)]) continue;
            const Range r = cell_range(i, k);
            for (auto x = r.x0; x <= r.x1; ++x)
                for (auto y = r.y0; y <= r.y1; ++y) {
                    const std::uint64_t key = cell_key(k, x, y);
                    for (std::uint32_t e = slot_head[slot_of(key)]; e != kEmpty; e = next_entry[e]) {
                        const std::uint32_t j = entry_seg[e];
                        if (j == i || (cls[j] == cls[i] && j < i)) continue;  // same class: test once
                        candidates.push_back(j);
                    }
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
