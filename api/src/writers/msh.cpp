// Gmsh MSH 4.1 (ASCII) as gmsh itself writes a meshed model: the domain's topology as
// entities (a point entity at each curve end, a curve entity per domain curve bounded by its
// end points, one surface bounded by the loops' curves with their orientation signs), every
// node classified on the entity it lies on (curve nodes in the curve's direction), line elements
// on their curves, triangles on the surface, and physical groups named by the tags (one per
// tag over its curves, "domain" for the surface). gmsh can extrude such a file and dolfinx
// reads its facet tags. Embedded curves are curve entities that bound nothing (MSH has no
// record of what a curve is embedded in). A closed curve is two curve entities.

#include <algorithm>
#include <cmath>

#include "writers/common.hpp"

namespace meshd::api {

using namespace writers;

namespace {

void write_box(std::ostream& os, const core::Box& b) {
    os << Num(b.lo.x) << ' ' << Num(b.lo.y) << " 0 " << Num(b.hi.x) << ' ' << Num(b.hi.y) << " 0";
}

// A curve entity: a domain curve, or half of a closed one (gmsh 4.8 cannot extrude a curve
// whose two ends are one point: a closed curve is written as two, split at its middle node).
struct CurveEntity {
    core::CurveId curve;
    std::vector<core::VertexId> nodes;  // inside the entity, in the curve's direction
    std::vector<const core::MeshEdge*> edges;
    core::VertexId begin = core::kNoVertex, end = core::kNoVertex;
};

std::vector<CurveEntity> curve_entities(const Mesh& m, std::vector<std::vector<size_t>>& of_curve) {
    size_t ncurve_ids = m.curve_ends.size();
    for (const core::MeshEdge& e : m.edges) ncurve_ids = std::max<size_t>(ncurve_ids, e.curve + size_t{1});
    std::vector<std::vector<const core::MeshEdge*>> edges_of(ncurve_ids);
    for (const core::MeshEdge& e : m.edges) edges_of[e.curve].push_back(&e);
    std::vector<std::vector<core::VertexId>> nodes_of(ncurve_ids);
    for (core::VertexId v = 0; v < m.point_count(); ++v)
        if (m.curve[v] < ncurve_ids && m.kind[v] != core::PointKind::Interior && m.kind[v] != core::PointKind::Corner)
            nodes_of[m.curve[v]].push_back(v);
    of_curve.assign(ncurve_ids, {});
    std::vector<CurveEntity> out;
    std::vector<size_t> rank(m.point_count(), 0);  // a node's place along its closed curve
    for (core::CurveId c = 0; c < ncurve_ids; ++c) {
        if (edges_of[c].empty()) continue;
        std::vector<core::VertexId>& nodes = nodes_of[c];
        std::sort(nodes.begin(), nodes.end(), [&](core::VertexId a, core::VertexId b) { return m.param[a] < m.param[b]; });
        const std::array<core::VertexId, 2> ends =
            c < m.curve_ends.size() ? m.curve_ends[c] : std::array<core::VertexId, 2>{core::kNoVertex, core::kNoVertex};
        if (ends[0] == core::kNoVertex || ends[0] != ends[1] || nodes.size() < 2) {
            of_curve[c].push_back(out.size());
            out.push_back({c, std::move(nodes), std::move(edges_of[c]), ends[0], ends[1]});
            continue;
        }
        // Closed: ranks along the curve (the closing point before the first node for the edge
        // that leaves it, after the last for the edge that comes back), split at rank k / 2.
        const size_t k = nodes.size(), mid = k / 2;
        for (size_t i = 0; i < k; ++i) rank[nodes[i]] = i;  // only this curve's nodes are read
        CurveEntity first{c, {}, {}, ends[0], nodes[mid]}, second{c, {}, {}, nodes[mid], ends[1]};
        first.nodes.assign(nodes.begin(), nodes.begin() + static_cast<std::ptrdiff_t>(mid));
        second.nodes.assign(nodes.begin() + static_cast<std::ptrdiff_t>(mid) + 1, nodes.end());
        for (const core::MeshEdge* e : edges_of[c]) {
            auto rank_of = [&](core::VertexId v, core::VertexId other) -> long long {
                if (v != ends[0]) return static_cast<long long>(rank[v]);
                return rank[other] < mid ? -1 : static_cast<long long>(k);
            };
            const long long top = std::max(rank_of(e->a, e->b), rank_of(e->b, e->a));
            (top <= static_cast<long long>(mid) ? first : second).edges.push_back(e);
        }
        of_curve[c] = {out.size(), out.size() + 1};
        out.push_back(std::move(first));
        out.push_back(std::move(second));
    }
    return out;
}

}  // namespace

void write_msh(const MeshResult& r, std::ostream& os) {
    const Mesh& m = r.mesh;
    const size_t np = m.point_count();
    const size_t ntags = m.tags.size();

    // Curve entities, tagged 1.. in curve order; point entities at their ends, tagged 1.. in
    // point order; every other node on the surface.
    std::vector<std::vector<size_t>> of_curve;
    const std::vector<CurveEntity> curves = curve_entities(m, of_curve);
    std::vector<std::uint32_t> point_tag(np, 0);
    for (const CurveEntity& ce : curves)
        for (core::VertexId v : {ce.begin, ce.end})
            if (v != core::kNoVertex) point_tag[v] = 1;
    std::vector<core::VertexId> points;
    for (core::VertexId v = 0; v < np; ++v)
        if (point_tag[v]) {
            points.push_back(v);
            point_tag[v] = static_cast<std::uint32_t>(points.size());
        }
    std::vector<bool> classified(np, false);
    for (core::VertexId v : points) classified[v] = true;
    for (const CurveEntity& ce : curves)
        for (core::VertexId v : ce.nodes) classified[v] = true;
    std::vector<core::VertexId> on_surface;
    for (core::VertexId v = 0; v < np; ++v)
        if (!classified[v]) on_surface.push_back(v);

    // Physical groups: one per tag (1..n) over its curves, the surface as n + 1.
    os << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n" << ntags + 1 << '\n';
    for (size_t g = 0; g < ntags; ++g) os << "1 " << g + 1 << " \"" << m.tags[g] << "\"\n";  // tags hold no '"' (request.cpp)
    os << "2 " << ntags + 1 << " \"domain\"\n$EndPhysicalNames\n";

    os << "$Entities\n" << points.size() << ' ' << curves.size() << " 1 0\n";
    for (core::VertexId v : points) os << point_tag[v] << ' ' << Num(m.x[v]) << ' ' << Num(m.y[v]) << " 0 0\n";
    for (size_t i = 0; i < curves.size(); ++i) {
        const CurveEntity& ce = curves[i];
        core::Box b;
        for (const core::MeshEdge* e : ce.edges) {
            b.add(m.point(e->a));
            b.add(m.point(e->b));
        }
        os << i + 1 << ' ';
        write_box(os, b);
        os << " 1 " << ce.edges.front()->tag + 1;
        if (ce.begin != core::kNoVertex && ce.end != core::kNoVertex)
            os << " 2 " << point_tag[ce.begin] << " -" << point_tag[ce.end] << '\n';
        else
            os << " 0\n";
    }
    {
        core::Box b;
        for (core::VertexId v = 0; v < np; ++v) b.add(m.point(v));
        if (b.empty()) b.add(core::Vec2{0, 0});
        std::vector<long long> bounding;
        for (const auto& loop : m.loops)
            for (const core::Mesh::LoopCurve& u : loop) {
                if (u.curve >= of_curve.size()) continue;
                const std::vector<size_t>& ids = of_curve[u.curve];
                if (u.reversed)
                    for (auto it = ids.rbegin(); it != ids.rend(); ++it) bounding.push_back(-static_cast<long long>(*it + 1));
                else
                    for (size_t id : ids) bounding.push_back(static_cast<long long>(id + 1));
            }
        os << "1 ";
        write_box(os, b);
        os << " 1 " << ntags + 1 << ' ' << bounding.size();
        for (long long t : bounding) os << ' ' << t;
        os << '\n';
    }
    os << "$EndEntities\n";

    // Nodes by entity: the points, the curves (in the curve's direction), the surface. Without
    // parametric coordinates, as gmsh writes by default: meshio and the readers built on it
    // refuse parametric nodes.
    // Second order: the edge nodes of a curve's edges on that curve, the others on the surface.
    const bool quadratic = m.order() == 2;
    const size_t nall = all_points(m);
    std::vector<std::vector<size_t>> curve_extra(curves.size());
    std::vector<size_t> surface_extra;
    if (quadratic) {
        std::vector<bool> on_curve(m.edge_nodes.size(), false);
        for (size_t i = 0; i < curves.size(); ++i)
            for (const core::MeshEdge* e : curves[i].edges) {
                curve_extra[i].push_back(edge_middle(m, *e));
                on_curve[curve_extra[i].back() - np] = true;
            }
        for (size_t k = 0; k < m.edge_nodes.size(); ++k)
            if (!on_curve[k]) surface_extra.push_back(np + k);
    }
    auto coords = [&](size_t v) {
        const core::Vec2 p = any_point(m, v);
        os << Num(p.x) << ' ' << Num(p.y) << " 0\n";
    };
    os << "$Nodes\n" << points.size() + curves.size() + 1 << ' ' << nall << " 1 " << nall << '\n';
    for (core::VertexId v : points) os << "0 " << point_tag[v] << " 0 1\n" << v + 1 << '\n' << Num(m.x[v]) << ' ' << Num(m.y[v]) << " 0\n";
    for (size_t i = 0; i < curves.size(); ++i) {
        os << "1 " << i + 1 << " 0 " << curves[i].nodes.size() + curve_extra[i].size() << '\n';
        for (core::VertexId v : curves[i].nodes) os << v + 1 << '\n';
        for (size_t v : curve_extra[i]) os << v + 1 << '\n';
        for (core::VertexId v : curves[i].nodes) coords(v);
        for (size_t v : curve_extra[i]) coords(v);
    }
    os << "2 1 0 " << on_surface.size() + surface_extra.size() << '\n';
    for (core::VertexId v : on_surface) os << v + 1 << '\n';
    for (size_t v : surface_extra) os << v + 1 << '\n';
    for (core::VertexId v : on_surface) coords(v);
    for (size_t v : surface_extra) coords(v);
    os << "$EndNodes\n";

    // Elements: the lines on their curves, the triangles on the surface (types 1 and 2, or
    // 8 and 9 at second order: 3-node lines and 6-node triangles).
    // Quads (type 3, the boundary layers) in a block of their own on the same surface.
    const size_t nelem = m.triangles.size() + m.quads.size() + m.edges.size();
    const size_t blocks = curves.size() + 1 + (m.quads.empty() ? 0 : 1);
    os << "$Elements\n" << blocks << ' ' << nelem << " 1 " << nelem << '\n';
    size_t id = 1;
    for (size_t i = 0; i < curves.size(); ++i) {
        os << "1 " << i + 1 << (quadratic ? " 8 " : " 1 ") << curves[i].edges.size() << '\n';
        for (const core::MeshEdge* e : curves[i].edges) {
            os << id++ << ' ' << e->a + 1 << ' ' << e->b + 1;
            if (quadratic) os << ' ' << edge_middle(m, *e) + 1;
            os << '\n';
        }
    }
    os << "2 1 " << (quadratic ? 9 : 2) << ' ' << m.triangles.size() << '\n';
    for (size_t t = 0; t < m.triangles.size(); ++t) {
        os << id++;
        if (quadratic) {
            for (size_t v : six_nodes(m, t)) os << ' ' << v + 1;
        } else {
            for (auto v : m.triangles[t].v) os << ' ' << v + 1;
        }
        os << '\n';
    }
    if (!m.quads.empty()) {
        os << "2 1 3 " << m.quads.size() << '\n';
        for (const auto& q : m.quads) os << id++ << ' ' << q[0] + 1 << ' ' << q[1] + 1 << ' ' << q[2] + 1 << ' ' << q[3] + 1 << '\n';
    }
    os << "$EndElements\n";
}

}  // namespace meshd::api
