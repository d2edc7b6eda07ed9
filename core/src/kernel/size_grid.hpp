#pragma once
// Hashed grids by size class: the local queries of the interior's advancing front and of the
// advancing-front triangulator, and the crossing search of kernel/crossings.cpp.
//
// An object of size s belongs to class k = floor(log2(L / s)) (L: the domain extent), so
// c_k = L 2^-k is in [s, 2s). The grid of class k has cells of 2 c_k (or as many c_k as its
// user asks). Points and segments are entered once, in the grid of their class; a query
// from a place of size s looks in the grids of a few classes around its own (see the users),
// where objects of comparable size are found within one or two cells. Objects much finer or
// coarser than the query are not seen: with densities that change by less than a factor 4
// over one element this is exact, and otherwise the proximity and crossing tests err on the
// permissive side.

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "meshd/core/vec2.hpp"
#include "kernel/memory.hpp"

namespace meshd::core::detail {

/// Chains of items by grid cell (size class k, column x, row y). The cells are kept in
/// blocks of 4 x 4 that share one slot of an open-addressing hash map and one cache line of
/// chain heads, so a query over a few neighbouring cells costs one or two hash probes
/// rather than one per cell. An item is stored in its chain entry (for the interior's
/// points: the coordinates and size, so a proximity test reads one entry and nothing else).
///
/// With kRetiring, each cell has a second chain, of retired items: a query that no longer
/// needs an item moves it there as it passes (any_in_retiring), and only lookups that ask
/// for every item (any_in_all) walk it. The retired heads sit in the block's second cache
/// line, which the other queries never read.
///
/// Each block also has two masks of its 16 cells (bit 4 (x & 3) + (y & 3)): those whose chain
/// of items holds any, and those that ever held one. A query ANDs the mask of its rectangle
/// with them and visits the cells of the bits left, in the order of the bits, which is the
/// order of the loops over x, then y, that it replaces: most cells of a query's rectangle are
/// empty, and a query looked at each (on the load run's square, the loops over cells were
/// two thirds of the grids' instructions in the crossing test).
///
/// With a Summary type other than NoSummary, each block also keeps one Summary, which the
/// user updates as it enters items (push_summarised) and which a query can read to pass over
/// the whole block (any_in_retiring_unless).
struct NoSummary {};

template <class Item, bool kRetiring = false, class Summary = NoSummary>
class CellGrid {
    static constexpr bool kSummaries = !std::is_same_v<Summary, NoSummary>;

public:
    static constexpr std::uint32_t kNone = UINT32_MAX;

    CellGrid() { rehash(1024); }

    /// Room for this many entries without growing. (On the benchmark case a block of the
    /// interior's grids holds about 100 entries of points and 290 of segments; room is made for
    /// blocks of 32.)
    void reserve(size_t entries) {
        reserve_huge(entries_, entries);
        reserve_huge(blocks_, entries / 32);
        reserve_huge(masks_, entries / 32);
        if constexpr (kSummaries) reserve_huge(summaries_, entries / 32);
        if (2 * (entries / 32) > slots_.size()) rehash(std::bit_ceil(2 * (entries / 32)));
    }

    /// Whether any item of class k was ever entered (then a query of class k can end before it
    /// computes its cells: most classes around a query's own are empty where the sizes vary
    /// gently).
    bool has_class(int k) const { return (classes_ & class_bit(k)) != 0; }
    /// Whether no item was ever entered.
    bool empty() const { return classes_ == 0; }

    std::uint32_t head(int k, std::int64_t x, std::int64_t y) const {
        const std::uint32_t b = find_block(k, x, y);
        return b == kNone ? kNone : blocks_[b].head[within(x, y)];
    }
    void push(int k, std::int64_t x, std::int64_t y, const Item& item) { push_into_block(k, x, y, item); }
    /// push(), then update(summary) on the summary of the item's block.
    template <class Update>
    void push_summarised(int k, std::int64_t x, std::int64_t y, const Item& item, Update&& update) {
        static_assert(kSummaries);
        update(summaries_[push_into_block(k, x, y, item)]);
    }
    /// update(summary) on the summary of every existing block of class k that holds a cell of
    /// [x0, x1] x [y0, y1].
    template <class Update>
    void update_summaries(int k, std::int64_t x0, std::int64_t x1, std::int64_t y0, std::int64_t y1, Update&& update) {
        static_assert(kSummaries);
        if (!(classes_ & class_bit(k))) return;
        for (std::int64_t bx = x0 >> 2; bx <= x1 >> 2; ++bx)
            for (std::int64_t by = y0 >> 2; by <= y1 >> 2; ++by)
                if (const std::uint32_t b = find_block(k, bx << 2, by << 2); b != kNone) update(summaries_[b]);
    }
    std::uint32_t next(std::uint32_t entry) const { return entries_[entry].next; }
    const Item& item(std::uint32_t entry) const { return entries_[entry].item; }

    /// Calls visit(item) for the items of the cells [x0, x1] x [y0, y1] of class k, block by
    /// block, until it returns true; returns whether it did. Retired items are not visited.
    template <class Visit>
    bool any_in(int k, std::int64_t x0, std::int64_t x1, std::int64_t y0, std::int64_t y1, Visit&& visit) const {
        return any_entry_in(k, x0, x1, y0, y1, [&](const Item& item, std::uint32_t) { return visit(item); });
    }
    /// any_in(), visit(item, entry) also given the item's entry: the count of pushes before it
    /// (a user that pushes each of its objects once, in the order of their ids, need not store
    /// the id in the item).
    template <class Visit>
    bool any_entry_in(int k, std::int64_t x0, std::int64_t x1, std::int64_t y0, std::int64_t y1, Visit&& visit) const {
        return for_cells(*this, k, x0, x1, y0, y1, &Masks::live, [&](std::uint32_t b, size_t c) {
            for (std::uint32_t e = blocks_[b].head[c]; e != kNone; e = entries_[e].next)
                if (visit(entries_[e].item, e)) return true;
            return false;
        });
    }

    /// any_in(), but an item for which retire(item) is true is first moved to its cell's
    /// retired chain and not visited. retire() must stay true for an item once it is.
    template <class Retire, class Visit>
    bool any_in_retiring(int k, std::int64_t x0, std::int64_t x1, std::int64_t y0, std::int64_t y1, Retire&& retire,
                         Visit&& visit) {
        static_assert(kRetiring);
        return for_cells(*this, k, x0, x1, y0, y1, &Masks::live,
                         [&](std::uint32_t b, size_t c) { return retiring_cell(b, c, retire, visit); });
    }

    /// any_in_retiring(), passing over every block for which skip(its summary) is true.
    template <class Skip, class Retire, class Visit>
    bool any_in_retiring_unless(int k, std::int64_t x0, std::int64_t x1, std::int64_t y0, std::int64_t y1, Skip&& skip,
                                Retire&& retire, Visit&& visit) {
        static_assert(kRetiring && kSummaries);
        return for_cells(
            *this, k, x0, x1, y0, y1, &Masks::live,
            [&](std::uint32_t b, size_t c) { return retiring_cell(b, c, retire, visit); },
            [&](std::uint32_t b) { return !skip(static_cast<const Summary&>(summaries_[b])); });
    }

    /// any_in() over the retired items as well.
    template <class Visit>
    bool any_in_all(int k, std::int64_t x0, std::int64_t x1, std::int64_t y0, std::int64_t y1, Visit&& visit) const {
        static_assert(kRetiring);
        return for_cells(*this, k, x0, x1, y0, y1, &Masks::ever, [&](std::uint32_t b, size_t c) {
            const Block& blk = blocks_[b];
            for (const std::uint32_t first : {blk.head[c], blk.retired[c]})
                for (std::uint32_t e = first; e != kNone; e = entries_[e].next)
                    if (visit(entries_[e].item)) return true;
            return false;
        });
    }

private:
    // push(); returns the item's block.
    std::uint32_t push_into_block(int k, std::int64_t x, std::int64_t y, const Item& item) {
        classes_ |= class_bit(k);
        const std::uint32_t b = block(k, x, y);
        const size_t c = within(x, y);
        std::uint32_t& h = blocks_[b].head[c];
        entries_.push_back({item, h});
        h = static_cast<std::uint32_t>(entries_.size() - 1);
        masks_[b].live |= static_cast<std::uint16_t>(1u << c);
        masks_[b].ever |= static_cast<std::uint16_t>(1u << c);
        return b;
    }

    // The cell c of block b for any_in_retiring: retires what `retire` says, visits the rest.
    template <class Retire, class Visit>
    bool retiring_cell(std::uint32_t b, size_t c, Retire& retire, Visit& visit) {
        Block& blk = blocks_[b];
        std::uint32_t* link = &blk.head[c];
        for (std::uint32_t e = *link; e != kNone; e = *link) {
            Entry& entry = entries_[e];
            if (retire(entry.item)) {
                *link = entry.next;
                entry.next = blk.retired[c];
                blk.retired[c] = e;
                continue;
            }
            if (visit(entry.item)) return true;
            link = &entry.next;
        }
        if (blk.head[c] == kNone) masks_[b].live &= static_cast<std::uint16_t>(~(1u << c));
        return false;
    }

    struct NoChains {};
    struct alignas(64) Block {
        std::array<std::uint32_t, 16> head;
        [[no_unique_address]] std::conditional_t<kRetiring, std::array<std::uint32_t, 16>, NoChains> retired;
    };

    // The cells of a block that hold items (live) or ever held one (ever), by bit
    // 4 (x & 3) + (y & 3).
    struct Masks {
        std::uint16_t live = 0, ever = 0;
    };

    // Calls cell(block id, index within it) for the cells [x0, x1] x [y0, y1] of class k whose
    // bit is set in the block's mask `which` (block by block, within a block along x, then y),
    // until it returns true; returns whether it did. (Self: the grid, const or not, so that
    // the blocks are as writable as the grid.)
    // `keep(block id)`, when given, decides whether a block's cells are visited at all.
    struct EveryBlock {
        bool operator()(std::uint32_t) const { return true; }
    };
    template <class Self, class Cell, class Keep = EveryBlock>
    static bool for_cells(Self& self, int k, std::int64_t x0, std::int64_t x1, std::int64_t y0, std::int64_t y1,
                          std::uint16_t Masks::*which, Cell&& cell, Keep&& keep = Keep{}) {
        if (!(self.classes_ & class_bit(k))) return false;  // no item of this class anywhere
        for (std::int64_t bx = x0 >> 2; bx <= x1 >> 2; ++bx) {
            // The columns x0..x1 within this block: 4 bits each.
            const auto xa = static_cast<unsigned>(std::max(x0, bx << 2) & 3);
            const auto xb = static_cast<unsigned>(std::min(x1, (bx << 2) + 3) & 3);
            const unsigned columns = ((1u << (4 * (xb - xa + 1))) - 1u) << (4 * xa);
            for (std::int64_t by = y0 >> 2; by <= y1 >> 2; ++by) {
                const std::uint32_t b = self.find_block(k, bx << 2, by << 2);
                if (b == kNone) continue;
                // The rows y0..y1 within this block, in every column.
                const auto ya = static_cast<unsigned>(std::max(y0, by << 2) & 3);
                const auto yb = static_cast<unsigned>(std::min(y1, (by << 2) + 3) & 3);
                const unsigned rows = (((1u << (yb - ya + 1)) - 1u) << ya) * 0x1111u;
                const unsigned cells = columns & rows & self.masks_[b].*which;
                if (cells == 0 || !keep(b)) continue;  // only a block with cells to visit asks keep
                for (unsigned m = cells; m != 0; m &= m - 1)
                    if (cell(b, static_cast<size_t>(std::countr_zero(m)))) return true;
            }
        }
        return false;
    }
    struct Slot {
        std::uint64_t key;
        std::uint32_t block;  // kNone: empty
    };
    struct Entry {
        Item item;
        std::uint32_t next;
    };

    static std::uint64_t block_key(int k, std::int64_t x, std::int64_t y) {
        constexpr std::uint64_t mask = (std::uint64_t{1} << 28) - 1;
        return (static_cast<std::uint64_t>(k) << 56) | ((static_cast<std::uint64_t>(x >> 2) & mask) << 28) |
               (static_cast<std::uint64_t>(y >> 2) & mask);
    }
    // The bit of class k in classes_ (classes beyond 63 share the last bit).
    static std::uint64_t class_bit(int k) { return std::uint64_t{1} << std::clamp(k, 0, 63); }
    static size_t within(std::int64_t x, std::int64_t y) { return static_cast<size_t>((x & 3) << 2 | (y & 3)); }
    size_t slot_of(std::uint64_t key) const {
        const size_t mask = slots_.size() - 1;
        size_t s = static_cast<size_t>((key * 0x9E3779B97F4A7C15ull) >> shift_);
        while (slots_[s].block != kNone && slots_[s].key != key) s = (s + 1) & mask;
        return s;
    }
    std::uint32_t find_block(int k, std::int64_t x, std::int64_t y) const {
        return slots_[slot_of(block_key(k, x, y))].block;
    }
    std::uint32_t block(int k, std::int64_t x, std::int64_t y) {
        const std::uint64_t key = block_key(k, x, y);
        size_t s = slot_of(key);
        if (slots_[s].block != kNone) return slots_[s].block;
        if (2 * (blocks_.size() + 1) > slots_.size()) {
            rehash(2 * slots_.size());
            s = slot_of(key);
        }
        Block fresh;
        fresh.head.fill(kNone);
        if constexpr (kRetiring) fresh.retired.fill(kNone);
        blocks_.push_back(fresh);
        masks_.push_back(Masks{});
        if constexpr (kSummaries) summaries_.push_back(Summary{});
        slots_[s] = {key, static_cast<std::uint32_t>(blocks_.size() - 1)};
        return slots_[s].block;
    }
    void rehash(size_t n) {
        Array<Slot> old = std::move(slots_);
        slots_.assign(n, Slot{0, kNone});
        shift_ = 64 - std::countr_zero(n);
        for (const Slot& o : old)
            if (o.block != kNone) slots_[slot_of(o.key)] = o;
    }

    Array<Slot> slots_;
    int shift_ = 64;
    std::uint64_t classes_ = 0;  // bit k: the grid holds an item of class k (a query of any
                                 // other class ends before its first hash probe)
    Array<Block> blocks_;
    Array<Masks> masks_;  // by block
    Array<Entry> entries_;
    struct NoSummaries {};
    [[no_unique_address]] std::conditional_t<kSummaries, Array<Summary>, NoSummaries> summaries_;  // by block
};

using CellMap = CellGrid<std::uint32_t>;

class SizeClasses {
public:
    /// `cells`: the cells' width in c_k (2 unless told).
    SizeClasses(Vec2 origin, double extent, double cells = 2.0) : origin_(origin), extent_(extent) {
        for (int k = 0; k <= kMax; ++k) {
            cell_[static_cast<size_t>(k)] = cells * std::ldexp(extent, -k);
            inv_cell_[static_cast<size_t>(k)] = 1.0 / cell_[static_cast<size_t>(k)];
        }
    }
    int class_of(double size) const {
        if (!(size > 0.0)) return kMax;
        // floor(log2(extent / size)), exactly: the exponent of a normal double (std::ilogb,
        // a call into the maths library, for the rest).
        const double r = extent_ / size;
        const auto biased = static_cast<int>((std::bit_cast<std::uint64_t>(r) >> 52) & 0x7ff);
        const int k = biased != 0 && biased != 0x7ff ? biased - 1023 : std::ilogb(r);
        return k < 1 ? 1 : (k > kMax ? kMax : k);
    }
    double cell(int k) const { return cell_[static_cast<size_t>(k)]; }
    Vec2 origin() const { return origin_; }
    /// The cell of v; saturated at +-2^62 (and 0 for NaN), so that no value converts out of
    /// range. Callers keep their queries inside the grid's extent.
    std::int64_t index(double v, double o, int k) const {
        const double f = (v - o) * inv_cell_[static_cast<size_t>(k)];
        constexpr double kLimit = 0x1p62;
        if (!(f > -kLimit)) return f != f ? 0 : -static_cast<std::int64_t>(kLimit);
        if (!(f < kLimit)) return static_cast<std::int64_t>(kLimit);
        // floor(f) by truncation (std::floor is a call into the maths library without SSE4.1).
        const auto i = static_cast<std::int64_t>(f);
        return static_cast<double>(i) > f ? i - 1 : i;
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
