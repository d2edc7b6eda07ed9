// The shortest round-trip decimal of a double; see shortest.hpp.
//
// A normal double v = m 2^e (m of 53 bits) reads back from every decimal strictly between
// the midpoints to its neighbours, and from the midpoints themselves when m is even (the
// reader rounds a tie to the even neighbour). In units of 2^(e-2) those midpoints are
// 4m - 2 and 4m + 2 (4m - 1 below a power of two, whose lower neighbour is half as far).
// Scaled by 10^s with s = 17 - floor(log10 2^(e+52)), v is at least 10^17 and below 2 10^18,
// and the interval is at least 16 units wide: the shortest decimal is the multiple of the
// largest power of ten 10^j that lies in it. For e in [-85, 0], s is in [2, 27] (5^s below
// 2^64) and shift = 2 - e - s in [0, 60]: each bound is (4m +- 2) 5^s, one 64 x 64-bit
// product, over 2^shift, its floor and whether the shift dropped anything exact.

#include "writers/shortest.hpp"

#include <array>
#include <bit>
#include <charconv>
#include <cstdint>
#include <cstring>

namespace meshd::api::writers {

namespace {

__extension__ typedef unsigned __int128 u128;  // GCC and Clang on 64-bit targets

constexpr int kLowestExponent = -85;  // e = -85: s = 27 (5^27 < 2^64), shift = 60
constexpr int kHighestExponent = 0;   // e = 0: shift = 0

constexpr std::array<std::uint64_t, 28> kPow5 = [] {
    std::array<std::uint64_t, 28> p{};
    p[0] = 1;
    for (size_t i = 1; i < p.size(); ++i) p[i] = p[i - 1] * 5;
    return p;
}();

constexpr char kZeros[] = "000000000000000000000000";

constexpr std::array<std::uint64_t, 20> kPow10 = [] {
    std::array<std::uint64_t, 20> p{};
    p[0] = 1;
    for (size_t i = 1; i < p.size(); ++i) p[i] = p[i - 1] * 10;
    return p;
}();

int digit_count(std::uint64_t d) {
    // floor(log10 2^b) for the bit width b, then one comparison (d >= 1 here).
    const int t = (static_cast<int>(std::bit_width(d)) * 1233) >> 12;
    return t + (d >= kPow10[static_cast<size_t>(t)] ? 1 : 0);
}

// The 8 digits of x < 10^8 (leading zeros included) at p: four independent pairs.
[[gnu::always_inline]] inline void put8(char* p, std::uint32_t x) {
    const std::uint32_t high = x / 10000, low = x % 10000;
    std::memcpy(p, kDigitPairs.data() + 2 * (high / 100), 2);
    std::memcpy(p + 2, kDigitPairs.data() + 2 * (high % 100), 2);
    std::memcpy(p + 4, kDigitPairs.data() + 2 * (low / 100), 2);
    std::memcpy(p + 6, kDigitPairs.data() + 2 * (low % 100), 2);
}

// The 24 digits of d (leading zeros included) ending at end: three blocks of eight, not a
// chain of a division per pair.
void put24(char* end, std::uint64_t d) {
    put8(end - 8, static_cast<std::uint32_t>(d % 100'000'000));
    d /= 100'000'000;
    put8(end - 16, static_cast<std::uint32_t>(d % 100'000'000));
    put8(end - 24, static_cast<std::uint32_t>(d / 100'000'000));  // below 10^4
}

// floor(p / 2^shift) for shift in [0, 60] and a quotient below 2^64, and whether the shift
// dropped nothing: on the two halves (a shift of a 128-bit number by any amount takes
// branches or selects for amounts past 64).
std::uint64_t floor_shifted(u128 p, int shift, bool& exact) {
    const auto low = static_cast<std::uint64_t>(p), high = static_cast<std::uint64_t>(p >> 64);
    exact = (low & ((std::uint64_t{1} << shift) - 1)) == 0;
    return (low >> shift) | ((high << 1) << (63 - shift));
}

// d (n digits, no trailing zero) times 10^e10, in the shorter of the fixed and scientific
// forms, fixed on a tie. The copies are of fixed sizes (a few vector moves rather than calls
// to memcpy), so they write past the number's end, within kShortestMax: the fixed form is
// the shorter only with at most 5 trailing and 4 leading zeros, and n is at most 17.
char* put_decimal(char* out, std::uint64_t d, int n, int e10) {
    char block[48];
    put24(block + 24, d);
    std::memcpy(block + 24, kZeros, 24);  // read by the copies, never part of the number
    const char* digits = block + 24 - n;  // and 24 characters after it are readable
    const int x = e10 + n - 1;            // the scientific exponent
    const int fixed_len = e10 >= 0 ? n + e10 : (-e10 < n ? n + 1 : 2 - e10);
    const int sci_len = n + (n > 1 ? 1 : 0) + 2 + (x >= 100 || x <= -100 ? 3 : 2);
    if (fixed_len <= sci_len) {
        if (e10 >= 0) {
            std::memcpy(out, digits, 24);
            std::memcpy(out + n, kZeros, 8);
        } else if (-e10 < n) {
            const int whole = n + e10;
            std::memcpy(out, digits, 24);
            out[whole] = '.';
            std::memcpy(out + whole + 1, digits + whole, 24);
        } else {
            out[0] = '0';
            out[1] = '.';
            std::memcpy(out + 2, kZeros, 8);
            std::memcpy(out + 2 - e10 - n, digits, 24);
        }
        return out + fixed_len;
    }
    out[0] = digits[0];
    out[1] = '.';
    std::memcpy(out + 2, digits + 1, 24);
    char* p = out + (n > 1 ? n + 1 : 1);
    *p++ = 'e';
    *p++ = x < 0 ? '-' : '+';
    const int ax = x < 0 ? -x : x;
    if (ax >= 100) {
        *p++ = static_cast<char>('0' + ax / 100);
        std::memcpy(p, kDigitPairs.data() + 2 * (ax % 100), 2);
    } else {
        std::memcpy(p, kDigitPairs.data() + 2 * ax, 2);
    }
    return p + 2;
}

}  // namespace

int floor_log10_pow2(int e) {
    // 78913 / 2^18 is log10(2) to within 8e-7; over [-33, 52] no multiple of log10(2) but
    // zero's is that close to an integer (the test checks the range against powers of ten).
    return (e * 78913) >> 18;
}

char* shortest(char* out, double v) {
    static_assert(kShortestMax >= 1 + 19 + 25, "room for the sign and put_decimal's fixed copies");
    const auto bits = std::bit_cast<std::uint64_t>(v);
    const auto biased = static_cast<int>((bits >> 52) & 0x7ff);
    const std::uint64_t fraction = bits & ((std::uint64_t{1} << 52) - 1);
    const int e = biased - 1075;
    if (biased == 0 || biased == 0x7ff || e < kLowestExponent || e > kHighestExponent)
        return std::to_chars(out, out + kShortestMax, v).ptr;
    if (bits >> 63) *out++ = '-';
    const std::uint64_t m = fraction | (std::uint64_t{1} << 52);
    const bool ends_read_back = (m & 1) == 0;
    const int s = 17 - floor_log10_pow2(e + 52);
    const int shift = 2 - e - s;
    // 4m, 4m + 2 and 4m - 2 (or 4m - 1) times 5^s: one product, two sums.
    const std::uint64_t pow5 = kPow5[static_cast<size_t>(s)];
    const u128 at = static_cast<u128>(4 * m) * pow5;
    const u128 below = static_cast<u128>(pow5) << (fraction != 0 || biased == 1 ? 1 : 0);
    bool exact, up_exact, down_exact;
    const std::uint64_t value = floor_shifted(at, shift, exact);
    const std::uint64_t upper = floor_shifted(at + (static_cast<u128>(pow5) << 1), shift, up_exact);
    const std::uint64_t lower = floor_shifted(at - below, shift, down_exact);
    // The integers the double reads back from: at least 14 of them (the interval is 2^e 10^s
    // = 10^(1.35 + a fraction) >= 22 units wide, 3/4 of that below a power of two, less one
    // at each end where the ends do not read back).
    std::uint64_t lo = down_exact && ends_read_back ? lower : lower + 1;
    std::uint64_t hi = up_exact && !ends_read_back ? upper - 1 : upper;
    // The largest j such that a multiple of 10^j lies in [lo, hi] (j >= 1, as ten integers
    // in a row hold a multiple of 10); lo and hi become the least and the greatest of those
    // multiples, over 10^j, d the value's digits before the last j, `last` the digit after
    // them and `zeros` whether everything after that is zero.
    hi /= 10;
    lo = (lo + 9) / 10;
    std::uint64_t d = value / 10;
    std::uint64_t last = value % 10;
    bool zeros = exact;
    int j = 1;
    for (;;) {
        const std::uint64_t h = hi / 10, l = (lo + 9) / 10;
        if (h < l) break;
        hi = h;
        lo = l;
        zeros = zeros && last == 0;
        last = d % 10;
        d /= 10;
        ++j;
    }
    // v to the nearest multiple of 10^j (a tie to the even one), kept within [lo, hi].
    d += static_cast<std::uint64_t>(last > 5 || (last == 5 && (!zeros || (d & 1) != 0)));
    d = d < lo ? lo : d > hi ? hi : d;
    return put_decimal(out, d, digit_count(d), j - s);
}

}  // namespace meshd::api::writers
