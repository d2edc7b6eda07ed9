// Writers: each format parsed back here by a reader written against the format's
// specification (the real readers of each ecosystem run in tests/formats/readback.py).

#include <gtest/gtest.h>

#include <bit>
#include <cstring>
#include <nlohmann/json.hpp>
#include <sstream>

#include "meshd/api/request.hpp"
#include "meshd/api/writers.hpp"

using namespace meshd;

namespace {

const core::MeshResult& sample() {
    static const core::MeshResult r = [] {
        const std::string body = R"({"geometry": {"points": {"A": [0,0], "M": [0.5,0], "B": [1,0], "C": [1,1], "D": [0,1], "W": [0.5,0.5]},
            "curves": {"b1": {"type": "line", "from": "A", "to": "M", "tag": "wall"},
                       "b2": {"type": "line", "from": "M", "to": "B", "tag": "wall"},
                       "right": {"type": "line", "from": "B", "to": "C", "tag": "outlet"},
                       "top": {"type": "line", "from": "C", "to": "D", "tag": "wall"},
                       "left": {"type": "line", "from": "D", "to": "A", "tag": "inlet"},
                       "wake": {"type": "line", "from": "M", "to": "W", "tag": "wake line"}},
            "loops": [["b1", "b2", "right", "top", "left"]], "embedded": ["wake"]},
            "density": {"size": "0.05 + 0.05*x"}})";
        const api::MeshRequest req = api::parse_request(body);
        return core::generate_mesh(req.geometry, req.density, req.options);
    }();
    return r;
}

std::string written(api::Format f) {
    std::ostringstream os;
    api::write_mesh(f, sample(), os);
    return os.str();
}

double get_be_double(const char* p) {
    std::uint64_t u;
    std::memcpy(&u, p, 8);
    if constexpr (std::endian::native == std::endian::little) u = __builtin_bswap64(u);
    double d;
    std::memcpy(&d, &u, 8);
    return d;
}

std::int32_t get_be_int(const char* p) {
    std::uint32_t u;
    std::memcpy(&u, p, 4);
    if constexpr (std::endian::native == std::endian::little) u = __builtin_bswap32(u);
    std::int32_t i;
    std::memcpy(&i, &u, 4);
    return i;
}

}  // namespace

TEST(Writers, JsonIsTheContractShape) {
    const auto& m = sample().mesh;
    const auto j = nlohmann::json::parse(written(api::Format::Json));
    ASSERT_EQ(j["mesh"]["points"].size(), m.point_count());
    ASSERT_EQ(j["mesh"]["triangles"].size(), m.triangles.size());
    // Doubles round-trip exactly.
    for (size_t v = 0; v < m.point_count(); ++v) {
        EXPECT_EQ(j["mesh"]["points"][v][0].get<double>(), m.x[v]);
        EXPECT_EQ(j["mesh"]["points"][v][1].get<double>(), m.y[v]);
    }
    for (const auto& t : j["mesh"]["triangles"])
        for (const auto& i : t) EXPECT_LT(i.get<size_t>(), m.point_count());
    const auto& b = j["mesh"]["boundaries"];
    EXPECT_TRUE(b.contains("wall"));
    EXPECT_TRUE(b.contains("outlet"));
    EXPECT_TRUE(b.contains("inlet"));
    EXPECT_TRUE(b.contains("wake line"));  // embedded curves appear under their tags
    size_t edges = 0;
    for (const auto& [tag, list] : b.items()) edges += list.size();
    EXPECT_EQ(edges, m.edges.size());
    const auto& mt = j["metrics"];
    EXPECT_EQ(mt["triangles"], m.triangles.size());
    EXPECT_EQ(mt["points"].get<size_t>(), mt["boundary_points"].get<size_t>() + mt["interior_points"].get<size_t>());
    EXPECT_EQ(mt["quality"]["histogram"].size(), 10u);
    for (const char* k : {"boundary", "interior", "triangulation", "smoothing", "total"})
        EXPECT_TRUE(mt["timings_ms"].contains(k)) << k;
}

// The metrics object member by member, against the figures it was written from: counts as
// JSON integers, figures as JSON reals even where whole (a typed client reads "60.0" as a
// double), a figure that is not a number as null, every optional member where it applies.
TEST(Writers, MetricsJsonHoldsEveryFigureWithItsType) {
    core::MeshResult r;
    auto& q = r.quality;
    q.points = 12;
    q.boundary_points = 5;
    q.interior_points = 7;
    q.triangles = 9;
    q.quads = 3;
    q.angle_min = 31.25;
    q.angle_max = 100.0;  // whole: still a real
    q.angle_mean = 60.0;
    q.quality_min = 0.1 + 0.2;  // 0.30000000000000004: the shortest text that reads back
    q.quality_mean = 1e-7;
    for (size_t i = 0; i < q.quality_histogram.size(); ++i) q.quality_histogram[i] = 10 * i + 1;
    q.size_ratio_mean = std::nan("");
    q.size_ratio_within_sqrt2 = 1.0;
    q.curved_edges = 4;
    q.straightened_edges = 2;
    q.scaled_jacobian_min = 0.75;
    core::QualityMetrics::Layers l;
    l.layers_min = 2;
    l.layers_max = 20;
    l.first_height_min = 1e-5;
    l.first_height_max = 2.5e-5;
    l.aspect_ratio_max = 1234.5;
    l.scaled_jacobian_min = 0.5;
    l.skew_max = 0.125;
    l.columns = 40;
    l.cut_back = 6;
    l.cut_back_at = {{1.5, -2.0}, {3e20, 4.0}};
    q.boundary_layers = {l, core::QualityMetrics::Layers{}};
    r.mesh.edge_nodes.push_back({0, 1});  // second order: "curved" is written
    r.timings = {0.5, 1.0, 2.0, 3.0, 7.25};
    r.stats.orient_exact = 384;
    r.stats.incircle_exact = 0;
    r.stats.gradation_applied = 0.2;

    const auto j = nlohmann::json::parse(api::metrics_json(r));
    auto integer = [](const nlohmann::json& v, std::int64_t want) {
        EXPECT_TRUE(v.is_number_integer()) << v;
        EXPECT_EQ(v.get<std::int64_t>(), want);
    };
    auto real = [](const nlohmann::json& v, double want) {
        EXPECT_TRUE(v.is_number_float()) << v;
        EXPECT_EQ(v.get<double>(), want);
    };
    integer(j["points"], 12);
    integer(j["boundary_points"], 5);
    integer(j["interior_points"], 7);
    integer(j["triangles"], 9);
    integer(j["quads"], 3);
    real(j["angle_deg"]["min"], 31.25);
    real(j["angle_deg"]["max"], 100.0);
    real(j["angle_deg"]["mean"], 60.0);
    real(j["quality"]["min"], 0.1 + 0.2);
    real(j["quality"]["mean"], 1e-7);
    ASSERT_EQ(j["quality"]["histogram"].size(), 10u);
    for (size_t i = 0; i < 10; ++i) integer(j["quality"]["histogram"][i], static_cast<std::int64_t>(10 * i + 1));
    EXPECT_TRUE(j["size_ratio"]["mean"].is_null());
    real(j["size_ratio"]["within_sqrt2"], 1.0);
    integer(j["curved"]["edges"], 4);
    integer(j["curved"]["straightened"], 2);
    real(j["curved"]["scaled_jacobian_min"], 0.75);
    ASSERT_EQ(j["boundary_layers"].size(), 2u);
    const auto& b = j["boundary_layers"][0];
    integer(b["columns"], 40);
    integer(b["layers"]["min"], 2);
    integer(b["layers"]["max"], 20);
    real(b["first_height"]["min"], 1e-5);
    real(b["first_height"]["max"], 2.5e-5);
    real(b["aspect_ratio_max"], 1234.5);
    real(b["scaled_jacobian_min"], 0.5);
    real(b["skew_max"], 0.125);
    integer(b["cut_back"]["columns"], 6);
    ASSERT_EQ(b["cut_back"]["at"].size(), 2u);
    real(b["cut_back"]["at"][0][0], 1.5);
    real(b["cut_back"]["at"][0][1], -2.0);
    real(b["cut_back"]["at"][1][0], 3e20);
    real(b["cut_back"]["at"][1][1], 4.0);
    EXPECT_TRUE(j["boundary_layers"][1]["cut_back"]["at"].is_array());
    EXPECT_TRUE(j["boundary_layers"][1]["cut_back"]["at"].empty());
    real(j["timings_ms"]["boundary"], 0.5);
    real(j["timings_ms"]["interior"], 1.0);
    real(j["timings_ms"]["triangulation"], 2.0);
    real(j["timings_ms"]["smoothing"], 3.0);
    real(j["timings_ms"]["total"], 7.25);
    integer(j["predicates_exact"]["orient"], 384);
    integer(j["predicates_exact"]["incircle"], 0);
    real(j["gradation_applied"], 0.2);
    // The members in the contract's order.
    std::vector<std::string> keys;
    const auto ordered = nlohmann::ordered_json::parse(api::metrics_json(r));
    for (const auto& [k, v] : ordered.items()) keys.push_back(k);
    EXPECT_EQ(keys, (std::vector<std::string>{"points", "boundary_points", "interior_points", "triangles", "quads",
                                              "angle_deg", "quality", "size_ratio", "curved", "boundary_layers",
                                              "timings_ms", "predicates_exact", "gradation_applied"}));

    // Without the optional parts: no quads, no curved edges, no layers, no gradation.
    core::MeshResult plain;
    plain.quality.points = 3;
    const auto p = nlohmann::json::parse(api::metrics_json(plain));
    for (const char* k : {"quads", "curved", "boundary_layers", "gradation_applied"}) EXPECT_FALSE(p.contains(k)) << k;
    integer(p["points"], 3);
    real(p["angle_deg"]["min"], 0.0);
}

TEST(Writers, VtkIsBinaryBigEndianUnstructuredGrid) {
    const auto& m = sample().mesh;
    const std::string s = written(api::Format::Vtk);
    ASSERT_EQ(s.rfind("# vtk DataFile Version 3.0\n", 0), 0u);
    EXPECT_NE(s.find("\nBINARY\nDATASET UNSTRUCTURED_GRID\n"), std::string::npos);
    const std::string head = "POINTS " + std::to_string(m.point_count()) + " double\n";
    const size_t p = s.find(head);
    ASSERT_NE(p, std::string::npos);
    const char* data = s.data() + p + head.size();
    for (size_t v = 0; v < m.point_count(); ++v) {
        EXPECT_EQ(get_be_double(data + 24 * v), m.x[v]);
        EXPECT_EQ(get_be_double(data + 24 * v + 8), m.y[v]);
    }
    const std::string cells = "CELLS " + std::to_string(m.triangles.size() + m.edges.size()) + " ";
    const size_t c = s.find(cells);
    ASSERT_NE(c, std::string::npos);
    const char* cd = s.data() + s.find('\n', c) + 1;
    EXPECT_EQ(get_be_int(cd), 3);
    EXPECT_EQ(get_be_int(cd + 4), static_cast<std::int32_t>(m.triangles[0].v[0]));
    EXPECT_NE(s.find("SCALARS tag int 1"), std::string::npos);
    EXPECT_NE(s.find("SCALARS quality double 1"), std::string::npos);
    EXPECT_NE(s.find("POINT_DATA " + std::to_string(m.point_count()) + "\nSCALARS target_size double 1"), std::string::npos);
}

TEST(Writers, Su2HasOneMarkerPerTagAndOnlyUsedPoints) {
    const auto& m = sample().mesh;
    std::istringstream in(written(api::Format::Su2));
    std::string line;
    size_t nelem = 0, npoin = 0, nmark = 0;
    std::vector<std::string> markers;
    std::vector<bool> used(m.point_count(), false);
    while (std::getline(in, line)) {
        if (line.rfind("NELEM=", 0) == 0) {
            nelem = std::stoul(line.substr(6));
            for (size_t i = 0; i < nelem; ++i) {
                std::getline(in, line);
                std::istringstream ls(line);
                int type;
                size_t a, b, c;
                ls >> type >> a >> b >> c;
                EXPECT_EQ(type, 5);
                used[a] = used[b] = used[c] = true;
            }
        } else if (line.rfind("NPOIN=", 0) == 0) {
            npoin = std::stoul(line.substr(6));
        } else if (line.rfind("NMARK=", 0) == 0) {
            nmark = std::stoul(line.substr(6));
        } else if (line.rfind("MARKER_TAG=", 0) == 0) {
            markers.push_back(line.substr(12));
        }
    }
    EXPECT_EQ(nelem, m.triangles.size());
    EXPECT_EQ(npoin, m.point_count());
    EXPECT_EQ(std::count(used.begin(), used.end(), true), static_cast<long>(m.point_count()));
    EXPECT_EQ(nmark, 4u);
    EXPECT_EQ(markers, (std::vector<std::string>{"wall", "outlet", "inlet", "wake_line"}));
}

TEST(Writers, MshHasPhysicalGroupsAndAllSections) {
    const std::string s = written(api::Format::Msh);
    for (const char* sec : {"$MeshFormat\n4.1 0 8\n", "$PhysicalNames", "$Entities", "$Nodes", "$Elements"})
        EXPECT_NE(s.find(sec), std::string::npos) << sec;
    EXPECT_NE(s.find("1 1 \"wall\""), std::string::npos);
    EXPECT_NE(s.find("\"domain\""), std::string::npos);
}

TEST(Writers, SvgDrawsEveryTriangle) {
    const auto& m = sample().mesh;
    const std::string s = written(api::Format::Svg);
    size_t paths = 0;
    for (size_t p = s.find("<path fill="); p != std::string::npos; p = s.find("<path fill=", p + 1)) ++paths;
    EXPECT_EQ(paths, m.triangles.size());
    EXPECT_NE(s.find("<title>wall</title>"), std::string::npos);
}

TEST(Writers, FormatNames) {
    for (auto f : {api::Format::Json, api::Format::Vtk, api::Format::Su2, api::Format::Msh, api::Format::Svg})
        EXPECT_EQ(api::parse_format(api::format_name(f)), f);
    EXPECT_FALSE(api::parse_format("stl").has_value());
    EXPECT_STREQ(api::content_type(api::Format::Vtk), "application/octet-stream");
}

// A tag may hold markup characters (the rule of docs/api.md refuses only control characters
// and double quotes): SVG gets them as entities, never as markup; MSH and SU2 keep the name.
TEST(Writers, TagsAreEscapedInSvgAndKeptWholeInMshAndSu2) {
    const std::string tag = "<script>alert('&')</script>";
    const api::MeshRequest req = api::parse_request(
        nlohmann::json{{"geometry",
                        {{"points", {{"A", {0, 0}}, {"B", {1, 0}}, {"C", {1, 1}}, {"D", {0, 1}}}},
                         {"curves",
                          {{"bottom", {{"type", "line"}, {"from", "A"}, {"to", "B"}, {"tag", tag}}},
                           {"right", {{"type", "line"}, {"from", "B"}, {"to", "C"}}},
                           {"top", {{"type", "line"}, {"from", "C"}, {"to", "D"}}},
                           {"left", {{"type", "line"}, {"from", "D"}, {"to", "A"}}}}},
                         {"loops", {{"bottom", "right", "top", "left"}}}}},
                       {"density", {{"size", 0.25}}}}
            .dump());
    const core::MeshResult r = core::generate_mesh(req.geometry, req.density, req.options);
    auto text = [&](api::Format f) {
        std::ostringstream os;
        api::write_mesh(f, r, os);
        return os.str();
    };
    const std::string svg = text(api::Format::Svg);
    EXPECT_EQ(svg.find("<script"), std::string::npos);
    EXPECT_NE(svg.find("<title>&lt;script&gt;alert(&apos;&amp;&apos;)&lt;/script&gt;</title>"), std::string::npos);
    EXPECT_NE(text(api::Format::Msh).find("\"" + tag + "\"\n"), std::string::npos);
    EXPECT_NE(text(api::Format::Su2).find("MARKER_TAG= " + tag + "\n"), std::string::npos);
}

// SU2 marker names end at white space, so spaces are written as '_'. "far field" and
// "far_field" are two boundary conditions: they must stay two markers, the later renamed.
TEST(Writers, Su2KeepsTagsApartThatReadAlikeWithUnderscores) {
    const api::MeshRequest req = api::parse_request(
        nlohmann::json{{"geometry",
                        {{"points", {{"A", {0, 0}}, {"B", {1, 0}}, {"C", {1, 1}}, {"D", {0, 1}}}},
                         {"curves",
                          {{"bottom", {{"type", "line"}, {"from", "A"}, {"to", "B"}, {"tag", "far field"}}},
                           {"right", {{"type", "line"}, {"from", "B"}, {"to", "C"}, {"tag", "far_field"}}},
                           {"top", {{"type", "line"}, {"from", "C"}, {"to", "D"}, {"tag", "wall"}}},
                           {"left", {{"type", "line"}, {"from", "D"}, {"to", "A"}, {"tag", "wall"}}}}},
                         {"loops", {{"bottom", "right", "top", "left"}}}}},
                       {"density", {{"size", 0.25}}}}
            .dump());
    const core::MeshResult r = core::generate_mesh(req.geometry, req.density, req.options);
    std::ostringstream os;
    api::write_mesh(api::Format::Su2, r, os);
    std::istringstream in(os.str());
    std::vector<std::string> markers;
    for (std::string line; std::getline(in, line);)
        if (line.rfind("MARKER_TAG= ", 0) == 0) markers.push_back(line.substr(12));
    ASSERT_EQ(markers.size(), 3u);
    std::sort(markers.begin(), markers.end());
    EXPECT_TRUE(std::adjacent_find(markers.begin(), markers.end()) == markers.end());
    EXPECT_NE(std::find(markers.begin(), markers.end(), "far_field"), markers.end());
    EXPECT_NE(std::find(markers.begin(), markers.end(), "far_field_2"), markers.end());
}
