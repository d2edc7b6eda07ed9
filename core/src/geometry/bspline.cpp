// Clamped B-splines: evaluation by de Boor's algorithm, derivative through the derivative's
// control points, the paper's knot vector (3.33-3.35) and its control-polygon
// parametrisation (3.30-3.32).

#include "geometry/bspline.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "kernel/constructions.hpp"
#include "meshd/core/errors.hpp"
#include "kernel/tolerances.hpp"

namespace meshd::core {

namespace {

Vec2 de_boor(const std::vector<Vec2>& ctrl, const double* knots, int p, size_t k,
             double t) {
    // k is the knot span: knots[k] <= t < knots[k+1], p <= k <= n. make_bspline refuses
    // degrees above kMaxDegree, so the work array fits on the stack.
    Vec2 work[BSplineCurve::kMaxDegree + 1];
    const size_t up = static_cast<size_t>(p);
    for (size_t j = 0; j <= up; ++j) work[j] = ctrl[k - up + j];
    for (size_t r = 1; r <= up; ++r) {
        for (size_t j = up; j >= r; --j) {
            const size_t i = k - up + j;
            const double denom = knots[i + up + 1 - r] - knots[i];
            const double alpha = denom > 0.0 ? (t - knots[i]) / denom : 0.0;
            work[j] = (1.0 - alpha) * work[j - 1] + alpha * work[j];
        }
    }
    return work[up];
}

}  // namespace

BSplineCurve::BSplineCurve(std::vector<Vec2> control_points, int degree,
                           std::vector<double> knots, CurveType reported_type, bool c1_joins)
    : control_(std::move(control_points)),
      degree_(degree),
      knots_(std::move(knots)),
      type_(reported_type),
      c1_joins_(c1_joins) {
    const size_t p = static_cast<size_t>(degree_);
    if (p >= 1) {
        deriv_control_.reserve(control_.size() - 1);
        for (size_t i = 0; i + 1 < control_.size(); ++i) {
            const double dk = knots_[i + p + 1] - knots_[i + 1];
            const Vec2 q = dk > 0.0 ? (static_cast<double>(p) / dk) * (control_[i + 1] - control_[i])
                                    : Vec2{0.0, 0.0};
            deriv_control_.push_back(q);
        }
    }
}

size_t BSplineCurve::span(double t) const {
    const size_t p = static_cast<size_t>(degree_);
    const size_t n = control_.size() - 1;
    if (t >= knots_[n + 1]) {
        // Last non-empty span, so that the end point is reached.
        size_t k = n;
        while (k > p && knots_[k] >= knots_[k + 1]) --k;
        return k;
    }
    if (t <= knots_[p]) {
        size_t k = p;
        while (k < n && knots_[k] >= knots_[k + 1]) ++k;
        return k;
    }
    // knots[k] <= t < knots[k+1]
    auto it = std::upper_bound(knots_.begin() + static_cast<std::ptrdiff_t>(p),
                               knots_.begin() + static_cast<std::ptrdiff_t>(n + 1), t);
    return static_cast<size_t>(it - knots_.begin()) - 1;
}

Vec2 BSplineCurve::point(double t) const {
    t = std::clamp(t, t_begin(), t_end());
    if (t == t_begin()) return control_.front();
    if (t == t_end()) return control_.back();
    return de_boor(control_, knots_.data(), degree_, span(t), t);
}

Vec2 BSplineCurve::derivative(double t) const {
    t = std::clamp(t, t_begin(), t_end());
    const size_t k = span(t);
    // The derivative is a B-spline of degree p-1 on the knots without the first and last:
    // control point i of C' belongs to knot index i+1; its span index is k-1.
    if (degree_ == 1) return deriv_control_[k - 1];
    return de_boor(deriv_control_, knots_.data() + 1, degree_ - 1, k - 1, t);
}

std::vector<double> BSplineCurve::breaks() const {
    std::vector<double> out;
    const size_t p = static_cast<size_t>(degree_);
    const size_t n = control_.size() - 1;
    for (size_t i = p + 1; i <= n; ++i) {
        if (knots_[i] > t_begin() && knots_[i] < t_end() && (out.empty() || out.back() < knots_[i]))
            out.push_back(knots_[i]);
    }
    return out;
}

std::vector<double> BSplineCurve::corners() const {
    // A knot of multiplicity >= p makes the curve only C0 there: a corner when the one-sided
    // tangents point in different directions.
    std::vector<double> out;
    const size_t p = static_cast<size_t>(degree_);
    const size_t n = control_.size() - 1;
    size_t i = p + 1;
    while (i <= n) {
        size_t j = i;
        while (j + 1 <= n && knots_[j + 1] == knots_[i]) ++j;
        const size_t mult = j - i + 1;
        if (mult >= p && !c1_joins_) {
            // With multiplicity p the curve passes through control point i-1 and its one-sided
            // tangents are along the adjacent control polygon legs.
            const Vec2 left = control_[i - 1] - control_[i - 2];
            const Vec2 right = control_[i] - control_[i - 1];
            if (norm(left) > 0.0 && norm(right) > 0.0) {
                const double angle = angle_between(left, right);
                if (angle > tol::kCornerAngle) out.push_back(knots_[i]);
            }
        }
        i = j + 1;
    }
    return out;
}

bool BSplineCurve::corner_at_ends() const {
    const Vec2 a = derivative(t_begin());
    const Vec2 b = derivative(t_end());
    if (norm(a) == 0.0 || norm(b) == 0.0) return true;
    return angle_between(a, b) > tol::kCornerAngle;
}

double BSplineCurve::greville(size_t i) const {
    const size_t p = static_cast<size_t>(degree_);
    double s = 0.0;
    for (size_t j = 1; j <= p; ++j) s += knots_[i + j];
    return s / static_cast<double>(p);
}

std::vector<double> BSplineCurve::paper_knots(const std::vector<Vec2>& ctrl, int degree) {
    const size_t p = static_cast<size_t>(degree);
    const size_t n = ctrl.size() - 1;
    std::vector<double> cum(ctrl.size(), 0.0);
    for (size_t i = 1; i <= n; ++i) cum[i] = cum[i - 1] + distance(ctrl[i - 1], ctrl[i]);
    const double total = cum[n];
    std::vector<double> knots;
    knots.reserve(n + p + 2);
    for (size_t i = 0; i <= p; ++i) knots.push_back(0.0);
    for (size_t j = 1; j + p <= n; ++j) {
        double s = 0.0;
        for (size_t i = j; i < j + p; ++i) s += cum[i];
        knots.push_back(s / static_cast<double>(p));
    }
    for (size_t i = 0; i <= p; ++i) knots.push_back(total);
    return knots;
}

std::unique_ptr<Curve> make_bspline(std::vector<Vec2> ctrl, int degree,
                                    std::optional<std::vector<double>> knots) {
    if (degree < 1 || degree > BSplineCurve::kMaxDegree)
        throw GeometryError(GeometryErrorKind::BadDegree,
                            "B-spline degree must be between 1 and 15, got " +
                                std::to_string(degree),
                            {Subject::curve({}, {"degree"})});
    for (size_t i = 0; i < ctrl.size(); ++i) {
        if (!is_finite(ctrl[i]))
            throw GeometryError(GeometryErrorKind::NonFinite, "control point is not finite",
                                {Subject::curve({}, {"control_points", std::to_string(i)})});
    }
    const size_t p = static_cast<size_t>(degree);
    if (ctrl.size() < p + 1)
        throw GeometryError(GeometryErrorKind::TooFewControlPoints,
                            "a B-spline of degree " + std::to_string(degree) + " needs at least " +
                                std::to_string(p + 1) + " control points, got " +
                                std::to_string(ctrl.size()),
                            {Subject::curve({}, {"control_points"})});
    std::vector<double> u;
    if (knots) {
        u = std::move(*knots);
        const size_t want = ctrl.size() + p + 1;
        if (u.size() != want)
            throw GeometryError(GeometryErrorKind::BadKnots,
                                "expected " + std::to_string(want) + " knots (control points + degree + 1), got " +
                                    std::to_string(u.size()),
                                {Subject::curve({}, {"knots"})});
        for (size_t i = 0; i < u.size(); ++i) {
            if (!std::isfinite(u[i]))
                throw GeometryError(GeometryErrorKind::NonFinite, "knot is not finite",
                                    {Subject::curve({}, {"knots", std::to_string(i)})});
            if (i > 0 && u[i] < u[i - 1])
                throw GeometryError(GeometryErrorKind::BadKnots, "knots must not decrease",
                                    {Subject::curve({}, {"knots", std::to_string(i)})});
        }
        for (size_t i = 1; i <= p; ++i) {
            if (u[i] != u[0] || u[u.size() - 1 - i] != u.back())
                throw GeometryError(GeometryErrorKind::BadKnots,
                                    "knots must be clamped: the first and the last " +
                                        std::to_string(p + 1) + " knots must be equal",
                                    {Subject::curve({}, {"knots"})});
        }
        if (!(u.back() > u.front()))
            throw GeometryError(GeometryErrorKind::BadKnots, "knot vector spans an empty interval",
                                {Subject::curve({}, {"knots"})});
        for (size_t i = p + 1; i + p + 1 < u.size(); ++i) {
            size_t mult = 1;
            while (i + mult + p + 1 < u.size() && u[i + mult] == u[i]) ++mult;
            if (mult > p)
                throw GeometryError(GeometryErrorKind::BadKnots,
                                    "an interior knot repeats more than degree times",
                                    {Subject::curve({}, {"knots", std::to_string(i)})});
        }
    } else {
        u = BSplineCurve::paper_knots(ctrl, degree);
        if (!(u.back() > 0.0))
            throw GeometryError(GeometryErrorKind::ZeroLength, "all control points coincide",
                                {Subject::curve({}, {"control_points"})});
        for (size_t i = p + 1; i + p + 1 < u.size(); ++i) {
            if (u[i] <= u[i - 1] && i > p + 1)
                throw GeometryError(
                    GeometryErrorKind::BadKnots,
                    "consecutive control points coincide, so the paper's knot vector repeats a knot; "
                    "give knots explicitly or remove the duplicate",
                    {Subject::curve({}, {"control_points", std::to_string(i - p)})});
        }
    }
    return std::make_unique<BSplineCurve>(std::move(ctrl), degree, std::move(u));
}

namespace {

class ControlPolygonParametrisation final : public CurveParametrisation {
public:
    explicit ControlPolygonParametrisation(const BSplineCurve& c) {
        const auto& v = c.control_points();
        s_.push_back(0.0);
        t_.push_back(c.t_begin());
        double acc = 0.0;
        for (size_t i = 1; i < v.size(); ++i) {
            const double leg = distance(v[i - 1], v[i]);
            if (leg == 0.0) continue;  // coincident control points add no length
            acc += leg;
            const double g = i + 1 == v.size() ? c.t_end() : c.greville(i);
            s_.push_back(acc);
            t_.push_back(std::max(g, t_.back()));
        }
    }
    double length() const override { return s_.back(); }
    double param_at(double s) const override {
        if (s <= 0.0) return t_.front();
        if (s >= s_.back()) return t_.back();
        const size_t i = static_cast<size_t>(std::upper_bound(s_.begin(), s_.end(), s) - s_.begin());
        const double f = (s - s_[i - 1]) / (s_[i] - s_[i - 1]);
        return t_[i - 1] + f * (t_[i] - t_[i - 1]);
    }
    double spacing_at(double t) const override {
        if (t <= t_.front()) return 0.0;
        if (t >= t_.back()) return s_.back();
        const size_t i = static_cast<size_t>(std::upper_bound(t_.begin(), t_.end(), t) - t_.begin());
        const double dt = t_[i] - t_[i - 1];
        const double f = dt > 0.0 ? (t - t_[i - 1]) / dt : 0.0;
        return s_[i - 1] + f * (s_[i] - s_[i - 1]);
    }

private:
    std::vector<double> s_, t_;
};

}  // namespace

std::unique_ptr<CurveParametrisation> make_control_polygon_parametrisation(const BSplineCurve& c) {
    return std::make_unique<ControlPolygonParametrisation>(c);
}

}  // namespace meshd::core
