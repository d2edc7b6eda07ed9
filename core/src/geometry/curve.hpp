#pragma once
/// The curve interface of the domain model (paper, section 2: "any new type of curve can be
/// introduced"). Every curve is a map C: [t0, t1] -> R^2, topologically a segment; a closed
/// curve has C(t0) == C(t1). A new curve type is one new file implementing Curve plus a
/// factory declared below.
///
/// Breaks are parameters where the curve is not smooth (B-spline knots, the leading edge of
/// an airfoil): numerical integration splits there. Corners are the breaks where the tangent
/// turns; the point generator always places a point at a corner.

#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "meshd/core/domain.hpp"
#include "meshd/core/mesher.hpp"
#include "meshd/core/vec2.hpp"

namespace meshd::core {

enum class CurveType { Line, Arc, BSpline, Spline, Naca, Airfoil };

class Curve {
public:
    virtual ~Curve() = default;

    virtual CurveType type() const = 0;
    virtual double t_begin() const = 0;
    virtual double t_end() const = 0;
    /// C(t) for t in [t_begin, t_end].
    virtual Vec2 point(double t) const = 0;
    /// dC/dt. At a break it may be either one-sided value.
    virtual Vec2 derivative(double t) const = 0;
    /// Sorted parameters strictly inside (t_begin, t_end) where the curve is not C-infinity.
    virtual std::vector<double> breaks() const { return {}; }
    /// Sorted parameters strictly inside (t_begin, t_end) where the tangent direction jumps.
    virtual std::vector<double> corners() const { return {}; }
    /// True when the tangent direction jumps at the closing point of a closed curve.
    virtual bool corner_at_ends() const { return true; }
    /// A lower bound of the curve's radius of curvature everywhere (0 when not known; infinite
    /// for a straight curve). The boundary's sizes are capped by the curvature (shape_cap in
    /// boundary.cpp), which a size well below this bound cannot reach.
    virtual double least_radius() const { return 0.0; }
    /// The curve's own control polygon, when it has one (B-splines): the paper's
    /// section 3.3 parametrisation needs it.
    virtual const class BSplineCurve* as_bspline() const { return nullptr; }

    Vec2 start() const { return point(t_begin()); }
    Vec2 end() const { return point(t_end()); }
};

/// Maps a spacing coordinate s in [0, length()] to the curve parameter t, monotonically.
/// Points are generated on [0, length()] by the one-dimensional method of section 3.1 and
/// mapped onto the curve by C(t(s)).
class CurveParametrisation {
public:
    virtual ~CurveParametrisation() = default;
    virtual double length() const = 0;
    virtual double param_at(double s) const = 0;
    /// Inverse of param_at: the spacing coordinate of parameter t.
    virtual double spacing_at(double t) const = 0;
};

/// Arc-length parametrisation of any curve: adaptive Gauss-Legendre on each smooth piece,
/// a cumulative table, Newton with bisection safeguard to invert. O(pieces) memory,
/// O(log pieces) per query.
std::unique_ptr<CurveParametrisation> make_arc_length(const Curve& curve);

/// The parametrisation the point generator uses for this curve.
std::unique_ptr<CurveParametrisation> make_parametrisation(const Curve& curve,
                                                           SplineSpacing mode);

/// Arc length of the whole curve.
double curve_length(const Curve& curve);

// ---------------------------------------------------------------------------------------
// Factories. They throw GeometryError (with a field path relative to the curve, no curve
// name: the domain builder adds it).

std::unique_ptr<Curve> make_line(Vec2 a, Vec2 b);

/// Arc of the circle with centre `center` from a to b. When `full` the arc is the whole
/// circle starting and ending at a (b must equal a).
std::unique_ptr<Curve> make_arc(Vec2 a, Vec2 b, Vec2 center, ArcDirection dir, bool full);

/// Clamped B-spline of the given degree. Without knots, the paper's knot vector from the
/// control polygon's chord lengths (eqs. 3.33-3.35), see bspline.cpp.
std::unique_ptr<Curve> make_bspline(std::vector<Vec2> control_points, int degree,
                                    std::optional<std::vector<double>> knots);

/// C2 cubic spline through the points with chord-length parameters (a cubic B-spline
/// interpolating them). Periodic when the first and last points coincide and `allow_periodic`,
/// else natural end conditions.
std::unique_ptr<Curve> make_spline_through(std::vector<Vec2> points, bool allow_periodic = true);

std::unique_ptr<Curve> make_naca(const NacaSpec& spec);

/// Thickness and camber of a NACA section in chord units, exposed for tests and tools.
struct NacaSection {
    double thickness;  ///< half thickness y_t(x)
    double camber;     ///< y_c(x)
    double slope;      ///< dy_c/dx
};
NacaSection naca_section(const NacaSpec& spec, double x_over_c);

std::unique_ptr<Curve> make_airfoil(const AirfoilSpec& spec);

/// The curve `whole` restricted to [ta, tb] (t_begin <= ta < tb <= t_end), keeping its
/// parameter, breaks and corners. It has no control polygon of its own: its points are
/// spaced by arc length.
std::unique_ptr<Curve> make_part(std::shared_ptr<const Curve> whole, double ta, double tb);

/// The points of an airfoil file in contour order (trailing edge, upper surface, leading
/// edge, lower surface, trailing edge), in the file's own coordinates. Throws BadAirfoil.
struct AirfoilPoints {
    std::string name;        ///< first header line, when the file has one
    std::vector<Vec2> points;
    bool lednicer = false;   ///< the file was in Lednicer (two-surface) layout
};
AirfoilPoints parse_airfoil_dat(std::string_view text);

}  // namespace meshd::core
