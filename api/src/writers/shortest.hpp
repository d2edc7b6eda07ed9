#pragma once
// The shortest decimal text that reads back to a double, in std::to_chars(double)'s format
// (the same characters for every double), faster for the numbers a mesh holds.
//
// std::to_chars took about 530 instructions a coordinate: 8% of a small request's
// instructions went into its JSON answer's numbers (docs/benchmarks.md). Mesh coordinates and
// sizes are normal doubles between 2^-33 (about 1.2e-10) and 2^53; for those the decimal
// interval that rounds to the double scales to integers below 2^64 exactly, with one 64-bit
// product (shortest.cpp), and the shortest number in it is read off by dividing by ten: about
// 300 instructions and a fifth less time. Every other double (zero, subnormal, huge, tiny,
// not finite) goes to std::to_chars.

#include <array>
#include <charconv>
#include <cstddef>
#include <cstdint>
#include <cstring>

namespace meshd::api::writers {

/// Room `shortest` needs at `out` (it writes past the number, within this).
inline constexpr std::size_t kShortestMax = 48;

/// Writes the shortest decimal that reads back to v as std::to_chars(first, last, v) would
/// (the fixed or the scientific form, whichever is shorter, fixed on a tie; among the
/// shortest, the one nearest v, an exact tie to the even digit) into out, which has room for
/// kShortestMax characters. Returns the end of what was written.
char* shortest(char* out, double v);

/// floor(log10(2^e)) for e in [-33, 52], the range `shortest` asks (exposed for its test).
int floor_log10_pow2(int e);

/// The two digits of each number below 100, in order.
inline constexpr std::array<char, 200> kDigitPairs = [] {
    std::array<char, 200> t{};
    for (int i = 0; i < 100; ++i) {
        t[static_cast<std::size_t>(2 * i)] = static_cast<char>('0' + i / 10);
        t[static_cast<std::size_t>(2 * i + 1)] = static_cast<char>('0' + i % 10);
    }
    return t;
}();

/// Writes v in decimal at out, which has room for 10 characters, as std::to_chars would, and
/// returns the end. A mesh's indices: below 10^6 in a branch or three for their length and a
/// pair of digits per step (std::to_chars took 41 instructions an index: its length by a loop,
/// then a checked copy), the rest by std::to_chars.
inline char* put_unsigned(char* out, std::uint32_t v) {
    auto pair = [](char* at, std::uint32_t p) { std::memcpy(at, kDigitPairs.data() + 2 * p, 2); };
    if (v < 100) {
        if (v < 10) {
            *out = static_cast<char>('0' + v);
            return out + 1;
        }
        pair(out, v);
        return out + 2;
    }
    if (v < 10000) {
        const std::uint32_t high = v / 100, low = v % 100;
        if (v < 1000) {
            *out = static_cast<char>('0' + high);
            pair(out + 1, low);
            return out + 3;
        }
        pair(out, high);
        pair(out + 2, low);
        return out + 4;
    }
    if (v < 1000000) {
        const std::uint32_t high = v / 10000, low = v % 10000;
        char* at = out;
        if (high < 10) *at++ = static_cast<char>('0' + high);
        else pair(at, high), at += 2;
        pair(at, low / 100);
        pair(at + 2, low % 100);
        return at + 4;
    }
    return std::to_chars(out, out + 10, v).ptr;
}

}  // namespace meshd::api::writers
