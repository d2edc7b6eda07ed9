// Legacy VTK, binary (big-endian): triangles and tagged edges with their data.

#include <algorithm>
#include <cmath>

#include "writers/common.hpp"

namespace meshd::api {

using namespace writers;

void write_vtk(const MeshResult& r, std::ostream& os) {
    const Mesh& m = r.mesh;
    const bool quadratic = m.order() == 2;  // VTK_QUADRATIC_TRIANGLE and VTK_QUADRATIC_EDGE
    const size_t np = all_points(m), nt = m.triangles.size(), nq = m.quads.size(), ne = m.edges.size();
    const std::int32_t tri_nodes = quadratic ? 6 : 3, edge_nodes = quadratic ? 3 : 2;
    os << "# vtk DataFile Version 3.0\n";
    std::string title = "meshd tags:";
    for (size_t i = 0; i < m.tags.size(); ++i) title += " " + std::to_string(i) + "=" + m.tags[i];
    for (char& c : title)
        if (c == '\n' || c == '\r') c = ' ';
    if (title.size() > 255) title.resize(255);
    os << title << "\nBINARY\nDATASET UNSTRUCTURED_GRID\n";
    os << "POINTS " << np << " double\n";
    for (size_t v = 0; v < np; ++v) {
        const core::Vec2 p = any_point(m, v);
        put_be(os, p.x);
        put_be(os, p.y);
        put_be(os, 0.0);
    }
    os << "\nCELLS " << nt + nq + ne << ' '
       << static_cast<size_t>(tri_nodes + 1) * nt + 5 * nq + static_cast<size_t>(edge_nodes + 1) * ne << '\n';
    for (size_t t = 0; t < nt; ++t) {
        put_be(os, tri_nodes);
        if (quadratic) {
            for (size_t v : six_nodes(m, t)) put_be(os, static_cast<std::int32_t>(v));
        } else {
            for (auto v : m.triangles[t].v) put_be(os, static_cast<std::int32_t>(v));
        }
    }
    for (const auto& q : m.quads) {
        put_be(os, std::int32_t{4});
        for (auto v : q) put_be(os, static_cast<std::int32_t>(v));
    }
    for (const auto& e : m.edges) {
        put_be(os, edge_nodes);
        put_be(os, static_cast<std::int32_t>(e.a));
        put_be(os, static_cast<std::int32_t>(e.b));
        if (quadratic) put_be(os, static_cast<std::int32_t>(edge_middle(m, e)));
    }
    os << "\nCELL_TYPES " << nt + nq + ne << '\n';
    for (size_t i = 0; i < nt; ++i) put_be(os, std::int32_t{quadratic ? 22 : 5});
    for (size_t i = 0; i < nq; ++i) put_be(os, std::int32_t{9});  // VTK_QUAD
    for (size_t i = 0; i < ne; ++i) put_be(os, std::int32_t{quadratic ? 21 : 3});
    os << "\nCELL_DATA " << nt + nq + ne << "\nSCALARS tag int 1\nLOOKUP_TABLE default\n";
    for (size_t i = 0; i < nt + nq; ++i) put_be(os, std::int32_t{-1});
    for (const auto& e : m.edges) put_be(os, static_cast<std::int32_t>(e.tag));
    os << "\nSCALARS quality double 1\nLOOKUP_TABLE default\n";
    for (const auto& t : m.triangles) put_be(os, tri_quality(m, t));
    for (const auto& q : m.quads) put_be(os, quad_quality(m, q));
    for (size_t i = 0; i < ne; ++i) put_be(os, 0.0);
    os << "\nPOINT_DATA " << np << "\nSCALARS target_size double 1\nLOOKUP_TABLE default\n";
    for (const double size : point_sizes(m)) put_be(os, size);
    os << '\n';
}

}  // namespace meshd::api
