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
