#pragma once
/// Gradation (docs/api.md, density.gradation): sizes may grow by at most the ratio g from one
/// element to the next, i.e. |grad h| <= g - 1. The corrected field is the lower envelope
///
///   h'(x) = min( h(x), min_i ( h_i + (g - 1) |x - s_i| ) )
///
/// of cones over sample points s_i of the domain with their sizes h_i (the boundary points
/// and samples of the interior at about the local size): the largest field below h that grows
/// no faster than g - 1 between samples. Queries use a tree of boxes over the sources in
/// Hilbert order whose nodes keep their smallest h_i, pruned by h_min + (g - 1) * distance to
/// the node's box: O(log n) on graded fields.
///
/// A query also leaves a lower bound of the envelope where it was made: the cones are
/// (g - 1)-Lipschitz, so a later query nearby whose `upper` lies below that bound less the
/// slope times the distance is answered without a search (the advancing front asks in runs
/// along the front, mostly where the field is well below the envelope). Queries come from one
/// thread at a time, as for the field the envelope caps.

#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "kernel/memory.hpp"
#include "meshd/core/vec2.hpp"

namespace meshd::core {

class GradationField {
public:
    /// How the sources lie, which decides the tree and how far a query searches (the answers
    /// are the same either way; gradation.cpp has the figures).
    enum class Spread {
        Curves,  ///< along curves (the caps of the size field): a k-d tree, wide searches
        Domain,  ///< over the domain at about the local size (a gradation's samples)
    };
    /// The sources and their sizes are copied.
    GradationField(std::span<const Vec2> sources, std::span<const double> sizes, double ratio, Spread spread);
    /// min_i (h_i + (g - 1) |x - s_i|).
    double operator()(Vec2 x) const { return capped(x, HUGE_VAL); }
    /// min(upper, min_i (h_i + (g - 1) |x - s_i|)): only the sources whose cones come below
    /// `upper` at x are looked at, so a field already below the envelope costs little.
    double capped(Vec2 x, double upper) const;

private:
    static constexpr std::uint32_t kLeafSize = 32;
    std::uint32_t build(std::uint32_t lb, std::uint32_t le, std::uint32_t n);
    double search(Vec2 x, double upper) const;

    struct Node {
        Box box;
        double hmin;
        std::uint32_t begin, end, left, right;
    };
    double least_cone(std::uint32_t b, std::uint32_t e, Vec2 x) const;

    Array<double> x_, y_, h_;  // the sources in tree order (three more entries: least_cone)
    Array<Node> nodes_;
    double slope_;
    double search_factor_;  // a query searches up to this times its bound
    // The last search: where, and a lower bound of the envelope there.
    mutable Vec2 last_at_{0.0, 0.0};
    mutable double last_floor_ = -HUGE_VAL;
};

}  // namespace meshd::core
