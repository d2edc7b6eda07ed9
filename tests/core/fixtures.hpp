#pragma once
// Domains shared by the core tests.

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "meshd/core/density.hpp"
#include "meshd/core/domain.hpp"
#include "meshd/core/mesh.hpp"
#include "geometry/curve.hpp"
#include "triangulation/triangulation.hpp"

namespace meshd::test {

using core::ArcDirection;
using core::ArcShape;
using core::CurveSpec;
using core::DomainSpec;
using core::LineShape;
using core::LoopItem;
using core::Vec2;

inline CurveSpec line(std::string name, std::string from, std::string to,
                      std::optional<std::string> tag = std::nullopt) {
    return {std::move(name), LineShape{}, std::move(from), std::move(to), std::move(tag)};
}

inline CurveSpec arc(std::string name, std::string from, std::string to, Vec2 center,
                     ArcDirection dir = ArcDirection::Ccw, std::optional<std::string> tag = std::nullopt) {
    return {std::move(name), ArcShape{center, dir}, std::move(from), std::move(to), std::move(tag)};
}

inline std::vector<LoopItem> loop(std::initializer_list<const char*> names) {
    std::vector<LoopItem> out;
    for (const char* n : names) {
        if (n[0] == '-') out.push_back({n + 1, true});
        else out.push_back({n, false});
    }
    return out;
}

/// Unit square [0, 1]^2 with four tagged sides.
inline DomainSpec unit_square() {
    DomainSpec s;
    s.points = {{"A", {0, 0}}, {"B", {1, 0}}, {"C", {1, 1}}, {"D", {0, 1}}};
    s.curves = {line("bottom", "A", "B", "wall"), line("right", "B", "C", "outlet"),
                line("top", "C", "D", "wall"), line("left", "D", "A", "inlet")};
    s.loops = {loop({"bottom", "right", "top", "left"})};
    return s;
}

/// NACA 0012 (chord 1, leading edge at the origin) in a circular far field of radius R
/// centred at (0.5, 0).
inline DomainSpec naca_in_circle(const std::string& code = "0012", double radius = 20.0) {
    DomainSpec s;
    s.points = {{"F", {0.5 + radius, 0.0}}};
    core::NacaSpec naca;
    naca.code = code;
    s.curves.push_back({"wing", naca, std::nullopt, std::nullopt, std::string("wall")});
    s.curves.push_back(arc("farfield", "F", "F", {0.5, 0.0}, ArcDirection::Ccw, "farfield"));
    s.loops = {loop({"farfield"}), loop({"wing"})};
    return s;
}

/// A density of one size expression everywhere.
inline core::DensitySpec density_of(std::string expr) {
    core::DensitySpec d;
    d.size = std::move(expr);
    return d;
}

/// A three-element high-lift wing (NACA 2412 main, 0012 slat at 20 degrees, 0012 flap with a
/// blunt trailing edge at 20 degrees, its leading edge where asked), tagged "wall", in a
/// circle of radius 10 about (0.5, 0) tagged "farfield".
inline DomainSpec three_element_wing(Vec2 flap_leading_edge) {
    using core::AirfoilSurface;
    using core::NacaSpec;
    using core::TrailingEdge;
    DomainSpec s;
    s.points = {{"F", {10.5, 0.0}}};
    NacaSpec main_wing{"2412", {1.0, {0.0, 0.0}, 0.0}, TrailingEdge::Closed, AirfoilSurface::Both};
    NacaSpec slat{"0012", {0.15, {-0.17, -0.03}, 20.0}, TrailingEdge::Closed, AirfoilSurface::Both};
    NacaSpec flap{"0012", {0.3, flap_leading_edge, 20.0}, TrailingEdge::Open, AirfoilSurface::Both};
    s.curves.push_back({"main", main_wing, std::nullopt, std::nullopt, std::string("wall")});
    s.curves.push_back({"slat", slat, std::nullopt, std::nullopt, std::string("wall")});
    s.curves.push_back({"flap", flap, std::nullopt, std::nullopt, std::string("wall")});
    s.curves.push_back(arc("farfield", "F", "F", {0.5, 0.0}));
    s.loops = {loop({"farfield"}), loop({"main"}), loop({"slat"}), loop({"flap"})};
    return s;
}

/// Triangles as sorted vertex triples (each rotated to start at its smallest vertex), for
/// comparing triangulations whatever their order.
inline std::vector<std::array<std::uint32_t, 3>> canonical(const core::Array<core::Triangle>& tris) {
    std::vector<std::array<std::uint32_t, 3>> out;
    for (const core::Triangle& t : tris) {
        std::array<std::uint32_t, 3> v = t.v;
        while (v[0] > v[1] || v[0] > v[2]) std::rotate(v.begin(), v.begin() + 1, v.end());
        out.push_back(v);
    }
    std::sort(out.begin(), out.end());
    return out;
}

/// Whether two meshes have the same points, bit for bit, in the same order.
inline bool same_points(const core::Mesh& a, const core::Mesh& b) {
    if (a.point_count() != b.point_count()) return false;
    for (size_t i = 0; i < a.point_count(); ++i)
        if (a.x[i] != b.x[i] || a.y[i] != b.y[i]) return false;
    return true;
}

/// A mesh from a triangulation of points with constraints, for check_mesh: the constraints as
/// its edges (embedded unless loop segments), `holes` holes.
inline core::Mesh mesh_of(const std::vector<Vec2>& pts, size_t holes, const core::TriangulationResult& r,
                          const std::vector<core::Constraint>& cons) {
    core::Mesh m;
    for (const Vec2& p : pts) {
        m.x.push_back(p.x);
        m.y.push_back(p.y);
        m.kind.push_back(core::PointKind::Interior);
    }
    m.triangles = r.triangles;
    for (const core::Constraint& c : cons) m.edges.push_back({c.a, c.b, 0, core::kNoCurve, !c.loop});
    m.holes = holes;
    return m;
}

/// What smoothing may do to the points that are not interior, `smoothed` against `raw` (the
/// same request without smoothing): corners and boundary-layer points stay; points on curves
/// may slide along their curve but stay on it, at their parameter, and between their
/// neighbours there (every curve edge runs in the same direction of the parameter as before).
/// Returns what is violated (empty when all holds); `moved` gets how many points slid.
inline std::vector<std::string> fixed_points_kept(const core::Domain& domain, const core::Mesh& smoothed,
                                                  const core::Mesh& raw, size_t* moved = nullptr) {
    using core::PointKind;
    std::vector<std::string> broken;
    if (smoothed.point_count() != raw.point_count()) return {"point counts differ"};
    const double tol = 1e-12 * domain.extent();
    size_t slid = 0;
    for (size_t v = 0; v < raw.point_count(); ++v) {
        if (raw.kind[v] == PointKind::Interior) continue;
        const bool same = smoothed.x[v] == raw.x[v] && smoothed.y[v] == raw.y[v];
        if (raw.kind[v] == PointKind::Boundary || raw.kind[v] == PointKind::Embedded) {
            const core::Curve& g = *domain.curves()[smoothed.curve[v]].geometry;
            if (distance(g.point(smoothed.param[v]), smoothed.point(static_cast<core::VertexId>(v))) > tol)
                broken.push_back("point " + std::to_string(v) + " is off its curve");
            slid += same ? 0 : 1;
        } else if (!same) {
            broken.push_back("point " + std::to_string(v) + " (a corner or a layer's) moved");
        }
    }
    for (const core::MeshEdge& e : raw.edges) {
        if (raw.curve[e.a] != e.curve || raw.curve[e.b] != e.curve) continue;
        const double before = raw.param[e.b] - raw.param[e.a], after = smoothed.param[e.b] - smoothed.param[e.a];
        if ((before > 0) != (after > 0) || after == 0)
            broken.push_back("edge " + std::to_string(e.a) + "-" + std::to_string(e.b) + " turned along its curve");
    }
    if (moved) *moved = slid;
    return broken;
}

}  // namespace meshd::test
