// The request layer: a valid request parses into the right core types; every request of
// the catalogue (tests/data/bad_requests.json) is refused with its status and JSON pointer.

#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "support.hpp"
#include <sstream>

#include "meshd/api/problem.hpp"
#include "meshd/api/request.hpp"
#include "meshd/core/errors.hpp"

using namespace meshd;

using meshd::test::read_file;

namespace {


// The answer the service would give: the problem, or status 200.
api::Problem answer(const std::string& body) {
    try {
        const api::MeshRequest r = api::parse_request(body);
        core::generate_mesh(r.geometry, r.density, r.options);
        return {200, "", "", "", ""};
    } catch (...) {
        return api::problem_of(std::current_exception());
    }
}

}  // namespace

TEST(Request, TheContractExampleParses) {
    const std::string body = read_file(MESHD_SOURCE_DIR "/examples/naca0012.json");
    const api::MeshRequest r = api::parse_request(body);
    ASSERT_EQ(r.geometry.points.size(), 2u);
    EXPECT_EQ(r.geometry.points[1].first, "F");
    ASSERT_EQ(r.geometry.curves.size(), 2u);
    EXPECT_EQ(r.geometry.curves[0].name, "wing");
    const auto* naca = std::get_if<core::NacaSpec>(&r.geometry.curves[0].shape);
    ASSERT_NE(naca, nullptr);
    EXPECT_EQ(naca->code, "0012");
    EXPECT_EQ(r.geometry.curves[0].tag, std::optional<std::string>("wall"));
    const auto* arc = std::get_if<core::ArcShape>(&r.geometry.curves[1].shape);
    ASSERT_NE(arc, nullptr);
    EXPECT_EQ(arc->center.x, 0.5);
    ASSERT_EQ(r.geometry.loops.size(), 2u);
    EXPECT_EQ(r.geometry.loops[1][0].curve, "wing");
    ASSERT_TRUE(r.density.size.has_value());
    EXPECT_NE(std::get<std::string>(*r.density.size).find("1.008930411365"), std::string::npos);
    EXPECT_EQ(r.options.smoothing_iterations, 5);
}

TEST(Request, ReversedCurvesAndOptions) {
    const std::string body = R"({"geometry": {"points": {"A": [0,0], "B": [1,0], "C": [0,1]},
        "curves": {"ab": {"type": "line", "from": "A", "to": "B"}, "bc": {"type": "line", "from": "B", "to": "C"},
                   "ac": {"type": "line", "from": "A", "to": "C"}},
        "loops": [["ab", "bc", "-ac"]]},
        "density": {"size": 0.2, "min": 0.01, "max": 1, "interior": "interpolate"},
        "options": {"triangulator": "advancing-front", "smoothing_iterations": 0, "max_points": 5000, "timeout_s": 2.5}})";
    const api::MeshRequest r = api::parse_request(body);
    EXPECT_TRUE(r.geometry.loops[0][2].reversed);
    EXPECT_EQ(r.geometry.loops[0][2].curve, "ac");
    EXPECT_EQ(r.options.triangulator, core::Triangulator::AdvancingFront);
    EXPECT_EQ(r.options.max_points, 5000u);
    EXPECT_EQ(r.timeout_s, 2.5);
    EXPECT_EQ(r.density.interior, core::InteriorMode::Interpolate);
    const core::MeshResult m = core::generate_mesh(r.geometry, r.density, r.options);
    EXPECT_GT(m.mesh.triangles.size(), 0u);
}

// The contract's min_angle_deg: 0 asked is "off, the paper's pure method", so it turns the
// defaults' last resort for 30 degrees off too; an absent member keeps the defaults, and a
// bound asked keeps the last resort under it (the mesh still gets 30 where it needs it).
TEST(Request, MinAngleZeroAskedTurnsEveryRefinementOff) {
    auto parsed = [](const std::string& options) {
        return api::parse_request(R"({"geometry": {"points": {"A": [0,0], "B": [1,0], "C": [0,1]},
            "curves": {"ab": {"type": "line", "from": "A", "to": "B"}, "bc": {"type": "line", "from": "B", "to": "C"},
                       "ca": {"type": "line", "from": "C", "to": "A"}},
            "loops": [["ab", "bc", "ca"]]}, "density": {"size": 0.2}, "options": )" + options + "}");
    };
    const api::MeshRequest absent = parsed("{}");
    EXPECT_EQ(absent.options.min_angle_deg, 0.0);
    EXPECT_TRUE(absent.options.sharp_last_resort);
    const api::MeshRequest zero = parsed(R"({"min_angle_deg": 0})");
    EXPECT_EQ(zero.options.min_angle_deg, 0.0);
    EXPECT_FALSE(zero.options.sharp_last_resort);
    const api::MeshRequest twenty = parsed(R"({"min_angle_deg": 20})");
    EXPECT_EQ(twenty.options.min_angle_deg, 20.0);
    EXPECT_TRUE(twenty.options.sharp_last_resort);
}

TEST(Request, CatalogueOfBadRequests) {
    const auto cat = nlohmann::ordered_json::parse(read_file(MESHD_SOURCE_DIR "/tests/data/bad_requests.json"));
    ASSERT_GE(cat["cases"].size(), 40u);
    // The base request itself is fine.
    EXPECT_EQ(answer(cat["base"].dump()).status, 200);
    for (const auto& c : cat["cases"]) {
        const std::string name = c["name"];
        const std::string body = c.contains("raw") ? c["raw"].get<std::string>() : c["body"].dump();
        const api::Problem p = answer(body);
        EXPECT_EQ(p.status, c["status"].get<int>()) << name << ": " << p.detail;
        EXPECT_EQ(p.pointer, c["pointer"].get<std::string>()) << name << ": " << p.detail;
        EXPECT_FALSE(p.type.empty()) << name;
        EXPECT_FALSE(p.title.empty()) << name;
        EXPECT_FALSE(p.detail.empty()) << name;
        // The problem is valid JSON with the same fields.
        const auto j = nlohmann::json::parse(p.to_json());
        EXPECT_EQ(j["status"], p.status) << name;
    }
}

TEST(Problem, PointerTokensAreEscaped) {
    EXPECT_EQ(api::pointer_token("a/b~c"), "a~1b~0c");
    core::GeometryError e(core::GeometryErrorKind::BadNaca, "x", {core::Subject::curve("wing/1", {"code"})});
    EXPECT_EQ(api::problem_from(e).pointer, "/geometry/curves/wing~11/code");
}

// A bug's answer says what broke but not where in meshd's source (that goes to the log).
TEST(Problem, InternalErrorsKeepSourceLocationsOutOfTheAnswer) {
    std::string log;
    const api::Problem p = api::problem_of(
        std::make_exception_ptr(core::InternalError("a loop is open", "/build/meshd/core/src/x.cpp", 42)), &log);
    EXPECT_EQ(p.status, 500);
    EXPECT_NE(p.detail.find("a loop is open"), std::string::npos);
    EXPECT_EQ(p.detail.find("x.cpp"), std::string::npos);
    EXPECT_EQ(p.to_json().find("/build/"), std::string::npos);
    EXPECT_NE(log.find("x.cpp:42"), std::string::npos);
}

TEST(Request, FoamOptionsNameTagsOfTheGeometry) {
    nlohmann::ordered_json j = nlohmann::ordered_json::parse(read_file(MESHD_SOURCE_DIR "/examples/naca0012.json"));
    j["options"]["patch_types"] = {{"wall", "wall"}, {"farfield", "patch"}};
    j["options"]["slab_thickness"] = 0.25;
    const api::MeshRequest r = api::parse_request(j.dump());
    EXPECT_EQ(r.foam.patch_types.at("wall"), "wall");
    EXPECT_EQ(r.foam.patch_types.at("farfield"), "patch");
    EXPECT_EQ(r.foam.slab_thickness, 0.25);
    // A key that is no tag of the geometry (a typo) is refused with its pointer.
    j["options"]["patch_types"] = {{"wal", "wall"}};
    const api::Problem p = answer(j.dump());
    EXPECT_EQ(p.status, 400);
    EXPECT_EQ(p.pointer, "/options/patch_types/wal");
}
