// The JSON response of the API (mesh and metrics).

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "writers/common.hpp"

namespace meshd::api {

using namespace writers;

namespace {

// The metrics object's text, member by member: nlohmann's object built it from a map of
// allocated nodes (0.85% of the load run's server time in session 51's profile; by hand,
// about 50,000 instructions fewer an answer).
class ObjectText {
public:
    explicit ObjectText(std::string& s) : s_(s) { s_ += '{'; }
    ~ObjectText() { s_ += '}'; }
    ObjectText(const ObjectText&) = delete;
    ObjectText& operator=(const ObjectText&) = delete;

    std::string& key(std::string_view k) {
        if (!first_) s_ += ',';
        first_ = false;
        s_ += '"';
        s_ += k;
        s_ += "\":";
        return s_;
    }
    template <class I>
    void count(std::string_view k, I v) {
        put_count(key(k), v);
    }
    void real(std::string_view k, double v) { put_real(key(k), v); }

    template <class I>
        requires std::is_integral_v<I>
    static void put_count(std::string& s, I v) {
        char buf[24];
        s.append(buf, static_cast<size_t>(std::to_chars(buf, buf + sizeof buf, v).ptr - buf));
    }
    // A real stays one for typed readers ("60.0", not "60"); not finite: null, as JSON has
    // no such number.
    static void put_real(std::string& s, double v) {
        if (!std::isfinite(v)) {
            s += "null";
            return;
        }
        char buf[kShortestMax];
        char* const end = shortest(buf, v);
        s.append(buf, static_cast<size_t>(end - buf));
        if (std::find_if(buf, end, [](char c) { return c == '.' || c == 'e'; }) == end) s += ".0";
    }

private:
    std::string& s_;
    bool first_ = true;
};

}  // namespace

std::string metrics_json(const MeshResult& r) {
    const auto& q = r.quality;
    std::string s;
    s.reserve(512);
    {
        ObjectText j(s);
        j.count("points", q.points);
        j.count("boundary_points", q.boundary_points);
        j.count("interior_points", q.interior_points);
        j.count("triangles", q.triangles);
        if (q.quads) j.count("quads", q.quads);
        {
            ObjectText a(j.key("angle_deg"));
            a.real("min", q.angle_min);
            a.real("max", q.angle_max);
            a.real("mean", q.angle_mean);
        }
        {
            ObjectText a(j.key("quality"));
            a.real("min", q.quality_min);
            a.real("mean", q.quality_mean);
            std::string& h = a.key("histogram");
            h += '[';
            for (size_t i = 0; i < q.quality_histogram.size(); ++i) {
                if (i) h += ',';
                ObjectText::put_count(h, q.quality_histogram[i]);
            }
            h += ']';
        }
        {
            ObjectText a(j.key("size_ratio"));
            a.real("mean", q.size_ratio_mean);
            a.real("within_sqrt2", q.size_ratio_within_sqrt2);
        }
        if (r.mesh.order() == 2) {
            ObjectText a(j.key("curved"));
            a.count("edges", q.curved_edges);
            a.count("straightened", q.straightened_edges);
            a.real("scaled_jacobian_min", q.scaled_jacobian_min);
        }
        if (!q.boundary_layers.empty()) {
            std::string& list = j.key("boundary_layers");
            list += '[';
            for (size_t i = 0; i < q.boundary_layers.size(); ++i) {
                const auto& l = q.boundary_layers[i];
                if (i) list += ',';
                ObjectText o(list);
                o.count("columns", l.columns);
                {
                    ObjectText a(o.key("layers"));
                    a.count("min", l.layers_min);
                    a.count("max", l.layers_max);
                }
                {
                    ObjectText a(o.key("first_height"));
                    a.real("min", l.first_height_min);
                    a.real("max", l.first_height_max);
                }
                o.real("aspect_ratio_max", l.aspect_ratio_max);
                o.real("scaled_jacobian_min", l.scaled_jacobian_min);
                o.real("skew_max", l.skew_max);
                ObjectText c(o.key("cut_back"));
                c.count("columns", l.cut_back);
                std::string& at = c.key("at");
                at += '[';
                for (size_t k = 0; k < l.cut_back_at.size(); ++k) {
                    at += k ? ",[" : "[";
                    ObjectText::put_real(at, l.cut_back_at[k].x);
                    at += ',';
                    ObjectText::put_real(at, l.cut_back_at[k].y);
                    at += ']';
                }
                at += ']';
            }
            list += ']';
        }
        {
            ObjectText a(j.key("timings_ms"));
            a.real("boundary", r.timings.boundary_ms);
            a.real("interior", r.timings.interior_ms);
            a.real("triangulation", r.timings.triangulation_ms);
            a.real("smoothing", r.timings.smoothing_ms);
            a.real("total", r.timings.total_ms);
        }
        {
            ObjectText a(j.key("predicates_exact"));
            a.count("orient", r.stats.orient_exact);
            a.count("incircle", r.stats.incircle_exact);
        }
        if (r.stats.gradation_applied > 0.0) j.real("gradation_applied", r.stats.gradation_applied);
    }
    return s;
}

void write_json(const MeshResult& r, std::ostream& stream, bool sizes) {
    const Mesh& m = r.mesh;
    TextOut os(stream);
    const bool quadratic = m.order() == 2;
    // Second order: the edge nodes follow the vertices; triangles list six nodes and edges
    // three (their ends, then their middle node).
    os << "{\"mesh\":{" << (quadratic ? "\"order\":2," : "") << "\"points\":[";
    for (size_t v = 0; v < all_points(m); ++v) {
        const core::Vec2 p = any_point(m, v);
        // shortest() takes kShortestMax at each number, whatever it writes.
        char* at = os.claim(2 * kShortestMax + 4);
        if (v) *at++ = ',';
        *at++ = '[';
        at = shortest(at, p.x);
        *at++ = ',';
        at = shortest(at, p.y);
        *at++ = ']';
        os.done(at);
    }
    os << ']';
    if (sizes) {
        os << ",\"sizes\":[";
        const std::vector<double> size = point_sizes(m);
        for (size_t v = 0; v < size.size(); ++v) {
            if (v) os << ',';
            os << Num(size[v]);
        }
        os << ']';
    }
    os << ",\"triangles\":[";
    for (size_t t = 0; t < m.triangles.size(); ++t) {
        const auto& T = m.triangles[t];
        char* at = os.claim(40);  // ",[" and three indices of at most 10 digits, two commas
        if (t) *at++ = ',';
        *at++ = '[';
        for (int i = 0; i < 3; ++i) {
            if (i) *at++ = ',';
            at = put_unsigned(at, T.v[static_cast<size_t>(i)]);
        }
        os.done(at);
        if (quadratic) {
            const auto six = six_nodes(m, t);
            os << ',' << six[3] << ',' << six[4] << ',' << six[5];
        }
        os << ']';
    }
    os << ']';
    if (!m.quads.empty()) {
        os << ",\"quads\":[";
        for (size_t q = 0; q < m.quads.size(); ++q) {
            const auto& Q = m.quads[q];
            if (q) os << ',';
            os << '[' << Q[0] << ',' << Q[1] << ',' << Q[2] << ',' << Q[3] << ']';
        }
        os << ']';
    }
    os << ",\"boundaries\":{";
    const auto groups = edges_by_tag(m);
    for (size_t g = 0; g < groups.size(); ++g) {
        os << (g ? "," : "") << nlohmann::json(m.tags[g]).dump() << ":[";
        for (size_t i = 0; i < groups[g].size(); ++i) {
            if (i) os << ',';
            os << '[' << groups[g][i]->a << ',' << groups[g][i]->b;
            if (quadratic) os << ',' << edge_middle(m, *groups[g][i]);
            os << ']';
        }
        os << ']';
    }
    os << "}},\"metrics\":" << metrics_json(r) << "}\n";
}

}  // namespace meshd::api
