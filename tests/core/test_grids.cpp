// The size-class grids' cell map (blocks of 4 x 4 cells behind one hash slot) against a plain
// list, the segment grid's pair searches against a test of every pair, and the request for
// huge pages under large arrays.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

#include "kernel/crossings.hpp"
#include "kernel/memory.hpp"
#include "kernel/predicates.hpp"
#include "kernel/size_grid.hpp"

using namespace meshd::core;
using detail::CellGrid;

namespace {

struct Placed {
    int k;
    std::int64_t x, y;
    std::uint32_t id;
};

std::vector<std::uint32_t> brute(const std::vector<Placed>& all, int k, std::int64_t x0, std::int64_t x1,
                                 std::int64_t y0, std::int64_t y1) {
    std::vector<std::uint32_t> out;
    for (const Placed& p : all)
        if (p.k == k && p.x >= x0 && p.x <= x1 && p.y >= y0 && p.y <= y1) out.push_back(p.id);
    std::sort(out.begin(), out.end());
    return out;
}

}  // namespace

TEST(CellGrid, EveryBoxQuerySeesExactlyTheItemsOfItsCells) {
    std::mt19937_64 rng(7);
    std::uniform_int_distribution<std::int64_t> coord(-40, 40);  // across block edges and zero
    std::uniform_int_distribution<int> cls(1, 4);
    CellGrid<std::uint32_t> grid;
    std::vector<Placed> all;
    // Enough items to make the map grow several times (blocks and slots).
    for (std::uint32_t id = 0; id < 20000; ++id) {
        const Placed p{cls(rng), coord(rng), coord(rng), id};
        grid.push(p.k, p.x, p.y, p.id);
        all.push_back(p);
    }
    std::uniform_int_distribution<std::int64_t> width(0, 9);
    for (int q = 0; q < 2000; ++q) {
        const int k = cls(rng);
        const std::int64_t x0 = coord(rng), y0 = coord(rng);
        const std::int64_t x1 = x0 + width(rng), y1 = y0 + width(rng);
        std::vector<std::uint32_t> seen;
        EXPECT_FALSE(grid.any_in(k, x0, x1, y0, y1, [&](std::uint32_t id) {
            seen.push_back(id);
            return false;
        }));
        std::sort(seen.begin(), seen.end());
        ASSERT_EQ(seen, brute(all, k, x0, x1, y0, y1)) << "class " << k << " [" << x0 << ", " << x1 << "] x [" << y0 << ", " << y1 << "]";
    }
    // One cell through its chain.
    const Placed& p = all[1234];
    std::vector<std::uint32_t> chain;
    for (auto e = grid.head(p.k, p.x, p.y); e != CellGrid<std::uint32_t>::kNone; e = grid.next(e))
        chain.push_back(grid.item(e));
    std::sort(chain.begin(), chain.end());
    EXPECT_EQ(chain, brute(all, p.k, p.x, p.x, p.y, p.y));
    // A cell never written, in a block never made.
    EXPECT_EQ(grid.head(9, 1000, 1000), CellGrid<std::uint32_t>::kNone);
}

TEST(CellGrid, AQueryStopsAtTheFirstItemItsVisitorAccepts) {
    CellGrid<std::uint32_t> grid;
    grid.reserve(64);
    for (std::uint32_t id = 0; id < 10; ++id) grid.push(3, id % 5, 0, id);
    int visits = 0;
    EXPECT_TRUE(grid.any_in(3, 0, 4, 0, 0, [&](std::uint32_t) { return ++visits == 3; }));
    EXPECT_EQ(visits, 3);
    EXPECT_FALSE(grid.any_in(3, 5, 8, 0, 0, [](std::uint32_t) { return true; }));
}

// The class of a size is floor(log2(extent / size)) within [1, kMax], the maths library's
// ilogb being the oracle, for sizes from subnormal to far above the extent.
TEST(SizeClasses, TheClassOfASizeIsTheFloorOfTheLogOfExtentOverSize) {
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> mantissa(1.0, 2.0);
    std::uniform_int_distribution<int> exponent(-1074, 1023);
    for (const double extent : {1.0, 3.7e-5, 6.1e7}) {
        const detail::SizeClasses classes(Vec2{0, 0}, extent);
        auto want = [&](double size) { return std::clamp(std::ilogb(extent / size), 1, detail::SizeClasses::kMax); };
        for (int i = 0; i < 20000; ++i) {
            const double size = std::ldexp(mantissa(rng), exponent(rng));
            ASSERT_EQ(classes.class_of(size), want(size)) << "size " << size << " extent " << extent;
        }
        for (const double size : {extent, extent / 2, std::nextafter(extent / 2, 0.0), extent * 0x1p-60,
                                  extent * 0x1p-61, 4.9e-324, 1e300})
            EXPECT_EQ(classes.class_of(size), want(size)) << size;
        EXPECT_EQ(classes.class_of(0.0), detail::SizeClasses::kMax);
        EXPECT_EQ(classes.class_of(-1.0), detail::SizeClasses::kMax);
        EXPECT_EQ(classes.class_of(std::nan("")), detail::SizeClasses::kMax);
    }
}

// Items retired by a query as it passes are seen by no later box query, nor by the query
// that retires them, and still by any_in_all; the others stay in their chains, and a query
// that stops early retires only what it passed.
TEST(CellGrid, RetiredItemsLeaveTheBoxQueriesAndStayForTheFullLookup) {
    std::mt19937_64 rng(5);
    std::uniform_int_distribution<std::int64_t> coord(-12, 12);
    CellGrid<std::uint32_t, true> grid;
    std::vector<Placed> all;
    for (std::uint32_t id = 0; id < 6000; ++id) {
        const Placed p{2, coord(rng), coord(rng), id};
        grid.push(p.k, p.x, p.y, p.id);
        all.push_back(p);
    }
    auto retire = [](std::uint32_t id) { return id % 3 == 0; };
    auto live = [&](std::vector<std::uint32_t> ids) {
        ids.erase(std::remove_if(ids.begin(), ids.end(), retire), ids.end());
        return ids;
    };
    auto collect = [&](auto&& query) {
        std::vector<std::uint32_t> seen;
        query([&](std::uint32_t id) {
            seen.push_back(id);
            return false;
        });
        std::sort(seen.begin(), seen.end());
        return seen;
    };
    // A query that stops at the first item it accepts retires only the items before it.
    std::uint32_t stopped_at = 0;
    std::vector<std::uint32_t> passed;
    EXPECT_TRUE(grid.any_in_retiring(2, 0, 0, 0, 0, [&](std::uint32_t id) {
        if (retire(id)) passed.push_back(id);
        return retire(id);
    }, [&](std::uint32_t id) {
        stopped_at = id;
        return true;
    }));
    EXPECT_FALSE(retire(stopped_at));
    const auto cell0 = brute(all, 2, 0, 0, 0, 0);
    const auto still = collect([&](auto v) { return grid.any_in(2, 0, 0, 0, 0, v); });
    for (const std::uint32_t id : cell0) {
        const bool gone = std::find(passed.begin(), passed.end(), id) != passed.end();
        EXPECT_EQ(std::binary_search(still.begin(), still.end(), id), !gone) << id;
    }
    // A retiring query over everything visits exactly the live items ...
    EXPECT_EQ(collect([&](auto v) { return grid.any_in_retiring(2, -12, 12, -12, 12, retire, v); }),
              live(brute(all, 2, -12, 12, -12, 12)));
    // ... and from then on every box query sees only those, and any_in_all sees all.
    std::uniform_int_distribution<std::int64_t> width(0, 6);
    for (int q = 0; q < 500; ++q) {
        const std::int64_t x0 = coord(rng), y0 = coord(rng), x1 = x0 + width(rng), y1 = y0 + width(rng);
        const auto want = brute(all, 2, x0, x1, y0, y1);
        ASSERT_EQ(collect([&](auto v) { return grid.any_in(2, x0, x1, y0, y1, v); }), live(want));
        ASSERT_EQ(collect([&](auto v) { return grid.any_in_all(2, x0, x1, y0, y1, v); }), want);
    }
}

// Per-block summaries (the interior's block-by-block crossing proof): each block's summary
// is what push_summarised folded into it, by the block of 4 x 4 cells an item's cell lies in;
// a query passes over exactly the blocks `skip` names, visiting the others' live items as
// any_in_retiring would; update_summaries reaches every block that meets its rectangle.
TEST(CellGrid, SummariesFollowTheBlocksAndLetAQueryPassOverThem) {
    struct Sum {
        std::uint32_t count = 0, largest = 0;
    };
    std::mt19937_64 rng(17);
    std::uniform_int_distribution<std::int64_t> coord(-20, 20);
    CellGrid<std::uint32_t, true, Sum> grid;
    std::vector<Placed> all;
    for (std::uint32_t id = 0; id < 3000; ++id) {
        const Placed p{4, coord(rng), coord(rng), id};
        grid.push_summarised(p.k, p.x, p.y, p.id, [&](Sum& s) {
            ++s.count;
            s.largest = std::max(s.largest, id);
        });
        all.push_back(p);
    }
    // The summary of the block holding (x, y), from the items themselves.
    auto block_of = [](std::int64_t v) { return v >> 2; };
    auto expected = [&](std::int64_t bx, std::int64_t by) {
        Sum s;
        for (const Placed& p : all)
            if (block_of(p.x) == bx && block_of(p.y) == by) {
                ++s.count;
                s.largest = std::max(s.largest, p.id);
            }
        return s;
    };
    auto retire = [](std::uint32_t id) { return id % 5 == 0; };
    std::uniform_int_distribution<std::int64_t> width(0, 9);
    for (int q = 0; q < 300; ++q) {
        const std::int64_t x0 = coord(rng), y0 = coord(rng), x1 = x0 + width(rng), y1 = y0 + width(rng);
        // Pass over the blocks whose largest id is odd; each summary asked must be its block's.
        std::vector<std::uint32_t> seen;
        bool summaries_right = true;
        grid.any_in_retiring_unless(
            4, x0, x1, y0, y1,
            [&](const Sum& s) {
                bool found = false;
                for (std::int64_t bx = block_of(x0); bx <= block_of(x1); ++bx)
                    for (std::int64_t by = block_of(y0); by <= block_of(y1); ++by) {
                        const Sum e = expected(bx, by);
                        found = found || (e.count == s.count && e.largest == s.largest);
                    }
                summaries_right = summaries_right && found;
                return s.largest % 2 == 1;
            },
            retire,
            [&](std::uint32_t id) {
                seen.push_back(id);
                return false;
            });
        EXPECT_TRUE(summaries_right) << q;
        std::vector<std::uint32_t> want;
        for (const std::uint32_t id : brute(all, 4, x0, x1, y0, y1)) {
            const Placed& p = all[id];
            if (!retire(id) && expected(block_of(p.x), block_of(p.y)).largest % 2 == 0) want.push_back(id);
        }
        std::sort(seen.begin(), seen.end());
        ASSERT_EQ(seen, want) << q;
    }
    // Marking every block that meets a rectangle reaches those and no other.
    grid.update_summaries(4, -3, 5, 2, 9, [](Sum& s) { s.largest = 1000001; });
    std::uint32_t marked = 0, blocks = 0;
    grid.any_in_retiring_unless(
        4, -20, 20, -20, 20,
        [&](const Sum& s) {
            ++blocks;
            marked += s.largest == 1000001 ? 1 : 0;
            return true;
        },
        retire, [](std::uint32_t) { return false; });
    // Blocks -1..1 along x and 0..2 along y, all holding items (3,000 items over 11 x 11 blocks).
    EXPECT_EQ(marked, 9u);
    EXPECT_GT(blocks, marked);
}

// The order of a query's visits, which the interior's proximity test depends on (the first
// offending point decides where the front closes): block by block (4 x 4 cells, by column
// block, then row block), within a block cell by cell along x, then y, and within a cell the
// latest item first. Also after retirement has emptied cells and new items went into them.
TEST(CellGrid, AQueryVisitsBlockByBlockThenAlongXThenYLatestFirst) {
    std::mt19937_64 rng(11);
    std::uniform_int_distribution<std::int64_t> coord(-10, 10);
    CellGrid<std::uint32_t, true> grid;
    std::vector<Placed> all;
    auto push = [&](std::uint32_t id) {
        const Placed p{3, coord(rng), coord(rng), id};
        grid.push(p.k, p.x, p.y, p.id);
        all.push_back(p);
    };
    std::vector<bool> retired;
    // The expected sequence, from the rule above.
    auto expected = [&](std::int64_t x0, std::int64_t x1, std::int64_t y0, std::int64_t y1) {
        std::vector<Placed> in;
        for (const Placed& p : all)
            if (p.x >= x0 && p.x <= x1 && p.y >= y0 && p.y <= y1 && !retired[p.id]) in.push_back(p);
        auto key = [](const Placed& p) { return std::tuple(p.x >> 2, p.y >> 2, p.x, p.y, -static_cast<std::int64_t>(p.id)); };
        std::sort(in.begin(), in.end(), [&](const Placed& a, const Placed& b) { return key(a) < key(b); });
        std::vector<std::uint32_t> ids;
        for (const Placed& p : in) ids.push_back(p.id);
        return ids;
    };
    std::uniform_int_distribution<std::int64_t> width(0, 9);
    auto check = [&](int queries) {
        for (int q = 0; q < queries; ++q) {
            const std::int64_t x0 = coord(rng), y0 = coord(rng), x1 = x0 + width(rng), y1 = y0 + width(rng);
            std::vector<std::uint32_t> seen;
            grid.any_in(3, x0, x1, y0, y1, [&](std::uint32_t id) {
                seen.push_back(id);
                return false;
            });
            ASSERT_EQ(seen, expected(x0, x1, y0, y1)) << "[" << x0 << ", " << x1 << "] x [" << y0 << ", " << y1 << "]";
        }
    };
    for (std::uint32_t id = 0; id < 300; ++id) push(id);
    retired.assign(300, false);
    check(300);
    // Every item of the left half retired by one query that passes them all: those cells are
    // empty now ...
    for (const Placed& p : all) retired[p.id] = p.x < 0;
    grid.any_in_retiring(3, -10, -1, -10, 10, [&](std::uint32_t id) { return retired[id]; },
                         [](std::uint32_t) { return false; });
    check(300);
    // ... and seen again once items go into them.
    for (std::uint32_t id = 300; id < 500; ++id) {
        push(id);
        retired.push_back(false);
    }
    check(300);
}

#if defined(__linux__)
// The line of /proc/self/smaps starting with `field` for the mapping that holds address a.
static std::string smaps_field_at(std::uintptr_t a, const std::string& field) {
    std::ifstream smaps("/proc/self/smaps");
    std::string line;
    bool inside = false;
    while (std::getline(smaps, line)) {
        std::uintptr_t lo = 0, hi = 0;
        char dash = 0;
        std::istringstream head(line);
        if (head >> std::hex >> lo >> dash >> hi && dash == '-') {
            inside = a >= lo && a < hi;
            continue;
        }
        if (inside && line.rfind(field, 0) == 0) return line;
    }
    return {};
}

// Kibibytes of a smaps line ("Rss:   4096 kB").
static std::size_t smaps_kib(const std::string& line) {
    std::istringstream in(line.substr(line.find(':') + 1));
    std::size_t kib = 0;
    in >> kib;
    return kib;
}

// The VmFlags of the mapping holding address a.
static std::string vm_flags_at(std::uintptr_t a) { return smaps_field_at(a, "VmFlags:"); }

// Segments of sizes from 1e-6 to 1 (as a wall's first layers beside its outer ones), many
// sharing an end: each search must give exactly the pairs that a test of every pair gives,
// each once.
TEST(SegmentGrid, BoxOverlapsAndCrossingsAreTheSameAsTestingEveryPair) {
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    detail::SegmentSoup soup;
    for (int i = 0; i < 1500; ++i) {
        const Vec2 a{u(rng), u(rng)};
        const double len = std::pow(10.0, -6.0 * u(rng)), angle = 6.283185307179586 * u(rng);
        soup.points.push_back(a);
        soup.points.push_back(a + len * Vec2{std::cos(angle), std::sin(angle)});
        const auto n = static_cast<std::uint32_t>(soup.points.size());
        soup.segments.push_back({n - 2, n - 1});
        if (i % 3 == 0 && n > 2) soup.segments.push_back({n - 1, n - 3});  // a chain: shared ends
    }
    using Pairs = std::vector<std::pair<std::uint32_t, std::uint32_t>>;
    Pairs boxes, crossings;
    detail::for_each_box_overlap(soup, [&](std::uint32_t i, std::uint32_t j) { boxes.emplace_back(i, j); });
    detail::for_each_crossing(soup, [&](std::uint32_t i, std::uint32_t j) { crossings.emplace_back(i, j); });
    Pairs want_boxes, want_crossings;
    const auto n = static_cast<std::uint32_t>(soup.segments.size());
    for (std::uint32_t i = 0; i < n; ++i)
        for (std::uint32_t j = i + 1; j < n; ++j) {
            const Vec2 a = soup.points[soup.segments[i][0]], b = soup.points[soup.segments[i][1]];
            const Vec2 c = soup.points[soup.segments[j][0]], d = soup.points[soup.segments[j][1]];
            if (std::max(std::min(a.x, b.x), std::min(c.x, d.x)) <= std::min(std::max(a.x, b.x), std::max(c.x, d.x)) &&
                std::max(std::min(a.y, b.y), std::min(c.y, d.y)) <= std::min(std::max(a.y, b.y), std::max(c.y, d.y)))
                want_boxes.emplace_back(i, j);
            const auto& s = soup.segments[i];
            const auto& t = soup.segments[j];
            const bool neighbours = s[0] == t[0] || s[0] == t[1] || s[1] == t[0] || s[1] == t[1];
            if (!neighbours && segments_intersect(a, b, c, d)) want_crossings.emplace_back(i, j);
        }
    std::sort(boxes.begin(), boxes.end());
    std::sort(crossings.begin(), crossings.end());
    EXPECT_GT(want_boxes.size(), 100u);
    EXPECT_GT(want_crossings.size(), 20u);
    EXPECT_EQ(boxes, want_boxes);
    EXPECT_EQ(crossings, want_crossings);  // random chains do not fold back on themselves
}

// The searches over runs of a soup: within one run, the pairs of that run only; between two
// runs, every pair of one segment from each, as testing every such pair finds them, each once.
// The runs are thin layers' columns and rungs (the crowd of long segments over short ones
// that the runs are there for) and random segments over them.
TEST(SegmentGrid, CrossingsWithinAndBetweenRunsAreTheSameAsTestingEveryPair) {
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    detail::SegmentSoup soup;
    auto add = [&](Vec2 a, Vec2 b) {
        soup.points.push_back(a);
        soup.points.push_back(b);
        const auto n = static_cast<std::uint32_t>(soup.points.size());
        soup.segments.push_back({n - 2, n - 1});
    };
    // Run 0: a strip of 300 levels 1e-4 apart leaning at 50 degrees, its two columns as chains
    // (shared ends) and its rungs.
    const Vec2 dir{std::cos(0.87), std::sin(0.87)};
    const auto base = static_cast<std::uint32_t>(soup.points.size());
    for (int l = 0; l <= 300; ++l) {
        soup.points.push_back(Vec2{0.2, 0.2} + 1e-4 * l * dir);
        soup.points.push_back(Vec2{0.35, 0.2} + 1e-4 * l * dir);
    }
    for (std::uint32_t l = 0; l < 300; ++l) {
        soup.segments.push_back({base + 2 * l, base + 2 * l + 2});
        soup.segments.push_back({base + 2 * l + 1, base + 2 * l + 3});
        soup.segments.push_back({base + 2 * l + 2, base + 2 * l + 3});
    }
    const auto strip_end = static_cast<std::uint32_t>(soup.segments.size());
    // Run 1: segments of sizes from 1e-5 to 0.3 over and around it, some sharing the strip's
    // points, some chained among themselves.
    for (int i = 0; i < 400; ++i) {
        const Vec2 a{0.1 + 0.4 * u(rng), 0.1 + 0.4 * u(rng)};
        const double len = 0.3 * std::pow(10.0, -4.5 * u(rng)), angle = 6.283185307179586 * u(rng);
        add(a, a + len * Vec2{std::cos(angle), std::sin(angle)});
        if (i % 5 == 0) soup.segments.back()[0] = base + 2 * static_cast<std::uint32_t>(rng() % 300);
        if (i % 7 == 0 && i > 0) soup.segments.push_back({soup.segments.back()[1], soup.segments[soup.segments.size() - 2][1]});
    }
    const auto end = static_cast<std::uint32_t>(soup.segments.size());
    using Pairs = std::vector<std::pair<std::uint32_t, std::uint32_t>>;
    auto crossing = [&](std::uint32_t i, std::uint32_t j) {
        const auto& s = soup.segments[i];
        const auto& t = soup.segments[j];
        const Vec2 a = soup.points[s[0]], b = soup.points[s[1]], c = soup.points[t[0]], d = soup.points[t[1]];
        const bool neighbours = s[0] == t[0] || s[0] == t[1] || s[1] == t[0] || s[1] == t[1];
        if (!neighbours) return segments_intersect(a, b, c, d);
        // A common end: only a collinear overlap.
        const std::uint32_t shared = (s[0] == t[0] || s[0] == t[1]) ? s[0] : s[1];
        const Vec2 p = soup.points[shared], so = soup.points[s[0] == shared ? s[1] : s[0]],
                   to = soup.points[t[0] == shared ? t[1] : t[0]];
        return orient2d(p, so, to) == Orientation::Collinear && dot(so - p, to - p) >= 0.0;
    };
    Pairs want_between, want_within;
    for (std::uint32_t i = 0; i < strip_end; ++i)
        for (std::uint32_t j = strip_end; j < end; ++j)
            if (crossing(i, j)) want_between.emplace_back(i, j);
    for (std::uint32_t i = strip_end; i < end; ++i)
        for (std::uint32_t j = i + 1; j < end; ++j)
            if (crossing(i, j)) want_within.emplace_back(i, j);
    Pairs between, within, strip;
    detail::for_each_crossing_between(soup, {0, strip_end}, {strip_end, end},
                                      [&](std::uint32_t i, std::uint32_t j) { between.emplace_back(i, j); });
    detail::for_each_crossing(soup, {strip_end, end}, [&](std::uint32_t i, std::uint32_t j) { within.emplace_back(i, j); });
    // The strip alone: its columns and rungs meet only at their shared ends.
    detail::for_each_crossing(soup, {0, strip_end}, [&](std::uint32_t i, std::uint32_t j) { strip.emplace_back(i, j); });
    std::sort(between.begin(), between.end());
    std::sort(within.begin(), within.end());
    EXPECT_GT(want_between.size(), 100u);
    EXPECT_GT(want_within.size(), 20u);
    EXPECT_EQ(between, want_between);
    EXPECT_EQ(within, want_within);
    EXPECT_TRUE(strip.empty());
    // Each way round the same pairs.
    Pairs reversed;
    detail::for_each_crossing_between(soup, {strip_end, end}, {0, strip_end},
                                      [&](std::uint32_t i, std::uint32_t j) { reversed.emplace_back(j, i); });
    std::sort(reversed.begin(), reversed.end());
    EXPECT_EQ(reversed, want_between);
    // Runs short enough to be tested pair by pair (at most 4,096 pairs), each way round: the
    // same pairs as the oracle's within them.
    size_t small_pairs = 0;
    for (std::uint32_t first = 0; first + 40 <= strip_end; first += 37) {
        const detail::SegmentRange a{first, first + 40}, b{strip_end + first % 300, strip_end + first % 300 + 100};
        Pairs want, got, got_reversed;
        for (const auto& [i, j] : want_between)
            if (i >= a.first && i < a.last && j >= b.first && j < b.last) want.emplace_back(i, j);
        detail::for_each_crossing_between(soup, a, b, [&](std::uint32_t i, std::uint32_t j) { got.emplace_back(i, j); });
        detail::for_each_crossing_between(soup, b, a, [&](std::uint32_t i, std::uint32_t j) { got_reversed.emplace_back(j, i); });
        std::sort(got.begin(), got.end());
        std::sort(got_reversed.begin(), got_reversed.end());
        EXPECT_EQ(got, want) << first;
        EXPECT_EQ(got_reversed, want) << first;
        small_pairs += want.size();
    }
    EXPECT_GT(small_pairs, 10u);
    // The same through RunCrossings, whose grids are made once for every pair asked: the
    // whole strip against the rest, then its pieces (short and long) against the rest's.
    std::vector<detail::SegmentRange> runs{{0, strip_end}, {strip_end, end}};
    for (std::uint32_t first = 0; first + 300 <= strip_end; first += 300) runs.push_back({first, first + 300});
    for (std::uint32_t first = strip_end; first + 30 <= end; first += 30) runs.push_back({first, first + 30});
    detail::RunCrossings rc(soup, runs);
    Pairs whole;
    rc.between(0, 1, [&](std::uint32_t i, std::uint32_t j) { whole.emplace_back(i, j); });
    std::sort(whole.begin(), whole.end());
    EXPECT_EQ(whole, want_between);
    for (size_t r = 2; r < runs.size(); ++r)
        for (size_t q = 2; q < runs.size(); ++q) {
            const bool strip_r = runs[r].last <= strip_end, strip_q = runs[q].last <= strip_end;
            if (strip_r == strip_q) continue;
            const detail::SegmentRange a = runs[r], b = runs[q];
            Pairs want, got;
            for (const auto& [i, j] : want_between) {
                const bool ok = strip_r ? (i >= a.first && i < a.last && j >= b.first && j < b.last)
                                        : (j >= a.first && j < a.last && i >= b.first && i < b.last);
                if (ok) want.emplace_back(i, j);
            }
            rc.between(r, q, [&](std::uint32_t i, std::uint32_t j) {
                got.emplace_back(strip_r ? i : j, strip_r ? j : i);
            });
            std::sort(got.begin(), got.end());
            ASSERT_EQ(got, want) << r << " " << q;
        }
}

// Whether the convex hulls of two small point sets meet, exactly: a pair of one set's points
// and a pair of the other's cross or touch, or a point of one lies in (or on) a triangle of
// the other's points (the hull is the union of those triangles; a set of one or two points
// is its segment or point).
static bool hulls_meet(const std::vector<Vec2>& a, const std::vector<Vec2>& b) {
    auto in_hull = [](Vec2 p, const std::vector<Vec2>& s) {
        for (size_t i = 0; i < s.size(); ++i)
            for (size_t j = i; j < s.size(); ++j)
                for (size_t k = j; k < s.size(); ++k) {
                    const Orientation o1 = orient2d(s[i], s[j], p), o2 = orient2d(s[j], s[k], p),
                                      o3 = orient2d(s[k], s[i], p);
                    const bool no_right = o1 != Orientation::Right && o2 != Orientation::Right && o3 != Orientation::Right;
                    const bool no_left = o1 != Orientation::Left && o2 != Orientation::Left && o3 != Orientation::Left;
                    // Inside either turn of the triangle; a degenerate one is its segments, tested below.
                    if ((no_right || no_left) && orient2d(s[i], s[j], s[k]) != Orientation::Collinear) return true;
                }
        return false;
    };
    for (size_t i = 0; i < a.size(); ++i)
        for (size_t j = i; j < a.size(); ++j)
            for (size_t k = 0; k < b.size(); ++k)
                for (size_t l = k; l < b.size(); ++l)
                    if (segments_intersect(a[i], a[j], b[k], b[l])) return true;
    for (const Vec2& p : a)
        if (in_hull(p, b)) return true;
    for (const Vec2& p : b)
        if (in_hull(p, a)) return true;
    return false;
}

// The layers' crossing test passes over two strips (or a strip and a boundary segment) only
// on hulls_apart's word: it must never say so of sets whose hulls meet or come within the
// margin, and it should say so of thin slanted strips a little apart.
TEST(HullsApart, NeverSaysSoOfHullsThatMeetOrComeWithinTheMargin) {
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    int apart = 0, meet = 0;
    for (int trial = 0; trial < 20000; ++trial) {
        // Points around two centres whose distance varies from overlap to far apart, some
        // sets thin (a strip) and some of two points, at scales from 1e-6 to 1e6.
        const double scale = std::pow(10.0, 6.0 * u(rng));
        const Vec2 shift{scale * 2.0 * u(rng), scale * 2.0 * u(rng)};
        auto make = [&](Vec2 centre) {
            std::vector<Vec2> s;
            const auto n = static_cast<size_t>(2 + (rng() % 3));
            const double thin = rng() % 4 == 0 ? 1e-4 : 1.0;
            for (size_t i = 0; i < n; ++i) s.push_back(centre + scale * Vec2{u(rng), thin * u(rng)});
            return s;
        };
        const std::vector<Vec2> a = make(Vec2{0.0, 0.0} + shift), b = make(scale * Vec2{1.5 * u(rng), 1.5 * u(rng)} + shift);
        const double margin = 1e-9 * scale * 4.0;
        const bool said = detail::hulls_apart(a, b, margin);
        const bool touching = hulls_meet(a, b);
        if (said) {
            ++apart;
            ASSERT_FALSE(touching) << "trial " << trial;
            // Nor within the margin: moved by it towards each other along any axis, the hulls still miss.
            for (const Vec2 d : {Vec2{1, 0}, Vec2{-1, 0}, Vec2{0, 1}, Vec2{0, -1}}) {
                std::vector<Vec2> moved = a;
                for (Vec2& p : moved) p = p + 0.7 * margin * d;
                ASSERT_FALSE(hulls_meet(moved, b)) << "trial " << trial;
            }
        }
        meet += touching ? 1 : 0;
    }
    EXPECT_GT(apart, 3000);  // it does say so, often
    EXPECT_GT(meet, 2000);   // and the trials held many that meet

    // Two thin strips leaning at 60 degrees, side by side a little apart, as a wall's layers
    // are: their boxes overlap, their hulls do not, and the test sees it; sharing a corner, or
    // closer than the margin, they are not apart.
    const Vec2 lean{0.5, 0.8660254037844386};
    const std::vector<Vec2> s1{{0.0, 0.0}, {0.01, 0.0}, lean, lean + Vec2{0.01, 0.0}};
    std::vector<Vec2> s2 = s1;
    for (Vec2& p : s2) p = p + Vec2{0.02, 0.0};
    EXPECT_TRUE(detail::hulls_apart(s1, s2, 1e-9));
    s2[0] = s1[1];
    EXPECT_FALSE(detail::hulls_apart(s1, s2, 1e-9));
    std::vector<Vec2> s3 = s1;
    for (Vec2& p : s3) p = p + Vec2{0.01 + 1e-10, 0.0};
    EXPECT_FALSE(detail::hulls_apart(s1, s3, 1e-9));
    EXPECT_TRUE(detail::hulls_apart(s1, s3, 1e-11));
}

TEST(HugePages, ALargeReservationIsMarkedForHugePagesAndKeepsItsContents) {
    std::ifstream thp("/sys/kernel/mm/transparent_hugepage/enabled");
    std::string mode((std::istreambuf_iterator<char>(thp)), std::istreambuf_iterator<char>());
    // Where the kernel offers no transparent huge pages at all, madvise refuses and nothing
    // can be checked; this project's machines offer them ("madvise" mode).
    ASSERT_FALSE(mode.empty() || mode.find("[never]") != std::string::npos)
        << "transparent huge pages are off on this machine: " << mode;

    std::vector<std::uint64_t> v{1, 2, 3};
    detail::reserve_huge(v, std::size_t{4} << 20);  // 32 MiB
    ASSERT_GE(v.capacity(), std::size_t{4} << 20);
    EXPECT_EQ(v, (std::vector<std::uint64_t>{1, 2, 3}));
    constexpr std::uintptr_t kHuge = std::uintptr_t{2} << 20;
    const std::uintptr_t aligned = (reinterpret_cast<std::uintptr_t>(v.data()) + kHuge - 1) & ~(kHuge - 1);
    EXPECT_NE(vm_flags_at(aligned).find(" hg"), std::string::npos) << vm_flags_at(aligned);

    // A small array is left alone (no whole huge page inside it).
    std::vector<std::uint64_t> small;
    detail::reserve_huge(small, 1000);
    EXPECT_EQ(vm_flags_at(reinterpret_cast<std::uintptr_t>(small.data())).find(" hg"), std::string::npos);

    std::vector<std::uint32_t> filled;
    detail::assign_huge(filled, std::size_t{3} << 20, std::uint32_t{7});
    EXPECT_EQ(filled.size(), std::size_t{3} << 20);
    EXPECT_TRUE(std::all_of(filled.begin(), filled.end(), [](std::uint32_t x) { return x == 7; }));
}

// The stages' own arrays start on a huge page whatever malloc would have done, keep their
// contents as they grow, and populate() makes their pages without a write.
TEST(HugePages, AnArrayStartsOnAHugePageAndPopulateMakesItsPagesAtOnce) {
    std::ifstream thp("/sys/kernel/mm/transparent_hugepage/enabled");
    std::string mode((std::istreambuf_iterator<char>(thp)), std::istreambuf_iterator<char>());
    ASSERT_FALSE(mode.empty() || mode.find("[never]") != std::string::npos)
        << "transparent huge pages are off on this machine: " << mode;
    constexpr std::uintptr_t kHuge = std::uintptr_t{2} << 20;

    Array<std::uint64_t> v{1, 2, 3};
    detail::reserve_huge(v, (std::size_t{3} << 20) + 5);  // 24 MiB and a bit: 13 huge pages
    const auto at = reinterpret_cast<std::uintptr_t>(v.data());
    EXPECT_EQ(at % kHuge, 0u);
    EXPECT_EQ(v, (Array<std::uint64_t>{1, 2, 3}));
    EXPECT_NE(vm_flags_at(at).find(" hg"), std::string::npos) << vm_flags_at(at);
    // Nothing past the first page has been written: the mapping is almost all unmade.
    const std::size_t bytes = v.capacity() * sizeof(std::uint64_t);
    EXPECT_LT(smaps_kib(smaps_field_at(at, "Rss:")), bytes / 2048) << smaps_field_at(at, "Rss:");
    detail::populate(v.data(), bytes);
    EXPECT_GE(smaps_kib(smaps_field_at(at, "Rss:")), bytes / 1024) << smaps_field_at(at, "Rss:");
    // (Whether the kernel found free huge pages for them depends on its memory's
    // fragmentation; the advice and the alignment above are what the code controls.)

    // Growing past the reservation moves the contents to new storage on a huge page.
    const std::size_t past = v.capacity() + 10;
    for (std::uint64_t i = 3; i < past; ++i) v.push_back(i + 1);
    EXPECT_EQ(v.size(), past);
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(v.data()) % kHuge, 0u);
    std::uint64_t want = 0;
    EXPECT_TRUE(std::all_of(v.begin(), v.end(), [&](std::uint64_t x) { return x == ++want; }));

    // Small ones come from operator new and work as any vector, aligned as their type asks
    // (the interior grids' blocks are cache lines; UBSan reports a misaligned one).
    Array<int> small(1000, 5);
    EXPECT_EQ(std::count(small.begin(), small.end(), 5), 1000);
    struct alignas(64) Line {
        char bytes[64];
    };
    for (int i = 0; i < 8; ++i) {
        Array<Line> lines(static_cast<std::size_t>(i) + 1);
        EXPECT_EQ(reinterpret_cast<std::uintptr_t>(lines.data()) % 64, 0u);
    }
}

// Freed large blocks serve the next large allocations of the same thread inside a
// BlockReuse: the same pages, a kept block cut to the size asked (its rest kept), or kept
// blocks gathered into one, their pages moved, with fresh pages only for what they do not
// cover. The blocks kept never take the thread's large blocks above the most that were live at
// once, the outermost scope returns them, and nothing is kept outside a scope or from another
// thread. (The expected figures follow from the rules in memory.hpp, step by step.)
TEST(BlockReuse, FreedBlocksServeTheNextAllocationsAndNeverRaiseThePeak) {
    constexpr std::size_t MiB = std::size_t{1} << 20;
    constexpr std::uintptr_t kHuge = std::uintptr_t{2} << 20;
    using Bytes = Array<char>;
    auto address = [](const void* p) { return reinterpret_cast<std::uintptr_t>(p); };
    auto mapped = [&](const void* p) { return !smaps_field_at(address(p), "Size:").empty(); };
    auto counters = [] { return detail::block_counters(); };
    ASSERT_EQ(counters().kept_bytes, 0u);

    // Outside a scope a freed block is unmapped at once.
    {
        Bytes outside(8 * MiB);
        const char* at = outside.data();
        EXPECT_EQ(address(at) % kHuge, 0u);
        Bytes().swap(outside);
        EXPECT_EQ(counters().kept_bytes, 0u);
        EXPECT_FALSE(mapped(at));
    }

    const char* kept_at = nullptr;
    {
        const detail::BlockReuse scope;
        const auto start = counters();
        auto reused = [&] { return counters().reused_bytes - start.reused_bytes; };
        auto fresh = [&] { return counters().mapped_bytes - start.mapped_bytes; };
        // The test's own account: its live blocks and the most live at once, which the live
        // and kept blocks together must never exceed.
        std::size_t live = 0, most = 0;
        auto take = [&](std::size_t mib) {
            live += mib * MiB;
            most = std::max(most, live);
        };
        auto give = [&](Bytes& v) {
            live -= v.size();
            Bytes().swap(v);
        };
        auto within_the_peak = [&] { return live + counters().kept_bytes <= most; };

        Bytes a(64 * MiB, 'a');  // fresh: live 64
        take(64);
        const char* A = a.data();
        give(a);  // kept: 64 at A
        EXPECT_EQ(counters().kept_bytes, 64 * MiB);
        EXPECT_TRUE(mapped(A));

        // A smaller block takes the front of it; the rest stays kept, its pages made.
        Bytes b(40 * MiB);  // live 40, kept 24 at A + 40
        take(40);
        EXPECT_EQ(b.data(), A);
        EXPECT_EQ(counters().kept_bytes, 24 * MiB);
        EXPECT_TRUE(mapped(A + 40 * MiB));
        EXPECT_EQ(reused(), 40 * MiB);
        EXPECT_TRUE(within_the_peak());

        // A block larger than any kept one gathers them: their pages move to it, and only
        // what they do not cover is fresh.
        Bytes c(32 * MiB);  // the 24 moved, 8 fresh: live 72, kept 0
        take(32);
        EXPECT_EQ(address(c.data()) % kHuge, 0u);
        EXPECT_FALSE(mapped(A + 40 * MiB));  // moved, pages and all
        EXPECT_EQ(counters().kept_bytes, 0u);
        EXPECT_EQ(reused(), 64 * MiB);
        EXPECT_EQ(fresh(), (64 + 8) * MiB);
        c[0] = 'c';
        c[32 * MiB - 1] = 'c';  // every byte of it is there (ASan and the kernel would say)
        const char* C = c.data();

        // Several kept blocks, the largest first, the last only in part.
        give(c);
        give(b);  // kept: 32 at C, 40 at A; live 0
        Bytes d(50 * MiB);  // the 40 and 10 of the 32: live 50, kept 22 at C + 10, nothing fresh
        take(50);
        EXPECT_FALSE(mapped(A));
        EXPECT_FALSE(mapped(C));
        EXPECT_TRUE(mapped(C + 10 * MiB));
        EXPECT_EQ(counters().kept_bytes, 22 * MiB);
        EXPECT_EQ(reused(), (64 + 50) * MiB);
        EXPECT_EQ(fresh(), 72 * MiB);
        d[0] = 'd';
        d[50 * MiB - 1] = 'd';
        EXPECT_TRUE(within_the_peak());

        // A nested scope keeps nothing of its own and returns nothing when it ends.
        {
            const detail::BlockReuse inner;
            give(d);  // kept 22 and 50
        }
        EXPECT_EQ(counters().kept_bytes, 72 * MiB);
        EXPECT_TRUE(within_the_peak());

        // The smallest kept block that holds it, then a gathering of the rest: nothing fresh
        // while the kept blocks cover the size, then fresh pages only for what is past them.
        Bytes e(30 * MiB);  // the front of the 50: live 30, kept 22 and 20
        take(30);
        Bytes f(30 * MiB);  // the 22 and 8 of the 20: live 60, kept 12
        take(30);
        EXPECT_EQ(counters().kept_bytes, 12 * MiB);
        EXPECT_EQ(fresh(), 72 * MiB);
        EXPECT_TRUE(within_the_peak());
        Bytes g(40 * MiB);  // the 12 and 28 fresh: live 100, the most, kept 0
        take(40);
        EXPECT_EQ(counters().kept_bytes, 0u);
        EXPECT_EQ(fresh(), 100 * MiB);
        kept_at = g.data();
        give(e);
        give(f);
        give(g);
        EXPECT_EQ(counters().kept_bytes, 100 * MiB);
        EXPECT_TRUE(within_the_peak());
        EXPECT_TRUE(mapped(kept_at));
    }
    // The outermost scope returned everything.
    EXPECT_EQ(counters().kept_bytes, 0u);
    EXPECT_FALSE(mapped(kept_at));

    // A block freed on another thread is not this thread's to keep.
    {
        const detail::BlockReuse scope;
        Bytes e(4 * MiB);
        const char* at = e.data();
        std::thread([&] { Bytes().swap(e); }).join();
        EXPECT_EQ(counters().kept_bytes, 0u);
        EXPECT_FALSE(mapped(at));
    }
}
#endif

#if defined(__linux__) && defined(__SANITIZE_ADDRESS__)
#include <sanitizer/asan_interface.h>

// Under AddressSanitizer (the sanitize build), the large blocks, which are mappings of their
// own rather than malloc's, are still watched: the bytes past those asked for, up to the
// block's whole huge pages, and a kept block, are poisoned; a block taken again is usable as
// far as asked; what is unmapped is left clean for the next mapping there. An overrun into
// the rounding is reported.
TEST(BlockReuse, AddressSanitizerWatchesTheLargeBlocks) {
    constexpr std::size_t MiB = std::size_t{1} << 20;
    using Bytes = Array<char>;
    auto poisoned = [](const char* p) { return __asan_address_is_poisoned(p) != 0; };
    const detail::BlockReuse scope;
    const std::size_t asked = 3 * MiB + 5;  // a block of two huge pages, 4 MiB
    Bytes a(asked, 'a');
    char* const at = a.data();
    EXPECT_FALSE(poisoned(at));
    EXPECT_FALSE(poisoned(at + asked - 1));
    EXPECT_TRUE(poisoned(at + asked));
    EXPECT_TRUE(poisoned(at + 4 * MiB - 1));
    EXPECT_DEATH(
        {
            volatile char c = at[asked + 100];
            (void)c;
        },
        "use-after-poison");

    Bytes().swap(a);  // kept, whole
    EXPECT_EQ(detail::block_counters().kept_bytes, 4 * MiB);
    EXPECT_TRUE(poisoned(at));
    EXPECT_TRUE(poisoned(at + 2 * MiB));

    Bytes b(2 * MiB);  // the kept block's first huge page; its second one stays kept
    ASSERT_EQ(b.data(), at);
    EXPECT_FALSE(poisoned(at));
    EXPECT_FALSE(poisoned(at + 2 * MiB - 1));
    EXPECT_TRUE(poisoned(at + 2 * MiB));
    EXPECT_EQ(detail::block_counters().kept_bytes, 2 * MiB);

    Bytes c(4 * MiB);  // the kept page moved to a new block of two, the second one fresh
    EXPECT_FALSE(poisoned(c.data()));
    EXPECT_FALSE(poisoned(c.data() + 4 * MiB - 1));
    EXPECT_FALSE(poisoned(at + 2 * MiB));  // no longer mapped there: left clean
}
#endif
