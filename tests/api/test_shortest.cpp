// The writers' shortest round-trip numbers against the standard library's: the same
// characters for every double tried, and each reads back to its double.

#include <gtest/gtest.h>

#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <string_view>

#include "writers/shortest.hpp"

namespace {

using meshd::api::writers::floor_log10_pow2;
using meshd::api::writers::kShortestMax;
using meshd::api::writers::put_unsigned;
using meshd::api::writers::shortest;

std::string ours(double v) {
    char buf[kShortestMax];
    return {buf, shortest(buf, v)};
}

std::string library(double v) {
    char buf[64];
    return {buf, std::to_chars(buf, buf + sizeof buf, v).ptr};
}

// The same text as std::to_chars, and it reads back to v; the first difference is reported.
::testing::AssertionResult same_as_library(double v) {
    const std::string a = ours(v), b = library(v);
    if (a != b)
        return ::testing::AssertionFailure() << "bits " << std::bit_cast<std::uint64_t>(v) << ": " << a << " against "
                                             << b;
    double back = 0;
    const auto [end, ec] = std::from_chars(a.data(), a.data() + a.size(), back);
    if (ec != std::errc() || end != a.data() + a.size() || std::bit_cast<std::uint64_t>(back) != std::bit_cast<std::uint64_t>(v))
        return ::testing::AssertionFailure() << a << " does not read back";
    return ::testing::AssertionSuccess();
}

TEST(Shortest, TheScaleIsFloorOfLog10OfTwoToTheExponent) {
    // Against powers of ten, in long double (2^e is exact there, and no 2^e in the range is
    // within a part in 10^4 of a power of ten but 2^0).
    for (int e = -46; e <= 52; ++e) {
        const long double p = std::ldexp(1.0L, e);
        const int k = floor_log10_pow2(e);
        EXPECT_LE(std::pow(10.0L, k), p) << e;
        EXPECT_GT(std::pow(10.0L, k + 1), p) << e;
    }
}

TEST(Shortest, MeshLikeNumbersAreTheLibrarys) {
    // Uniform in the exponents the fast path takes ([2^-46, 2^53)) and around them, both signs.
    std::mt19937_64 rng(12345);
    std::uniform_int_distribution<int> exponent(-60, 60);
    std::uniform_int_distribution<std::uint64_t> fraction(0, (std::uint64_t{1} << 52) - 1);
    for (int i = 0; i < 1'000'000; ++i) {
        const std::uint64_t bits = (static_cast<std::uint64_t>(exponent(rng) + 1023) << 52) | fraction(rng) |
                                   (static_cast<std::uint64_t>(i & 1) << 63);
        ASSERT_TRUE(same_as_library(std::bit_cast<double>(bits)));
    }
}

TEST(Shortest, AnyBitPatternIsTheLibrarys) {
    // Everything else goes to the library; NaNs and infinities included.
    std::mt19937_64 rng(777);
    for (int i = 0; i < 300'000; ++i) {
        const double v = std::bit_cast<double>(rng());
        if (std::isnan(v)) {
            EXPECT_EQ(ours(v), library(v));
            continue;
        }
        ASSERT_TRUE(same_as_library(v));
    }
    for (const double v : {0.0, -0.0, HUGE_VAL, -HUGE_VAL, 5e-324, 2.2250738585072014e-308, 1.7976931348623157e308})
        EXPECT_TRUE(same_as_library(v));
}

TEST(Shortest, ShortDecimalsComeBackAsWritten) {
    // Decimals of 1 to 17 digits read into doubles: their own digits are the shortest, and
    // the choice between the fixed and the scientific form is the library's.
    std::mt19937_64 rng(99);
    for (int digits = 1; digits <= 17; ++digits)
        for (int e = -20; e <= 20; ++e)
            for (int i = 0; i < 40; ++i) {
                std::uint64_t d = rng() % 900'000'000'000'000'000ULL + 100'000'000'000'000'000ULL;
                std::string text = std::to_string(d).substr(0, static_cast<size_t>(digits)) + "e" + std::to_string(e);
                double v = 0;
                std::from_chars(text.data(), text.data() + text.size(), v);
                ASSERT_TRUE(same_as_library(v)) << text;
            }
    for (const double v : {0.1, 0.2, 0.3, 1.0, 10.0, 100.0, 1000.0, 1e4, 1e5, 1e-4, 1e-5, 123456.0, 0.001, 1.5e-7, 1e15, 1e16})
        EXPECT_TRUE(same_as_library(v));
}

TEST(Shortest, PowersOfTwoAndExactTies) {
    // A power of two has its lower neighbour half as far as its upper one; 1 + 2^-k is, for
    // some k, exactly halfway between its two shortest candidates (1 + 2^-17 =
    // 1.00000762939453125: 1.0000076293945312, the even one).
    for (int e = -70; e <= 70; ++e) {
        EXPECT_TRUE(same_as_library(std::ldexp(1.0, e)));
        EXPECT_TRUE(same_as_library(-std::ldexp(1.0, e)));
        EXPECT_TRUE(same_as_library(std::nextafter(std::ldexp(1.0, e), 0.0)));
        EXPECT_TRUE(same_as_library(std::nextafter(std::ldexp(1.0, e), HUGE_VAL)));
    }
    for (int k = 1; k <= 52; ++k)
        for (int e = -40; e <= 40; ++e) EXPECT_TRUE(same_as_library(std::ldexp(1.0 + std::ldexp(1.0, -k), e)));
    EXPECT_EQ(ours(1.0 + std::ldexp(1.0, -17)), "1.0000076293945312");
    // Integers up to 2^53 and about it.
    for (std::uint64_t n = 1; n < (std::uint64_t{1} << 53); n = n * 3 + 1) EXPECT_TRUE(same_as_library(static_cast<double>(n)));
    EXPECT_TRUE(same_as_library(9007199254740992.0));
    EXPECT_TRUE(same_as_library(9007199254740994.0));
}

}  // namespace

// put_unsigned writes what std::to_chars writes: at every change of length, around it, and
// at random over the whole range.
TEST(Shortest, IndicesAreTheLibrarys) {
    auto check = [](std::uint32_t v) {
        char ours_buf[16], lib_buf[16];
        const std::string a(ours_buf, put_unsigned(ours_buf, v));
        const std::string b(lib_buf, std::to_chars(lib_buf, lib_buf + sizeof lib_buf, v).ptr);
        EXPECT_EQ(a, b) << v;
    };
    std::uint64_t p = 1;
    for (int k = 0; k <= 10; ++k, p *= 10)
        for (std::int64_t d = -2; d <= 2; ++d) {
            const std::int64_t v = static_cast<std::int64_t>(p) + d;
            if (v >= 0 && v <= static_cast<std::int64_t>(UINT32_MAX)) check(static_cast<std::uint32_t>(v));
        }
    check(UINT32_MAX);
    for (std::uint32_t v = 0; v < 20000; ++v) check(v);
    std::mt19937 rng(7);
    for (int i = 0; i < 200000; ++i) check(static_cast<std::uint32_t>(rng()) >> (rng() % 32));
}
