#pragma once
/// Mesh writers: the JSON response of docs/api.md, legacy VTK (binary, big-endian), SU2, Gmsh
/// MSH 4.1 and SVG. All write straight to a stream as they go: no second copy of the mesh
/// is built as text.

#include <map>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>

#include "meshd/core/mesher.hpp"

namespace meshd::api {

enum class Format { Json, Vtk, Su2, Msh, Svg, Foam, Cgns };

inline constexpr Format kFormats[] = {Format::Json, Format::Vtk, Format::Su2, Format::Msh,
                                      Format::Svg,  Format::Foam, Format::Cgns};

std::optional<Format> parse_format(std::string_view name);
/// Why format `f` cannot hold a second-order mesh (su2, foam), or nothing. write_mesh throws
/// std::invalid_argument with this text for an order-2 mesh; the server answers 422 first.
std::optional<std::string> second_order_refusal(Format f);
const char* format_name(Format f);
/// Every format's name, joined by ", " (for messages).
std::string format_list();
const char* content_type(Format f);

/// The metrics object of the JSON response (docs/api.md), as JSON text.
std::string metrics_json(const core::MeshResult& r);

/// Memory a finished result holds (its arrays, roughly), for the server's result budget.
size_t result_bytes(const core::MeshResult& r);

struct FoamOptions;
/// `foam`: the options of format=foam (the request's patch_types and slab_thickness).
void write_mesh(Format f, const core::MeshResult& r, std::ostream& os, const FoamOptions& foam);
void write_mesh(Format f, const core::MeshResult& r, std::ostream& os);

/// `sizes`: also the target size (rho) at each point, as "sizes" beside "points" (the web page
/// colours triangles by their size against it; `?sizes=true` on format=json).
void write_json(const core::MeshResult& r, std::ostream& os, bool sizes = false);
/// Triangles (VTK_TRIANGLE) then loop and embedded edges (VTK_LINE); cell data "tag" (the
/// tag id of each line, -1 for triangles) and "quality" (radius ratio, 0 for lines); point
/// data "target_size". Tag names are in the header line.
void write_vtk(const core::MeshResult& r, std::ostream& os);
void write_su2(const core::MeshResult& r, std::ostream& os);
void write_msh(const core::MeshResult& r, std::ostream& os);

struct FoamOptions {
    /// Tag -> OpenFOAM patch type (wall, symmetryPlane, ...); other tags are `patch`.
    std::map<std::string, std::string> patch_types;
    /// The slab's thickness; default: the mean length of the boundary edges.
    std::optional<double> slab_thickness;
};
/// An OpenFOAM constant/polyMesh as a tar archive (foam.cpp): the mesh extruded one cell
/// thick, one patch per tag (named by the tag, characters OpenFOAM refuses as '_'), the slab's
/// faces in the empty patch frontAndBack.
void write_foam(const core::MeshResult& r, std::ostream& os, const FoamOptions& options = {});
/// CGNS/HDF5 (cgns.cpp): one unstructured zone, a TRI_3 section, a BAR_2 section per tag,
/// a boundary condition (and family) per loop tag, typed from `options.patch_types`.
void write_cgns(const core::MeshResult& r, std::ostream& os, const FoamOptions& options = {});
/// view: the window of the plane to draw (default: the whole mesh); triangles and edges
/// outside it are left out.
void write_svg(const core::MeshResult& r, std::ostream& os, std::optional<core::Box> view = std::nullopt);

}  // namespace meshd::api
