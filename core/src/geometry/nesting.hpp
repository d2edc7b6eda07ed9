#pragma once
// Where points lie among a domain's loops given as closed polygons: inside the outer one, in
// a hole. build_domain asks it of the loops flattened from the curves, discretise_boundary of
// the loops its points make (a chord of a coarse curve can leave a hole outside the domain
// without crossing anything).

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "kernel/crossings.hpp"
#include "meshd/core/vec2.hpp"

namespace meshd::core::detail {

/// Winding numbers of points around one closed polygon (non-zero: inside), with the exact
/// orientation predicate. The edges are bucketed by horizontal bands, so that a point meets
/// only the edges of its band: a domain's holes are all asked about against the outer loop,
/// and a plain scan would cost holes x edges. The band count is cut back until the edges,
/// each listed in every band its y-range spans, fill at most 16 entries per edge. Holds a
/// reference to the ring.
class RingIndex {
public:
    explicit RingIndex(const std::vector<Vec2>& ring);
    int winding(Vec2 p) const;

private:
    size_t band(double y) const;
    std::pair<size_t, size_t> span(double y0, double y1) const;

    const std::vector<Vec2>& ring_;
    double lo_, hi_, inv_ = 0.0;
    size_t bands_ = 1;
    std::vector<size_t> start_;
    std::vector<std::uint32_t> edges_;
};

/// The loops of a domain as rings (closed polygons, any orientation): ring `outer` bounds
/// it, every other one is a hole. Each ring is indexed when first asked about; the holes'
/// boxes are in a size-class grid, so that a point meets only the holes whose box holds it.
/// Holds a reference to the rings.
class LoopNesting {
public:
    LoopNesting(const std::vector<std::vector<Vec2>>& rings, size_t outer);
    ~LoopNesting();
    LoopNesting(const LoopNesting&) = delete;  // the grid refers to box_soup_
    LoopNesting& operator=(const LoopNesting&) = delete;

    /// Whether p is inside the outer ring.
    bool inside_outer(Vec2 p);
    /// A hole ring other than `except` that holds p, if any.
    std::optional<size_t> hole_holding(Vec2 p, size_t except);

private:
    int winding(size_t ring, Vec2 p);

    const std::vector<std::vector<Vec2>>& rings_;
    size_t outer_;
    std::vector<Box> boxes_;
    std::vector<std::unique_ptr<RingIndex>> index_;
    std::vector<size_t> holes_;  // ring of each box in the grid's soup
    SegmentSoup box_soup_;       // each hole's box as the segment along its diagonal
    std::unique_ptr<SegmentGrid> box_grid_;
};

}  // namespace meshd::core::detail
