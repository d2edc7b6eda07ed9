// Hilbert orders; see spatial_order.hpp.

#include "kernel/spatial_order.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include "kernel/memory.hpp"

namespace meshd::core::detail {

namespace {

// Hilbert index on a 2^12 grid, four levels per table lookup. The coordinates seen at a
// level are the original ones complemented (f) and/or swapped (s): both operations commute,
// so the state of the walk down the curve is just the pair (f, s). The table maps a state
// and four bits of x and of y to eight digits and the state after them.
class HilbertTable {
public:
    HilbertTable() {
        for (std::uint32_t st = 0; st < 4; ++st)
            for (std::uint32_t xc = 0; xc < 16; ++xc)
                for (std::uint32_t yc = 0; yc < 16; ++yc) {
                    std::uint32_t f = st & 1u, sw = st >> 1;
                    std::uint32_t x = sw ? yc : xc, y = sw ? xc : yc;
                    if (f) {
                        x ^= 15u;
                        y ^= 15u;
                    }
                    std::uint32_t d = 0;
                    for (int k = 3; k >= 0; --k) {
                        const std::uint32_t rx = (x >> k) & 1u, ry = (y >> k) & 1u;
                        d = (d << 2) | ((3u * rx) ^ ry);
                        if (ry == 0) {
                            if (rx == 1) {  // lower-right quadrant: reflect
                                x ^= 15u;
                                y ^= 15u;
                                f ^= 1u;
                            }
                            std::swap(x, y);  // lower quadrants: transpose
                            sw ^= 1u;
                        }
                    }
                    entry_[(st << 8) | (xc << 4) | yc] = static_cast<std::uint16_t>(d | ((f | (sw << 1)) << 8));
                }
    }
    std::uint32_t index(std::uint32_t x, std::uint32_t y) const {
        std::uint32_t d = 0, st = 0;
        for (int c = 2; c >= 0; --c) {
            const std::uint32_t e = entry_[(st << 8) | (((x >> (4 * c)) & 15u) << 4) | ((y >> (4 * c)) & 15u)];
            d = (d << 8) | (e & 255u);
            st = e >> 8;
        }
        return d;
    }

private:
    std::array<std::uint16_t, 1024> entry_{};
};

// Sorts (key << 32 | index) on the key's low `bits` bits (stable LSD radix passes of a byte
// each: the Hilbert order's 24 bits in three, the BRIO's 28 in four; the index bits are in
// order already) and returns the indices.
Array<std::uint32_t> sort_keys(Array<std::uint64_t>& keys, int bits) {
    Array<std::uint64_t> tmp;
    assign_huge(tmp, keys.size(), std::uint64_t{0});
    std::array<size_t, 257> count{};
    for (int shift = 32; shift < 32 + bits; shift += 8) {
        count.fill(0);
        for (const std::uint64_t k : keys) ++count[((k >> shift) & 255u) + 1];
        for (size_t b = 0; b < 256; ++b) count[b + 1] += count[b];
        for (const std::uint64_t k : keys) tmp[count[(k >> shift) & 255u]++] = k;
        keys.swap(tmp);
    }
    Array<std::uint32_t> order;
    assign_huge(order, keys.size(), std::uint32_t{0});
    for (size_t i = 0; i < keys.size(); ++i) order[i] = static_cast<std::uint32_t>(keys[i]);
    return order;
}

// (Hilbert index << 32 | i) for every point, plus `round(i) << 56`.
template <class Round>
Array<std::uint64_t> hilbert_keys(std::span<const Vec2> pts, Round round) {
    static const HilbertTable hilbert;
    Box box;
    for (const Vec2& p : pts) box.add(p);
    const double w = std::fmax(box.hi.x - box.lo.x, box.hi.y - box.lo.y);
    const double scale = w > 0.0 ? 4095.0 / w : 0.0;
    Array<std::uint64_t> keys;
    assign_huge(keys, pts.size(), std::uint64_t{0});
    for (size_t i = 0; i < pts.size(); ++i) {
        const auto hx = static_cast<std::uint32_t>((pts[i].x - box.lo.x) * scale);
        const auto hy = static_cast<std::uint32_t>((pts[i].y - box.lo.y) * scale);
        const std::uint64_t key = (static_cast<std::uint64_t>(round(i)) << 24) |
                                  hilbert.index(std::min(hx, 4095u), std::min(hy, 4095u));
        keys[i] = (key << 32) | i;
    }
    return keys;
}

}  // namespace

Array<std::uint32_t> hilbert_order(std::span<const Vec2> pts) {
    Array<std::uint64_t> keys = hilbert_keys(pts, [](size_t) { return 0u; });
    return sort_keys(keys, 24);
}

Array<std::uint32_t> brio_order(std::span<const Vec2> pts) {
    std::uint32_t last = 0;  // index of the last round
    for (size_t m = pts.size(); m > 8 * 64 && last < 15; m /= 8) ++last;
    Array<std::uint64_t> keys = hilbert_keys(pts, [last](size_t i) {
        // A 64-bit mix of the index (splitmix64's finaliser); three bits per round.
        std::uint64_t h = (i + 1) * 0x9E3779B97F4A7C15ull;
        h = (h ^ (h >> 30)) * 0xBF58476D1CE4E5B9ull;
        h = (h ^ (h >> 27)) * 0x94D049BB133111EBull;
        h ^= h >> 31;
        std::uint32_t round = last;
        while (round > 0 && (h & 7u) == 0) {
            --round;
            h >>= 3;
        }
        return round;
    });
    return sort_keys(keys, 28);
}

}  // namespace meshd::core::detail
