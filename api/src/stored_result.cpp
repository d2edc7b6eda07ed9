#include "meshd/api/stored_result.hpp"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>

namespace meshd::api {

namespace {

constexpr std::string_view kMagic = "MESHDR03";

class Writer {
public:
    explicit Writer(std::string& out) : out_(out) {}
    void u8(std::uint8_t v) { out_.push_back(static_cast<char>(v)); }
    void u32(std::uint32_t v) {
        for (int i = 0; i < 4; ++i) out_.push_back(static_cast<char>((v >> (8 * i)) & 0xffu));
    }
    void u64(std::uint64_t v) {
        for (int i = 0; i < 8; ++i) out_.push_back(static_cast<char>((v >> (8 * i)) & 0xffu));
    }
    void f64(double v) { u64(std::bit_cast<std::uint64_t>(v)); }
    void str(const std::string& s) {
        u64(s.size());
        out_ += s;
    }

private:
    std::string& out_;
};

class Reader {
public:
    explicit Reader(std::string_view in) : in_(in) {}
    std::uint8_t u8() { return static_cast<std::uint8_t>(take(1)[0]); }
    std::uint32_t u32() {
        const std::string_view b = take(4);
        std::uint32_t v = 0;
        for (int i = 0; i < 4; ++i) v |= static_cast<std::uint32_t>(static_cast<unsigned char>(b[static_cast<size_t>(i)])) << (8 * i);
        return v;
    }
    std::uint64_t u64() {
        const std::string_view b = take(8);
        std::uint64_t v = 0;
        for (int i = 0; i < 8; ++i) v |= static_cast<std::uint64_t>(static_cast<unsigned char>(b[static_cast<size_t>(i)])) << (8 * i);
        return v;
    }
    double f64() { return std::bit_cast<double>(u64()); }
    /// A count of elements of `size` bytes each that the rest of the input can hold.
    size_t count(size_t size) {
        const std::uint64_t n = u64();
        if (n > (in_.size() - at_) / size) throw StoredResultError("stored result: a count runs past its end");
        return static_cast<size_t>(n);
    }
    std::string str() {
        const size_t n = count(1);
        return std::string(take(n));
    }
    std::string_view take(size_t n) {
        if (n > in_.size() - at_) throw StoredResultError("stored result: cut short");
        const std::string_view s = in_.substr(at_, n);
        at_ += n;
        return s;
    }
    bool done() const { return at_ == in_.size(); }

private:
    std::string_view in_;
    size_t at_ = 0;
};

}  // namespace

std::string encode_result(const core::MeshResult& r) {
    const core::Mesh& m = r.mesh;
    std::string out;
    out.reserve(kMagic.size() + 64 + m.point_count() * 37 + m.triangles.size() * 26 + m.edges.size() * 17 + 512);
    out += kMagic;
    Writer w(out);
    w.u64(m.point_count());
    for (size_t i = 0; i < m.point_count(); ++i) {
        w.f64(m.x[i]);
        w.f64(m.y[i]);
        w.u8(static_cast<std::uint8_t>(m.kind[i]));
        w.u32(m.curve[i]);
        w.f64(m.param[i]);
    }
    w.u64(m.target_size.size());
    for (double v : m.target_size) w.f64(v);
    w.u64(m.triangles.size());
    for (const core::Triangle& t : m.triangles) {
        for (auto v : t.v) w.u32(v);
        for (auto n : t.n) w.u32(n);
        w.u8(t.constrained);
        w.u8(t.boundary);
        w.u8(t.layer);
    }
    w.u64(m.quads.size());
    for (const auto& q : m.quads)
        for (auto v : q) w.u32(v);
    w.u64(m.edges.size());
    for (const core::MeshEdge& e : m.edges) {
        w.u32(e.a);
        w.u32(e.b);
        w.u32(e.tag);
        w.u32(e.curve);
        w.u8(e.embedded ? 1 : 0);
    }
    w.u64(m.tags.size());
    for (const std::string& t : m.tags) w.str(t);
    w.u64(m.holes);
    w.u64(m.curve_ends.size());
    for (const auto& ends : m.curve_ends) {
        w.u32(ends[0]);
        w.u32(ends[1]);
    }
    w.u64(m.loops.size());
    for (const auto& loop : m.loops) {
        w.u64(loop.size());
        for (const core::Mesh::LoopCurve& u : loop) {
            w.u32(u.curve);
            w.u8(u.reversed ? 1 : 0);
        }
    }
    w.u64(m.edge_nodes.size());
    for (const core::Vec2& p : m.edge_nodes) {
        w.f64(p.x);
        w.f64(p.y);
    }
    if (!m.edge_nodes.empty()) {
        for (const auto& e : m.edge_node)
            for (std::uint32_t k : e) w.u32(k);
        for (std::uint32_t k : m.edge_node_of_edge) w.u32(k);
    }

    const core::QualityMetrics& q = r.quality;
    for (size_t v : {q.points, q.boundary_points, q.interior_points, q.triangles}) w.u64(v);
    for (double v : {q.angle_min, q.angle_max, q.angle_mean, q.quality_min, q.quality_mean}) w.f64(v);
    for (std::uint64_t v : q.quality_histogram) w.u64(v);
    w.f64(q.size_ratio_mean);
    w.f64(q.size_ratio_within_sqrt2);
    w.u64(q.curved_edges);
    w.u64(q.straightened_edges);
    w.f64(q.scaled_jacobian_min);
    w.u64(q.quads);
    w.u64(q.boundary_layers.size());
    for (const auto& l : q.boundary_layers) {
        w.u64(static_cast<std::uint64_t>(l.layers_min));
        w.u64(static_cast<std::uint64_t>(l.layers_max));
        for (double v : {l.first_height_min, l.first_height_max, l.aspect_ratio_max, l.scaled_jacobian_min, l.skew_max})
            w.f64(v);
        w.u64(l.columns);
        w.u64(l.cut_back);
        w.u64(l.cut_back_at.size());
        for (const core::Vec2& p : l.cut_back_at) {
            w.f64(p.x);
            w.f64(p.y);
        }
    }

    const core::StageTimings& t = r.timings;
    for (double v : {t.boundary_ms, t.interior_ms, t.triangulation_ms, t.smoothing_ms, t.total_ms}) w.f64(v);

    const core::MeshStats& s = r.stats;
    w.f64(s.forecast_points);
    for (std::uint64_t v : {s.interior.candidates, s.interior.accepted, s.interior.rejected_near, s.interior.rejected_crossing,
                            s.interior.rejected_outside, s.triangulation.flips, s.triangulation.walk_steps,
                            s.triangulation.duplicates, s.smoothing_moves, s.smoothing_flips, s.refinement_points,
                            s.orient_exact, s.incircle_exact})
        w.u64(v);
    return out;
}

core::MeshResult decode_result(std::string_view bytes) {
    if (bytes.substr(0, kMagic.size()) != kMagic) throw StoredResultError("stored result: not a meshd result of this version");
    Reader rd(bytes.substr(kMagic.size()));
    core::MeshResult r;
    core::Mesh& m = r.mesh;
    const size_t np = rd.count(29);
    m.x.resize(np);
    m.y.resize(np);
    m.kind.resize(np);
    m.curve.resize(np);
    m.param.resize(np);
    for (size_t i = 0; i < np; ++i) {
        m.x[i] = rd.f64();
        m.y[i] = rd.f64();
        const std::uint8_t kind = rd.u8();
        if (kind > static_cast<std::uint8_t>(core::PointKind::Layer)) throw StoredResultError("stored result: a point of no known kind");
        m.kind[i] = static_cast<core::PointKind>(kind);
        m.curve[i] = rd.u32();
        m.param[i] = rd.f64();
    }
    m.target_size.resize(rd.count(8));
    for (double& v : m.target_size) v = rd.f64();
    m.triangles.resize(rd.count(27));
    for (core::Triangle& t : m.triangles) {
        for (auto& v : t.v) {
            v = rd.u32();
            if (v >= np) throw StoredResultError("stored result: a triangle names a point it does not hold");
        }
        for (auto& n : t.n) n = rd.u32();
        t.constrained = rd.u8();
        t.boundary = rd.u8();
        t.layer = rd.u8();
    }
    m.quads.resize(rd.count(16));
    for (auto& q : m.quads)
        for (auto& v : q) {
            v = rd.u32();
            if (v >= np) throw StoredResultError("stored result: a quad names a point it does not hold");
        }
    for (const core::Triangle& t : m.triangles)
        for (auto n : t.n)
            if (n != core::kNoTriangle && n >= m.triangles.size())
                throw StoredResultError("stored result: a triangle names a neighbour it does not hold");
    m.edges.resize(rd.count(17));
    for (core::MeshEdge& e : m.edges) {
        e.a = rd.u32();
        e.b = rd.u32();
        e.tag = rd.u32();
        e.curve = rd.u32();
        e.embedded = rd.u8() != 0;
        if (e.a >= np || e.b >= np) throw StoredResultError("stored result: an edge names a point it does not hold");
    }
    m.tags.resize(rd.count(8));
    for (std::string& t : m.tags) t = rd.str();
    for (const core::MeshEdge& e : m.edges)
        if (e.tag >= m.tags.size()) throw StoredResultError("stored result: an edge names a tag it does not hold");
    m.holes = static_cast<size_t>(rd.u64());
    m.curve_ends.resize(rd.count(8));
    for (auto& ends : m.curve_ends) {
        for (auto& v : ends) {
            v = rd.u32();
            if (v != core::kNoVertex && v >= np) throw StoredResultError("stored result: a curve ends at a point it does not hold");
        }
    }
    m.loops.resize(rd.count(8));
    for (auto& loop : m.loops) {
        loop.resize(rd.count(5));
        for (core::Mesh::LoopCurve& u : loop) {
            u.curve = rd.u32();
            u.reversed = rd.u8() != 0;
            if (u.curve >= m.curve_ends.size()) throw StoredResultError("stored result: a loop runs along a curve it does not hold");
        }
    }
    m.edge_nodes.resize(rd.count(16));
    for (core::Vec2& p : m.edge_nodes) {
        p.x = rd.f64();
        p.y = rd.f64();
    }
    if (!m.edge_nodes.empty()) {
        auto node = [&] {
            const std::uint32_t k = rd.u32();
            if (k >= m.edge_nodes.size()) throw StoredResultError("stored result: an edge node it does not hold");
            return k;
        };
        m.edge_node.resize(m.triangles.size());
        for (auto& e : m.edge_node)
            for (std::uint32_t& k : e) k = node();
        m.edge_node_of_edge.resize(m.edges.size());
        for (std::uint32_t& k : m.edge_node_of_edge) k = node();
    }

    core::QualityMetrics& q = r.quality;
    for (size_t* v : {&q.points, &q.boundary_points, &q.interior_points, &q.triangles}) *v = static_cast<size_t>(rd.u64());
    for (double* v : {&q.angle_min, &q.angle_max, &q.angle_mean, &q.quality_min, &q.quality_mean}) *v = rd.f64();
    for (std::uint64_t& v : q.quality_histogram) v = rd.u64();
    q.size_ratio_mean = rd.f64();
    q.size_ratio_within_sqrt2 = rd.f64();
    q.curved_edges = rd.u64();
    q.straightened_edges = rd.u64();
    q.scaled_jacobian_min = rd.f64();
    q.quads = static_cast<size_t>(rd.u64());
    q.boundary_layers.resize(rd.count(72));
    for (auto& l : q.boundary_layers) {
        l.layers_min = static_cast<int>(std::min<std::uint64_t>(rd.u64(), core::kMaxLayers));
        l.layers_max = static_cast<int>(std::min<std::uint64_t>(rd.u64(), core::kMaxLayers));
        for (double* v : {&l.first_height_min, &l.first_height_max, &l.aspect_ratio_max, &l.scaled_jacobian_min, &l.skew_max})
            *v = rd.f64();
        l.columns = rd.u64();
        l.cut_back = rd.u64();
        l.cut_back_at.resize(rd.count(16));
        for (core::Vec2& p : l.cut_back_at) {
            p.x = rd.f64();
            p.y = rd.f64();
        }
    }

    core::StageTimings& t = r.timings;
    for (double* v : {&t.boundary_ms, &t.interior_ms, &t.triangulation_ms, &t.smoothing_ms, &t.total_ms}) *v = rd.f64();

    core::MeshStats& s = r.stats;
    s.forecast_points = rd.f64();
    for (std::uint64_t* v : {&s.interior.candidates, &s.interior.accepted, &s.interior.rejected_near,
                             &s.interior.rejected_crossing, &s.interior.rejected_outside, &s.triangulation.flips,
                             &s.triangulation.walk_steps, &s.triangulation.duplicates, &s.smoothing_moves,
                             &s.smoothing_flips, &s.refinement_points, &s.orient_exact, &s.incircle_exact})
        *v = rd.u64();
    if (!rd.done()) throw StoredResultError("stored result: bytes after its end");
    return r;
}

}  // namespace meshd::api
