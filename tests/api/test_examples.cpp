// Every request of examples/ as a user sends it, through the request layer and the mesher:
// the smallest angle of the defaults (30 degrees; a wedge between two constrained edges and
// the layers' own cells aside) holds, and still holds with each density made coarser or
// finer by a constant factor (the examples' sizes for other Reynolds numbers or budgets).

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "meshd/api/request.hpp"
#include "meshd/core/mesher.hpp"
#include "random/random_domains.hpp"
#include "support.hpp"

using namespace meshd;

namespace {

std::vector<std::filesystem::path> requests_in(const std::string& dir) {
    std::vector<std::filesystem::path> out;
    for (const auto& e : std::filesystem::directory_iterator(MESHD_SOURCE_DIR "/" + dir))
        if (e.path().extension() == ".json") out.push_back(e.path());
    std::sort(out.begin(), out.end());
    return out;
}

std::vector<std::filesystem::path> examples() { return requests_in("examples"); }

// The request with every size it names multiplied by k: an expression density's size (and
// its max), or eq. 6.1's curve sizes (and its floor).
std::string scaled(const std::string& body, double k) {
    nlohmann::ordered_json j = nlohmann::ordered_json::parse(body);
    nlohmann::ordered_json& d = j["density"];
    const std::string factor = " * " + std::to_string(k);
    if (d.contains("size")) d["size"] = "(" + d["size"].get<std::string>() + ")" + factor;
    if (d.contains("curves"))
        for (auto& [name, size] : d["curves"].items()) size = "(" + size.get<std::string>() + ")" + factor;
    for (const char* bound : {"max", "min"})
        if (d.contains(bound)) d[bound] = d[bound].get<double>() * k;
    return j.dump();
}

double smallest_angle(const std::string& body, size_t& points, double* gradation_applied = nullptr) {
    const api::MeshRequest r = api::parse_request(body);
    const core::MeshResult m = core::generate_mesh(r.geometry, r.density, r.options);
    points = m.mesh.point_count();
    if (gradation_applied) *gradation_applied = m.stats.gradation_applied;
    return test::smallest_free_angle(m.mesh).first;
}

}  // namespace

TEST(Examples, EveryExampleMeshesAtThirtyDegreesOrMore) {
    const auto files = examples();
    ASSERT_GE(files.size(), 7u);
    for (const auto& f : files) {
        size_t points = 0;
        double graded = -1.0;
        const double angle = smallest_angle(test::read_file(f.string()), points, &graded);
        EXPECT_GE(angle, 30.0) << f.filename();
        EXPECT_GT(points, 500u) << f.filename();
        // Their fields follow the mesh: none is made again with the jump gradation.
        EXPECT_EQ(graded, 0.0) << f.filename();
    }
}

// bench/hard/: sizes that jump 10- to 400-fold across a line or swing every 0.1, channels
// 100 and 1,000 times longer than wide, holes and embedded lines 0.001 from a wall or from
// each other, curve sizes 50 times off the interior's, thin and open airfoils. With the
// defaults, each at 30 degrees or more: the jumps and the swings by the jump gradation
// (MeshOptions::jump_gradation; before it, 24.3 and 29.95 on two of them).
TEST(Examples, EveryHardRequestMeshesAtThirtyDegreesOrMore) {
    const auto files = requests_in("bench/hard");
    ASSERT_GE(files.size(), 20u);
    size_t graded_count = 0;
    for (const auto& f : files) {
        size_t points = 0;
        double graded = -1.0;
        const double angle = smallest_angle(test::read_file(f.string()), points, &graded);
        EXPECT_GE(angle, 30.0) << f.filename();
        graded_count += graded > 0.0 ? 1 : 0;
    }
    EXPECT_GE(graded_count, 3u);  // the jumps, at least
}

// From twice the points to a few dozen: the coarsest meshes, where a curve's few segments
// meet the interior's few points, are where an angle would fall first.
TEST(Examples, ThirtyDegreesHoldWithTheDensitiesScaled) {
    for (const auto& f : examples()) {
        const std::string body = test::read_file(f.string());
        size_t base = 0;
        smallest_angle(body, base);
        for (const double k : {0.7, 2.0, 3.0, 5.0, 8.0, 13.0}) {
            size_t points = 0;
            // (The channel at 13 times its sizes makes its cylinder a hexagon of 0.15 sides,
            // the wake leaving one corner: the one interior point above that corner had its
            // best place at angles of 30, 30 and 120 exactly, and the repair's search stopped
            // at 29.999. That triangle, two fixed corners and one interior, now takes a closing
            // round: 70 points instead of 63, at 30.03.)
            const double angle = smallest_angle(scaled(body, k), points);
            EXPECT_GE(angle, 30.0) << f.filename() << " sizes x" << k;
            // The factor reached the mesh: fewer points for coarser sizes, more for finer.
            if (k < 1.0) EXPECT_GT(points, base) << f.filename() << " sizes x" << k;
            else EXPECT_LT(points, base) << f.filename() << " sizes x" << k;
        }
    }
}

// The crossing proof made block by block (interior.cpp, crosses_front) passes over blocks of
// short front segments on graded fields, where the whole-domain proof gives way at once.
// Checking, every block it would pass over is looked at all the same and each of its segments
// checked against the proof's premise: short, and its ends outside the disks about the
// candidate's side that (4.22) keeps points out of. None may fail, on every example and hard
// request, and the meshes must be the ones made without any proof.
TEST(Examples, TheBlockByBlockCrossingProofCoversWhatItPassesOver) {
    std::vector<std::filesystem::path> files = examples();
    for (const auto& f : requests_in("bench/hard")) files.push_back(f);
    ASSERT_GE(files.size(), 30u);
    std::uint64_t blocks = 0, graded_used = 0;
    for (const auto& f : files) {
        const api::MeshRequest r = api::parse_request(test::read_file(f.string()));
        core::MeshOptions o = r.options;
        o.interior.check_crossing_proof = true;
        const core::MeshResult checked = core::generate_mesh(r.geometry, r.density, o);
        EXPECT_EQ(checked.stats.interior.proof_violations, 0u) << f.filename();
        o.interior.check_crossing_proof = false;
        const core::MeshResult proven = core::generate_mesh(r.geometry, r.density, o);
        o.interior.crossing_proof = false;
        const core::MeshResult plain = core::generate_mesh(r.geometry, r.density, o);
        EXPECT_EQ(plain.stats.interior.blocks_proven, 0u) << f.filename();
        // (Not as many blocks as without checking: looking at a block retires its consumed
        // segments, and a block left with nothing to look at is not asked again.)
        EXPECT_EQ(checked.stats.interior.blocks_proven > 0, proven.stats.interior.blocks_proven > 0) << f.filename();
        for (const core::MeshResult* m : {&checked, &proven}) {
            ASSERT_EQ(m->mesh.triangles.size(), plain.mesh.triangles.size()) << f.filename();
            EXPECT_TRUE(test::same_mesh(m->mesh, plain.mesh)) << f.filename();
        }
        blocks += proven.stats.interior.blocks_proven;
        graded_used += proven.stats.interior.blocks_proven > 0 && proven.stats.interior.crossings_proven == 0 ? 1 : 0;
    }
    std::printf("[ block-by-block crossing proof ] %llu blocks passed over, used on %llu graded requests of %zu\n",
                static_cast<unsigned long long>(blocks), static_cast<unsigned long long>(graded_used), files.size());
    // The checks mean something only where the proof was used, and it is meant for graded fields.
    EXPECT_GE(graded_used, files.size() / 2);
}
