#pragma once
/// Graded points on all curves of a domain (paper, section 3) and the resulting boundary
/// polygons.
///
/// Each used curve is discretised once, in its own direction, from its start to its end,
/// split at its corners (which are always points); the points follow rho by the method of
/// section 3.1 applied to the curve's spacing coordinate (arc length, or for B-splines
/// optionally the control-polygon length of section 3.3). Curve ends are the shared points
/// of the domain. Loops are closed polygons with the domain on their left; embedded curves
/// are polylines.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "density/size_field.hpp"
#include "meshd/core/domain.hpp"
#include "meshd/core/observer.hpp"
#include "triangulation/triangulation.hpp"

namespace meshd::core {

struct BoundaryOptions {
    SplineSpacing spline_spacing = SplineSpacing::ArcLength;
    /// Refuse (TooManyPoints) when more boundary points would be made. 0: no limit.
    size_t max_points = 0;
};

struct BoundarySegment {
    VertexId a, b;  ///< domain on the left of a -> b for loop segments
    CurveId curve;
};

/// What placing one curve's points read of rho (SizeField::on_curve): where, the largest
/// value, and how many stations its profiles took. A cap of rho whose cones stay at or above
/// that value over the box leaves the curve's points as they were.
struct CurveReads {
    Box box;
    double largest = 0.0;
    size_t stations = 0;
    double floor = 0.0;  ///< the profile's floor it was placed with (sample_density)
};

struct Discretisation {
    // Points, struct of arrays.
    std::vector<double> x, y;
    std::vector<CurveId> curve;   ///< owning curve; kNoCurve for domain points (curve ends)
    std::vector<double> param;    ///< curve parameter t (0 for domain points)
    /// rho at each point as the points were placed: the curve's density, capped where it
    /// would not keep the curve's shape (kMaxSegmentTurn); at a curve end, the smallest of
    /// the curves meeting there.
    std::vector<double> rho;

    /// Per domain curve, the sizes it placed its start and its end for (a curve end's `rho`
    /// is the smallest of the curves meeting there).
    std::vector<std::array<double, 2>> end_rho;
    /// Per domain curve, its vertices from start to end (empty for unused curves).
    std::vector<std::vector<VertexId>> curve_vertices;
    /// Per domain curve, what placing it read of rho.
    std::vector<CurveReads> reads;
    /// Loops in Domain::loops() order, each a cycle of vertices (the first not repeated).
    std::vector<std::vector<VertexId>> loops;
    /// Embedded curves in Domain::embedded() order, as polylines.
    std::vector<std::vector<VertexId>> embedded;
    /// All segments: the loops' (domain on the left) in loop order, then the embedded.
    std::vector<BoundarySegment> segments;
    size_t loop_segment_count = 0;

    size_t size() const { return x.size(); }
    Vec2 point(VertexId v) const { return {x[v], y[v]}; }
};

/// Fills loops, embedded and segments of `d` from its curve_vertices, in the domain's order.
void link_loops(const Domain& domain, Discretisation& d);

/// Curves whose points an earlier discretisation placed for the same rho along them (a cap
/// since that does not reach them): taken from it as they are.
struct KeptCurves {
    const Discretisation& from;
    std::vector<bool> keep;  ///< per domain curve
};

/// discretise_boundary's refusal of chords that cross one another or leave a loop or an
/// embedded curve out of the domain (or in a hole) where the curves do not: a density too
/// coarse for the gap between two curves. Carries the middle of each offending chord with half
/// its length, a cap of the curves' spacing there that the caller may try (generate_mesh does).
class CoarseChords : public GeometryError {
public:
    CoarseChords(std::string message, std::vector<Subject> subjects, SizeCaps finer)
        : GeometryError(GeometryErrorKind::DiscretisationCrosses, std::move(message), std::move(subjects)),
          finer_(std::move(finer)) {}
    const SizeCaps& finer() const { return finer_; }

private:
    SizeCaps finer_;
};

/// Throws GeometryError (density invalid on a curve, too many points, the discretised
/// polygons running the wrong way), CoarseChords or Cancelled. The curves `kept` marks are
/// copied from its discretisation, the same points as placing them again would give.
Discretisation discretise_boundary(const Domain& domain, const SizeField& rho,
                                   const BoundaryOptions& options = {},
                                   Observer* observer = nullptr, const KeptCurves* kept = nullptr);

/// The constrained Delaunay triangulation of the discretised boundary alone (no interior
/// points), built once per mesh: the point estimate, the gradation samples and the
/// interior's walks through the domain all use it.
struct BoundaryTriangulation {
    Array<Vec2> points;  ///< the discretisation's points, in its order
    Array<Triangle> triangles;
};
BoundaryTriangulation triangulate_boundary(const Discretisation& d);

/// The discretisation as a triangulator's input: its points, and its segments as constraints
/// (loop segments marked as loops).
Array<Vec2> points_of(const Discretisation& d);
std::vector<Constraint> constraints_of(const Discretisation& d);

/// Sets the sources of eq. 6.1 from the discretisation: every segment's start and length.
void set_interpolation_sources(SizeField& rho, const Discretisation& d);

/// How well segment lengths follow rho: for each segment AB the ratio
/// |AB| / ((rho(A) + rho(B)) / 2), where rho is the size the points were placed for (the
/// curve's density, capped where it would not keep the curve's shape).
struct SpacingStats {
    size_t segments = 0;
    double mean_abs_error = 0.0;  ///< mean |ratio - 1|
    double max_abs_error = 0.0;   ///< max |ratio - 1|
    double rms_error = 0.0;
    double min_ratio = 0.0, max_ratio = 0.0;
};
/// Statistics per curve (indexed by CurveId; empty stats for unused curves) and overall.
struct SpacingReport {
    std::vector<SpacingStats> per_curve;
    SpacingStats overall;
};
SpacingReport spacing_report(const Domain& domain, const Discretisation& d);

}  // namespace meshd::core
