// An OpenFOAM case's constant/polyMesh (points, faces, owner, neighbour, boundary) as a tar
// archive: the 2D mesh extruded one cell thick in z, a prism per triangle and a hexahedron
// per quad (the boundary layers). Faces are in the order OpenFOAM requires: the internal
// faces first, by owner and then neighbour (upper triangular), each pointing from its owner
// (the lower cell) into its neighbour; then the boundary faces patch by patch, pointing out of the domain: one patch per tag, then the two
// faces of the slab in `frontAndBack` of type empty. Embedded edges are internal faces (a tag
// on embedded curves alone has no patch).
//
// The archive is written as it goes: each file is formatted twice, once to count its bytes
// for the tar header and once into the stream, so that no copy of the mesh is held as text.

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdio>
#include <map>
#include <streambuf>
#include <unordered_map>

#include "writers/common.hpp"

namespace meshd::api {

using namespace writers;

namespace {

// A stream buffer that only counts what is written to it.
class CountingBuf : public std::streambuf {
public:
    size_t count() const { return n_; }

protected:
    std::streamsize xsputn(const char*, std::streamsize n) override {
        n_ += static_cast<size_t>(n);
        return n;
    }
    int overflow(int c) override {
        if (c != traits_type::eof()) ++n_;
        return c == traits_type::eof() ? 0 : c;
    }

private:
    size_t n_ = 0;
};

// A ustar header block: name, size, type ('0' file, '5' directory); mode 0644/0755, owner
// and time 0 (the same mesh gives the same bytes).
void tar_header(std::ostream& os, const std::string& name, size_t size, char type) {
    std::array<char, 512> h{};
    std::snprintf(h.data(), 100, "%s", name.c_str());
    std::snprintf(h.data() + 100, 8, "%07o", type == '5' ? 0755u : 0644u);
    std::snprintf(h.data() + 108, 8, "%07o", 0u);
    std::snprintf(h.data() + 116, 8, "%07o", 0u);
    std::snprintf(h.data() + 124, 12, "%011llo", static_cast<unsigned long long>(size));
    std::snprintf(h.data() + 136, 12, "%011o", 0u);
    h[156] = type;
    std::memcpy(h.data() + 257, "ustar", 6);
    std::memcpy(h.data() + 263, "00", 2);
    std::memset(h.data() + 148, ' ', 8);
    unsigned sum = 0;
    for (char c : h) sum += static_cast<unsigned char>(c);
    std::snprintf(h.data() + 148, 8, "%06o", sum);
    h[155] = ' ';
    os.write(h.data(), 512);
}

// One file of the archive: its bytes counted, then written, then padded to a block.
template <class Write>
void tar_file(std::ostream& os, const std::string& name, Write&& write) {
    CountingBuf counter;
    std::ostream counting(&counter);
    write(counting);
    tar_header(os, name, counter.count(), '0');
    write(os);
    static const std::array<char, 512> zeros{};
    os.write(zeros.data(), static_cast<std::streamsize>((512 - counter.count() % 512) % 512));
}

void foam_header(std::ostream& os, const char* cls, const char* object, const std::string& note = {}) {
    os << "FoamFile\n{\n    version     2.0;\n    format      ascii;\n    class       " << cls << ";\n";
    if (!note.empty()) os << "    note        \"" << note << "\";\n";
    os << "    location    \"constant/polyMesh\";\n    object      " << object << ";\n}\n\n";
}

struct Face {
    std::uint32_t owner, neighbour;   // neighbour: kNoTriangle for boundary faces
    std::uint32_t a, b;               // the edge, the owner on its left
};

}  // namespace

void write_foam(const MeshResult& r, std::ostream& os, const FoamOptions& options) {
    const Mesh& m = r.mesh;
    const size_t np = m.point_count(), nt = m.triangles.size(), nq = m.quads.size(), nc = nt + nq;

    // The tag of every loop edge, by its two points.
    std::unordered_map<std::uint64_t, core::TagId> tag_of;
    double boundary_length = 0.0;
    size_t boundary_edges = 0;
    auto key = [](std::uint32_t a, std::uint32_t b) {
        return (static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
    };
    for (const core::MeshEdge& e : m.edges) {
        if (e.embedded) continue;
        tag_of[key(e.a, e.b)] = e.tag;
        boundary_length += core::distance(m.point(e.a), m.point(e.b));
        ++boundary_edges;
    }
    const double h = options.slab_thickness.value_or(boundary_edges ? boundary_length / static_cast<double>(boundary_edges) : 1.0);

    // Cells: the triangles (prisms), then the quads (hexahedra). Across a triangle's side the
    // neighbour is its adjacent triangle, or the quad that has the side the other way round.
    std::unordered_map<std::uint64_t, std::uint32_t> quad_side;  // directed side -> cell
    auto directed = [](std::uint32_t a, std::uint32_t b) { return (static_cast<std::uint64_t>(a) << 32) | b; };
    for (size_t q = 0; q < nq; ++q)
        for (size_t i = 0; i < 4; ++i)
            quad_side.emplace(directed(m.quads[q][i], m.quads[q][(i + 1) % 4]), static_cast<std::uint32_t>(nt + q));
    auto across = [&](std::uint32_t a, std::uint32_t b) {  // the cell with side b -> a, if a quad
        const auto it = quad_side.find(directed(b, a));
        return it == quad_side.end() ? core::kNoTriangle : it->second;
    };
    // Internal faces by owner, then neighbour; boundary faces by tag.
    std::vector<Face> internal;
    std::vector<std::vector<Face>> by_tag(m.tags.size());
    std::array<Face, 4> own{};
    size_t n_own = 0;
    auto side_of = [&](std::uint32_t c, std::uint32_t a, std::uint32_t b, std::uint32_t other) {
        if (other == core::kNoTriangle) {
            const auto it = tag_of.find(key(a, b));
            if (it != tag_of.end()) by_tag[it->second].push_back({c, core::kNoTriangle, a, b});
        } else if (other > c) {
            own[n_own++] = {c, other, a, b};
        }
    };
    auto flush = [&] {
        // At most four: by neighbour, insertion.
        for (size_t i = 1; i < n_own; ++i)
            for (size_t j = i; j > 0 && own[j].neighbour < own[j - 1].neighbour; --j) std::swap(own[j], own[j - 1]);
        for (size_t i = 0; i < n_own; ++i) internal.push_back(own[i]);
        n_own = 0;
    };
    for (std::uint32_t t = 0; t < nt; ++t) {
        const core::Triangle& T = m.triangles[t];
        for (std::uint32_t i = 0; i < 3; ++i) {
            const std::uint32_t a = T.v[(i + 1) % 3], b = T.v[(i + 2) % 3];
            side_of(t, a, b, T.n[i] != core::kNoTriangle ? T.n[i] : across(a, b));
        }
        flush();
    }
    if (nq) {
        // A quad's neighbour: the cell holding its side the other way round.
        std::unordered_map<std::uint64_t, std::uint32_t> tri_side;
        for (std::uint32_t t = 0; t < nt; ++t)
            for (std::uint32_t i = 0; i < 3; ++i)
                if (m.triangles[t].n[i] == core::kNoTriangle)
                    tri_side.emplace(directed(m.triangles[t].v[(i + 1) % 3], m.triangles[t].v[(i + 2) % 3]), t);
        for (size_t q = 0; q < nq; ++q) {
            const std::uint32_t c = static_cast<std::uint32_t>(nt + q);
            for (size_t i = 0; i < 4; ++i) {
                const std::uint32_t a = m.quads[q][i], b = m.quads[q][(i + 1) % 4];
                std::uint32_t other = across(a, b);
                if (other == core::kNoTriangle) {
                    const auto it = tri_side.find(directed(b, a));
                    if (it != tri_side.end()) other = it->second;
                }
                side_of(c, a, b, other);
            }
            flush();
        }
    }
    size_t n_boundary = 0;
    for (const auto& f : by_tag) n_boundary += f.size();
    const size_t nfaces = internal.size() + n_boundary + 2 * nc;

    // Patch names: OpenFOAM words (letters, digits, _ - . +; not starting with a digit).
    std::vector<std::string> names = tag_names(
        m.tags, [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.' || c == '+'; },
        {"frontAndBack"});
    for (std::string& n : names)
        if (n.empty() || std::isdigit(static_cast<unsigned char>(n[0]))) n = "tag_" + n;

    const std::string dir = "constant/polyMesh/";
    tar_header(os, "constant/", 0, '5');
    tar_header(os, dir, 0, '5');

    tar_file(os, dir + "points", [&](std::ostream& out) {
        foam_header(out, "vectorField", "points");
        out << 2 * np << "\n(\n";
        for (size_t v = 0; v < np; ++v) out << '(' << Num(m.x[v]) << ' ' << Num(m.y[v]) << " 0)\n";
        for (size_t v = 0; v < np; ++v) out << '(' << Num(m.x[v]) << ' ' << Num(m.y[v]) << ' ' << Num(h) << ")\n";
        out << ")\n";
    });
    // A side face a -> b with the owner on the left: (a, b, b', a') points to the right, out
    // of the owner. The slab's faces: the bottom (v0, v2, v1) down, the top (v0', v1', v2') up.
    const std::uint32_t top = static_cast<std::uint32_t>(np);
    auto side = [&](std::ostream& out, const Face& f) {
        out << "4(" << f.a << ' ' << f.b << ' ' << f.b + top << ' ' << f.a + top << ")\n";
    };
    tar_file(os, dir + "faces", [&](std::ostream& out) {
        foam_header(out, "faceList", "faces");
        out << nfaces << "\n(\n";
        for (const Face& f : internal) side(out, f);
        for (const auto& patch : by_tag)
            for (const Face& f : patch) side(out, f);
        for (const core::Triangle& T : m.triangles) out << "3(" << T.v[0] << ' ' << T.v[2] << ' ' << T.v[1] << ")\n";
        for (const auto& Q : m.quads) out << "4(" << Q[0] << ' ' << Q[3] << ' ' << Q[2] << ' ' << Q[1] << ")\n";
        for (const core::Triangle& T : m.triangles)
            out << "3(" << T.v[0] + top << ' ' << T.v[1] + top << ' ' << T.v[2] + top << ")\n";
        for (const auto& Q : m.quads)
            out << "4(" << Q[0] + top << ' ' << Q[1] + top << ' ' << Q[2] + top << ' ' << Q[3] + top << ")\n";
        out << ")\n";
    });
    const std::string note = "nPoints:" + std::to_string(2 * np) + "  nCells:" + std::to_string(nc) +
                             "  nFaces:" + std::to_string(nfaces) + "  nInternalFaces:" + std::to_string(internal.size());
    tar_file(os, dir + "owner", [&](std::ostream& out) {
        foam_header(out, "labelList", "owner", note);
        out << nfaces << "\n(\n";
        for (const Face& f : internal) out << f.owner << '\n';
        for (const auto& patch : by_tag)
            for (const Face& f : patch) out << f.owner << '\n';
        for (int slab_side = 0; slab_side < 2; ++slab_side)
            for (size_t c = 0; c < nc; ++c) out << c << '\n';
        out << ")\n";
    });
    tar_file(os, dir + "neighbour", [&](std::ostream& out) {
        foam_header(out, "labelList", "neighbour", note);
        out << internal.size() << "\n(\n";
        for (const Face& f : internal) out << f.neighbour << '\n';
        out << ")\n";
    });
    tar_file(os, dir + "boundary", [&](std::ostream& out) {
        foam_header(out, "polyBoundaryMesh", "boundary");
        size_t used = 0;
        for (const auto& f : by_tag) used += f.empty() ? 0u : 1u;
        out << used + 1 << "\n(\n";
        size_t start = internal.size();
        auto patch = [&](const std::string& name, const std::string& type, size_t n) {
            out << "    " << name << "\n    {\n        type            " << type << ";\n";
            if (type == "wall" || type == "empty" || type == "symmetryPlane" || type == "symmetry")
                out << "        inGroups        List<word> 1(" << type << ");\n";
            out << "        nFaces          " << n << ";\n        startFace       " << start << ";\n    }\n";
            start += n;
        };
        for (size_t g = 0; g < m.tags.size(); ++g) {
            if (by_tag[g].empty()) continue;  // a tag of embedded curves only: internal faces
            const auto it = options.patch_types.find(m.tags[g]);
            patch(names[g], it == options.patch_types.end() ? "patch" : it->second, by_tag[g].size());
        }
        patch("frontAndBack", "empty", 2 * nc);
        out << ")\n";
    });
    static const std::array<char, 1024> end{};
    os.write(end.data(), end.size());
}

}  // namespace meshd::api
