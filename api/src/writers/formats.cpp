// The formats by name and content type, the dispatch to their writers, result sizes.

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "writers/common.hpp"

namespace meshd::api {

using namespace writers;

std::optional<Format> parse_format(std::string_view n) {
    for (const Format f : kFormats)
        if (n == format_name(f)) return f;
    return std::nullopt;
}

std::string format_list() {
    std::string out;
    for (const Format f : kFormats) out += (out.empty() ? "" : ", ") + std::string(format_name(f));
    return out;
}

const char* format_name(Format f) {
    switch (f) {
        case Format::Json: return "json";
        case Format::Vtk: return "vtk";
        case Format::Su2: return "su2";
        case Format::Msh: return "msh";
        case Format::Svg: return "svg";
        case Format::Foam: return "foam";
        case Format::Cgns: return "cgns";
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
        case Format::Foam: return "application/x-tar";
        case Format::Cgns: return "application/x-hdf5";
    }
    return "application/octet-stream";
}

size_t result_bytes(const core::MeshResult& r) {
    const core::Mesh& m = r.mesh;
    return m.point_count() * (3 * sizeof(double) + sizeof(core::PointKind) + sizeof(core::CurveId) + sizeof(double)) +
           m.triangles.size() * sizeof(core::Triangle) + m.edges.size() * sizeof(core::MeshEdge) + 4096;
}

void write_mesh(Format f, const MeshResult& r, std::ostream& os) { write_mesh(f, r, os, FoamOptions{}); }

std::optional<std::string> second_order_refusal(Format f) {
    if (f == Format::Su2) return "SU2's native mesh format has no second-order triangles; ask for order 1, or take msh, vtk or cgns";
    if (f == Format::Foam) return "OpenFOAM has no curved cells; ask for order 1 for format=foam";
    return std::nullopt;
}

void write_mesh(Format f, const MeshResult& r, std::ostream& os, const FoamOptions& foam) {
    if (r.mesh.order() == 2)
        if (auto why = second_order_refusal(f)) throw std::invalid_argument(*why);
    switch (f) {
        case Format::Json: write_json(r, os); break;
        case Format::Vtk: write_vtk(r, os); break;
        case Format::Su2: write_su2(r, os); break;
        case Format::Msh: write_msh(r, os); break;
        case Format::Svg: write_svg(r, os); break;
        case Format::Foam: write_foam(r, os, foam); break;
        case Format::Cgns: write_cgns(r, os, foam); break;
    }
}

}  // namespace meshd::api
