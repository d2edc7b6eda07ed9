// Legacy VTK, binary (big-endian): triangles and tagged edges with their data.

#include <algorithm>
#include <cmath>

#include "writers/common.hpp"

namespace meshd::api {

using namespace writers;

void write_vtk(const MeshResult& r, std::ostream& os) {
    const Mesh& m = r.mesh;
    const size_t np = m.point_count(), nt = m.triangles.size(), ne = m.edges.size();
    os << "# vtk DataFile Version 3.0\n";
    std::string title = "meshd tags:";
    for (size_t i = 0; i < m.tags.size(); ++i) title += " " + std::to_string(i) + "=" + m.tags[i];
    for (char& c : title)
        if (c == '\n' || c == '\r') c = ' ';
    if (title.size() > 255) title.resize(255);
    os << title << "\nBINARY\nDATASET UNSTRUCTURED_GRID\n";
    os << "POINTS " << np << " double\n";
    for (size_t v = 0; v < np; ++v) {
        put_be(os, m.x[v]);
        put_be(os, m.y[v]);
        put_be(os, 0.0);
    }
    os << "\nCELLS " << nt + ne << ' ' << 4 * nt + 3 * ne << '\n';
    for (const auto& t : m.triangles) {
        put_be(os, std::int32_t{3});
        for (auto v : t.v) put_be(os, static_cast<std::int32_t>(v));
    }
    for (const auto& e : m.edges) {
        put_be(os, std::int32_t{2});
        put_be(os, static_cast<std::int32_t>(e.a));
        put_be(os, static_cast<std::int32_t>(e.b));
    }
    os << "\nCELL_TYPES " << nt + ne << '\n';
    for (size_t i = 0; i < nt; ++i) put_be(os, std::int32_t{5});
    for (size_t i = 0; i < ne; ++i) put_be(os, std::int32_t{3});
    os << "\nCELL_DATA " << nt + ne << "\nSCALARS tag int 1\nLOOKUP_TABLE default\n";
    for (size_t i = 0; i < nt; ++i) put_be(os, std::int32_t{-1});
    for (const auto& e : m.edges) put_be(os, static_cast<std::int32_t>(e.tag));
    os << "\nSCALARS quality double 1\nLOOKUP_TABLE default\n";
    for (const auto& t : m.triangles) put_be(os, tri_quality(m, t));
    for (size_t i = 0; i < ne; ++i) put_be(os, 0.0);
    os << "\nPOINT_DATA " << np << "\nSCALARS target_size double 1\nLOOKUP_TABLE default\n";
    for (size_t v = 0; v < np; ++v) put_be(os, v < m.target_size.size() ? m.target_size[v] : 0.0);
    os << '\n';
}

}  // namespace meshd::api
