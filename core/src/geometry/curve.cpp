// The curve interface's shared parts: names, numerical arc length and its inverse, and the
// two simplest curve types (line and circular arc, paper sections 3.1 and 3.2).

#include "geometry/curve.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "geometry/bspline.hpp"
#include "meshd/core/errors.hpp"
#include "kernel/tolerances.hpp"

namespace meshd::core {

namespace {

// 8-point Gauss-Legendre rule on [-1, 1]: exact for polynomials of degree 15.
constexpr std::array<double, 4> kGlNodes = {0.1834346424956498, 0.5255324099163290,
                                            0.7966664774136267, 0.9602898564975363};
constexpr std::array<double, 4> kGlWeights = {0.3626837833783620, 0.3137066458778873,
                                              0.2223810344533745, 0.1012285362903763};

double gauss_length(const Curve& c, double a, double b) {
    const double half = 0.5 * (b - a);
    const double mid = 0.5 * (a + b);
    double sum = 0.0;
    for (size_t i = 0; i < kGlNodes.size(); ++i) {
        sum += kGlWeights[i] * (norm(c.derivative(mid - half * kGlNodes[i])) +
                                norm(c.derivative(mid + half * kGlNodes[i])));
    }
    return sum * half;
}

// Arc length on a piece [t0, t1] is modelled by the cubic Hermite interpolant of s(t) with
// the end values and the end speeds |C'|. Pieces are split until that cubic matches the
// Gauss-Legendre integral at the piece's quarter points within kArcLength relative to the
// curve's length, so both directions (s of t and t of s) need no curve evaluations.
struct Piece {
    double t0, t1;  // parameter interval
    double s0, s1;  // arc length at t0, t1
    double d0, d1;  // speed |C'| at t0, t1
};

// Hermite cubic of a piece at normalised u in [0, 1] (value and derivative in u).
inline double hermite(const Piece& p, double u) {
    const double dt = p.t1 - p.t0;
    const double u2 = u * u, u3 = u2 * u;
    return (2 * u3 - 3 * u2 + 1) * p.s0 + (u3 - 2 * u2 + u) * dt * p.d0 + (-2 * u3 + 3 * u2) * p.s1 +
           (u3 - u2) * dt * p.d1;
}
inline double hermite_du(const Piece& p, double u) {
    const double dt = p.t1 - p.t0;
    const double u2 = u * u;
    return (6 * u2 - 6 * u) * p.s0 + (3 * u2 - 4 * u + 1) * dt * p.d0 + (-6 * u2 + 6 * u) * p.s1 +
           (3 * u2 - 2 * u) * dt * p.d1;
}

class ArcLengthParametrisation final : public CurveParametrisation {
public:
    explicit ArcLengthParametrisation(const Curve& c) {
        std::vector<double> cuts{c.t_begin()};
        for (double b : c.breaks()) cuts.push_back(b);
        cuts.push_back(c.t_end());
        // A first estimate of the length sets the absolute accuracy.
        double rough = 0.0;
        for (size_t i = 0; i + 1 < cuts.size(); ++i) rough += gauss_length(c, cuts[i], cuts[i + 1]);
        abs_tol_ = tol::kArcLength * std::max(rough, 1e-300) + 1e-300;
        double s = 0.0;
        for (size_t i = 0; i + 1 < cuts.size(); ++i) {
            if (!(cuts[i + 1] > cuts[i])) continue;
            const double ta = cuts[i], tb = cuts[i + 1];
            // One-sided speeds at breaks: sample just inside the piece.
            const double eps = 1e-12 * (tb - ta);
            build(c, ta, tb, norm(c.derivative(ta + eps)), norm(c.derivative(tb - eps)), 0, s);
        }
        if (pieces_.empty()) pieces_.push_back({c.t_begin(), c.t_end(), 0.0, 0.0, 0.0, 0.0});
        total_ = s;
    }

    double length() const override { return total_; }

    double param_at(double s) const override {
        if (s <= 0.0) return pieces_.front().t0;
        if (s >= total_) return pieces_.back().t1;
        auto it = std::upper_bound(pieces_.begin(), pieces_.end(), s,
                                   [](double v, const Piece& p) { return v < p.s0; });
        const Piece& p = *(it - 1);
        if (!(p.s1 > p.s0)) return p.t0;
        // Solve hermite(u) = s on [0, 1]: Newton, safeguarded by bisection.
        double lo = 0.0, hi = 1.0;
        double u = (s - p.s0) / (p.s1 - p.s0);
        for (int iter = 0; iter < 60; ++iter) {
            const double f = hermite(p, u) - s;
            if (f > 0.0) hi = u; else lo = u;
            const double df = hermite_du(p, u);
            double next = df > 0.0 ? u - f / df : 0.5 * (lo + hi);
            if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
            if (std::fabs(next - u) <= 1e-15) { u = next; break; }
            u = next;
        }
        return p.t0 + u * (p.t1 - p.t0);
    }

    double spacing_at(double t) const override {
        if (t <= pieces_.front().t0) return 0.0;
        if (t >= pieces_.back().t1) return total_;
        auto it = std::upper_bound(pieces_.begin(), pieces_.end(), t,
                                   [](double v, const Piece& p) { return v < p.t0; });
        const Piece& p = *(it - 1);
        return hermite(p, (std::min(t, p.t1) - p.t0) / (p.t1 - p.t0));
    }

private:
    void build(const Curve& c, double a, double b, double da, double db, int depth, double& s) {
        const double m = 0.5 * (a + b);
        const double q1 = 0.25 * (3 * a + b), q3 = 0.25 * (a + 3 * b);
        const double l1 = gauss_length(c, a, q1), l2 = gauss_length(c, q1, m);
        const double l3 = gauss_length(c, m, q3), l4 = gauss_length(c, q3, b);
        const double whole = l1 + l2 + l3 + l4;
        Piece p{a, b, s, s + whole, da, db};
        const double err = std::max({std::fabs(hermite(p, 0.25) - (s + l1)),
                                     std::fabs(hermite(p, 0.5) - (s + l1 + l2)),
                                     std::fabs(hermite(p, 0.75) - (s + l1 + l2 + l3))});
        if (!std::isfinite(err) || pieces_.size() >= kMaxPieces)
            throw GeometryError(GeometryErrorKind::BadParameter,
                                "the curve's length cannot be computed: its shape is too extreme");
        if (depth >= 50 || err <= abs_tol_ || !(m > a && m < b)) {
            pieces_.push_back(p);
            s += whole;
            return;
        }
        const double dm = norm(c.derivative(m));
        build(c, a, m, da, dm, depth + 1, s);
        build(c, m, b, dm, db, depth + 1, s);
    }

    // A curve no flattening could follow with this many pieces is refused rather than
    // refined without end (a point far out makes every piece's error non-finite or huge).
    static constexpr size_t kMaxPieces = size_t{1} << 18;

    std::vector<Piece> pieces_;
    double total_ = 0.0;
    double abs_tol_ = 0.0;
};

// Curves of constant speed (lines, arcs): arc length is linear in the parameter.
class UniformParametrisation final : public CurveParametrisation {
public:
    explicit UniformParametrisation(const Curve& c)
        : t0_(c.t_begin()), t1_(c.t_end()), speed_(norm(c.derivative(c.t_begin()))) {}
    double length() const override { return speed_ * (t1_ - t0_); }
    double param_at(double s) const override {
        return std::clamp(t0_ + s / speed_, t0_, t1_);
    }
    double spacing_at(double t) const override { return speed_ * (std::clamp(t, t0_, t1_) - t0_); }

private:
    double t0_, t1_, speed_;
};

// ---------------------------------------------------------------------------------------

class LineCurve final : public Curve {
public:
    LineCurve(Vec2 a, Vec2 b) : a_(a), b_(b) {}
    CurveType type() const override { return CurveType::Line; }
    double t_begin() const override { return 0.0; }
    double t_end() const override { return 1.0; }
    Vec2 point(double t) const override {
        if (t >= 1.0) return b_;
        return lerp(a_, b_, t);
    }
    Vec2 derivative(double) const override { return b_ - a_; }
    double least_radius() const override { return HUGE_VAL; }

private:
    Vec2 a_, b_;
};

// Arc of a circle parametrised by the turned angle: C(t) = S + R (cos(a0 + sign t),
// sin(a0 + sign t)), t in [0, sweep].
class ArcCurve final : public Curve {
public:
    ArcCurve(Vec2 a, Vec2 b, Vec2 center, double radius, double a0, double sweep, double sign)
        : a_(a), b_(b), c_(center), r_(radius), a0_(a0), sweep_(sweep), sign_(sign) {}
    CurveType type() const override { return CurveType::Arc; }
    double t_begin() const override { return 0.0; }
    double t_end() const override { return sweep_; }
    Vec2 point(double t) const override {
        if (t <= 0.0) return a_;
        if (t >= sweep_) return b_;
        const double ang = a0_ + sign_ * t;
        return {c_.x + r_ * std::cos(ang), c_.y + r_ * std::sin(ang)};
    }
    Vec2 derivative(double t) const override {
        const double ang = a0_ + sign_ * t;
        return {-sign_ * r_ * std::sin(ang), sign_ * r_ * std::cos(ang)};
    }
    bool corner_at_ends() const override { return sweep_ < 2.0 * std::numbers::pi; }
    double least_radius() const override { return r_; }

private:
    Vec2 a_, b_, c_;
    double r_, a0_, sweep_, sign_;
};

}  // namespace

std::unique_ptr<CurveParametrisation> make_arc_length(const Curve& curve) {
    if (curve.type() == CurveType::Line || curve.type() == CurveType::Arc)
        return std::make_unique<UniformParametrisation>(curve);
    return std::make_unique<ArcLengthParametrisation>(curve);
}

std::unique_ptr<CurveParametrisation> make_parametrisation(const Curve& curve,
                                                           SplineSpacing mode) {
    if (mode == SplineSpacing::ControlPolygon) {
        if (const BSplineCurve* b = curve.as_bspline())
            return make_control_polygon_parametrisation(*b);
    }
    return make_arc_length(curve);
}

double curve_length(const Curve& curve) { return make_arc_length(curve)->length(); }

std::unique_ptr<Curve> make_line(Vec2 a, Vec2 b) {
    if (!is_finite(a) || !is_finite(b))
        throw GeometryError(GeometryErrorKind::NonFinite, "line end is not finite");
    if (a == b)
        throw GeometryError(GeometryErrorKind::ZeroLength, "line from a point to itself has zero length");
    return std::make_unique<LineCurve>(a, b);
}

std::unique_ptr<Curve> make_arc(Vec2 a, Vec2 b, Vec2 center, ArcDirection dir, bool full) {
    if (!is_finite(a) || !is_finite(b))
        throw GeometryError(GeometryErrorKind::NonFinite, "arc end is not finite");
    if (!is_finite(center))
        throw GeometryError(GeometryErrorKind::NonFinite, "arc centre is not finite",
                            {Subject::curve({}, {"center"})});
    const double ra = distance(center, a);
    const double rb = distance(center, b);
    if (!(ra > 0.0))
        throw GeometryError(GeometryErrorKind::ZeroLength, "arc start coincides with its centre",
                            {Subject::curve({}, {"center"})});
    if (std::fabs(rb - ra) > tol::kArcRadius * ra)
        throw GeometryError(GeometryErrorKind::ArcEndsOffCircle,
                            "arc ends are not on one circle about the centre: |from - center| = " +
                                std::to_string(ra) + ", |to - center| = " + std::to_string(rb),
                            {Subject::curve({}, {"center"})});
    const double pi = std::numbers::pi;
    const double a0 = std::atan2(a.y - center.y, a.x - center.x);
    const double b0 = std::atan2(b.y - center.y, b.x - center.x);
    const double sign = dir == ArcDirection::Ccw ? 1.0 : -1.0;
    double sweep;
    if (full) {
        sweep = 2.0 * pi;
    } else {
        if (a == b)
            throw GeometryError(GeometryErrorKind::ZeroLength, "arc from a point to itself");
        sweep = sign * (b0 - a0);
        while (sweep <= 0.0) sweep += 2.0 * pi;
        while (sweep > 2.0 * pi) sweep -= 2.0 * pi;
    }
    return std::make_unique<ArcCurve>(a, full ? a : b, center, ra, a0, sweep, sign);
}

}  // namespace meshd::core
