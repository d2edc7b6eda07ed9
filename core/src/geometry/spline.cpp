// Cubic spline through points (the paper's "boundary given by a set of points, approximated
// by B-splines", introduction and section 3.3).
//
// The interpolant is the C2 piecewise cubic with chord-length parameters: node tangents D_k
// solve the tridiagonal system of second-derivative continuity (natural ends) or its cyclic
// version (closed curves). Each cubic piece is then written in Bezier form, so the result is
// a cubic B-spline whose interior knots have multiplicity 3 and whose control polygon hugs the
// curve closely. Linear time in the number of points.

#include <cmath>
#include <string>

#include "geometry/composite.hpp"
#include "geometry/bspline.hpp"
#include "meshd/core/errors.hpp"

namespace meshd::core {

namespace {

// Solves the tridiagonal system a_i x_{i-1} + b_i x_i + c_i x_{i+1} = d_i (Thomas algorithm).
void solve_tridiagonal(std::vector<double> a, std::vector<double> b, std::vector<double> c,
                       std::vector<Vec2>& d) {
    const size_t n = b.size();
    for (size_t i = 1; i < n; ++i) {
        const double w = a[i] / b[i - 1];
        b[i] -= w * c[i - 1];
        d[i] -= w * d[i - 1];
    }
    d[n - 1] = d[n - 1] / b[n - 1];
    for (size_t i = n - 1; i-- > 0;) d[i] = (d[i] - c[i] * d[i + 1]) / b[i];
}

// Cyclic tridiagonal: a_0 multiplies x_{n-1}, c_{n-1} multiplies x_0 (Sherman-Morrison).
void solve_cyclic(const std::vector<double>& a, std::vector<double> b, const std::vector<double>& c,
                  std::vector<Vec2>& d) {
    const size_t n = b.size();
    const double alpha = c[n - 1];  // row n-1, column 0
    const double beta = a[0];       // row 0, column n-1
    const double gamma = -b[0];
    b[0] -= gamma;
    b[n - 1] -= alpha * beta / gamma;
    std::vector<Vec2> u(n, Vec2{0.0, 0.0});
    u[0] = {gamma, gamma};
    u[n - 1] = {alpha, alpha};
    solve_tridiagonal(a, b, c, d);
    solve_tridiagonal(a, b, c, u);
    // z = A'^{-1} u (same in both components), v = (1, 0, ..., 0, beta / gamma)
    const double vz = u[0].x + beta / gamma * u[n - 1].x;
    const double vx = d[0].x + beta / gamma * d[n - 1].x;
    const double vy = d[0].y + beta / gamma * d[n - 1].y;
    const double fx = vx / (1.0 + vz), fy = vy / (1.0 + vz);
    for (size_t i = 0; i < n; ++i) d[i] = {d[i].x - fx * u[i].x, d[i].y - fy * u[i].x};
}

}  // namespace

std::unique_ptr<Curve> detail::make_spline(std::vector<Vec2> input, bool allow_periodic,
                                           CurveType type) {
    for (size_t i = 0; i < input.size(); ++i) {
        if (!is_finite(input[i]))
            throw GeometryError(GeometryErrorKind::NonFinite, "spline point is not finite",
                                {Subject::curve({}, {"through", std::to_string(i)})});
    }
    // Consecutive duplicates carry no information (a repeated leading-edge point, say).
    std::vector<Vec2> p;
    p.reserve(input.size());
    for (Vec2 q : input)
        if (p.empty() || !(q == p.back())) p.push_back(q);
    const bool closed = p.size() > 2 && p.front() == p.back();
    if (p.size() < 2 || (closed && p.size() < 4))
        throw GeometryError(GeometryErrorKind::TooFewControlPoints,
                            "a spline needs at least 2 distinct points (3 when closed)",
                            {Subject::curve({}, {"through"})});
    const bool periodic = closed && allow_periodic;

    const size_t n = p.size() - 1;  // number of pieces
    std::vector<double> h(n);
    for (size_t k = 0; k < n; ++k) h[k] = distance(p[k], p[k + 1]);

    std::vector<Vec2> tangent;
    if (periodic) {
        // Unknowns D_0..D_{n-1}; node n is node 0.
        std::vector<double> a(n), b(n), c(n);
        tangent.assign(n, Vec2{});
        for (size_t k = 0; k < n; ++k) {
            const size_t km = (k + n - 1) % n;
            const double hp = h[km], hk = h[k];
            a[k] = hk;
            b[k] = 2.0 * (hp + hk);
            c[k] = hp;
            tangent[k] = 3.0 * (hk / hp * (p[k] - p[km]) + hp / hk * (p[k + 1] - p[k]));
        }
        if (n == 2) {
            // Degenerate cyclic case: the two couplings fall on the same entries.
            const Vec2 d0 = tangent[0], d1 = tangent[1];
            const double a00 = b[0], a01 = a[0] + c[0], a10 = a[1] + c[1], a11 = b[1];
            const double det = a00 * a11 - a01 * a10;
            tangent[0] = (a11 * d0 - a01 * d1) / det;
            tangent[1] = (a00 * d1 - a10 * d0) / det;
        } else {
            solve_cyclic(a, b, c, tangent);
        }
        tangent.push_back(tangent[0]);
    } else {
        std::vector<double> a(n + 1), b(n + 1), c(n + 1);
        tangent.assign(n + 1, Vec2{});
        a[0] = 0.0; b[0] = 2.0; c[0] = 1.0;
        tangent[0] = 3.0 * (p[1] - p[0]) / h[0];
        for (size_t k = 1; k < n; ++k) {
            a[k] = h[k];
            b[k] = 2.0 * (h[k - 1] + h[k]);
            c[k] = h[k - 1];
            tangent[k] = 3.0 * (h[k] / h[k - 1] * (p[k] - p[k - 1]) + h[k - 1] / h[k] * (p[k + 1] - p[k]));
        }
        a[n] = 1.0; b[n] = 2.0; c[n] = 0.0;
        tangent[n] = 3.0 * (p[n] - p[n - 1]) / h[n - 1];
        solve_tridiagonal(a, b, c, tangent);
    }

    std::vector<Vec2> ctrl;
    ctrl.reserve(3 * n + 1);
    std::vector<double> knots;
    knots.reserve(3 * n + 5);
    double t = 0.0;
    for (int i = 0; i < 4; ++i) knots.push_back(0.0);
    for (size_t k = 0; k < n; ++k) {
        ctrl.push_back(p[k]);
        ctrl.push_back(p[k] + (h[k] / 3.0) * tangent[k]);
        ctrl.push_back(p[k + 1] - (h[k] / 3.0) * tangent[k + 1]);
        t += h[k];
        const int mult = k + 1 < n ? 3 : 4;
        for (int i = 0; i < mult; ++i) knots.push_back(t);
    }
    ctrl.push_back(p[n]);
    return std::make_unique<BSplineCurve>(std::move(ctrl), 3, std::move(knots), type,
                                          /*c1_joins=*/true);
}

std::unique_ptr<Curve> make_spline_through(std::vector<Vec2> points, bool allow_periodic) {
    return detail::make_spline(std::move(points), allow_periodic, CurveType::Spline);
}

}  // namespace meshd::core
