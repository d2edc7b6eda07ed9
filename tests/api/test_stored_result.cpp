// A finished mesh as bytes for a shared job store: decoded, it is the same result (every
// field, every format's bytes), and bytes that are not one are refused without a crash.

#include <gtest/gtest.h>

#include <algorithm>
#include <nlohmann/json.hpp>
#include <sstream>

#include "meshd/api/request.hpp"
#include "meshd/api/stored_result.hpp"
#include "meshd/api/writers.hpp"
#include "meshd/core/mesher.hpp"
#include "support.hpp"

using namespace meshd;

namespace {

const core::MeshResult& naca() {
    static const core::MeshResult r = [] {
        const api::MeshRequest req = api::parse_request(test::read_file(MESHD_SOURCE_DIR "/examples/naca0012.json"));
        return core::generate_mesh(req.geometry, req.density, req.options);
    }();
    return r;
}

std::string written(api::Format f, const core::MeshResult& r) {
    std::ostringstream os;
    api::write_mesh(f, r, os);
    return os.str();
}

}  // namespace

TEST(StoredResult, DecodedIsTheSameResultInEveryField) {
    const core::MeshResult& a = naca();
    const std::string bytes = api::encode_result(a);
    const core::MeshResult b = api::decode_result(bytes);
    EXPECT_EQ(a.mesh.x, b.mesh.x);
    EXPECT_EQ(a.mesh.y, b.mesh.y);
    EXPECT_EQ(a.mesh.kind, b.mesh.kind);
    EXPECT_EQ(a.mesh.curve, b.mesh.curve);
    EXPECT_EQ(a.mesh.param, b.mesh.param);
    EXPECT_EQ(a.mesh.target_size, b.mesh.target_size);
    ASSERT_EQ(a.mesh.triangles.size(), b.mesh.triangles.size());
    for (size_t i = 0; i < a.mesh.triangles.size(); ++i) {
        EXPECT_EQ(a.mesh.triangles[i].v, b.mesh.triangles[i].v);
        EXPECT_EQ(a.mesh.triangles[i].n, b.mesh.triangles[i].n);
        EXPECT_EQ(a.mesh.triangles[i].constrained, b.mesh.triangles[i].constrained);
        EXPECT_EQ(a.mesh.triangles[i].boundary, b.mesh.triangles[i].boundary);
    }
    ASSERT_EQ(a.mesh.edges.size(), b.mesh.edges.size());
    for (size_t i = 0; i < a.mesh.edges.size(); ++i) {
        EXPECT_EQ(a.mesh.edges[i].a, b.mesh.edges[i].a);
        EXPECT_EQ(a.mesh.edges[i].b, b.mesh.edges[i].b);
        EXPECT_EQ(a.mesh.edges[i].tag, b.mesh.edges[i].tag);
        EXPECT_EQ(a.mesh.edges[i].curve, b.mesh.edges[i].curve);
        EXPECT_EQ(a.mesh.edges[i].embedded, b.mesh.edges[i].embedded);
    }
    EXPECT_EQ(a.mesh.tags, b.mesh.tags);
    EXPECT_EQ(a.mesh.holes, b.mesh.holes);
    EXPECT_EQ(a.mesh.curve_ends, b.mesh.curve_ends);
    ASSERT_EQ(a.mesh.loops.size(), b.mesh.loops.size());
    for (size_t l = 0; l < a.mesh.loops.size(); ++l) {
        ASSERT_EQ(a.mesh.loops[l].size(), b.mesh.loops[l].size());
        for (size_t i = 0; i < a.mesh.loops[l].size(); ++i) {
            EXPECT_EQ(a.mesh.loops[l][i].curve, b.mesh.loops[l][i].curve);
            EXPECT_EQ(a.mesh.loops[l][i].reversed, b.mesh.loops[l][i].reversed);
        }
    }
    EXPECT_EQ(a.quality.quality_histogram, b.quality.quality_histogram);
    EXPECT_EQ(a.quality.angle_min, b.quality.angle_min);
    EXPECT_EQ(a.timings.total_ms, b.timings.total_ms);
    EXPECT_EQ(a.stats.forecast_points, b.stats.forecast_points);
    EXPECT_EQ(a.stats.incircle_exact, b.stats.incircle_exact);
    EXPECT_EQ(a.quality.scaled_jacobian_min, b.quality.scaled_jacobian_min);
    // Every field above, and the metrics object, through the writers: the same bytes.
    EXPECT_EQ(api::metrics_json(a), api::metrics_json(b));
    for (const char* name : {"json", "vtk", "su2", "msh", "svg", "foam"}) {
        const api::Format f = *api::parse_format(name);
        EXPECT_EQ(written(f, a), written(f, b)) << name;
    }
    // About 90 bytes per point (docs in stored_result.hpp): far below the JSON answer.
    EXPECT_LT(bytes.size(), 100 * a.mesh.point_count() + 1024);
}

TEST(StoredResult, BytesThatAreNotOneAreRefused) {
    const std::string bytes = api::encode_result(naca());
    EXPECT_THROW(api::decode_result(""), api::StoredResultError);
    // Results of earlier versions (no edge nodes; no curved-edge figures) and of a later one
    // are refused: a store reads them as expired.
    for (const char* other : {"MESHDR01", "MESHDR02", "MESHDR04"})
        EXPECT_THROW(api::decode_result(other + bytes.substr(8)), api::StoredResultError) << other;
    EXPECT_THROW(api::decode_result(bytes + "x"), api::StoredResultError);
    // Cut anywhere: refused, never read past the end (the sanitizer build checks).
    for (size_t cut = 0; cut < bytes.size(); cut += 1 + bytes.size() / 97)
        EXPECT_THROW(api::decode_result(std::string_view(bytes).substr(0, cut)), api::StoredResultError) << cut;
    // A count far beyond the bytes (would allocate terabytes): refused before allocating.
    std::string huge = bytes;
    for (size_t i = 8; i < 16; ++i) huge[i] = '\x7f';
    EXPECT_THROW(api::decode_result(huge), api::StoredResultError);
    // A triangle naming a point past the end: refused (a writer would read out of range).
    const size_t points = naca().mesh.point_count();
    const size_t first_triangle = 8 + 8 + points * 29 + 8 + naca().mesh.target_size.size() * 8 + 8;
    std::string bad = bytes;
    for (size_t i = 0; i < 4; ++i) bad[first_triangle + i] = '\xff';
    EXPECT_THROW(api::decode_result(bad), api::StoredResultError);
}

// A second-order mesh keeps its edge nodes: the same files after the round trip.
TEST(StoredResult, ASecondOrderMeshKeepsItsEdgeNodes) {
    api::MeshRequest req = api::parse_request(test::read_file(MESHD_SOURCE_DIR "/examples/naca0012.json"));
    req.options.order = 2;
    const core::MeshResult a = core::generate_mesh(req.geometry, req.density, req.options);
    ASSERT_EQ(a.mesh.order(), 2);
    const core::MeshResult b = api::decode_result(api::encode_result(a));
    ASSERT_EQ(b.mesh.order(), 2);
    ASSERT_EQ(a.mesh.edge_nodes.size(), b.mesh.edge_nodes.size());
    for (size_t k = 0; k < a.mesh.edge_nodes.size(); ++k) {
        EXPECT_EQ(a.mesh.edge_nodes[k].x, b.mesh.edge_nodes[k].x);
        EXPECT_EQ(a.mesh.edge_nodes[k].y, b.mesh.edge_nodes[k].y);
    }
    EXPECT_EQ(a.mesh.edge_node, b.mesh.edge_node);
    EXPECT_EQ(a.mesh.edge_node_of_edge, b.mesh.edge_node_of_edge);
    for (const char* name : {"json", "vtk", "msh", "svg"}) {
        const api::Format f = *api::parse_format(name);
        EXPECT_EQ(written(f, a), written(f, b)) << name;
    }
    // The JSON metrics report the curved edges: the airfoil and the far field are curves, so
    // every boundary edge has its node on one, and no triangle folds.
    const auto metrics = nlohmann::json::parse(written(api::Format::Json, b))["metrics"];
    ASSERT_TRUE(metrics.contains("curved"));
    EXPECT_EQ(metrics["curved"]["edges"].get<size_t>() + metrics["curved"]["straightened"].get<size_t>(),
              a.mesh.edges.size());
    EXPECT_GE(metrics["curved"]["scaled_jacobian_min"].get<double>(), 0.1);
    EXPECT_FALSE(nlohmann::json::parse(written(api::Format::Json, naca()))["metrics"].contains("curved"));
}

// su2 and foam cannot hold 6-node triangles: writing one is refused with the reason.
TEST(SecondOrderFormats, Su2AndFoamRefuseWithTheReason) {
    api::MeshRequest req = api::parse_request(test::read_file(MESHD_SOURCE_DIR "/examples/naca0012.json"));
    req.options.order = 2;
    const core::MeshResult a = core::generate_mesh(req.geometry, req.density, req.options);
    for (const char* name : {"su2", "foam"}) {
        const api::Format f = *api::parse_format(name);
        ASSERT_TRUE(api::second_order_refusal(f)) << name;
        EXPECT_THROW(written(f, a), std::invalid_argument) << name;
    }
    for (const char* name : {"json", "vtk", "msh", "cgns", "svg"}) EXPECT_FALSE(api::second_order_refusal(*api::parse_format(name))) << name;
}

// The SVG of a second-order mesh draws every edge as a quadratic Bezier through its edge node:
// three per triangle, one per tagged edge.
TEST(SecondOrderFormats, SvgDrawsCurvedEdges) {
    api::MeshRequest req = api::parse_request(test::read_file(MESHD_SOURCE_DIR "/examples/naca0012.json"));
    req.options.order = 2;
    const core::MeshResult a = core::generate_mesh(req.geometry, req.density, req.options);
    const std::string svg = written(api::Format::Svg, a);
    EXPECT_EQ(static_cast<size_t>(std::count(svg.begin(), svg.end(), 'Q')), 3 * a.mesh.triangles.size() + a.mesh.edges.size());
}

// A mesh with boundary layers keeps its quads, its layer triangles and its layer figures: the
// same files (every format) and metrics after the round trip.
TEST(StoredResult, AMeshWithBoundaryLayersKeepsItsQuads) {
    api::MeshRequest req = api::parse_request(test::read_file(MESHD_SOURCE_DIR "/examples/naca0012.json"));
    core::BoundaryLayerSpec s;
    s.curves = {"wing"};
    s.first_height = 1e-4;
    s.layers = 12;
    req.options.boundary_layers = {s};
    const core::MeshResult a = core::generate_mesh(req.geometry, req.density, req.options);
    ASSERT_FALSE(a.mesh.quads.empty());
    const core::MeshResult b = api::decode_result(api::encode_result(a));
    EXPECT_EQ(a.mesh.quads, b.mesh.quads);
    ASSERT_EQ(a.mesh.triangles.size(), b.mesh.triangles.size());
    for (size_t t = 0; t < a.mesh.triangles.size(); ++t) EXPECT_EQ(a.mesh.triangles[t].layer, b.mesh.triangles[t].layer);
    EXPECT_EQ(a.mesh.kind, b.mesh.kind);
    EXPECT_EQ(api::metrics_json(a), api::metrics_json(b));
    for (const char* name : {"json", "vtk", "su2", "msh", "svg", "foam"}) {
        const api::Format f = *api::parse_format(name);
        EXPECT_EQ(written(f, a), written(f, b)) << name;
    }
    const auto metrics = nlohmann::json::parse(api::metrics_json(b));
    ASSERT_TRUE(metrics.contains("boundary_layers"));
    EXPECT_EQ(metrics["quads"].get<size_t>(), a.mesh.quads.size());
    EXPECT_EQ(metrics["boundary_layers"][0]["layers"]["max"].get<int>(), 12);
}
