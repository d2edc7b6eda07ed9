// Exact orientation on inputs where naive floating point gets the sign wrong.

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "kernel/predicates.hpp"

using meshd::core::orient2d;
using meshd::core::Orientation;
using meshd::core::Vec2;

namespace {

// Exact sign for points that are integers times 2^-k (all of ours: coordinates near 0.5..24
// are multiples of 2^-53). Uses 128-bit integers.
__extension__ typedef __int128 Int128;

int exact_sign(Vec2 a, Vec2 b, Vec2 c) {
    auto to_int = [](double v) { return static_cast<Int128>(std::ldexp(v, 53)); };
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

TEST(Predicates, OrientIsAntisymmetricAndStableUnderRandomNearCollinearInput) {
    std::mt19937_64 rng(12345);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int k = 0; k < 20000; ++k) {
        const Vec2 a{u(rng) * 1e3, u(rng) * 1e3}, b{u(rng) * 1e3, u(rng) * 1e3};
        const double t = u(rng);
        Vec2 c = a + t * (b - a);  // nearly on the line ab
        c.x = std::nextafter(c.x, (k & 1) ? 1e9 : -1e9);
        const auto o1 = static_cast<int>(orient2d(a, b, c));
        EXPECT_EQ(static_cast<int>(orient2d(b, a, c)), -o1);
        EXPECT_EQ(static_cast<int>(orient2d(b, c, a)), o1);
        EXPECT_EQ(static_cast<int>(orient2d(c, a, b)), o1);
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
