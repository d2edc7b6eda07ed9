#pragma once
/// The paper's interior density, eq. (6.1):
///
///   rho(P) = sum_i (rho_i / d_i) / sum_i (1 / d_i),   d_i = |P - A_i|,
///
/// over the boundary segments A_i B_i with rho_i = |A_i B_i|. Evaluated naively it costs
/// O(N) per point. Here it is a treecode: the sources sit in a k-d tree whose nodes keep
/// their count, their sum of rho_i, their centroid c and their rho-weighted centroid c_rho.
/// For a node of radius r seen from distance D (about either centroid), the node's sums are
/// replaced by count / |P - c| and sum(rho) / |P - c_rho|. Expanding 1/|P - A| about the
/// centroid, the linear term cancels, and the remainder of each term is bounded by
/// r^2 / (D - r)^3, so the relative error of each sum is at most
///   delta(theta) = theta^2 (1 + theta) / (1 - theta)^3,  theta = r / D,
/// and the ratio's relative error is at most 2 delta / (1 - delta). The opening angle theta
/// is chosen from the requested tolerance so that this bound holds.

#include <cstdint>
#include <vector>

#include "meshd/core/vec2.hpp"

namespace meshd::core {

/// Up to this many sources eq. 6.1 is summed term by term, four or eight terms per
/// instruction. The treecode at the tolerance 1e-3 accepts a node only 45 of its radii away,
/// so it costs about 1 us at 150 sources and 4.4 to 4.7 us from 1,500 to 15,000; the plain sum
/// 0.51 ns per source on 256-bit registers (bench/bench_boundary.cpp, BM_InverseDistance,
/// 2026-12-03): they meet near 9,000. (On a processor without AVX the sum costs 1.28 ns per
/// source, and the treecode would be the faster from about 3,500.)
inline constexpr size_t kDirectSources = 8192;

namespace detail {
/// Whether the term-by-term sum runs on 256-bit registers (where the processor has AVX):
/// the same result to the bit, in about half the instructions. `wide_sums(false)` keeps it to
/// 128 bits, for the tests that compare the two; returns whether wide sums are in use.
bool wide_sums(bool allow = true);
}  // namespace detail

class InverseDistanceField {
public:
    /// starts[i] = A_i, values[i] = rho_i > 0. tolerance: bound on the relative error.
    InverseDistanceField(std::vector<Vec2> starts, std::vector<double> values,
                         double tolerance = 1e-3);

    /// rho at p: summed term by term below kDirectSources sources (the weights 1/d_i in
    /// single precision, the sums in double: within 4e-7 of the exact value, and faster there
    /// than the tree), else the treecode.
    double operator()(Vec2 p) const;
    /// The treecode whatever the number of sources (for its tests and benchmarks).
    double treecode(Vec2 p) const;
    /// The formula summed term by term, O(N), one term at a time: the reference for tests.
    double exact(Vec2 p) const;

private:
    struct Node {
        Vec2 c, c_rho;
        double count, rho_sum;
        double r, r_rho;   // radii about c and c_rho
        std::uint32_t begin, end;  // source range
        std::uint32_t left, right; // children (0: leaf)
    };
    // The sum term by term over the sources' coordinates and values in separate arrays
    // (vectorised; single-precision weights).
    double direct(Vec2 p) const;

    std::vector<Vec2> a_;
    std::vector<double> rho_;
    std::vector<double> x_, y_;  // a_ split, for direct(): only up to kDirectSources
    std::vector<Node> nodes_;
    double theta_;  // the opening angle that keeps the relative error within the tolerance
};

}  // namespace meshd::core
