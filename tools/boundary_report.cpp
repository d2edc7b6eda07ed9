// Prints, for the paper's Fig. 9 and Fig. 10 densities on a NACA 0012, the number of boundary
// points per curve and how closely the segments follow rho; then compares the two spacing
// modes of B-splines (arc length, the paper's control polygon) on airfoils given as points.
// Output is Markdown, ready for docs/method.md.

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "boundary/boundary.hpp"
#include "geometry/curve.hpp"
#include "meshd/core/errors.hpp"

using namespace meshd::core;

namespace {

CurveSpec line(std::string n, std::string a, std::string b, std::string tag) {
    return {std::move(n), LineShape{}, std::move(a), std::move(b), std::move(tag)};
}

// Fig. 9: NACA 0012 in a circular far field of radius 5 about (0.5, 0).
struct Case {
    std::string title;
    DomainSpec domain;
    DensitySpec density;
};

Case fig9() {
    Case c;
    c.title = "Fig. 9: NACA 0012, far field r = 5";
    c.domain.points = {{"F", {5.5, 0.0}}};
    NacaSpec naca;
    naca.code = "0012";
    c.domain.curves.push_back({"wing", naca, std::nullopt, std::nullopt, std::string("wall")});
    c.domain.curves.push_back({"farfield", ArcShape{{0.5, 0.0}, ArcDirection::Ccw}, "F", "F", std::string("farfield")});
    c.domain.loops = {{{"farfield", false}}, {{"wing", false}}};
    c.density.curves = {{"farfield", std::string("0.4*sqrt(x^2+y^2)+0.2")},
                        {"wing", std::string("0.05*sqrt((x+0.01)^2+y^2)")}};
    return c;
}

// Fig. 10: the upper half of a NACA 0012 on a symmetry plane, semicircular far field of
// radius 10 about (0.5, 0).
Case fig10() {
    Case c;
    c.title = "Fig. 10: half NACA 0012, far field r = 10";
    c.domain.points = {{"LE", {0, 0}}, {"TE", {1, 0}}, {"F1", {10.5, 0}}, {"F2", {-9.5, 0}}};
    NacaSpec naca;
    naca.code = "0012";
    naca.surface = AirfoilSurface::Upper;
    c.domain.curves.push_back({"wing", naca, "TE", "LE", std::string("wall")});
    c.domain.curves.push_back(line("wake_side", "TE", "F1", "symmetry"));
    c.domain.curves.push_back({"farfield", ArcShape{{0.5, 0.0}, ArcDirection::Ccw}, "F1", "F2", std::string("farfield")});
    c.domain.curves.push_back(line("front_side", "F2", "LE", "symmetry"));
    c.domain.loops = {{{"wake_side", false}, {"farfield", false}, {"front_side", false}, {"wing", true}}};
    c.density.size = std::string(
        "x < 0.5 ? 0.1*sqrt(x^2+y^2)+0.007 : 0.1*sqrt((x-1.008930411365)^2+y^2)+0.006");
    return c;
}

void report(const Case& c) {
    const Domain dom = build_domain(c.domain);
    SizeField rho(c.density, dom);
    const Discretisation d = discretise_boundary(dom, rho);
    const SpacingReport r = spacing_report(dom, d);
    std::printf("\n%s: %zu boundary points\n\n", c.title.c_str(), d.size());
    std::printf("| curve | points | mean abs(ratio-1) | max abs(ratio-1) | ratio range |\n");
    std::printf("|---|---:|---:|---:|---|\n");
    for (CurveId id = 0; id < dom.curves().size(); ++id) {
        const auto& st = r.per_curve[id];
        if (st.segments == 0) continue;
        std::printf("| %s | %zu | %.4f | %.4f | %.4f .. %.4f |\n", dom.curves()[id].name.c_str(),
                    d.curve_vertices[id].size(), st.mean_abs_error, st.max_abs_error, st.min_ratio,
                    st.max_ratio);
    }
    std::printf("| all | %zu | %.4f | %.4f | %.4f .. %.4f |\n", d.size(), r.overall.mean_abs_error,
                r.overall.max_abs_error, r.overall.min_ratio, r.overall.max_ratio);
}

// An airfoil as a point set (cosine spacing, n per surface), approximated by a spline: the
// paper's setting for B-spline boundaries. Both spacing modes on the same curve.
void compare_spline_modes() {
    std::printf("\nB-spline spacing modes: NACA sections given as 2 x 80 or 2 x 12 points (cosine spacing), either\n"
                "interpolated by a cubic spline or taken as the control polygon of a cubic B-spline with\n"
                "the paper's knots; wing density 0.002 + 0.05*sqrt((x-0.25)^2+y^2); ratio of each segment\n"
                "to (rho(A)+rho(B))/2\n\n");
    std::printf("| section | curve | mode | points | mean abs(ratio-1) | rms | max abs(ratio-1) |\n");
    std::printf("|---|---|---|---:|---:|---:|---:|\n");
    for (const char* code : {"0012", "23012"}) {
        NacaSpec ns;
        ns.code = code;
        auto exact = make_naca(ns);
        for (int per_side : {80, 12}) {
        std::vector<Vec2> pts;
        for (int i = 0; i <= 2 * per_side; ++i) pts.push_back(exact->point(static_cast<double>(i) / per_side));
        pts.back() = pts.front();
        for (int representation = 0; representation < 2; ++representation)
        for (auto mode : {SplineSpacing::ArcLength, SplineSpacing::ControlPolygon}) {
            DomainSpec s;
            s.points = {{"F", {10.5, 0.0}}};
            const CurveShape shape = representation == 0
                                         ? CurveShape{SplineShape{pts}}
                                         : CurveShape{BSplineShape{pts, 3, std::nullopt}};
            s.curves.push_back({"wing", shape, std::nullopt, std::nullopt, std::string("wall")});
            s.curves.push_back({"farfield", ArcShape{{0.5, 0.0}, ArcDirection::Ccw}, "F", "F", std::string("farfield")});
            s.loops = {{{"farfield", false}}, {{"wing", false}}};
            const Domain dom = build_domain(s);
            DensitySpec ds;
            ds.curves = {{"farfield", 1.0}, {"wall", std::string("0.002 + 0.05*sqrt((x-0.25)^2+y^2)")}};
            SizeField rho(ds, dom);
            BoundaryOptions opt;
            opt.spline_spacing = mode;
            const Discretisation d = discretise_boundary(dom, rho, opt);
            const SpacingReport r = spacing_report(dom, d);
            const CurveId w = *dom.find_curve("wing");
            const auto& st = r.per_curve[w];
            std::printf("| NACA %s | 2 x %d points, %s | %s | %zu | %.4f | %.4f | %.4f |\n", code, per_side,
                        representation == 0 ? "spline through them" : "as control polygon",
                        mode == SplineSpacing::ArcLength ? "arc length" : "control polygon",
                        d.curve_vertices[w].size(), st.mean_abs_error, st.rms_error, st.max_abs_error);
        }
        }
    }
}

}  // namespace

int main() {
    try {
        report(fig9());
        report(fig10());
        compare_spline_modes();
    } catch (const Error& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 1;
    }
    return 0;
}
