#pragma once
/// Interior points by the advancing front (paper, section 4, algorithm 4.1).
///
/// The front starts as the segments of the discretised boundary (loops with the domain on
/// their left; embedded curves in both directions), all active. The last active segment AB
/// proposes a point C on its left (the four cases of (4.6)), and
/// optionally corrects it towards (4.4) by a fixed-point iteration. C is accepted when every
/// other point P is farther than (rho(C) + rho(P)) / 2 (4.22), AC and BC cross no front
/// segment and no boundary or embedded segment, and C lies in the domain; then AB is
/// replaced by AC and CB. Otherwise AB becomes inactive; where C came too close to a point P
/// beside AB on the front and the field is coarser than the front there, the front closes on
/// P (AP and PB take AB's place), as the paper's front, finer than its field by a third or
/// more, would otherwise die after one row. The run ends when no segment is active.
///
/// Neighbour and crossing queries go through hashed grids by size class (the crossing test
/// leaves out the short segments that crossing_proof.hpp shows cannot cross: all of them on
/// nearly uniform fields, block by block of their grid on graded ones); being inside is decided by a straight walk in the
/// constrained triangulation of the boundary, with exact predicates. Each step costs O(1) on
/// graded meshes: the run is linear in the number of points.

#include <cstdint>
#include <vector>

#include "boundary/boundary.hpp"
#include "density/size_field.hpp"
#include "meshd/core/mesher.hpp"
#include "meshd/core/observer.hpp"

namespace meshd::core {

/// The interior points (not including the boundary's), in the order they were made.
/// `rho` must be ready for interior queries (set_interpolation_sources for eq. 6.1);
/// `walls` is the constrained triangulation of `boundary` (triangulate_boundary). Refuses
/// (TooManyPoints) beyond `max_points` points in all (0, or above kMaxPointsLimit: that
/// limit, which the front's packed ids need); `expected_points` (the
/// admission forecast, 0: unknown) sizes the arrays once instead of growing them, and each
/// time the points in all pass twice it, four times it and so on, the observer hears the
/// count (Observer::on_forecast). Throws GeometryError (density invalid, too many points),
/// Cancelled, or what the observer throws.
struct InteriorBudget {
    size_t max_points = 0;
    size_t expected_points = 0;
    /// Throw FieldJumps once this many candidates (and one more per 1,024 candidates made)
    /// have a size more than kFieldJump times off both ends of their segment; 0: never.
    std::uint64_t jumps_to_stop = 0;
    /// Memory the run holds besides what its points take (a gradation's sources): added to
    /// what the observer hears.
    size_t extra_bytes = 0;
};
/// Thrown by generate_interior_points (InteriorBudget::jumps_to_stop): the size field
/// changes faster than the front can follow. The pipeline catches it.
struct FieldJumps {};
Array<Vec2> generate_interior_points(const Domain& domain, const Discretisation& boundary,
                                     const BoundaryTriangulation& walls, const SizeField& rho,
                                     const InteriorOptions& options = {}, InteriorBudget budget = {},
                                     Observer* observer = nullptr, InteriorStats* stats = nullptr);

}  // namespace meshd::core
