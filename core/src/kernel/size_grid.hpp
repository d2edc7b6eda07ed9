#pragma once
// Hashed grids by size class: the local queries of the interior's advancing front and of the
// advancing-front triangulator, and the crossing search of kernel/crossings.cpp.
//
// An object of size s belongs to class k = floor(log2(L / s)) (L: the domain extent), so
// c_k = L 2^-k is in [s, 2s). The grid of class k has cells of 2 c_k. A point is entered
// in the grids of its class and of the two neighbouring classes; a query from a place of
// size s looks in a few grids around its own class (see the users), where points of
// comparable size are found within one or two cells. Segments are entered once, in their class; a segment
// query looks in three classes around its own. Objects much finer or coarser than the
// query are not seen: with densities that change by less than a factor 4 over one element
// this is exact, and otherwise the proximity and crossing tests err on the permissive side.

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "meshd/core/vec2.hpp"

namespace meshd::core::detail {

/// Open-addressing map from a 64-bit cell key to the head of a chain of entries.
class CellMap {
public:
    static constexpr std::uint32_t kNone = UINT32_MAX;

    CellMap() { resize(1024); }

    std::uint32_t head(std::uint64_t key) const {
        const size_t s = find(key);
        return heads_[s];
    }
    void push(std::uint64_t key, std::uint32_t item) {
        if (2 * (used_ + 1) > keys_.size()) resize(2 * keys_.size());
        size_t s = find(key);
        if (heads_[s] == kNone) {
            keys_[s] = key;
            ++used_;
        }
        next_.push_back(heads_[s]);
        item_.push_back(item);
        heads_[s] = static_cast<std::uint32_t>(item_.size() - 1);
    }
    std::uint32_t next(std::uint32_t entry) const { return next_[entry]; }
    std::uint32_t item(std::uint32_t entry) const { return item_[entry]; }

private:
    size_t find(std::uint64_t key) const {
        const size_t mask = keys_.size() - 1;
        size_t s = static_cast<size_t>((key * 0x9E3779B97F4A7C15ull) >> 17) & mask;
        while (heads_[s] != kNone && keys_[s] != key) s = (s + 1) & mask;
        return s;
    }
    void resize(size_t n) {
        std::vector<std::uint64_t> old_keys = std::move(keys_);
        std::vector<std::uint32_t> old_heads = std::move(heads_);
        keys_.assign(n, 0);
        heads_.assign(n, kNone);
        for (size_t i = 0; i < old_keys.size(); ++i) {
            if (old_heads[i] == kNone) continue;
            const size_t s = find(old_keys[i]);
            keys_[s] = old_keys[i];
            heads_[s] = old_heads[i];
        }
    }

    std::vector<std::uint64_t> keys_;
    std::vector<std::uint32_t> heads_;
    std::vector<std::uint32_t> next_, item_;
    size_t used_ = 0;
};

class SizeClasses {
public:
    SizeClasses(Vec2 origin, double extent) : origin_(origin), extent_(extent) {
        for (int k = 0; k <= kMax; ++k) {
            cell_[static_cast<size_t>(k)] = 2.0 * std::ldexp(extent, -k);
            inv_cell_[static_cast<size_t>(k)] = 1.0 / cell_[static_cast<size_t>(k)];
        }
    }
    int class_of(double size) const {
        if (!(size > 0.0)) return kMax;
        const int k = std::ilogb(extent_ / size);  // floor(log2(extent / size)), exactly
        return k < 1 ? 1 : (k > kMax ? kMax : k);
    }
    double cell(int k) const { return cell_[static_cast<size_t>(k)]; }
    Vec2 origin() const { return origin_; }
    /// The cell of v; saturated at +-2^62 (and 0 for NaN), so that no value converts out of
    /// range. Callers keep their queries inside the grid's extent.
    std::int64_t index(double v, double o, int k) const {
        const double f = std::floor((v - o) * inv_cell_[static_cast<size_t>(k)]);
        constexpr double kLimit = 0x1p62;
        if (!(f > -kLimit)) return f != f ? 0 : -static_cast<std::int64_t>(kLimit);
        if (!(f < kLimit)) return static_cast<std::int64_t>(kLimit);
        return static_cast<std::int64_t>(f);
    }
    std::int64_t ix(double x, int k) const { return index(x, origin_.x, k); }
    std::int64_t iy(double y, int k) const { return index(y, origin_.y, k); }
    static std::uint64_t key(int k, std::int64_t x, std::int64_t y) {
        constexpr std::uint64_t mask = (std::uint64_t{1} << 28) - 1;
        return (static_cast<std::uint64_t>(k) << 56) | ((static_cast<std::uint64_t>(x) & mask) << 28) |
               (static_cast<std::uint64_t>(y) & mask);
    }
    static constexpr int kMax = 60;

private:
    Vec2 origin_;
    double extent_;
    std::array<double, kMax + 1> cell_{}, inv_cell_{};
};

}  // namespace meshd::core::detail
