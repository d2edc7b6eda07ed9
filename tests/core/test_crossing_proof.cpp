// The interior's crossing proof (interior/crossing_proof.hpp) against a brute-force oracle: the
// shortest segment that crosses side XC with both ends outside the spacing disks of X and C,
// found by sampling the two circles, for sizes all through [size_lo, size_hi]. Whenever the
// proof says no short segment can cross, that shortest segment must not be short.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "interior/crossing_proof.hpp"

using namespace meshd::core::detail;

namespace {

// The distance from segment (0,0)-(d,0) to the nearest point outside both the disk about
// (0,0) of radius rx and the disk about (d,0) of radius rc, on one side of the line (the
// problem is symmetric): such a nearest point lies on one of the circles, so both are
// sampled, each sample kept when it is outside the other disk.
double oracle_gap(double d, double rx, double rc) {
    constexpr int kSamples = 8000;
    double best = HUGE_VAL;
    auto distance_to_segment = [d](double x, double y) {
        const double cx = std::clamp(x, 0.0, d);
        return std::hypot(x - cx, y);
    };
    for (int i = 0; i <= kSamples; ++i) {
        const double t = std::numbers::pi * i / kSamples;  // the upper half: y >= 0
        const double ax = rx * std::cos(t), ay = rx * std::sin(t);
        if (std::hypot(ax - d, ay) >= rc) best = std::min(best, distance_to_segment(ax, ay));
        const double cx = d + rc * std::cos(t), cy = rc * std::sin(t);
        if (std::hypot(cx, cy) >= rx) best = std::min(best, distance_to_segment(cx, cy));
    }
    return best;  // HUGE_VAL: one disk holds the other's whole upper circle (no such case below)
}

}  // namespace

TEST(CrossingProof, GapExceedsAgreesWithTheDistanceSampled) {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    int exceeds = 0, short_of = 0;
    for (int i = 0; i < 400; ++i) {
        const double d = 1.0, rx = 0.3 + 0.9 * u(rng), rc = 0.3 + 0.9 * u(rng);
        // Beside: the circles meet at a point whose foot is between X and C.
        const double x = (d * d + rx * rx - rc * rc) / (2.0 * d);
        if (!(x >= 0.0 && x <= d && rx > x)) {
            EXPECT_FALSE(gap_exceeds(d, rx, rc, 0.0)) << "rx " << rx << " rc " << rc;
            continue;
        }
        const double gap = oracle_gap(d, rx, rc);
        // A length on either side of twice the gap, beyond the sampling's error (an arc of
        // pi r / 8000 at most).
        const double len = 2.0 * gap * (0.9 + 0.2 * u(rng));
        if (std::fabs(len - 2.0 * gap) < 2e-3) continue;
        const bool expected = 2.0 * gap > len;
        EXPECT_EQ(gap_exceeds(d, rx, rc, len), expected) << "rx " << rx << " rc " << rc << " len " << len;
        (expected ? exceeds : short_of) += 1;
    }
    EXPECT_GT(exceeds, 50);
    EXPECT_GT(short_of, 50);
}

TEST(CrossingProof, NoShortSegmentCrossesWhereTheProofHolds) {
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    int held = 0, refused = 0;
    for (int i = 0; i < 250; ++i) {
        // Sizes of the kind the front meets: a spread of up to 2.5 between the least and the
        // largest, the candidate's side about the mean of its ends' sizes, the factor of
        // (4.22) around the default 0.8.
        const double lo = 1.0, hi = lo * (1.0 + 1.5 * u(rng));
        const double rx = lo + (hi - lo) * u(rng), rc = lo + (hi - lo) * u(rng);
        const double d = 0.5 * (rx + rc) * (0.8 + 0.5 * u(rng));
        const double p = 0.7 + 0.3 * u(rng);
        if (!short_segments_cannot_cross(d, rx, rc, lo, hi, p)) {
            ++refused;
            continue;
        }
        ++held;
        // Every size m of P and Q the sizes allow: the shortest crossing segment with ends of
        // size m runs from the nearest allowed point on one side of XC to the nearest on the
        // other, 2 oracle_gap long; with sizes above m it is only longer.
        for (int j = 0; j <= 20; ++j) {
            const double m = lo + (hi - lo) * j / 20.0;
            const double shortest = 2.0 * oracle_gap(d, 0.5 * p * (rx + m), 0.5 * p * (rc + m));
            EXPECT_GT(shortest, kShortSegment * m * (1.0 - 1e-3))
                << "a short segment crosses: d " << d << " rx " << rx << " rc " << rc << " sizes " << lo << ".." << hi
                << " proximity " << p << " m " << m;
        }
    }
    // Both answers occur, so the check above is not empty.
    EXPECT_GT(held, 40);
    EXPECT_GT(refused, 40);
}
