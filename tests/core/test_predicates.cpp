// Exact orientation on inputs where naive floating point gets the sign wrong.

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "kernel/constructions.hpp"
#include "kernel/predicates.hpp"

using meshd::core::fmax_inline;
using meshd::core::fmin_inline;
using meshd::core::orient2d;
using meshd::core::Orientation;
using meshd::core::Vec2;

namespace {

// Exact sign for points that are integers times 2^-k (all of ours: coordinates near 0.5..24
// are multiples of 2^-53). Uses 128-bit integers.
__extension__ typedef __int128 Int128;

int exact_sign(Vec2 a, Vec2 b, Vec2 c, int shift = 53) {
    auto to_int = [shift](double v) { return static_cast<Int128>(std::ldexp(v, shift)); };
    const Int128 ax = to_int(a.x), ay = to_int(a.y), bx = to_int(b.x), by = to_int(b.y),
                   cx = to_int(c.x), cy = to_int(c.y);
    // Differences first keeps the products within 128 bits here.
    const Int128 det = (ax - cx) * (by - cy) - (ay - cy) * (bx - cx);
    return (det > 0) - (det < 0);
}

int naive_sign(Vec2 a, Vec2 b, Vec2 c) {
    const double det = (a.x - c.x) * (b.y - c.y) - (a.y - c.y) * (b.x - c.x);
    return (det > 0) - (det < 0);
}

}  // namespace

TEST(Predicates, OrientSimpleCases) {
    EXPECT_EQ(orient2d({0, 0}, {1, 0}, {0, 1}), Orientation::Left);
    EXPECT_EQ(orient2d({0, 0}, {1, 0}, {0, -1}), Orientation::Right);
    EXPECT_EQ(orient2d({0, 0}, {1, 1}, {3, 3}), Orientation::Collinear);
}

// The classic experiment: a 256 x 256 grid of points one ulp apart near (0.5, 0.5),
// tested against the line through (12, 12) and (24, 24). Naive evaluation misjudges many.
TEST(Predicates, OrientNearDegenerateGridMatchesExactArithmetic) {
    const Vec2 b{12.0, 12.0}, c{24.0, 24.0};
    const double ulp = std::ldexp(1.0, -53);
    int naive_wrong = 0, checked = 0;
    for (int i = 0; i < 256; ++i) {
        for (int j = 0; j < 256; ++j) {
            const Vec2 a{0.5 + i * ulp, 0.5 + j * ulp};
            const int want = exact_sign(a, b, c);
            ASSERT_EQ(static_cast<int>(orient2d(a, b, c)), want) << "i=" << i << " j=" << j;
            naive_wrong += naive_sign(a, b, c) != want;
            ++checked;
        }
    }
    // The experiment only means something if the naive predicate fails here.
    EXPECT_GT(naive_wrong, 0);
    EXPECT_EQ(checked, 65536);
}

// Random points on a grid of step 2^-40 up to about 1000 (exact doubles, and exact 128-bit
// integers once scaled), the third one on the line through the first two or rounded onto it
// and nudged by at most a grid step: the sign against the exact one, and its symmetries.
TEST(Predicates, OrientMatchesExactArithmeticOnRandomNearCollinearInput) {
    std::mt19937_64 rng(12345);
    std::uniform_int_distribution<std::int64_t> coordinate(-(std::int64_t{1} << 50), std::int64_t{1} << 50);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::uniform_int_distribution<int> nudge(-1, 1);
    auto on_grid = [](double v) { return std::ldexp(std::round(std::ldexp(v, 40)), -40); };
    int collinear = 0, left = 0, right = 0;
    for (int k = 0; k < 20000; ++k) {
        const Vec2 a{std::ldexp(static_cast<double>(coordinate(rng)), -40), std::ldexp(static_cast<double>(coordinate(rng)), -40)};
        const Vec2 b{std::ldexp(static_cast<double>(coordinate(rng)), -40), std::ldexp(static_cast<double>(coordinate(rng)), -40)};
        const Vec2 on_line = a + u(rng) * (b - a);
        // Every fourth point exactly on the line (a + 2 (b - a) is exact on this grid).
        const Vec2 c = k % 4 == 0 ? a + 2.0 * (b - a)
                                  : Vec2{on_grid(on_line.x) + nudge(rng) * std::ldexp(1.0, -40), on_grid(on_line.y)};
        const int want = exact_sign(a, b, c, 40);
        const auto o1 = static_cast<int>(orient2d(a, b, c));
        ASSERT_EQ(o1, want) << "k=" << k;
        EXPECT_EQ(static_cast<int>(orient2d(b, a, c)), -o1);
        EXPECT_EQ(static_cast<int>(orient2d(b, c, a)), o1);
        EXPECT_EQ(static_cast<int>(orient2d(c, a, b)), o1);
        (want == 0 ? collinear : want > 0 ? left : right) += 1;
    }
    // All three answers occur: a predicate stuck on one of them cannot pass.
    EXPECT_GT(left, 0);
    EXPECT_GT(right, 0);
    EXPECT_GT(collinear, 0);
}

// fmax_inline and fmin_inline against the maths library's fmax and fmin, bit for bit: NaNs
// on either side, zeros of both signs, infinities, subnormals and random values, each pair
// both ways round.
TEST(Predicates, TheInlineMaxAndMinAreTheLibrarysToTheBit) {
    std::vector<double> v{0.0,      -0.0,      1.0,       -1.0,     HUGE_VAL, -HUGE_VAL, std::nan(""), -std::nan(""),
                          4.9e-324, -4.9e-324, 2.2e-308, 1.7e308, 0.1,      0.1 + 1e-17};
    std::mt19937_64 rng(17);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int i = 0; i < 200; ++i) v.push_back(std::ldexp(u(rng), static_cast<int>(rng() % 200) - 100));
    auto bits = [](double x) { return std::bit_cast<std::uint64_t>(x); };
    // A volatile pointer, so that the compiler calls the library rather than folding it.
    double (*volatile lib_max)(double, double) = std::fmax;
    double (*volatile lib_min)(double, double) = std::fmin;
    for (const double a : v)
        for (const double b : v) {
            const double want_max = lib_max(a, b), want_min = lib_min(a, b);
            if (std::isnan(want_max)) EXPECT_TRUE(std::isnan(fmax_inline(a, b))) << a << " " << b;
            else EXPECT_EQ(bits(fmax_inline(a, b)), bits(want_max)) << a << " " << b;
            if (std::isnan(want_min)) EXPECT_TRUE(std::isnan(fmin_inline(a, b))) << a << " " << b;
            else EXPECT_EQ(bits(fmin_inline(a, b)), bits(want_min)) << a << " " << b;
        }
}

TEST(Predicates, SegmentsIntersect) {
    using meshd::core::segments_intersect;
    EXPECT_TRUE(segments_intersect({0, 0}, {2, 2}, {0, 2}, {2, 0}));
    EXPECT_FALSE(segments_intersect({0, 0}, {1, 1}, {2, 2}, {3, 3}));
    EXPECT_TRUE(segments_intersect({0, 0}, {2, 2}, {1, 1}, {3, 3}));  // collinear overlap
    EXPECT_TRUE(segments_intersect({0, 0}, {2, 0}, {1, 0}, {1, 5}));  // T junction
    EXPECT_FALSE(segments_intersect({0, 0}, {2, 0}, {1, 1e-300}, {1, 5}));
}

// The side that closes a corner with a given angle at the other side's far end, checked by
// building the triangle and measuring that angle with atan2 (law of sines: a / sin(angle) =
// b / sin(pi - theta - angle)).
TEST(Constructions, TheShortestSideForAnAngleMakesThatAngleAtTheOtherSidesEnd) {
    using meshd::core::shortest_side_for_angle;
    const double deg = std::acos(-1.0) / 180.0;
    for (const double theta : {40.0, 75.0, 90.0, 105.0, 116.0}) {
        for (const double angle : {20.0, 31.0, 45.0}) {
            if (theta + angle >= 180.0) continue;
            const double b = 2.5;
            const double a = shortest_side_for_angle(b, theta * deg, angle * deg);
            // The corner at the origin: side b along x, side a at theta.
            const Vec2 far_b{b, 0.0}, far_a{a * std::cos(theta * deg), a * std::sin(theta * deg)};
            const Vec2 u = far_a - far_b, w = Vec2{0.0, 0.0} - far_b;
            const double at_b = std::atan2(u.x * w.y - u.y * w.x, u.x * w.x + u.y * w.y);
            EXPECT_NEAR(std::fabs(at_b) / deg, angle, 1e-9) << theta << " " << angle;
        }
    }
    // At 90 degrees and 30: a = b tan 30.
    EXPECT_NEAR(shortest_side_for_angle(1.0, 90.0 * deg, 30.0 * deg), std::tan(30.0 * deg), 1e-12);
}
