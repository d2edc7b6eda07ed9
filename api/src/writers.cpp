// The mesh writers of writers.hpp.

#include "meshd/api/writers.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <nlohmann/json.hpp>
#include <vector>

namespace meshd::api {

namespace {

using core::Mesh;
using core::MeshResult;

// Shortest text that reads back to the same double.
struct Num {
    char buf[32];
    size_t len;
    explicit Num(double v) {
        auto [p, ec] = std::to_chars(buf, buf + sizeof buf, v);
        len = ec == std::errc() ? static_cast<size_t>(p - buf) : 0;
    }
};
std::ostream& operator<<(std::ostream& os, const Num& n) { return os.write(n.buf, static_cast<std::streamsize>(n.len)); }

template <class T>
void put_be(std::ostream& os, T v) {
    static_assert(sizeof(T) == 4 || sizeof(T) == 8);
    using U = std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>;
    U u;
    std::memcpy(&u, &v, sizeof u);
    if constexpr (std::endian::native == std::endian::little) {
        if constexpr (sizeof(T) == 4) u = __builtin_bswap32(u);
        else u = __builtin_bswap64(u);
    }
    char b[sizeof u];
    std::memcpy(b, &u, sizeof u);
    os.write(b, sizeof b);
}

double tri_quality(const Mesh& m, const core::Triangle& t) {
    return core::radius_ratio(m.point(t.v[0]), m.point(t.v[1]), m.point(t.v[2]));
}

// Edges grouped by tag, in tag order.
std::vector<std::vector<const core::MeshEdge*>> edges_by_tag(const Mesh& m) {
    std::vector<std::vector<const core::MeshEdge*>> g(m.tags.size());
    for (const auto& e : m.edges) g[e.tag].push_back(&e);
    return g;
}

}  // namespace

std::optional<Format> parse_format(std::string_view n) {
    if (n == "json") return Format::Json;
    if (n == "vtk") return Format::Vtk;
    if (n == "su2") return Format::Su2;
    if (n == "msh") return Format::Msh;
    if (n == "svg") return Format::Svg;
    return std::nullopt;
}

const char* format_name(Format f) {
    switch (f) {
        case Format::Json: return "json";
        case Format::Vtk: return "vtk";
        case Format::Su2: return "su2";
        case Format::Msh: return "msh";
        case Format::Svg: return "svg";
    }
    return "json";
}

const char* content_type(Format f) {
    switch (f) {
        case Format::Json: return "application/json";
        case Format::Vtk: return "application/octet-stream";
        case Format::Su2: return "text/plain; charset=utf-8";
        case Format::Msh: return "text/plain; charset=utf-8";
        case Format::Svg: return "image/svg+xml";
    }
    return "application/octet-stream";
}

size_t result_bytes(const core::MeshResult& r) {
    const core::Mesh& m = r.mesh;
    return m.point_count() * (3 * sizeof(double) + sizeof(core::PointKind) + sizeof(core::CurveId) + sizeof(double)) +
           m.triangles.size() * sizeof(core::Triangle) + m.edges.size() * sizeof(core::MeshEdge) + 4096;
}

std::string metrics_json(const MeshResult& r) {
    const auto& q = r.quality;
    nlohmann::ordered_json j;
    j["points"] = q.points;
    j["boundary_points"] = q.boundary_points;
    j["interior_points"] = q.interior_points;
    j["triangles"] = q.triangles;
    j["angle_deg"] = {{"min", q.angle_min}, {"max", q.angle_max}, {"mean", q.angle_mean}};
    j["quality"] = {{"min", q.quality_min}, {"mean", q.quality_mean}, {"histogram", q.quality_histogram}};
    j["size_ratio"] = {{"mean", q.size_ratio_mean}, {"within_sqrt2", q.size_ratio_within_sqrt2}};
    j["timings_ms"] = {{"boundary", r.timings.boundary_ms},
                       {"interior", r.timings.interior_ms},
                       {"triangulation", r.timings.triangulation_ms},
                       {"smoothing", r.timings.smoothing_ms},
                       {"total", r.timings.total_ms}};
    j["predicates_exact"] = {{"orient", r.stats.orient_exact}, {"incircle", r.stats.incircle_exact}};
    return j.dump();
}

void write_json(const MeshResult& r, std::ostream& os) {
    const Mesh& m = r.mesh;
    os << "{\"mesh\":{\"points\":[";
    for (size_t v = 0; v < m.point_count(); ++v) os << (v ? ",[" : "[") << Num(m.x[v]) << ',' << Num(m.y[v]) << ']';
    os << "],\"triangles\":[";
    for (size_t t = 0; t < m.triangles.size(); ++t) {
        const auto& T = m.triangles[t];
        os << (t ? ",[" : "[") << T.v[0] << ',' << T.v[1] << ',' << T.v[2] << ']';
    }
    os << "],\"boundaries\":{";
    const auto groups = edges_by_tag(m);
    for (size_t g = 0; g < groups.size(); ++g) {
        os << (g ? "," : "") << nlohmann::json(m.tags[g]).dump() << ":[";
        for (size_t i = 0; i < groups[g].size(); ++i)
            os << (i ? ",[" : "[") << groups[g][i]->a << ',' << groups[g][i]->b << ']';
        os << ']';
    }
    os << "}},\"metrics\":" << metrics_json(r) << "}\n";
}

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

void write_su2(const MeshResult& r, std::ostream& os) {
    const Mesh& m = r.mesh;
    os << "% meshd\nNDIME= 2\nNELEM= " << m.triangles.size() << '\n';
    for (size_t t = 0; t < m.triangles.size(); ++t) {
        const auto& T = m.triangles[t];
        os << "5 " << T.v[0] << ' ' << T.v[1] << ' ' << T.v[2] << ' ' << t << '\n';
    }
    os << "NPOIN= " << m.point_count() << '\n';
    for (size_t v = 0; v < m.point_count(); ++v) os << Num(m.x[v]) << ' ' << Num(m.y[v]) << ' ' << v << '\n';
    const auto groups = edges_by_tag(m);
    size_t marks = 0;
    for (const auto& g : groups) marks += g.empty() ? 0u : 1u;
    os << "NMARK= " << marks << '\n';
    for (size_t g = 0; g < groups.size(); ++g) {
        if (groups[g].empty()) continue;
        std::string tag = m.tags[g];
        for (char& c : tag)
            if (c == ' ' || c == '\t' || c == '\n' || c == '\r') c = '_';
        os << "MARKER_TAG= " << tag << "\nMARKER_ELEMS= " << groups[g].size() << '\n';
        for (const auto* e : groups[g]) os << "3 " << e->a << ' ' << e->b << '\n';
    }
}

void write_msh(const MeshResult& r, std::ostream& os) {
    const Mesh& m = r.mesh;
    const auto groups = edges_by_tag(m);
    // Physical groups: one curve group per tag (tags 1..n), the surface as tag n + 1.
    const size_t ncurves = groups.size();
    os << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n" << ncurves + 1 << '\n';
    for (size_t g = 0; g < ncurves; ++g) os << "1 " << g + 1 << ' ' << nlohmann::json(m.tags[g]).dump() << '\n';
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
       << m.triangles.size() << " triangles</title>\n<g stroke=\"#333\" stroke-width=\"" << Num(stroke)
       << "\" stroke-linejoin=\"round\">\n";
    for (const auto& t : m.triangles) {
        if (!visible({t.v[0], t.v[1], t.v[2]})) continue;
        // Quality 0 -> red, 0.5 -> yellow, 1 -> pale green.
        const double q = tri_quality(m, t);
        const int red = q < 0.5 ? 230 : static_cast<int>(230 - (q - 0.5) * 2 * 130);
        const int green = q < 0.5 ? static_cast<int>(60 + q * 2 * 170) : 230;
        const int blue = q < 0.5 ? 60 : static_cast<int>(60 + (q - 0.5) * 2 * 130);
        char fill[8];
        std::snprintf(fill, sizeof fill, "#%02x%02x%02x", red, green, blue);
        os << "<path fill=\"" << fill << "\" d=\"M" << X(m.x[t.v[0]]) << ' ' << Y(m.y[t.v[0]]) << 'L'
           << X(m.x[t.v[1]]) << ' ' << Y(m.y[t.v[1]]) << 'L' << X(m.x[t.v[2]]) << ' ' << Y(m.y[t.v[2]]) << "Z\"/>\n";
    }
    os << "</g>\n";
    static constexpr std::array<const char*, 8> kColours = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd",
                                                            "#ff7f0e", "#17becf", "#e377c2", "#8c564b"};
    const auto groups = edges_by_tag(m);
    for (size_t g = 0; g < groups.size(); ++g) {
        os << "<g stroke=\"" << kColours[g % kColours.size()] << "\" stroke-width=\"" << Num(4 * stroke)
           << "\" fill=\"none\"><title>" << nlohmann::json(m.tags[g]).dump() << "</title>\n<path d=\"";
        for (const auto* e : groups[g])
            if (visible({e->a, e->b})) os << 'M' << X(m.x[e->a]) << ' ' << Y(m.y[e->a]) << 'L' << X(m.x[e->b]) << ' ' << Y(m.y[e->b]);
        os << "\"/></g>\n";
    }
    os << "</svg>\n";
}

void write_mesh(Format f, const MeshResult& r, std::ostream& os) {
    switch (f) {
        case Format::Json: write_json(r, os); break;
        case Format::Vtk: write_vtk(r, os); break;
        case Format::Su2: write_su2(r, os); break;
        case Format::Msh: write_msh(r, os); break;
        case Format::Svg: write_svg(r, os); break;
    }
}

}  // namespace meshd::api
