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

class InverseDistanceField {
public:
    /// starts[i] = A_i, values[i] = rho_i > 0. tolerance: bound on the relative error.
    InverseDistanceField(std::vector<Vec2> starts, std::vector<double> values,
                         double tolerance = 1e-3);

    double operator()(Vec2 p) const;
    /// The formula summed term by term, O(N): the reference for tests.
    double exact(Vec2 p) const;

private:
    struct Node {
        Vec2 c, c_rho;
        double count, rho_sum;
        double r, r_rho;   // radii about c and c_rho
        std::uint32_t begin, end;  // source range
        std::uint32_t left, right; // children (0: leaf)
    };
    std::vector<Vec2> a_;
    std::vector<double> rho_;
    std::vector<Node> nodes_;
    double theta_;  // the opening angle that keeps the relative error within the tolerance
};

}  // namespace meshd::core
