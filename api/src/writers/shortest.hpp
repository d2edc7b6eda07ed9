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

#include <cstddef>

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

}  // namespace meshd::api::writers
