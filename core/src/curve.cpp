// The curve interface's shared parts: names, numerical arc length and its inverse, and the
// two simplest curve types (line and circular arc, paper sections 3.1 and 3.2).

#include "meshd/core/curve.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "meshd/core/bspline.hpp"
#include "meshd/core/errors.hpp"
#include "meshd/core/tolerances.hpp"

namespace meshd::core {

const char* to_string(CurveType type) {
    switch (type) {
        case CurveType::Line: return "line";
        case CurveType::Arc: return "arc";
        case CurveType::BSpline: return "bspline";
        case CurveType::Spline: return "spline";
        case CurveType::Naca: return "naca";
        case CurveType::Airfoil: return "airfoil";
    }
    return "?";
}

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

struct Piece {
    double t0, t1;  // parameter interval
    double s0;      // arc length at t0
};

class ArcLengthParametrisation final : public CurveParametrisation {
public:
    explicit ArcLengthParametrisation(const Curve& c) : curve_(c) {
        std::vector<double> cuts{c.t_begin()};
        for (double b : c.breaks()) cuts.push_back(b);
        cuts.push_back(c.t_end());
        double s = 0.0;
        for (size_t i = 0; i + 1 < cuts.size(); ++i) {
            if (cuts[i + 1] > cuts[i]) integrate(cuts[i], cuts[i + 1], gauss_length(c, cuts[i], cuts[i + 1]), 0, s);
        }
        if (pieces_.empty()) pieces_.push_back({c.t_begin(), c.t_end(), 0.0});
        total_ = s;
    }

    double length() const override { return total_; }

    double param_at(double s) const override {
        if (s <= 0.0) return pieces_.front().t0;
        if (s >= total_) return pieces_.back().t1;
        auto it = std::upper_bound(pieces_.begin(), pieces_.end(), s,
                                   [](double v, const Piece& p) { return v < p.s0; });
        const Piece& p = *(it - 1);
        const double target = s - p.s0;
        const double piece_len = (it == pieces_.end() ? total_ : it->s0) - p.s0;
        double lo = p.t0, hi = p.t1;
        double t = piece_len > 0.0 ? p.t0 + (p.t1 - p.t0) * (target / piece_len) : p.t0;
        for (int iter = 0; iter < 60; ++iter) {
            const double f = gauss_length(curve_, p.t0, t) - target;
            if (std::fabs(f) <= 1e-14 * std::max(total_, 1e-300)) break;
            if (f > 0.0) hi = t; else lo = t;
            const double speed = norm(curve_.derivative(t));
            double next = speed > 0.0 ? t - f / speed : 0.5 * (lo + hi);
            if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
            if (next == t || hi - lo <= 1e-16 * std::fabs(hi)) { t = next; break; }
            t = next;
        }
        return t;
    }

    double spacing_at(double t) const override {
        if (t <= pieces_.front().t0) return 0.0;
        if (t >= pieces_.back().t1) return total_;
        auto it = std::upper_bound(pieces_.begin(), pieces_.end(), t,
                                   [](double v, const Piece& p) { return v < p.t0; });
        const Piece& p = *(it - 1);
        return p.s0 + gauss_length(curve_, p.t0, std::min(t, p.t1));
    }

private:
    // Adaptive Gauss-Legendre: split until the two halves agree with the whole.
    void integrate(double a, double b, double whole, int depth, double& s) {
        const double m = 0.5 * (a + b);
        const double left = gauss_length(curve_, a, m);
        const double right = gauss_length(curve_, m, b);
        const double err = std::fabs(left + right - whole);
        if (depth >= 40 || err <= tol::kArcLength * std::max(left + right, 1e-300) ||
            !(m > a && m < b)) {
            pieces_.push_back({a, m, s});
            s += left;
            pieces_.push_back({m, b, s});
            s += right;
            return;
        }
        integrate(a, m, left, depth + 1, s);
        integrate(m, b, right, depth + 1, s);
    }

    const Curve& curve_;
    std::vector<Piece> pieces_;
    double total_ = 0.0;
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
