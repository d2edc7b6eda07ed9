// SVG picture of the mesh, tags as colours (optionally a window of the plane).

#include <algorithm>
#include <cmath>

#include "writers/common.hpp"

namespace meshd::api {

using namespace writers;

namespace {
constexpr const char* kLayerFill = "#f3d9b1";
}  // namespace

void write_svg(const MeshResult& r, std::ostream& os, std::optional<core::Box> view) {
    const Mesh& m = r.mesh;
    core::Box b;
    if (view) {
        b = *view;
    } else {
        for (size_t v = 0; v < m.point_count(); ++v) b.add(m.point(static_cast<std::uint32_t>(v)));
    }
    if (b.empty()) b.add(core::Vec2{0, 0});
    auto visible = [&](std::initializer_list<std::uint32_t> vs) {
        if (!view) return true;
        core::Box e;
        for (auto v : vs) e.add(m.point(v));
        return !(e.hi.x < b.lo.x || e.lo.x > b.hi.x || e.hi.y < b.lo.y || e.lo.y > b.hi.y);
    };
    const double w = std::fmax(b.hi.x - b.lo.x, 1e-300), h = std::fmax(b.hi.y - b.lo.y, 1e-300);
    const double scale = 1000.0 / std::fmax(w, h);
    const double W = w * scale, H = h * scale;
    auto X = [&](double x) { return Num(std::round((x - b.lo.x) * scale * 1000.0) / 1000.0); };
    auto Y = [&](double y) { return Num(std::round((b.hi.y - y) * scale * 1000.0) / 1000.0); };
    const double stroke = 0.0005 * std::fmax(W, H);
    os << "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 " << Num(W) << ' ' << Num(H) << "\" width=\""
       << Num(W) << "\" height=\"" << Num(H) << "\">\n<title>meshd: " << m.point_count() << " points, "
       << m.triangles.size() << " triangles" << (m.quads.empty() ? "" : ", " + std::to_string(m.quads.size()) + " quads")
       << "</title>\n<g stroke=\"#333\" stroke-width=\"" << Num(stroke)
       << "\" stroke-linejoin=\"round\">\n";
    // Second order: each edge a quadratic Bezier through its edge node (control point
    // 2 node - (a + b) / 2), so curved boundaries are drawn curved.
    const bool quadratic = m.order() == 2;
    auto to = [&](core::VertexId from, core::VertexId end, size_t node) {
        if (!quadratic) {
            os << 'L' << X(m.x[end]) << ' ' << Y(m.y[end]);
            return;
        }
        const core::Vec2 p = any_point(m, node);
        os << 'Q' << X(2 * p.x - (m.x[from] + m.x[end]) / 2) << ' ' << Y(2 * p.y - (m.y[from] + m.y[end]) / 2) << ' '
           << X(m.x[end]) << ' ' << Y(m.y[end]);
    };
    for (size_t ti = 0; ti < m.triangles.size(); ++ti) {
        const auto& t = m.triangles[ti];
        if (!visible({t.v[0], t.v[1], t.v[2]})) continue;
        // Quality 0 -> red, 0.5 -> yellow, 1 -> pale green; the boundary layers' cells, thin
        // on purpose, in one colour of their own.
        if (t.layer) {
            os << "<path fill=\"" << kLayerFill << "\" d=\"M" << X(m.x[t.v[0]]) << ' ' << Y(m.y[t.v[0]]) << 'L'
               << X(m.x[t.v[1]]) << ' ' << Y(m.y[t.v[1]]) << 'L' << X(m.x[t.v[2]]) << ' ' << Y(m.y[t.v[2]]) << "Z\"/>\n";
            continue;
        }
        const double q = tri_quality(m, t);
        const int red = q < 0.5 ? 230 : static_cast<int>(230 - (q - 0.5) * 2 * 130);
        const int green = q < 0.5 ? static_cast<int>(60 + q * 2 * 170) : 230;
        const int blue = q < 0.5 ? 60 : static_cast<int>(60 + (q - 0.5) * 2 * 130);
        char fill[8];
        std::snprintf(fill, sizeof fill, "#%02x%02x%02x", red, green, blue);
        os << "<path fill=\"" << fill << "\" d=\"M" << X(m.x[t.v[0]]) << ' ' << Y(m.y[t.v[0]]);
        const auto six = quadratic ? six_nodes(m, ti) : std::array<size_t, 6>{};
        to(t.v[0], t.v[1], six[3]);
        to(t.v[1], t.v[2], six[4]);
        if (quadratic) to(t.v[2], t.v[0], six[5]);  // a straight closing side is Z's own
        os << "Z\"/>\n";
    }
    for (const auto& q : m.quads) {
        if (!visible({q[0], q[1], q[2], q[3]})) continue;
        os << "<path fill=\"" << kLayerFill << "\" d=\"M" << X(m.x[q[0]]) << ' ' << Y(m.y[q[0]]);
        for (size_t i = 1; i < 4; ++i) os << 'L' << X(m.x[q[i]]) << ' ' << Y(m.y[q[i]]);
        os << "Z\"/>\n";
    }
    os << "</g>\n";
    static constexpr std::array<const char*, 8> kColours = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd",
                                                            "#ff7f0e", "#17becf", "#e377c2", "#8c564b"};
    const auto groups = edges_by_tag(m);
    for (size_t g = 0; g < groups.size(); ++g) {
        os << "<g stroke=\"" << kColours[g % kColours.size()] << "\" stroke-width=\"" << Num(4 * stroke)
           << "\" fill=\"none\"><title>" << xml_escaped(m.tags[g]) << "</title>\n<path d=\"";
        for (const auto* e : groups[g])
            if (visible({e->a, e->b})) {
                os << 'M' << X(m.x[e->a]) << ' ' << Y(m.y[e->a]);
                to(e->a, e->b, quadratic ? edge_middle(m, *e) : 0);
            }
        os << "\"/></g>\n";
    }
    os << "</svg>\n";
}

}  // namespace meshd::api
