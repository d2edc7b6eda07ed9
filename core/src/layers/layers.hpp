#pragma once
// Boundary layers: columns of thin cells grown from the graded points of wall curves.
//
// Each wall vertex gets a column along its normal into the domain (the bisector of the two
// wall normals there, lengthened by 1 / cos(half the turn) so that a layer keeps its height
// from both walls); a convex corner that turns by more than kFanTurnDeg gets a fan of
// columns. Column k's point sits at the height s_k = first_height (1 + growth + ... +
// growth^(k-1)). A column stops at `layers`, at `thickness`, or before a layer taller than
// rho there. A wall that ends on a curve without layers slides its end column along it (or,
// where the curve goes on almost straight, turns a fan round to it); an embedded curve that
// leaves a wall takes the nearest column onto it. Then the columns
// are cut back:
//   1. along their own ray, to less than half the distance to any other boundary segment,
//      leaving a strip of half the local size between facing layers;
//   2. neighbours' tops differ by at most a factor 2 in height (fewer layers spread smoothly);
//   3. until no cell is inverted and no edge of the layers crosses another edge of the
//      layers or of the boundary (exact predicates, the size-class grids of
//      kernel/crossings.hpp: linear in the number of edges per round).
// The outer edge of the layers (the columns' tops, and the end columns of a wall that ends
// on a curve without layers) replaces the wall in the discretisation: the isotropic
// interior is meshed up to it as up to any boundary.

#include <array>
#include <cstdint>
#include <vector>

#include "boundary/boundary.hpp"
#include "density/size_field.hpp"
#include "meshd/core/mesher.hpp"

namespace meshd::core {

/// Convex corners that turn by more than this get a fan of columns.
inline constexpr double kFanTurnDeg = 60.0;
/// The largest angle between two columns of a fan.
inline constexpr double kFanStepDeg = 30.0;

struct GrownLayers {
    /// The boundary as the layers leave it: the discretisation's points (same ids; those of
    /// lines that layers slide on spread over the rest of the line), then the sliding
    /// columns' points on those lines. Its segments are the mesh's boundary edges.
    Discretisation boundary;
    /// The same with the walls replaced by the layers' outer edge: `boundary`'s points first,
    /// then the outer edge's new points (curve kNoCurve).
    Discretisation front;
    /// The other layer points, appended to the mesh after everything else.
    std::vector<Vec2> hidden;
    /// Cells: ids below front.size() are front points; kHidden | j is hidden[j].
    static constexpr std::uint32_t kHidden = 0x80000000u;
    std::vector<std::array<std::uint32_t, 4>> quads;
    std::vector<std::array<std::uint32_t, 3>> triangles;
    std::vector<QualityMetrics::Layers> figures;  ///< per BoundaryLayerSpec
};

/// Grows the layers of `specs` on the discretisation `d`. Throws GeometryError when a spec
/// names no loop curve or the layers would pass max_points points (0: no limit), or
/// Cancelled.
GrownLayers grow_layers(const Domain& domain, const Discretisation& d, const SizeField& rho,
                        const std::vector<BoundaryLayerSpec>& specs, size_t max_points = 0,
                        Observer* observer = nullptr);

}  // namespace meshd::core
