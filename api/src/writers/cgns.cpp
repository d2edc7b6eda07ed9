// CGNS (HDF5) through the CGNS library, as CFD codes read it: one base (cell and physical
// dimension 2), one unstructured zone, coordinates X and Y, a TRI_3 section of the
// triangles, then a BAR_2 section per tag of the loop edges (the boundary elements) and per
// tag of embedded edges; a boundary condition per loop tag over its section's element range
// (GridLocation EdgeCenter), of type FamilySpecified in a family of the tag's name whose
// FamilyBC carries the type from the request's patch_types (wall: BCWall, symmetry or
// symmetryPlane: BCSymmetryPlane, else BCTypeUserDefined), the pattern mesh generators use
// and readers expect. Names are cut to CGNS's 32 characters and kept apart.
//
// The library writes files and keeps global state: the file is written in a scratch
// directory under one process-wide lock, then copied to the stream and removed.

#include <cgnslib.h>
#include <fcntl.h>
#include <unistd.h>

#include <cstdlib>
#include <mutex>
#include <stdexcept>

#include "writers/common.hpp"

namespace meshd::api {

using namespace writers;

namespace {

constexpr size_t kCgnsName = 32;

[[noreturn]] void fail(const char* what) { throw std::runtime_error(std::string("CGNS: ") + what + ": " + cg_get_error()); }

void must(int status, const char* what) {
    if (status != CG_OK) fail(what);
}

BCType_t bc_type(const std::string& foam_type) {
    if (foam_type == "wall") return BCWall;
    if (foam_type == "symmetryPlane" || foam_type == "symmetry") return BCSymmetryPlane;
    return BCTypeUserDefined;
}

// A private directory for the file the library insists on creating itself (it refuses a
// path that exists, so a memory file's /proc path will not do): in $TMPDIR, else /tmp,
// else /dev/shm (a tmpfs even under a read-only root). Removed with its file at the end.
struct ScratchFile {
    std::string dir, path;
    ScratchFile() {
        std::vector<std::string> places;
        if (const char* t = std::getenv("TMPDIR"); t && *t) places.push_back(t);
        places.insert(places.end(), {"/tmp", "/dev/shm"});
        for (const std::string& place : places) {
            std::string tmpl = place + "/meshd-cgns-XXXXXX";
            if (mkdtemp(tmpl.data())) {
                dir = tmpl;
                path = dir + "/mesh.cgns";
                return;
            }
        }
        throw std::runtime_error("CGNS: no writable scratch directory ($TMPDIR, /tmp or /dev/shm)");
    }
    ~ScratchFile() {
        unlink(path.c_str());
        rmdir(dir.c_str());
    }
};

void write_file(const Mesh& m, const std::string& path, const FoamOptions& options) {
    const bool quadratic = m.order() == 2;  // TRI_6 and BAR_3
    const size_t nv = all_points(m), nt = m.triangles.size();
    if (nv > static_cast<size_t>(INT32_MAX) || nt + m.edges.size() > static_cast<size_t>(INT32_MAX))
        throw std::runtime_error("CGNS: the mesh has more elements than this CGNS library counts (2^31)");
    must(cg_set_file_type(CG_FILE_HDF5), "file type");
    int fn = 0;
    must(cg_open(path.c_str(), CG_MODE_WRITE, &fn), "open");
    // Closed on every path: an error leaves no file open in the library's tables.
    struct Closer {
        int fn;
        ~Closer() { cg_close(fn); }
    } closer{fn};
    int base = 0, zone = 0, coord = 0, section = 0;
    must(cg_base_write(fn, "Base", 2, 2, &base), "base");
    // Lengths in the request's own unit, which meshd does not know.
    must(cg_goto(fn, base, "end"), "goto base");
    must(cg_dataclass_write(NormalizedByUnknownDimensional), "data class");
    const size_t nq = m.quads.size();
    cgsize_t size[3] = {static_cast<cgsize_t>(nv), static_cast<cgsize_t>(nt + nq), 0};
    must(cg_zone_write(fn, base, "Zone", size, Unstructured, &zone), "zone");
    std::vector<double> c(nv);
    for (size_t i = 0; i < nv; ++i) c[i] = any_point(m, i).x;
    // Each coordinate a length: exponents 0 of mass, 1 of length, 0 of time, temperature, angle.
    const double length[5] = {0, 1, 0, 0, 0};
    auto write_coordinate = [&](const char* name) {
        must(cg_coord_write(fn, base, zone, RealDouble, name, c.data(), &coord), name);
        must(cg_goto(fn, base, "Zone_t", zone, "GridCoordinates_t", 1, "DataArray_t", coord, "end"), "goto coordinate");
        must(cg_exponents_write(RealDouble, length), "exponents");
    };
    write_coordinate("CoordinateX");
    for (size_t i = 0; i < nv; ++i) c[i] = any_point(m, i).y;
    write_coordinate("CoordinateY");
    c = {};

    std::vector<cgsize_t> conn;
    conn.reserve((quadratic ? 6 : 3) * nt);
    for (size_t t = 0; t < nt; ++t) {
        if (quadratic) {
            for (size_t v : six_nodes(m, t)) conn.push_back(static_cast<cgsize_t>(v) + 1);
        } else {
            for (size_t k = 0; k < 3; ++k) conn.push_back(static_cast<cgsize_t>(m.triangles[t].v[k]) + 1);
        }
    }
    must(cg_section_write(fn, base, zone, "Triangles", quadratic ? TRI_6 : TRI_3, 1, static_cast<cgsize_t>(nt), 0,
                          conn.data(), &section),
         "triangles");

    if (nq) {  // the boundary layers' quads: a QUAD_4 section after the triangles
        conn.clear();
        for (const auto& q : m.quads)
            for (auto v : q) conn.push_back(static_cast<cgsize_t>(v) + 1);
        must(cg_section_write(fn, base, zone, "Quadrilaterals", QUAD_4, static_cast<cgsize_t>(nt) + 1,
                              static_cast<cgsize_t>(nt + nq), 0, conn.data(), &section),
             "quadrilaterals");
    }

    // Names within 32 characters, apart from each other and from the sections above.
    std::set<std::string> taken{"Triangles", "Quadrilaterals"};
    auto fit = [&](const std::string& stem, const std::string& suffix) {
        std::string name = stem.substr(0, kCgnsName - suffix.size()) + suffix;
        for (int k = 2; taken.count(name); ++k) {
            const std::string more = suffix + "_" + std::to_string(k);
            name = stem.substr(0, kCgnsName - more.size()) + more;
        }
        taken.insert(name);
        return name;
    };
    std::vector<std::string> short_names;
    for (const std::string& n : tag_names(m.tags, [](char ch) { return ch != '/' && ch != '.'; })) short_names.push_back(fit(n, ""));

    cgsize_t next = static_cast<cgsize_t>(nt + nq) + 1;
    const auto groups = edges_by_tag(m);
    for (int pass = 0; pass < 2; ++pass) {  // the boundary, then the embedded edges
        const bool embedded = pass == 1;
        for (size_t tag = 0; tag < groups.size(); ++tag) {
            std::vector<const core::MeshEdge*> edges;
            for (const core::MeshEdge* e : groups[tag])
                if (e->embedded == embedded) edges.push_back(e);
            if (edges.empty()) continue;
            // A tag on both loop and embedded edges: the embedded ones get their own section.
            const bool both = !embedded ? false
                                        : std::any_of(groups[tag].begin(), groups[tag].end(),
                                                      [](const core::MeshEdge* e) { return !e->embedded; });
            const std::string name = both ? fit(short_names[tag], "_embedded") : short_names[tag];
            conn.clear();
            for (const core::MeshEdge* e : edges) {
                conn.push_back(static_cast<cgsize_t>(e->a) + 1);
                conn.push_back(static_cast<cgsize_t>(e->b) + 1);
                if (quadratic) conn.push_back(static_cast<cgsize_t>(edge_middle(m, *e)) + 1);
            }
            const cgsize_t first = next, last = next + static_cast<cgsize_t>(edges.size()) - 1;
            must(cg_section_write(fn, base, zone, name.c_str(), quadratic ? BAR_3 : BAR_2, first, last, 0, conn.data(),
                                  &section),
                 "edges");
            next = last + 1;
            if (embedded) continue;  // inside the domain: no boundary condition
            auto it = options.patch_types.find(m.tags[tag]);
            const BCType_t type = bc_type(it == options.patch_types.end() ? "" : it->second);
            int family = 0, fambc = 0, bc = 0;
            must(cg_family_write(fn, base, name.c_str(), &family), "family");
            must(cg_fambc_write(fn, base, family, "FamBC", type, &fambc), "family BC");
            const cgsize_t range[2] = {first, last};
            must(cg_boco_write(fn, base, zone, name.c_str(), FamilySpecified, PointRange, 2, range, &bc), "boundary condition");
            must(cg_boco_gridlocation_write(fn, base, zone, bc, EdgeCenter), "grid location");
            must(cg_goto(fn, base, "Zone_t", zone, "ZoneBC_t", 1, "BC_t", bc, "end"), "goto");
            must(cg_famname_write(name.c_str()), "family name");
        }
    }
}

}  // namespace

void write_cgns(const MeshResult& r, std::ostream& os, const FoamOptions& options) {
    ScratchFile file;
    {
        static std::mutex library;  // the CGNS library and HDF5 (serial) are not thread-safe
        std::lock_guard<std::mutex> lock(library);
        write_file(r.mesh, file.path, options);
    }
    const int fd = open(file.path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) throw std::runtime_error("CGNS: cannot read back the written file");
    std::vector<char> buf(1 << 16);
    ssize_t n = 0;
    while ((n = read(fd, buf.data(), buf.size())) > 0) os.write(buf.data(), n);
    close(fd);
    if (n < 0) throw std::runtime_error("CGNS: cannot read back the written file");
}

}  // namespace meshd::api
