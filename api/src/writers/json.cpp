// The JSON response of the API (mesh and metrics).

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "writers/common.hpp"

namespace meshd::api {

using namespace writers;

std::string metrics_json(const MeshResult& r) {
    const auto& q = r.quality;
    nlohmann::ordered_json j;
    j["points"] = q.points;
    j["boundary_points"] = q.boundary_points;
    j["interior_points"] = q.interior_points;
    j["triangles"] = q.triangles;
    if (q.quads) j["quads"] = q.quads;
    j["angle_deg"] = {{"min", q.angle_min}, {"max", q.angle_max}, {"mean", q.angle_mean}};
    j["quality"] = {{"min", q.quality_min}, {"mean", q.quality_mean}, {"histogram", q.quality_histogram}};
    j["size_ratio"] = {{"mean", q.size_ratio_mean}, {"within_sqrt2", q.size_ratio_within_sqrt2}};
    if (r.mesh.order() == 2)
        j["curved"] = {{"edges", q.curved_edges},
                       {"straightened", q.straightened_edges},
                       {"scaled_jacobian_min", q.scaled_jacobian_min}};
    if (!q.boundary_layers.empty()) {
        nlohmann::ordered_json layers = nlohmann::ordered_json::array();
        for (const auto& l : q.boundary_layers) {
            nlohmann::ordered_json at = nlohmann::ordered_json::array();
            for (const core::Vec2& p : l.cut_back_at) at.push_back({p.x, p.y});
            layers.push_back({{"columns", l.columns},
                              {"layers", {{"min", l.layers_min}, {"max", l.layers_max}}},
                              {"first_height", {{"min", l.first_height_min}, {"max", l.first_height_max}}},
                              {"aspect_ratio_max", l.aspect_ratio_max},
                              {"scaled_jacobian_min", l.scaled_jacobian_min},
                              {"skew_max", l.skew_max},
                              {"cut_back", {{"columns", l.cut_back}, {"at", at}}}});
        }
        j["boundary_layers"] = layers;
    }
    j["timings_ms"] = {{"boundary", r.timings.boundary_ms},
                       {"interior", r.timings.interior_ms},
                       {"triangulation", r.timings.triangulation_ms},
                       {"smoothing", r.timings.smoothing_ms},
                       {"total", r.timings.total_ms}};
    j["predicates_exact"] = {{"orient", r.stats.orient_exact}, {"incircle", r.stats.incircle_exact}};
    if (r.stats.gradation_applied > 0.0) j["gradation_applied"] = r.stats.gradation_applied;
    return j.dump();
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
            at = std::to_chars(at, at + 10, T.v[static_cast<size_t>(i)]).ptr;
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
