// Gmsh MSH 4.1 (ASCII) with physical groups per tag.

#include <algorithm>
#include <cmath>

#include "writers/common.hpp"

namespace meshd::api {

using namespace writers;

void write_msh(const MeshResult& r, std::ostream& os) {
    const Mesh& m = r.mesh;
    const auto groups = edges_by_tag(m);
    // Physical groups: one curve group per tag (tags 1..n), the surface as tag n + 1.
    const size_t ncurves = groups.size();
    os << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n" << ncurves + 1 << '\n';
    for (size_t g = 0; g < ncurves; ++g) os << "1 " << g + 1 << " \"" << m.tags[g] << "\"\n";  // tags hold no '"' (request.cpp)
    os << "2 " << ncurves + 1 << " \"domain\"\n$EndPhysicalNames\n";
    // Entities: one curve entity per tag, one surface. Bounding boxes of their nodes.
    auto box_of = [&](auto&& each) {
        core::Box b;
        each([&](std::uint32_t v) { b.add(m.point(v)); });
        if (b.empty()) b.add(core::Vec2{0, 0});
        return b;
    };
    os << "$Entities\n0 " << ncurves << " 1 0\n";
    for (size_t g = 0; g < ncurves; ++g) {
        const core::Box b = box_of([&](auto f) {
            for (const auto* e : groups[g]) { f(e->a); f(e->b); }
        });
        os << g + 1 << ' ' << Num(b.lo.x) << ' ' << Num(b.lo.y) << " 0 " << Num(b.hi.x) << ' ' << Num(b.hi.y)
           << " 0 1 " << g + 1 << " 0\n";
    }
    {
        const core::Box b = box_of([&](auto f) {
            for (std::uint32_t v = 0; v < m.point_count(); ++v) f(v);
        });
        os << "1 " << Num(b.lo.x) << ' ' << Num(b.lo.y) << " 0 " << Num(b.hi.x) << ' ' << Num(b.hi.y) << " 0 1 "
           << ncurves + 1 << ' ' << ncurves;
        for (size_t g = 0; g < ncurves; ++g) os << ' ' << g + 1;
        os << '\n';
    }
    os << "$EndEntities\n";
    // All nodes in the surface entity (tags 1..n).
    const size_t np = m.point_count();
    os << "$Nodes\n1 " << np << " 1 " << np << "\n2 1 0 " << np << '\n';
    for (size_t v = 0; v < np; ++v) os << v + 1 << '\n';
    for (size_t v = 0; v < np; ++v) os << Num(m.x[v]) << ' ' << Num(m.y[v]) << " 0\n";
    os << "$EndNodes\n";
    size_t nonempty = 0;
    for (const auto& g : groups) nonempty += g.empty() ? 0u : 1u;
    const size_t nelem = m.triangles.size() + m.edges.size();
    os << "$Elements\n" << nonempty + 1 << ' ' << nelem << " 1 " << nelem << '\n';
    size_t id = 1;
    for (size_t g = 0; g < ncurves; ++g) {
        if (groups[g].empty()) continue;
        os << "1 " << g + 1 << " 1 " << groups[g].size() << '\n';
        for (const auto* e : groups[g]) os << id++ << ' ' << e->a + 1 << ' ' << e->b + 1 << '\n';
    }
    os << "2 1 2 " << m.triangles.size() << '\n';
    for (const auto& t : m.triangles) os << id++ << ' ' << t.v[0] + 1 << ' ' << t.v[1] + 1 << ' ' << t.v[2] + 1 << '\n';
    os << "$EndElements\n";
}

}  // namespace meshd::api
