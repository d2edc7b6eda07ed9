#pragma once
/// Clamped B-spline curves (paper, section 3.3).
///
///   C(t) = sum_i V_i N_{i,p}(t),  t in [u_p, u_{n+1}]
///
/// with control points V_0..V_n, degree p and a clamped knot vector u_0..u_{n+p+1}
/// (first p+1 and last p+1 knots equal). The basis is evaluated by the standard Cox-de Boor
/// recursion (the paper's (3.27) is misprinted) in de Boor's triangular form.

#include <vector>

#include "geometry/curve.hpp"

namespace meshd::core {

class BSplineCurve final : public Curve {
public:
    /// Highest degree make_bspline accepts.
    static constexpr int kMaxDegree = 15;

    /// Preconditions (checked by make_bspline, not here): n + 1 >= p + 1, knots clamped and
    /// non-decreasing, size n + p + 2.
    BSplineCurve(std::vector<Vec2> control_points, int degree, std::vector<double> knots,
                 CurveType reported_type = CurveType::BSpline, bool c1_joins = false);

    CurveType type() const override { return type_; }
    double t_begin() const override { return knots_[static_cast<size_t>(degree_)]; }
    double t_end() const override { return knots_[control_.size()]; }
    Vec2 point(double t) const override;
    Vec2 derivative(double t) const override;
    std::vector<double> breaks() const override;
    std::vector<double> corners() const override;
    bool corner_at_ends() const override;
    const BSplineCurve* as_bspline() const override { return this; }

    int degree() const { return degree_; }
    const std::vector<Vec2>& control_points() const { return control_; }
    const std::vector<double>& knots() const { return knots_; }
    /// Greville abscissa of control point i: the mean of knots i+1..i+p.
    double greville(size_t i) const;

    /// The paper's default knots (eqs. 3.33-3.35) for these control points: clamped on
    /// [0, M], M the length of the control polygon, interior knots at the polygon length
    /// K(V) of the control points. The clamped vector has n - p interior knots but there are
    /// n - 1 interior control points, so for p > 1 knot j is the mean of K(V_j)..K(V_{j+p-1})
    /// (de Boor's averaging); for p = 1 this is exactly t_j = K(V_j).
    static std::vector<double> paper_knots(const std::vector<Vec2>& control_points, int degree);

private:
    size_t span(double t) const;

    std::vector<Vec2> control_;
    std::vector<Vec2> deriv_control_;  // control points of C', degree p - 1
    int degree_;
    std::vector<double> knots_;
    CurveType type_;
    bool c1_joins_;  // tangent continuous at every knot by construction (splines through points)
};

/// The paper's section 3.3 parametrisation: s is length along the control polygon; the
/// polygon length K(V_i) of control point i corresponds to its Greville abscissa, linearly
/// in between. For the paper's knots this is the map K of (3.31)-(3.35).
std::unique_ptr<CurveParametrisation> make_control_polygon_parametrisation(
    const BSplineCurve& curve);

}  // namespace meshd::core
