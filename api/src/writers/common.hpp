#pragma once
// What the writers share: shortest round-trip numbers, big-endian binary, edges by tag.

#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <ostream>
#include <set>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "meshd/api/writers.hpp"
#include "writers/shortest.hpp"

namespace meshd::api::writers {

using core::Mesh;
using core::MeshResult;

// Shortest text that reads back to the same double (std::to_chars's, faster: shortest.hpp),
// written where it goes.
struct Num {
    double v;
    explicit Num(double value) : v(value) {}
};
inline std::ostream& operator<<(std::ostream& os, const Num& n) {
    char buf[kShortestMax];
    return os.write(buf, shortest(buf, n.v) - buf);
}

// Text into a stream through a buffer of its own: doubles by shortest(), integers by
// to_chars and runs of characters by memcpy, the stream seeing one write per 64 KiB. Through
// the stream's own operators each token paid a sentry and a locale lookup: 3% of the server's
// time in the load run (docs/benchmarks.md). Flushes when destroyed.
class TextOut {
public:
    explicit TextOut(std::ostream& os) : os_(os) {}
    TextOut(const TextOut&) = delete;
    TextOut& operator=(const TextOut&) = delete;
    ~TextOut() { flush(); }

    TextOut& operator<<(char c) {
        room(1);
        buf_[n_++] = c;
        return *this;
    }
    TextOut& operator<<(std::string_view s) {
        if (s.size() > sizeof buf_ / 2) {
            flush();
            os_.write(s.data(), static_cast<std::streamsize>(s.size()));
            return *this;
        }
        room(s.size());
        std::memcpy(buf_ + n_, s.data(), s.size());
        n_ += s.size();
        return *this;
    }
    TextOut& operator<<(const char* s) { return *this << std::string_view(s); }
    TextOut& operator<<(const std::string& s) { return *this << std::string_view(s); }
    TextOut& operator<<(const Num& v) {
        room(kShortestMax);
        n_ = static_cast<size_t>(shortest(buf_ + n_, v.v) - buf_);
        return *this;
    }
    template <class I>
        requires std::is_integral_v<I>
    TextOut& operator<<(I v) {
        room(24);
        if constexpr (std::is_same_v<I, std::uint32_t>)  // a mesh's indices
            n_ = static_cast<size_t>(put_unsigned(buf_ + n_, v) - buf_);
        else
            n_ = static_cast<size_t>(std::to_chars(buf_ + n_, buf_ + sizeof buf_, v).ptr - buf_);
        return *this;
    }
    /// Room for k characters at the cursor returned; done(p) keeps what was written up to p.
    /// For runs of tokens written through a local pointer: each token through the operators
    /// above reloads the buffer's fill count, as any character stored may alias it.
    char* claim(size_t k) {
        room(k);
        return buf_ + n_;
    }
    void done(const char* p) { n_ = static_cast<size_t>(p - buf_); }
    // GCC at -O1 (the sanitizers' build) takes buf_ for unwritten where numbers went in by
    // shortest(), out of its sight: only the n_ characters written so far are passed.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
    void flush() {
        if (n_) os_.write(buf_, static_cast<std::streamsize>(n_));
        n_ = 0;
    }
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

private:
    void room(size_t k) {
        if (n_ + k > sizeof buf_) flush();
    }
    std::ostream& os_;
    size_t n_ = 0;
    char buf_[std::size_t{1} << 16];
};

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

inline double tri_quality(const Mesh& m, const core::Triangle& t) {
    return core::radius_ratio(m.point(t.v[0]), m.point(t.v[1]), m.point(t.v[2]));
}

// Second order: the points of a file are the vertices, then the edge nodes (Mesh::edge_nodes).
/// A quad's quality: its scaled Jacobian, the smallest over its corners of the sine of the
/// corner's angle (1 for a rectangle).
inline double quad_quality(const Mesh& m, const std::array<core::VertexId, 4>& q) {
    double lowest = 1.0;
    for (size_t i = 0; i < 4; ++i) {
        const core::Vec2 p = m.point(q[i]), e1 = m.point(q[(i + 1) % 4]) - p, e0 = m.point(q[(i + 3) % 4]) - p;
        lowest = std::fmin(lowest, core::cross(e1, e0) / (core::norm(e1) * core::norm(e0)));
    }
    return lowest;
}

inline size_t all_points(const Mesh& m) { return m.point_count() + m.edge_nodes.size(); }
inline core::Vec2 any_point(const Mesh& m, size_t id) {
    return id < m.point_count() ? m.point(static_cast<core::VertexId>(id)) : m.edge_nodes[id - m.point_count()];
}
/// The target size (rho) at every point of all_points(): an edge node takes its edge's ends'
/// mean.
inline std::vector<double> point_sizes(const Mesh& m) {
    std::vector<double> size(all_points(m), 0.0);
    for (size_t v = 0; v < m.point_count() && v < m.target_size.size(); ++v) size[v] = m.target_size[v];
    for (size_t t = 0; t < m.edge_node.size(); ++t)
        for (size_t i = 0; i < 3; ++i) {
            const auto a = m.triangles[t].v[(i + 1) % 3], b = m.triangles[t].v[(i + 2) % 3];
            if (a < m.target_size.size() && b < m.target_size.size())
                size[m.point_count() + m.edge_node[t][i]] = (m.target_size[a] + m.target_size[b]) / 2;
        }
    return size;
}

// A 6-node triangle in the order VTK, gmsh and CGNS share: corners, then the nodes on
// (v0, v1), (v1, v2), (v2, v0).
inline std::array<size_t, 6> six_nodes(const Mesh& m, size_t t) {
    const auto& v = m.triangles[t].v;
    const auto& e = m.edge_node[t];
    const size_t n = m.point_count();
    return {v[0], v[1], v[2], n + e[2], n + e[0], n + e[1]};
}
// The node on a mesh edge (second order).
inline size_t edge_middle(const Mesh& m, const core::MeshEdge& e) {
    return m.point_count() + m.edge_node_of_edge[static_cast<size_t>(&e - m.edges.data())];
}

// Edges grouped by tag, in tag order.
inline std::vector<std::vector<const core::MeshEdge*>> edges_by_tag(const Mesh& m) {
    std::vector<std::vector<const core::MeshEdge*>> g(m.tags.size());
    for (const auto& e : m.edges) g[e.tag].push_back(&e);
    return g;
}

/// Names for the tags in a format that allows fewer characters: every character `keep`
/// refuses becomes '_'; two tags that then read alike stay apart (the later gets "_2", "_3",
/// ...); names in `taken` are avoided the same way (docs/api.md, "Tags in files").
template <class Keep>
std::vector<std::string> tag_names(const std::vector<std::string>& tags, Keep keep, std::set<std::string> taken = {}) {
    std::vector<std::string> out;
    for (const std::string& t : tags) {
        std::string base = t;
        for (char& c : base)
            if (!keep(c)) c = '_';
        std::string name = base;
        for (int k = 2; taken.count(name); ++k) name = base + "_" + std::to_string(k);
        taken.insert(name);
        out.push_back(name);
    }
    return out;
}

/// Text for XML character data and attribute values: & < > " ' as entities.
inline std::string xml_escaped(const std::string& s) {
    std::string out;
    out.reserve(s.size());
    for (const char c : s) {
        switch (c) {
            case '&': out += "&amp;"; break;
            case '<': out += "&lt;"; break;
            case '>': out += "&gt;"; break;
            case '"': out += "&quot;"; break;
            case '\'': out += "&apos;"; break;
            default: out += c;
        }
    }
    return out;
}

}  // namespace meshd::api::writers
