#pragma once
/// When the interior's crossing test may leave out the front's short segments.
///
/// The advancing front (interior.cpp) accepts a candidate C for a front segment AB only when
/// AC and BC cross no segment of the front. Where every two points are spaced as (4.22) asks,
/// |PQ| >= p (rP + rQ) / 2 with p the proximity factor, a segment not much longer than the
/// sizes at its ends cannot reach across AC or BC: its ends would have to come closer to A,
/// B or C than (4.22) lets them. This header says when that holds for one side of one
/// candidate, so that the front need not keep its short segments where the test looks.

#include <cmath>

namespace meshd::core::detail {

/// A front segment is short when it is at most this many times as long as the smaller size at
/// its ends. Each segment the front makes spans about the mean of its ends' sizes, so where the
/// field changes gently almost every segment is short.
inline constexpr double kShortSegment = 1.1;

/// Whether every point outside both the disk about X of radius rx and the disk about C of
/// radius rc is farther than len / 2 from segment XC (length d > 0), where the points nearest
/// to the segment lie beside it; false where they do not (then nothing is claimed).
///
/// With X at the origin and C at (d, 0), a point (x, y) outside both disks has
/// y^2 >= rx^2 - x^2 and y^2 >= rc^2 - (d - x)^2. Over 0 <= x <= d the first bound falls and
/// the second rises with x, so the larger of the two is least where they are equal, at
/// x* = (d^2 + rx^2 - rc^2) / 2d, and is rx^2 - x*^2 there: the distance g from the segment
/// is its square root when x* is in [0, d] (beside), as the points beyond the ends are at
/// least rx from X or rc from C, no nearer. 2 g > len is 4 (rx^2 - x*^2) > len^2, which with
/// n = 2 d x* reads 4 d^2 rx^2 - n^2 > d^2 len^2: no division and no square root.
inline bool gap_exceeds(double d, double rx, double rc, double len) {
    const double d2 = d * d;
    const double n = d2 + rx * rx - rc * rc;
    return n >= 0.0 && n <= 2.0 * d2 && 4.0 * d2 * rx * rx - n * n > d2 * len * len;
}

/// Whether no short segment PQ (P and Q other than X and C) can cross side XC, of length d,
/// of a candidate C with size rc, X being A or B of size rx, given that every two points
/// (C included, apart from X) are spaced as (4.22) asks with factor `proximity` and that every
/// point's size lies in [size_lo, size_hi].
///
/// Why. Let PQ cross XC at Y. P lies outside the disks about X and C of radii
/// proximity (rx + rP) / 2 and proximity (rc + rP) / 2; with m the smaller of rP and rQ, both P
/// and Q lie outside the disks of radii proximity (rx + m) / 2 and proximity (rc + m) / 2, so
/// each is at least g(m) (gap_exceeds) from segment XC, and |PQ| = |PY| + |YQ| >= 2 g(m).
/// Short, |PQ| <= kShortSegment m. So no short segment crosses when 2 g(m) > kShortSegment m
/// for every m in [size_lo, size_hi]. Where the nearest points are beside, g(m)^2 is
/// (u m + v)^2 - (w m + z)^2 (the radius and x* are linear in m), whose square root is concave
/// where positive: for F = a m^2 + b m + c, (sqrt F)'' has the sign of 4ac - b^2, which is
/// -4 (u z - w v)^2 here. g grows with m (larger disks leave less outside them) and x* moves
/// linearly, so beside at both ends means beside between them; then 2 g(m) - kShortSegment m
/// is concave on [size_lo, size_hi] and positive on it when positive at both ends, which is
/// what is checked, with a margin far above the rounding of these few operations.
inline bool short_segments_cannot_cross(double d, double rx, double rc, double size_lo, double size_hi,
                                        double proximity) {
    const double h = 0.5 * proximity;
    for (const double m : {size_lo, size_hi})
        if (!gap_exceeds(d, h * (rx + m), h * (rc + m), kShortSegment * m * (1.0 + 0x1p-30))) return false;
    return true;
}

}  // namespace meshd::core::detail
