#pragma once
// Boundary layers: columns of thin cells grown from the graded points of wall curves.
//
// Each wall vertex gets a column along its normal into the domain (the bisector of the two
// wall normals there, lengthened by 1 / cos(half the turn) so that a layer keeps its height
// from both walls); a convex corner that turns by more than kFanTurnDeg gets a fan of
// columns. Column k's point sits at the height s_k = first_height (1 + growth + ... +
// growth^(k-1)). A column stops at `layers`, at `thickness`, or before a layer taller than
// rho there. A wall that ends on a curve without layers slides its end column along it (or,
// where the curve leaves at a blunt angle, turns a fan round to it); an embedded curve that
// leaves a wall takes the nearest column onto it. Two fans in a row (the corners of a blunt
// trailing edge's short base) part their columns on the segment between them. Then the
// columns are cut back:
//   1. along their own ray, to less than half the distance to any other boundary segment,
//      leaving a strip of the local size between facing layers (a row of isotropic
//      triangles); two columns whose rays cross, both short of the crossing, but a ray that
//      passes over another column's foot meets that column as a boundary (cut_by_rays);
//   1b. until no two tops come closer than that strip (half of it from either side), but
//      tops on one base or on bases at most two apart along a wall: rays that pass beside
//      each other at a slant keep no strip between their tops;
//   2. the outer edge rises from one column's top to the next by at most half the way
//      across (fewer layers spread smoothly, whatever the wall's spacing);
//   3. until no cell is inverted, no edge of the layers crosses another edge of the
//      layers or of the boundary (exact predicates, the size-class grids of
//      kernel/crossings.hpp: linear in the number of edges per round) and no point of the
//      boundary lies inside a cell (an embedded line ending within a layer, crossing none
//      of its edges).
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

/// A column of the layers, as grow_layers grows it again: the wall point it stands on, its
/// direction as first grown (a fan's column split off later, split_wide_fans, goes by the
/// column it turns from), and a number of layers.
struct LayerColumn {
    VertexId base;
    Vec2 dir;
    int levels;
};

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
    /// Per point of `front`: the column it is a point of (an index into `columns`, whose
    /// `levels` is the point's level), or -1 (a wall point or another curve's).
    std::vector<std::int32_t> column_of;
    std::vector<LayerColumn> columns;
};

struct LayerPlan;

/// Grows the layers of `specs` on the discretisation `d`. Throws GeometryError when a spec
/// names no loop curve or the layers would pass max_points points (0: no limit), or
/// Cancelled. With `plan` (plan_layers on an earlier discretisation, whose fans spaced `d`
/// and `rho`), no fan stands more than kFanCapRatio times as tall as planned, and a fan the
/// plan lacks not at all. With `limits` (columns of an earlier growth on the same `d` and
/// `rho`), each column named there keeps at most its `levels` layers before the cut-backs.
GrownLayers grow_layers(const Domain& domain, const Discretisation& d, const SizeField& rho,
                        const std::vector<BoundaryLayerSpec>& specs, size_t max_points = 0,
                        Observer* observer = nullptr, const LayerPlan* plan = nullptr,
                        const std::vector<LayerColumn>* limits = nullptr);

/// The growth per element of the size cap at the fans' corners (LayerPlan::fans): gentler
/// than the curves' agreement (1.5), as the isotropic triangles meet the fan's short tops
/// and the walls' columns there at once.
inline constexpr double kFanCapRatio = 1.25;

/// What the layers of `specs` will do to the discretisation `d`, before it is final.
struct LayerPlan {
    /// The corners where the layers fan (convex corners and the fans that turn to a line a
    /// wall ends on), each with the distance between neighbouring tops of its fan after the
    /// cut-backs. The fan's columns are short: its tops lie closer together than the wall's
    /// points nearby. The pipeline spaces the walls and the field no coarser than that at
    /// the corner (growing by kFanCapRatio), so that the layers' outer edge, the front the
    /// interior grows from, passes from the fan to the wall's columns without a jump in
    /// spacing.
    SizeCaps fans;
    /// Per entry of `fans`: the height of its tallest column. The fan's tops lie apart in
    /// proportion to it; a fan that grew taller on the final walls (where the caps made rho
    /// smaller in a gap its columns face, so that they are cut back less) would stand its
    /// tops farther apart than the walls were spaced for.
    std::vector<double> fan_heights;
    /// Per curve: layers stand on it (the interior meets their outer edge, not the curve).
    std::vector<bool> walls;
    /// Wall segments whose columns' tops stand more than 1.5 times the field there apart (a
    /// convex wall under thick layers): caps at their middles that bring the tops to the
    /// field. The pipeline places the walls for these as for the fans.
    SizeCaps tops;
    /// `fans` and `tops` as one set of caps.
    SizeCaps caps() const {
        SizeCaps all = fans;
        all.points.insert(all.points.end(), tops.points.begin(), tops.points.end());
        all.sizes.insert(all.sizes.end(), tops.sizes.begin(), tops.sizes.end());
        return all;
    }
};

/// Rounds of planning the fans again on the walls placed for them (narrow_fans), at most.
inline constexpr int kReplanRounds = 2;

/// The fans of `plan` whose tops stand closer in `again` (the plan made again on the walls
/// placed for `plan`) by more than a fifth: their gaps and heights taken from `again`. Fans
/// of `again` that `plan` lacks (the first walls left them no room: every column cut back)
/// join it, and so do its caps for tops far apart (`tops`), new or more than a fifth smaller.
/// True when any changed or joined (the walls are then placed again).
bool narrow_fans(LayerPlan& plan, const LayerPlan& again);

/// Grows the layers' columns on `d` as grow_layers does (and throws what it throws), without
/// making their cells.
LayerPlan plan_layers(const Domain& domain, const Discretisation& d, const SizeField& rho,
                      const std::vector<BoundaryLayerSpec>& specs, size_t max_points = 0,
                      Observer* observer = nullptr);

}  // namespace meshd::core
