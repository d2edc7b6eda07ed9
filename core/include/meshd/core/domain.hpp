#pragma once
/// The domain model of the paper's section 2: named points P, curves C with their ends in P,
/// loops of curves (one outer loop and holes) and embedded curves, with tags (boundary
/// markers) on curves.
///
/// DomainSpec is the description as a user writes it (it maps one to one onto the
/// `geometry` object of the service's request). build_domain() turns it into a Domain: it
/// constructs every curve, checks everything listed in the error kinds of errors.hpp and
/// fixes loop orientation so that the domain lies on the left of every loop (outer loop
/// counter-clockwise, holes clockwise).

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "meshd/core/observer.hpp"
#include "meshd/core/vec2.hpp"

namespace meshd::core {

class Curve;                 // the curve interface: src/geometry/curve.hpp
class CurveParametrisation;  // the same header

// ---------------------------------------------------------------------------------------
// The description, as a user writes it.

enum class ArcDirection { Ccw, Cw };

struct AirfoilPlacement {
    double chord = 1.0;
    Vec2 leading_edge{0.0, 0.0};
    /// Angle of attack in degrees: rotation about the leading edge, positive nose up.
    double angle_deg = 0.0;
};

enum class TrailingEdge {
    Closed,  ///< sharp trailing edge (NACA: the closed-edge thickness coefficient)
    Open,    ///< finite thickness, closed by a straight base line that belongs to the curve
};

enum class AirfoilSurface { Both, Upper, Lower };

struct NacaSpec {
    std::string code;  ///< "0012", "2412", "23012", "23112"
    AirfoilPlacement placement;
    TrailingEdge trailing_edge = TrailingEdge::Closed;
    /// Both: the closed contour (trailing edge, upper surface, leading edge, lower surface,
    /// trailing edge). Upper / Lower: the open curve from the trailing edge to the leading
    /// edge along that surface (for symmetry-plane domains).
    AirfoilSurface surface = AirfoilSurface::Both;
};

struct AirfoilSpec {
    std::string coordinates;  ///< the text of a Selig or Lednicer .dat file
    AirfoilPlacement placement;
    /// Open (default for files): a blunt trailing edge is kept and closed by a short line.
    /// Closed: a blunt trailing edge is made sharp by blending the gap into the surfaces.
    TrailingEdge trailing_edge = TrailingEdge::Open;
};

struct LineShape {};
struct ArcShape {
    Vec2 center;
    ArcDirection direction = ArcDirection::Ccw;
};
struct BSplineShape {
    std::vector<Vec2> control_points;
    int degree = 3;
    std::optional<std::vector<double>> knots;
};
struct SplineShape {
    std::vector<Vec2> through;
};
using CurveShape = std::variant<LineShape, ArcShape, BSplineShape, SplineShape, NacaSpec, AirfoilSpec>;

struct CurveSpec {
    std::string name;
    CurveShape shape;
    /// End point names. Required for lines and arcs; optional for the others, and when given
    /// they must name the points where the curve starts and ends.
    std::optional<std::string> from, to;
    /// Boundary marker; the curve's name when absent.
    std::optional<std::string> tag;
};

struct LoopItem {
    std::string curve;
    bool reversed = false;  ///< traversed from its end to its start ("-name")
};

struct DomainSpec {
    std::vector<std::pair<std::string, Vec2>> points;
    std::vector<CurveSpec> curves;
    std::vector<std::vector<LoopItem>> loops;
    std::vector<std::string> embedded;
};

// ---------------------------------------------------------------------------------------
// The validated domain.

using PointId = std::uint32_t;
using CurveId = std::uint32_t;
using TagId = std::uint32_t;
inline constexpr CurveId kNoCurve = UINT32_MAX;

struct DomainPoint {
    std::string name;  ///< empty for the unnamed end of a curve given without from/to
    Vec2 position;
};

/// A curve of the domain. Where an embedded curve ends on a curve away from its ends, that
/// curve is split there into parts that keep its name, tag and parameter; the touch point
/// is an end of each (DomainSpec's curves map to one or more DomainCurves).
struct DomainCurve {
    std::string name;
    TagId tag;
    std::shared_ptr<const Curve> geometry;
    PointId from, to;  ///< equal for a closed curve
    double length;     ///< arc length
    /// Arc length to parameter and back, built once with the domain (an airfoil's adaptive
    /// quadrature took 2 to 3 ms, and the boundary is placed several times per mesh).
    std::shared_ptr<const CurveParametrisation> arc_length;
};

struct CurveUse {
    CurveId curve;
    bool reversed;
};

struct DomainLoop {
    /// Curves in traversal order with the domain on the left.
    std::vector<CurveUse> items;
    int spec_index;  ///< position in DomainSpec::loops
    bool hole;
    double area;     ///< signed area of the traversal (> 0 outer, < 0 holes)
};

class Domain {
public:
    Domain();
    Domain(Domain&&) noexcept;
    Domain& operator=(Domain&&) noexcept;
    ~Domain();

    const std::vector<DomainPoint>& points() const { return points_; }
    const std::vector<DomainCurve>& curves() const { return curves_; }
    /// The outer loop first, then the holes in the order given.
    const std::vector<DomainLoop>& loops() const { return loops_; }
    const std::vector<CurveId>& embedded() const { return embedded_; }
    /// Each loop as a closed polygon (the first point not repeated), in loops() order with the
    /// domain on its left: the curves flattened to within a small fraction of the extent
    /// (kFlattenDeviation), from the geometry alone. The polygons do not cross.
    const std::vector<std::vector<Vec2>>& outlines() const { return outlines_; }
    const std::vector<std::string>& tags() const { return tags_; }
    /// Bounding box of all used curves.
    const Box& box() const { return box_; }
    double extent() const { return box_.diagonal(); }
    /// The curve of that name (its first part when it was split).
    std::optional<CurveId> find_curve(const std::string& name) const;
    /// Every part of the curve of that name, in its own direction (empty when unknown).
    const std::vector<CurveId>& curve_parts(const std::string& name) const;
    size_t hole_count() const { return loops_.empty() ? 0 : loops_.size() - 1; }

private:
    friend Domain build_domain(const DomainSpec& spec, Observer* observer);
    std::vector<DomainPoint> points_;
    std::vector<DomainCurve> curves_;
    std::vector<DomainLoop> loops_;
    std::vector<CurveId> embedded_;
    std::vector<std::vector<Vec2>> outlines_;
    std::vector<std::string> tags_;
    std::map<std::string, std::vector<CurveId>> curve_index_;
    Box box_;
};

/// Validates the description and builds the domain. Throws GeometryError naming the curves,
/// loops or points involved, or Cancelled when the observer asks to stop (it is asked between
/// curves and between the checks). Cost: O(n log n) in the size of the flattened curves.
Domain build_domain(const DomainSpec& spec, Observer* observer = nullptr);

}  // namespace meshd::core
