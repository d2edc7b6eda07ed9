// Exact orientation on inputs where naive floating point gets the sign wrong.

#include <gtest/gtest.h>

#include <algorithm>
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
__extension__ typedef unsigned __int128 UInt128;

int exact_sign(Vec2 a, Vec2 b, Vec2 c, int shift = 53) {
    auto to_int = [shift](double v) { return static_cast<Int128>(std::ldexp(v, shift)); };
    const Int128 ax = to_int(a.x), ay = to_int(a.y), bx = to_int(b.x), by = to_int(b.y),
                   cx = to_int(c.x), cy = to_int(c.y);
    // Differences first keeps the products within 128 bits here.
    const Int128 det = (ax - cx) * (by - cy) - (ay - cy) * (bx - cx);
    return (det > 0) - (det < 0);
}

// A signed integer of any size (32-bit limbs, least significant first), enough for the
// incircle determinant of doubles brought to one scale: the oracle of the exact stage.
struct Big {
    bool negative = false;
    std::vector<std::uint32_t> limbs;  // no leading zero limb; empty is zero

    static Big from(std::uint64_t m, int shift) {  // m 2^shift, shift >= 0
        Big r;
        std::vector<std::uint32_t> l(static_cast<size_t>(shift / 32) + 3, 0);
        const unsigned bits = static_cast<unsigned>(shift % 32);
        const auto wide = static_cast<UInt128>(m) << bits;
        for (size_t i = 0; i < 3; ++i) l[static_cast<size_t>(shift / 32) + i] = static_cast<std::uint32_t>(wide >> (32 * i));
        r.limbs = std::move(l);
        r.trim();
        return r;
    }
    void trim() {
        while (!limbs.empty() && limbs.back() == 0) limbs.pop_back();
        if (limbs.empty()) negative = false;
    }
    static int compare_magnitude(const Big& x, const Big& y) {
        if (x.limbs.size() != y.limbs.size()) return x.limbs.size() < y.limbs.size() ? -1 : 1;
        for (size_t i = x.limbs.size(); i-- > 0;)
            if (x.limbs[i] != y.limbs[i]) return x.limbs[i] < y.limbs[i] ? -1 : 1;
        return 0;
    }
    static Big add_magnitudes(const Big& x, const Big& y) {
        Big r;
        std::uint64_t carry = 0;
        for (size_t i = 0; i < std::max(x.limbs.size(), y.limbs.size()) || carry; ++i) {
            const std::uint64_t s = carry + (i < x.limbs.size() ? x.limbs[i] : 0) + (i < y.limbs.size() ? y.limbs[i] : 0);
            r.limbs.push_back(static_cast<std::uint32_t>(s));
            carry = s >> 32;
        }
        r.trim();
        return r;
    }
    static Big subtract_magnitudes(const Big& x, const Big& y) {  // |x| >= |y|
        Big r;
        std::int64_t borrow = 0;
        for (size_t i = 0; i < x.limbs.size(); ++i) {
            std::int64_t d = static_cast<std::int64_t>(x.limbs[i]) - borrow - (i < y.limbs.size() ? y.limbs[i] : 0);
            borrow = d < 0 ? 1 : 0;
            if (d < 0) d += std::int64_t{1} << 32;
            r.limbs.push_back(static_cast<std::uint32_t>(d));
        }
        r.trim();
        return r;
    }
    friend Big operator-(Big x) {
        if (!x.limbs.empty()) x.negative = !x.negative;
        return x;
    }
    friend Big operator+(const Big& x, const Big& y) {
        if (x.negative == y.negative) {
            Big r = add_magnitudes(x, y);
            r.negative = x.negative && !r.limbs.empty();
            return r;
        }
        const bool x_larger = compare_magnitude(x, y) >= 0;
        Big r = x_larger ? subtract_magnitudes(x, y) : subtract_magnitudes(y, x);
        r.negative = (x_larger ? x.negative : y.negative) && !r.limbs.empty();
        return r;
    }
    friend Big operator-(const Big& x, const Big& y) { return x + -y; }
    friend Big operator*(const Big& x, const Big& y) {
        Big r;
        r.limbs.assign(x.limbs.size() + y.limbs.size(), 0);
        for (size_t i = 0; i < x.limbs.size(); ++i) {
            std::uint64_t carry = 0;
            for (size_t j = 0; j < y.limbs.size() || carry; ++j) {
                const std::uint64_t t = r.limbs[i + j] + carry +
                                        (j < y.limbs.size() ? static_cast<std::uint64_t>(x.limbs[i]) * y.limbs[j] : 0);
                r.limbs[i + j] = static_cast<std::uint32_t>(t);
                carry = t >> 32;
            }
        }
        r.negative = x.negative != y.negative;
        r.trim();
        return r;
    }
    int sign() const { return limbs.empty() ? 0 : (negative ? -1 : 1); }
};

// The sign of the incircle determinant of a, b, c, d, the same expression as the predicate's
// (the lifts times the 2x2 minors of the differences to d), in exact integers: every
// coordinate is m 2^e, brought to the least e among the eight.
int exact_incircle_sign(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
    const double v[8] = {a.x, a.y, b.x, b.y, c.x, c.y, d.x, d.y};
    int least = 1 << 20;
    for (double x : v)
        if (x != 0.0) least = std::min(least, std::ilogb(x) - 52);
    std::vector<Big> n;
    for (double x : v) {
        if (x == 0.0) {
            n.emplace_back();
            continue;
        }
        const int e = std::ilogb(x) - 52;
        const auto m = static_cast<std::uint64_t>(std::fabs(std::ldexp(x, -e)));  // exact: 53 bits
        Big r = Big::from(m, e - least);
        r.negative = x < 0.0;
        n.push_back(r);
    }
    const Big adx = n[0] - n[6], ady = n[1] - n[7], bdx = n[2] - n[6], bdy = n[3] - n[7], cdx = n[4] - n[6], cdy = n[5] - n[7];
    const Big det = (adx * adx + ady * ady) * (bdx * cdy - cdx * bdy) + (bdx * bdx + bdy * bdy) * (cdx * ady - adx * cdy) +
                    (cdx * cdx + cdy * cdy) * (adx * bdy - bdx * ady);
    return det.sign();
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
// The exact stage of incircle, where the filter fails: four points of one circle (cos and
// sin, so cocircular to within rounding), circles far from the origin and across it (where
// the differences to d are not exact doubles and the stage takes its general path), lattice
// points exactly on a circle (the sign is 0), and points an ulp off those. The oracle is the
// same determinant in exact integers.
TEST(Predicates, IncircleExactStageMatchesIntegerArithmetic) {
    std::mt19937_64 rng(20261207);
    std::uniform_real_distribution<double> angle(0.0, 6.283185307179586), unit(-1.0, 1.0);
    int decided = 0, zeros = 0;
    auto check = [&](Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
        const int expected = exact_incircle_sign(a, b, c, d);
        EXPECT_EQ(meshd::core::detail::incircle_exact(a, b, c, d), expected)
            << a.x << "," << a.y << " " << b.x << "," << b.y << " " << c.x << "," << c.y << " " << d.x << "," << d.y;
        EXPECT_EQ(meshd::core::incircle(a, b, c, d), expected);  // the filter, then the stage
        ++(expected == 0 ? zeros : decided);
    };
    const Vec2 centres[] = {{0, 0}, {0.5, 0.5}, {1e-9, -3e-9}, {1024.0, -7.25}, {3.0e7, 1.0e-3}, {-0.3, 1e-12}};
    const double radii[] = {1.0, 1e-6, 0.37, 250.0, 1e-12};
    for (const Vec2 o : centres)
        for (const double r : radii)
            for (int k = 0; k < 40; ++k) {
                Vec2 p[4];
                for (auto& q : p) {
                    const double t = angle(rng);
                    q = {o.x + r * std::cos(t), o.y + r * std::sin(t)};
                }
                check(p[0], p[1], p[2], p[3]);
            }
    // Lattice points of x^2 + y^2 = 625^2 (the axes' and eight others), scaled by powers
    // of two and moved by dyadic offsets: exactly cocircular, so 0; one ulp outward or
    // inward on the fourth point decides the sign.
    const Vec2 lattice[] = {{625, 0}, {0, 625}, {-625, 0}, {0, -625}, {175, 600}, {-600, 175}, {336, -527}, {-527, -336},
                            {375, 500}, {-500, -375}, {220, -585}, {-585, 220}};
    for (const double scale : {1.0, 0x1p-40, 0x1p30})
        for (const Vec2 shift : {Vec2{0, 0}, Vec2{0x1p-20, -0x1p-18}, Vec2{4096.0, 0.5}})
            for (size_t i = 0; i + 3 < std::size(lattice); ++i) {
                auto at = [&](size_t j) { return Vec2{lattice[j].x * scale + shift.x, lattice[j].y * scale + shift.y}; };
                const Vec2 a = at(i), b = at(i + 1), c = at(i + 2), d = at(i + 3);
                check(a, b, c, d);
                check(a, b, c, {std::nextafter(d.x, 2 * d.x), d.y});
                check(a, b, c, {d.x, std::nextafter(d.y, 0.0)});
            }
    // Random quadruples with mixed magnitudes (the differences rarely exact).
    for (int k = 0; k < 300; ++k) {
        auto any = [&] { return std::ldexp(unit(rng), static_cast<int>(rng() % 60) - 40); };
        check({any(), any()}, {any(), any()}, {any(), any()}, {any(), any()});
    }
    EXPECT_GT(decided, 1000);
    EXPECT_GT(zeros, 50);
}

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
