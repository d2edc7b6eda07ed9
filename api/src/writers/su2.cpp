// SU2 native mesh: triangles, quadrilaterals and one marker per tag.

#include <algorithm>
#include <cmath>
#include <string>

#include "writers/common.hpp"

namespace meshd::api {

using namespace writers;

void write_su2(const MeshResult& r, std::ostream& os) {
    const Mesh& m = r.mesh;
    os << "% meshd\nNDIME= 2\nNELEM= " << m.triangles.size() + m.quads.size() << '\n';
    for (size_t t = 0; t < m.triangles.size(); ++t) {
        const auto& T = m.triangles[t];
        os << "5 " << T.v[0] << ' ' << T.v[1] << ' ' << T.v[2] << ' ' << t << '\n';
    }
    for (size_t q = 0; q < m.quads.size(); ++q) {  // 9: quadrilateral
        const auto& Q = m.quads[q];
        os << "9 " << Q[0] << ' ' << Q[1] << ' ' << Q[2] << ' ' << Q[3] << ' ' << m.triangles.size() + q << '\n';
    }
    os << "NPOIN= " << m.point_count() << '\n';
    for (size_t v = 0; v < m.point_count(); ++v) os << Num(m.x[v]) << ' ' << Num(m.y[v]) << ' ' << v << '\n';
    const auto groups = edges_by_tag(m);
    size_t marks = 0;
    for (const auto& g : groups) marks += g.empty() ? 0u : 1u;
    os << "NMARK= " << marks << '\n';
    // Marker names end at white space: spaces become '_'. Two tags that then read alike ("far
    // field", "far_field") must stay two markers: the later gets "_2", "_3", ... (docs/api.md).
    const std::vector<std::string> names =
        tag_names(m.tags, [](char c) { return c != ' ' && c != '\t' && c != '\n' && c != '\r'; });
    for (size_t g = 0; g < groups.size(); ++g) {
        if (groups[g].empty()) continue;
        os << "MARKER_TAG= " << names[g] << "\nMARKER_ELEMS= " << groups[g].size() << '\n';
        for (const auto* e : groups[g]) os << "3 " << e->a << ' ' << e->b << '\n';
    }
}

}  // namespace meshd::api
