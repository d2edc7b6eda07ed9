// NACA four- and five-digit airfoils, evaluated from their defining formulas.
//
// Chordwise position uses cosine spacing x = (1 - cos beta) / 2, beta in [0, pi], which makes
// sqrt(x) = sin(beta / 2) smooth at the leading edge, so arc length integrates accurately.
// Thickness: y_t = 5 t (0.2969 sqrt(x) - 0.1260 x - 0.3516 x^2 + 0.2843 x^3 - a4 x^4), with
// a4 = 0.1015 (open, blunt trailing edge) or 0.1036 (closed). The thickness is laid off
// perpendicular to the camber line. Camber lines:
// - 4 digits MPTT: m = M/100 at p = P/10, two parabolas meeting at p;
// - 5 digits LPSTT: design lift 3L/20, maximum camber at P/20, S = 1 reflexed; the cubic
//   camber line with the tabulated r, k1 (and k2/k1 when reflexed) for a design lift of 0.3,
//   scaled linearly with the design lift.
//
// Parameter u of the closed contour: [0, 1] upper surface from trailing to leading edge,
// [1, 2] lower surface back to the trailing edge, [2, 3] the straight base of an open
// trailing edge. That order is counter-clockwise.

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <numbers>

#include "geometry/composite.hpp"
#include "geometry/curve.hpp"
#include "meshd/core/errors.hpp"

namespace meshd::core {

namespace {

constexpr double kPi = std::numbers::pi;

struct Camber {
    double yc, slope, curvature;  // y_c, dy_c/dx, d2y_c/dx2
};

class NacaProfile {
public:
    explicit NacaProfile(const NacaSpec& spec) : spec_(spec) {
        const std::string& c = spec.code;
        for (char ch : c) {
            if (!std::isdigit(static_cast<unsigned char>(ch)))
                throw bad("NACA code must consist of digits, got \"" + c + "\"");
        }
        auto digit = [&](size_t i) { return c[i] - '0'; };
        if (c.size() == 4) {
            m_ = digit(0) / 100.0;
            p_ = digit(1) / 10.0;
            t_ = (digit(2) * 10 + digit(3)) / 100.0;
            if (m_ > 0.0 && p_ == 0.0)
                throw bad("NACA " + c + ": a cambered section needs a position of maximum camber");
            if (m_ == 0.0) p_ = 0.0;
            series_ = 4;
        } else if (c.size() == 5) {
            const int l = digit(0), p = digit(1), s = digit(2);
            t_ = (digit(3) * 10 + digit(4)) / 100.0;
            // Design lift 0.3 values, maximum camber at 0.05 .. 0.25 of the chord.
            static constexpr std::array<double, 5> kR = {0.0580, 0.1260, 0.2025, 0.2900, 0.3910};
            static constexpr std::array<double, 5> kK1 = {361.400, 51.640, 15.957, 6.643, 3.230};
            static constexpr std::array<double, 5> kRefR = {0.0, 0.1300, 0.2170, 0.3180, 0.4410};
            static constexpr std::array<double, 5> kRefK1 = {0.0, 51.990, 15.793, 6.520, 3.191};
            static constexpr std::array<double, 5> kRefK21 = {0.0, 0.000764, 0.00677, 0.0303, 0.1355};
            if (s > 1) throw bad("NACA " + c + ": the third digit must be 0 (normal) or 1 (reflex)");
            if (p < 1 || p > 5 || (s == 1 && p < 2))
                throw bad("NACA " + c + ": no tabulated camber line for this position digit");
            if (l < 1) throw bad("NACA " + c + ": the design lift digit must be at least 1");
            const size_t i = static_cast<size_t>(p - 1);
            reflex_ = s == 1;
            r_ = reflex_ ? kRefR[i] : kR[i];
            k1_ = (reflex_ ? kRefK1[i] : kK1[i]) * (0.15 * l / 0.3);
            k21_ = reflex_ ? kRefK21[i] : 0.0;
            series_ = 5;
        } else {
            throw bad("NACA code must have 4 or 5 digits, got \"" + c + "\"");
        }
        if (!(t_ > 0.0)) throw bad("NACA " + c + ": thickness must be positive");
        if (!(spec.placement.chord > 0.0) || !std::isfinite(spec.placement.chord))
            throw GeometryError(GeometryErrorKind::BadParameter, "chord must be positive and finite",
                                {Subject::curve({}, {"chord"})});
        if (!is_finite(spec.placement.leading_edge))
            throw GeometryError(GeometryErrorKind::NonFinite, "leading edge is not finite",
                                {Subject::curve({}, {"leading_edge"})});
        if (!std::isfinite(spec.placement.angle_deg))
            throw GeometryError(GeometryErrorKind::NonFinite, "angle is not finite",
                                {Subject::curve({}, {"angle_deg"})});
        a4_ = spec.trailing_edge == TrailingEdge::Closed ? 0.1036 : 0.1015;
        const double a = spec.placement.angle_deg * kPi / 180.0;
        cos_ = std::cos(a);
        sin_ = std::sin(a);
    }

    Camber camber(double x) const {
        if (series_ == 4) {
            if (m_ == 0.0) return {0.0, 0.0, 0.0};
            if (x < p_) {
                const double f = m_ / (p_ * p_);
                return {f * (2.0 * p_ * x - x * x), 2.0 * f * (p_ - x), -2.0 * f};
            }
            const double f = m_ / ((1.0 - p_) * (1.0 - p_));
            return {f * ((1.0 - 2.0 * p_) + 2.0 * p_ * x - x * x), 2.0 * f * (p_ - x), -2.0 * f};
        }
        const double r = r_, k = k1_ / 6.0, r3 = r * r * r;
        if (!reflex_) {
            if (x < r)
                return {k * (x * x * x - 3.0 * r * x * x + r * r * (3.0 - r) * x),
                        k * (3.0 * x * x - 6.0 * r * x + r * r * (3.0 - r)), k * (6.0 * x - 6.0 * r)};
            return {k * r3 * (1.0 - x), -k * r3, 0.0};
        }
        const double q = k21_, omr3 = (1.0 - r) * (1.0 - r) * (1.0 - r);
        const double d = x - r;
        if (x < r)
            return {k * (d * d * d - q * omr3 * x - r3 * x + r3), k * (3.0 * d * d - q * omr3 - r3),
                    k * 6.0 * d};
        return {k * (q * d * d * d - q * omr3 * x - r3 * x + r3),
                k * (3.0 * q * d * d - q * omr3 - r3), k * 6.0 * q * d};
    }

    /// Half thickness at x = sin^2(beta/2), with sqrt(x) passed in to stay smooth.
    double thickness(double x, double sx) const {
        return 5.0 * t_ * (0.2969 * sx + x * (-0.1260 + x * (-0.3516 + x * (0.2843 - a4_ * x))));
    }
    double thickness_dx_poly(double x) const {  // d/dx of the polynomial part
        return 5.0 * t_ * (-0.1260 + x * (-0.7032 + x * (0.8529 - 4.0 * a4_ * x)));
    }

    /// Point and derivative (with respect to beta) of a surface in chord units.
    /// upper: +1 for the upper surface, -1 for the lower.
    void surface(double beta, double upper, Vec2& pt, Vec2& d) const {
        const double x = 0.5 * (1.0 - std::cos(beta));
        const double sx = std::sin(0.5 * beta);
        const double dx = 0.5 * std::sin(beta);
        const double yt = thickness(x, sx);
        const double dyt = 5.0 * t_ * 0.2969 * 0.5 * std::cos(0.5 * beta) + thickness_dx_poly(x) * dx;
        const Camber cb = camber(x);
        const double th = std::atan(cb.slope);
        const double dth = cb.curvature / (1.0 + cb.slope * cb.slope) * dx;
        const double st = std::sin(th), ct = std::cos(th);
        pt = {x - upper * yt * st, cb.yc + upper * yt * ct};
        d = {dx - upper * (dyt * st + yt * ct * dth), cb.slope * dx + upper * (dyt * ct - yt * st * dth)};
    }

    Vec2 place(Vec2 q) const {
        const double c = spec_.placement.chord;
        // Rotation by -angle about the leading edge: positive angle raises the nose.
        return {spec_.placement.leading_edge.x + c * (cos_ * q.x + sin_ * q.y),
                spec_.placement.leading_edge.y + c * (-sin_ * q.x + cos_ * q.y)};
    }
    Vec2 place_dir(Vec2 q) const {
        const double c = spec_.placement.chord;
        return {c * (cos_ * q.x + sin_ * q.y), c * (-sin_ * q.x + cos_ * q.y)};
    }

    NacaSection section(double x) const {
        const Camber cb = camber(x);
        return {thickness(x, std::sqrt(x)), cb.yc, cb.slope};
    }

private:
    static GeometryError bad(const std::string& msg) {
        return GeometryError(GeometryErrorKind::BadNaca, msg, {Subject::curve({}, {"code"})});
    }

    NacaSpec spec_;
    int series_ = 4;
    double m_ = 0.0, p_ = 0.0, t_ = 0.0;
    bool reflex_ = false;
    double r_ = 0.0, k1_ = 0.0, k21_ = 0.0;
    double a4_ = 0.1036;
    double cos_ = 1.0, sin_ = 0.0;
};

// One or both surfaces. Both: u in [0, 2] as described at the top of the file.
// Single surface: u in [0, 1] from trailing to leading edge.
class NacaSurfaces final : public Curve {
public:
    NacaSurfaces(NacaProfile profile, AirfoilSurface which, bool closed_te)
        : prof_(std::move(profile)), which_(which) {
        Vec2 d;
        prof_.surface(kPi, 1.0, te_upper_, d);
        prof_.surface(kPi, -1.0, te_lower_, d);
        te_upper_ = prof_.place(te_upper_);
        te_lower_ = prof_.place(te_lower_);
        le_ = prof_.place({0.0, 0.0});
        if (closed_te) {
            // The closed-edge thickness vanishes at x = 1 up to rounding: make the ends equal.
            te_upper_ = te_lower_ = 0.5 * (te_upper_ + te_lower_);
        }
    }
    CurveType type() const override { return CurveType::Naca; }
    double t_begin() const override { return 0.0; }
    double t_end() const override { return which_ == AirfoilSurface::Both ? 2.0 : 1.0; }
    Vec2 point(double u) const override {
        Vec2 p, d;
        eval(u, p, d);
        return p;
    }
    Vec2 derivative(double u) const override {
        Vec2 p, d;
        eval(u, p, d);
        return d;
    }
    std::vector<double> breaks() const override {
        return which_ == AirfoilSurface::Both ? std::vector<double>{1.0} : std::vector<double>{};
    }

    Vec2 te_upper() const { return te_upper_; }
    Vec2 te_lower() const { return te_lower_; }

private:
    void eval(double u, Vec2& p, Vec2& d) const {
        u = std::clamp(u, t_begin(), t_end());
        const bool on_upper =
            which_ == AirfoilSurface::Upper || (which_ == AirfoilSurface::Both && u <= 1.0);
        if (u == 0.0) {
            p = which_ == AirfoilSurface::Lower ? te_lower_ : te_upper_;
        } else if (u == t_end() && which_ == AirfoilSurface::Both) {
            p = te_lower_;
        } else if (u == 1.0 && which_ != AirfoilSurface::Both) {
            p = le_;
        }
        double beta, dbeta;
        if (which_ == AirfoilSurface::Both && u > 1.0) {
            beta = kPi * (u - 1.0);
            dbeta = kPi;
        } else {
            beta = kPi * (1.0 - u);
            dbeta = -kPi;
        }
        Vec2 q, dq;
        prof_.surface(beta, on_upper ? 1.0 : -1.0, q, dq);
        const bool fixed = u == 0.0 || u == t_end() || (u == 1.0 && which_ != AirfoilSurface::Both);
        if (!fixed) p = prof_.place(q);
        d = dbeta * prof_.place_dir(dq);
    }

    NacaProfile prof_;
    AirfoilSurface which_;
    Vec2 te_upper_, te_lower_, le_;
};

}  // namespace

NacaSection naca_section(const NacaSpec& spec, double x_over_c) {
    return NacaProfile(spec).section(x_over_c);
}

std::unique_ptr<Curve> make_naca(const NacaSpec& spec) {
    NacaProfile profile(spec);
    auto surfaces = std::make_unique<NacaSurfaces>(std::move(profile), spec.surface,
                                                   spec.trailing_edge == TrailingEdge::Closed);
    if (spec.surface != AirfoilSurface::Both || spec.trailing_edge == TrailingEdge::Closed) {
        return surfaces;
    }
    const Vec2 lower = surfaces->te_lower(), upper = surfaces->te_upper();
    std::vector<std::unique_ptr<Curve>> pieces;
    pieces.push_back(std::move(surfaces));
    pieces.push_back(make_line(lower, upper));
    return std::make_unique<detail::CompositeCurve>(CurveType::Naca, std::move(pieces));
}

}  // namespace meshd::core
