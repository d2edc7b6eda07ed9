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
///
/// The pipeline asks the field at some eight points per mesh point (the interior's
/// candidates, the quality figures, the points' target sizes), each with every source. So
/// queries go through cells of a quadtree built as they come: a cell keeps the sum over the
/// sources far from it (at least 1/phi of its half-diagonal from its centre) as a cubic
/// polynomial about its centre, and the near ones as a list of nodes of the treecode's k-d
/// tree (each a range of the sources), summed term by term. 1/|P - A|
/// expanded about the centre C in Legendre polynomials, sum_l (-1)^l t^l P_l(cos g) / R with
/// R = |C - A| and t = |P - C| / R <= phi, leaves after the cubic term at most
/// t^4 / ((1 - t) R), so each far term is within delta = phi^4 (1 + phi) / (1 - phi) of its
/// value, and the ratio within 2 delta / (1 - delta) as above. A cell is split (its children
/// made on first use) while it has more than kCellNearSources near sources; a child takes its
/// parent's polynomial moved to its own centre plus those of its parent's near sources that
/// are far from it (its nodes whole: all far, all near, or opened), so making one costs its
/// parent's near list, not every source, and a cell keeps node numbers, not sources. A leaf,
/// never split, keeps copies of its near sources instead, in one range: a query sums them in
/// one pass of eight a step (about 21 sources in 3.4 nodes on Fig. 9: 7 steps of four, a
/// quarter of their lanes masked, became 3), within a bound on all leaves' copies
/// (kPackedCopies, kPackedCopiesPerSource; leaves made past it keep node numbers). A query
/// finds its leaf from the last query's, up to the first cell that holds it and down again;
/// the cells' places, links and near ranges sit apart from their polynomials, so that the way
/// reads a quarter of the bytes, and the polynomials keep their ten coefficients alone, three
/// cache lines a cell instead of five (Fig. 9 per triangle, against the NACA example's:
/// 1.39-1.44 times against 1.41-1.48 before, six alternated runs each).

#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "meshd/core/vec2.hpp"

namespace meshd::core {

/// Up to this many sources summed() adds eq. 6.1 term by term, four or eight terms per
/// instruction (above, the treecode; the field itself goes through the cells). The treecode at the tolerance 1e-3 accepts a node only 45 of its radii away,
/// so it costs about 1 us at 150 sources and 4.4 to 4.7 us from 1,500 to 15,000; the plain sum
/// 0.51 ns per source on 256-bit registers (bench/bench_boundary.cpp, BM_InverseDistance,
/// 2026-12-03): they meet near 9,000. (On a processor without AVX the sum costs 1.28 ns per
/// source, and the treecode would be the faster from about 3,500.)
inline constexpr size_t kDirectSources = 8192;
/// Above this many sources queries go through the cells (Fig. 9's 378 sources: the sum cost
/// 0.2 us a query); up to it, the term-by-term sum.
inline constexpr size_t kCellSources = 64;
/// A cell with more near sources than this is split.
inline constexpr size_t kCellNearSources = 48;
/// The query cells' leaves keep copies of their near sources up to the larger of these: so
/// many copies, or so many a source (then their node numbers, as inner cells do). Fig. 9
/// makes 60,037 copies; 2^17 copies are 3.1 MB.
inline constexpr size_t kPackedCopies = size_t{1} << 17;
inline constexpr size_t kPackedCopiesPerSource = 8;

namespace detail {
/// Whether the term-by-term sum runs on 256-bit registers (where the processor has AVX):
/// the same result to the bit, in about half the instructions. `wide_sums(false)` keeps it to
/// 128 bits, for the tests that compare the two; returns whether wide sums are in use.
bool wide_sums(bool allow = true);
}  // namespace detail

class InverseDistanceField {
public:
    /// starts[i] = A_i, values[i] = rho_i > 0. tolerance: bound on the relative error.
    /// packed_copies: the leaves' copies of their near sources at most (kPackedCopies and
    /// kPackedCopiesPerSource by default; the tests give a few, so that both kinds of leaf
    /// are asked).
    InverseDistanceField(std::vector<Vec2> starts, std::vector<double> values, double tolerance = 1e-3,
                         std::optional<size_t> packed_copies = std::nullopt);

    /// rho at p: summed term by term up to kCellSources sources (the weights 1/d_i in single
    /// precision, the sums in double: within 4e-7 of the exact value), else through the cells
    /// (within the tolerance and 4e-7; summed() outside the sources' box). The cells are made
    /// as queries come: one thread at a time.
    double operator()(Vec2 p) const;
    /// The term-by-term sum whatever the number of sources (for tests and benchmarks; it
    /// takes the treecode's place above kDirectSources).
    double summed(Vec2 p) const;
    /// The treecode whatever the number of sources (for its tests and benchmarks).
    double treecode(Vec2 p) const;
    /// The formula summed term by term, O(N), one term at a time: the reference for tests.
    double exact(Vec2 p) const;
    /// The copies of near sources the leaves made so far hold (at most packed_copies).
    size_t packed_sources() const { return near_x_.empty() ? 0 : near_x_.size() - 3; }

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

    // A cell of the query quadtree: the far sources' sums as cubic polynomials in
    // (P - centre), the coefficients of dx^i dy^j (i + j <= 3) in the order of kTerms
    // (inverse_distance.cpp): three cache lines.
    struct alignas(32) Cell {
        double num[10], den[10];
    };
    // Where a cell is, its links and its near sources, kept apart from its sums: a query's way
    // to its leaf reads only these.
    struct Place {
        Vec2 centre;
        double half;                // half its width
        std::uint32_t child[4];     // 0: not made yet
        std::uint32_t parent;       // the root's: 0
        // Into near_nodes_, k-d tree nodes, each a range of sources; a packed leaf's into
        // near_x_, near_y_, near_r_, its near sources copied out.
        std::uint32_t near_begin, near_end;
        bool leaf;
        bool packed;  // a leaf whose near sources are copied out (near_x_, ...)
    };
    double through_cells(Vec2 p) const;
    std::uint32_t make_child(std::uint32_t parent, int quadrant) const;
    void add_far(Cell& cell, Vec2 centre, double x, double y, double rho) const;

    std::vector<Vec2> a_;
    std::vector<double> rho_;
    std::vector<double> x_, y_;  // a_ split, for direct() and the cells' near sums
    // x_, y_ and rho_ hold three zeros past the last source: the cells' near sums read whole
    // steps of four past a range's end.
    std::vector<Node> nodes_;
    double theta_;  // the opening angle that keeps the relative error within the tolerance
    double phi_;    // the cells' (far: at least half-diagonal / phi from the centre)
    mutable std::vector<Cell> cells_;    // [0]: the root, over the sources' box
    mutable std::vector<Place> places_;  // places_[k]: cells_[k]'s
    mutable std::vector<std::uint32_t> near_nodes_;
    // The leaves' near sources, each leaf's in one range; three zeros past the last (read,
    // masked, by the last step of four).
    mutable std::vector<double> near_x_, near_y_, near_r_;
    void pad_near() const;  // those three zeros
    // Copies at most (24 bytes each): leaves made past it keep their node numbers. Leaves made
    // all over the plane hold some 200 copies a source (sources on two circles and 2 million
    // random queries: 137.1 MB at 16,000 sources, against 46.2 MB with node numbers).
    size_t packing_budget_;
    mutable std::vector<std::uint32_t> open_;  // make_child's stack
    mutable std::vector<std::pair<std::uint32_t, std::uint32_t>> far_ranges_;  // and its far nodes' sources
    mutable std::uint32_t last_leaf_ = 0;  // the last query's cell (queries come in runs)
};

}  // namespace meshd::core
