// Random valid domains (random/random_domains.hpp) through the whole pipeline. Every seed must
// give a mesh that passes check_mesh, or a GeometryError (a clear 422/413); nothing else may
// escape. The seed of a failure is printed. MESHD_RANDOM_DOMAINS sets the number of seeds
// (default 1000). meshd-random-census finds the seeds below 30 degrees and draws them.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <initializer_list>
#include <map>
#include <numbers>
#include <optional>
#include <random>
#include <set>
#include <string>

#include "fixtures.hpp"
#include "random/random_domains.hpp"

#include "layers/layers.hpp"
#include "meshd/core/errors.hpp"
#include "meshd/core/mesher.hpp"

using namespace meshd::core;
using namespace meshd::test;

namespace {

// The mesh `make` returns for seed's case, or nothing: a GeometryError is a clear refusal
// (counted and printed), anything else fails the test.
template <class Make>
std::optional<MeshResult> mesh_or_refusal(std::uint64_t seed, const RandomCase& rc, std::uint64_t& refused, Make&& make) {
    try {
        return make();
    } catch (const GeometryError& e) {
        ++refused;
        std::printf("[ seed %llu ] refused: %s (%s)\n", static_cast<unsigned long long>(seed), e.what(), rc.summary.c_str());
    } catch (const std::exception& e) {
        ADD_FAILURE() << "seed " << seed << " (" << rc.summary << "): " << e.what();
    }
    return std::nullopt;
}

// Seed's case with its boundary layers (layers_for), asserting it has curves to grow them on.
struct LayeredCase {
    RandomCase rc;
    Domain domain;
    MeshOptions options;
};
LayeredCase layered_case(std::uint64_t seed) {
    LayeredCase c{random_case(seed), {}, {}};
    c.domain = build_domain(c.rc.domain);
    const auto spec = layers_for(seed, c.rc, c.domain);
    EXPECT_TRUE(spec) << "seed " << seed << " has no curve for layers";
    if (spec) c.options.boundary_layers = {*spec};
    return c;
}

// Each seed's layered case (layered_case) meshed with the defaults: a valid mesh whose
// isotropic triangles keep 30 degrees; with `embedded`, the case must have an embedded curve.
void expect_thirty_degrees_with_layers(std::initializer_list<std::uint64_t> seeds, bool embedded = false) {
    for (const std::uint64_t seed : seeds) {
        const LayeredCase lc = layered_case(seed);
        if (embedded) {
            EXPECT_FALSE(lc.rc.domain.embedded.empty()) << seed;
        }
        const MeshResult r = generate_mesh(lc.domain, lc.rc.density, lc.options);
        EXPECT_TRUE(check_mesh(r.mesh, false).empty()) << seed;
        const auto [angle, where] = smallest_free_angle(r.mesh);
        EXPECT_GE(angle, 30.0) << "seed " << seed << " at (" << where.x << ", " << where.y << ")";
    }
}

// Seeds' meshes without layers, with the defaults: valid, and no free angle below 30 degrees.
void expect_thirty_degrees_without_layers(std::initializer_list<std::uint64_t> seeds) {
    for (const std::uint64_t seed : seeds) {
        const RandomCase rc = random_case(seed);
        const MeshResult r = generate_mesh(build_domain(rc.domain), rc.density, MeshOptions{});
        EXPECT_TRUE(check_mesh(r.mesh, false).empty()) << seed;
        const auto [angle, where] = smallest_free_angle(r.mesh);
        EXPECT_GE(angle, 30.0) << "seed " << seed << " at (" << where.x << ", " << where.y << ")";
    }
}

// The seed's layered mesh with the defaults: valid, at 30 degrees or more away from corners
// between two constrained edges, and with points of the refinement in it.
MeshResult expect_refined_to_thirty(std::uint64_t seed) {
    const LayeredCase lc = layered_case(seed);
    MeshResult r = generate_mesh(lc.domain, lc.rc.density, lc.options);
    EXPECT_TRUE(check_mesh(r.mesh, false).empty()) << seed;
    const auto [angle, where] = smallest_free_angle(r.mesh);
    EXPECT_GE(angle, 30.0) << "seed " << seed << " at (" << where.x << ", " << where.y << ")";
    EXPECT_GT(r.stats.refinement_points, 0u) << seed;
    return r;
}

}  // namespace

TEST(RandomDomains, EveryMeshIsValidOrTheRequestIsRefusedClearly) {
    std::uint64_t seeds = 1000;
    if (const char* s = std::getenv("MESHD_RANDOM_DOMAINS")) seeds = std::strtoull(s, nullptr, 10);
    std::uint64_t meshed = 0, refused = 0;
    std::vector<double> ratios;
    for (std::uint64_t seed = 1; seed <= seeds; ++seed) {
        const RandomCase rc = random_case(seed);
        MeshOptions o;
        o.max_points = 200000;
        o.smoothing_iterations = seed % 3 == 0 ? 0 : 3;
        if (seed % 4 == 1) o.triangulator = Triangulator::AdvancingFront;
        if (seed % 5 == 2) o.min_angle_deg = 28.0;
        const auto r = mesh_or_refusal(seed, rc, refused, [&] { return generate_mesh(rc.domain, rc.density, o); });
        if (!r) continue;
        const auto broken = check_mesh(r->mesh, o.smoothing_iterations == 0 && o.min_angle_deg == 0.0);
        if (!broken.empty()) ADD_FAILURE() << "seed " << seed << " (" << rc.summary << "): " << broken.front();
        ++meshed;
        // The admission forecast against the mesh (refinement for min_angle_deg adds points
        // the forecast does not count).
        if (o.min_angle_deg == 0.0) ratios.push_back(r->stats.forecast_points / static_cast<double>(r->quality.points));
    }
    std::printf("[ random domains ] %llu meshed, %llu refused\n", static_cast<unsigned long long>(meshed),
                static_cast<unsigned long long>(refused));
    // How close the forecast came: its purpose is to refuse what is far too large before any
    // work (the stages count exactly), so a factor of two either way is the bound that matters.
    std::sort(ratios.begin(), ratios.end());
    ASSERT_FALSE(ratios.empty());
    auto at = [&](double q) { return ratios[static_cast<size_t>(q * static_cast<double>(ratios.size() - 1))]; };
    std::printf("[ random domains ] forecast / points over %zu meshes: min %.3f, 5%% %.3f, median %.3f, 95%% %.3f, max %.3f\n",
                ratios.size(), ratios.front(), at(0.05), at(0.5), at(0.95), ratios.back());
    EXPECT_GT(ratios.front(), 0.5);
    EXPECT_LT(ratios.back(), 2.0);
    // The generator makes valid domains with fitting densities: refusals are the exception.
    EXPECT_GE(meshed, seeds * 9 / 10);
}

// Both triangulators on the same points: with the smoothing off the mesh is the constrained
// Delaunay triangulation of the boundary's and the front's points, which the perturbed
// in-circle test makes unique, so the paper's advancing front and the incremental insertion
// must give the same triangles on every domain (holes, embedded curves and corners that hide
// points from each other included). MESHD_RANDOM_TRIANGULATORS sets the number of seeds.
TEST(RandomDomains, BothTriangulatorsGiveTheSameTriangles) {
    std::uint64_t seeds = 150;
    if (const char* s = std::getenv("MESHD_RANDOM_TRIANGULATORS")) seeds = std::strtoull(s, nullptr, 10);
    std::uint64_t compared = 0, refused = 0;
    for (std::uint64_t seed = 1; seed <= seeds; ++seed) {
        const RandomCase rc = random_case(seed);
        MeshOptions o;
        o.max_points = 100000;
        o.smoothing_iterations = 0;
        const auto d = mesh_or_refusal(seed, rc, refused, [&] { return generate_mesh(rc.domain, rc.density, o); });
        if (!d) continue;
        o.triangulator = Triangulator::AdvancingFront;
        const auto f = mesh_or_refusal(seed, rc, refused, [&] { return generate_mesh(rc.domain, rc.density, o); });
        if (!f) {
            ADD_FAILURE() << "seed " << seed << ": refused with the advancing front only";
            continue;
        }
        ASSERT_EQ(f->mesh.point_count(), d->mesh.point_count()) << "seed " << seed;
        EXPECT_EQ(canonical(f->mesh.triangles), canonical(d->mesh.triangles)) << "seed " << seed << " (" << rc.summary << ")";
        ++compared;
    }
    std::printf("[ random domains, both triangulators ] %llu compared, %llu refused\n",
                static_cast<unsigned long long>(compared), static_cast<unsigned long long>(refused));
    EXPECT_GE(compared, seeds * 9 / 10);
}

// The interior's crossing proof (InteriorOptions::crossing_proof) only leaves out segments
// that cannot fail the crossing test: with it and without, every point and triangle is the
// same. A third of the random densities are uniform, where the proof holds through whole runs;
// the others drop it at the start or on the way. MESHD_RANDOM_PROOF sets the seed count.
TEST(RandomDomains, TheCrossingProofLeavesTheMeshAsItWas) {
    std::uint64_t seeds = 150;
    if (const char* s = std::getenv("MESHD_RANDOM_PROOF")) seeds = std::strtoull(s, nullptr, 10);
    std::uint64_t compared = 0, refused = 0, proven_runs = 0, proven = 0, candidates = 0, block_runs = 0;
    for (std::uint64_t seed = 1; seed <= seeds; ++seed) {
        const RandomCase rc = random_case(seed);
        MeshOptions o;
        o.max_points = 100000;
        const auto with = mesh_or_refusal(seed, rc, refused, [&] { return generate_mesh(rc.domain, rc.density, o); });
        if (!with) continue;
        o.interior.crossing_proof = false;
        const auto without = mesh_or_refusal(seed, rc, refused, [&] { return generate_mesh(rc.domain, rc.density, o); });
        if (!without) {
            ADD_FAILURE() << "seed " << seed << ": refused without the proof only";
            continue;
        }
        EXPECT_EQ(without->stats.interior.crossings_proven, 0u) << "seed " << seed;
        EXPECT_EQ(without->stats.interior.blocks_proven, 0u) << "seed " << seed;
        // The blocks the proof passed over, looked at all the same: each segment in them is
        // covered by the premise (crosses_front, check_premise).
        if (with->stats.interior.blocks_proven > 0) {
            o.interior.crossing_proof = true;
            o.interior.check_crossing_proof = true;
            const MeshResult checked = generate_mesh(rc.domain, rc.density, o);
            EXPECT_EQ(checked.stats.interior.proof_violations, 0u) << "seed " << seed << " (" << rc.summary << ")";
            EXPECT_GT(checked.stats.interior.blocks_proven, 0u) << "seed " << seed;
            ++block_runs;
        }
        ASSERT_EQ(with->mesh.point_count(), without->mesh.point_count()) << "seed " << seed << " (" << rc.summary << ")";
        ASSERT_EQ(with->mesh.triangles.size(), without->mesh.triangles.size()) << "seed " << seed;
        EXPECT_TRUE(same_mesh(with->mesh, without->mesh)) << "seed " << seed << " (" << rc.summary << ")";
        ++compared;
        proven_runs += with->stats.interior.crossings_proven > 0 ? 1 : 0;
        proven += with->stats.interior.crossings_proven;
        candidates += with->stats.interior.candidates;
    }
    std::printf("[ random domains, crossing proof ] %llu compared (%llu with the whole-domain proof used, %llu of "
                "%llu candidates; %llu with blocks passed over), %llu refused\n",
                static_cast<unsigned long long>(compared), static_cast<unsigned long long>(proven_runs),
                static_cast<unsigned long long>(proven), static_cast<unsigned long long>(candidates),
                static_cast<unsigned long long>(block_runs), static_cast<unsigned long long>(refused));
    EXPECT_GE(compared, seeds * 9 / 10);
    // The comparison means something only where the proofs were used.
    EXPECT_GE(proven_runs, compared / 10);
    EXPECT_GE(block_runs, compared / 3);
}

// Where it applies, the proof holds through the whole run: on the load run's square (a field
// from 0.016 to 0.026, a factor 1.6) every point the front accepts went through a crossing
// test that the proof covered, and with a field twice as steep (a factor 2.25, still in two
// neighbouring size classes) the first candidate's sides are beyond what the two inequalities
// cover at the range's ends, and the proof is never used.
TEST(RandomDomains, TheCrossingProofHoldsThroughANearUniformField) {
    MeshOptions o;
    const MeshResult gentle = generate_mesh(unit_square(), density_of("0.016 + 0.01 * x"), o);
    EXPECT_GT(gentle.stats.interior.accepted, 2000u);
    EXPECT_GE(gentle.stats.interior.crossings_proven, gentle.stats.interior.accepted);
    const MeshResult steep = generate_mesh(unit_square(), density_of("0.016 + 0.02 * x"), o);
    EXPECT_EQ(steep.stats.interior.crossings_proven, 0u);
}

// Curves spaced finer than the inside (0.02 against 0.025 to 0.028) make the front close on
// points (interior.cpp, close_on): the proof is used until the first closing, which needs every
// segment in the grid, and the mesh must come out as without the proof.
TEST(RandomDomains, TheCrossingProofGivesWayToClosingsWithTheMeshUnchanged) {
    const Domain dom = build_domain(unit_square());
    for (const double inside : {0.025, 0.026, 0.028}) {
        DensitySpec d;
        for (const char* side : {"bottom", "right", "top", "left"}) d.curves.push_back({side, 0.02});
        d.interior = InteriorMode::Expression;
        d.interior_expression = std::to_string(inside);
        MeshOptions o;
        const MeshResult with = generate_mesh(dom, d, o);
        o.interior.crossing_proof = false;
        const MeshResult without = generate_mesh(dom, d, o);
        EXPECT_GT(with.stats.interior.crossings_proven, 0u) << inside;
        ASSERT_EQ(with.mesh.point_count(), without.mesh.point_count()) << inside;
        EXPECT_TRUE(same_points(with.mesh, without.mesh)) << inside;
    }
}

// Where curves meet at a named point (a corner, a spoke leaving a hole, a wake line leaving the
// outer loop) the agreement caps the longer curves at the shortest first segment there: the
// triangle that closes such a corner is often made of those two segments alone, and its angles
// follow their ratio. The placement along a curve rounds to whole segments, so the ratio is
// held to 2 rather than 1.5 (it reached 3.07 on these domains before the corners were capped,
// and smallest angles of 15 degrees in triangles of fixed points only).
TEST(RandomDomains, CurvesMeetingAtAPointStartWithSegmentsOfAlikeLength) {
    double worst = 1.0;
    std::uint64_t worst_seed = 0;
    for (std::uint64_t seed = 1; seed <= 400; ++seed) {
        const RandomCase rc = random_case(seed);
        MeshOptions o;  // the placement itself: the smoothing may slide points along curves
        o.max_points = 200000;
        o.smoothing_iterations = 0;
        MeshResult r;
        try {
            r = generate_mesh(rc.domain, rc.density, o);
        } catch (const GeometryError&) {
            continue;  // refused clearly: the test above counts those
        }
        std::map<VertexId, std::pair<double, double>> at;  // shortest, longest edge at a corner
        for (const MeshEdge& e : r.mesh.edges) {
            const double l = distance(r.mesh.point(e.a), r.mesh.point(e.b));
            for (const VertexId v : {e.a, e.b}) {
                if (r.mesh.kind[v] != PointKind::Corner) continue;
                auto [it, fresh] = at.try_emplace(v, l, l);
                it->second.first = std::min(it->second.first, l);
                it->second.second = std::max(it->second.second, l);
            }
        }
        for (const auto& [v, range] : at)
            if (range.second / range.first > worst) {
                worst = range.second / range.first;
                worst_seed = seed;
            }
    }
    EXPECT_LE(worst, 2.0) << "seed " << worst_seed << " (" << random_case(worst_seed).summary << ")";
}


// Issue 15's target on these domains: with the defaults no angle below 30 degrees, but where
// the domain itself has one (a wake line leaving a corner at less than 30 degrees to a side:
// the triangle filling that wedge alone has both its sides on curves there). Before the
// smoothing could open triangles of fixed points only (a spoke beside a circle's coarse
// segments, a wake beside a side) 40 of the first 400 seeds were below 30 degrees, the worst
// at 23. The smoothing may slide points along their curves, nothing else of the boundary.
TEST(RandomDomains, NoAngleBelowThirtyDegreesButTheDomainsOwn) {
    double worst = 180.0;
    std::uint64_t worst_seed = 0;
    size_t slid = 0;
    for (std::uint64_t seed = 1; seed <= 500; ++seed) {
        const RandomCase rc = random_case(seed);
        const Domain domain = build_domain(rc.domain);
        MeshOptions o;
        o.max_points = 200000;
        MeshResult r, raw;
        try {
            r = generate_mesh(domain, rc.density, o);
            o.smoothing_iterations = 0;
            raw = generate_mesh(domain, rc.density, o);
        } catch (const GeometryError&) {
            continue;
        }
        size_t moved = 0;
        for (const std::string& e : fixed_points_kept(domain, r.mesh, raw.mesh, &moved))
            ADD_FAILURE() << "seed " << seed << ": " << e;
        slid += moved;
        const double angle = smallest_free_angle(r.mesh).first;
        if (angle < worst) {
            worst = angle;
            worst_seed = seed;
        }
    }
    std::printf("[ random domains ] smallest angle %.2f (seed %llu), %zu points slid along curves\n", worst,
                static_cast<unsigned long long>(worst_seed), slid);
    EXPECT_GE(worst, 30.0) << "seed " << worst_seed << " (" << random_case(worst_seed).summary << ")";
    EXPECT_GT(slid, 0u);
}

// The same domains with boundary layers on their holes, their spline outer loop or the lines'
// inlet side (whichever of those tags the domain has; a random first height from 1e-5 to 1e-3
// of the domain, growth 1.1 to 1.3, 5 to 30 layers): every mesh must be valid (quads convex
// and conforming, cells counted in the Euler characteristic) or the request refused clearly,
// and its triangles keep 30 degrees (issue 15: every domain of the property tests), but those
// with two sides on curves (smallest_free_angle).
TEST(RandomDomains, WithBoundaryLayersEveryMeshIsValidOrTheRequestIsRefusedClearly) {
    std::uint64_t meshed = 0, refused = 0;
    for (std::uint64_t seed = 1; seed <= 200; ++seed) {
        const RandomCase rc = random_case(seed);
        const Domain domain = build_domain(rc.domain);
        const auto spec = layers_for(seed, rc, domain);
        if (!spec) continue;
        MeshOptions o;
        o.max_points = 400000;
        o.boundary_layers = {*spec};
        if (seed % 5 == 1) o.triangulator = Triangulator::AdvancingFront;
        const auto r = mesh_or_refusal(seed, rc, refused, [&] { return generate_mesh(domain, rc.density, o); });
        if (!r) continue;
        const auto broken = check_mesh(r->mesh, false);
        if (!broken.empty()) ADD_FAILURE() << "seed " << seed << " (" << rc.summary << "): " << broken.front();
        EXPECT_GT(r->mesh.quads.size() + r->quality.boundary_layers.front().columns, 0u) << "seed " << seed;
        const auto [angle, where] = smallest_free_angle(r->mesh);
        EXPECT_GE(angle, 30.0) << "seed " << seed << " (" << rc.summary << ") at (" << where.x << ", " << where.y << ")";
        ++meshed;
    }
    std::printf("[ random domains with layers ] %llu meshed, %llu refused\n", static_cast<unsigned long long>(meshed),
                static_cast<unsigned long long>(refused));
    EXPECT_GE(meshed, 150u);
}

// Cases once below 30 degrees with the defaults, where a fixed point's fan held one triangle
// too many for its angle (a layer's top beside the isotropic mesh; a corner where an
// embedded curve leaves a hole): the repair flips an edge of the fan away and places the
// interior points around it again. Seeds 148, 123 and 100 with layers (17.7, 19.2 and 26.9
// degrees before), 1729 without (29.4).
TEST(RandomDomains, AFixedPointsFanGivesUpATriangleItHasNoRoomFor) {
    for (const auto& [seed, layered] : {std::pair{148u, true}, {123u, true}, {100u, true}, {1729u, false}}) {
        const RandomCase rc = random_case(seed);
        const Domain domain = build_domain(rc.domain);
        MeshOptions o;
        if (layered) {
            const auto spec = layers_for(seed, rc, domain);
            ASSERT_TRUE(spec) << seed;
            o.boundary_layers = {*spec};
        }
        const MeshResult r = generate_mesh(domain, rc.density, o);
        EXPECT_TRUE(check_mesh(r.mesh, false).empty()) << seed;
        const auto [angle, at] = smallest_free_angle(r.mesh);
        EXPECT_GE(angle, 30.0) << "seed " << seed << " at (" << at.x << ", " << at.y << ")";
    }
}

// The defaults' last resort: a triangle of the isotropic part that the repair left at 29.6
// degrees (seed 146694 with layers: the field grades from a small square hole's layers to a
// coarse far wall) is refined to 30 degrees, as min_angle_deg 30 would. A mesh the repair
// left at 30 or more (seed 148 with layers, once below 30 and mended otherwise) is not.
TEST(RandomDomains, ATriangleTheRepairLeavesSharpIsRefinedToThirtyDegrees) {
    const LayeredCase lc = layered_case(146694);
    const MeshResult r = expect_refined_to_thirty(146694);
    // The refinement asked of the request gives the same mesh: the defaults ask it of this one.
    MeshOptions asked = lc.options;
    asked.min_angle_deg = 30.0;
    EXPECT_TRUE(same_mesh(r.mesh, generate_mesh(lc.domain, lc.rc.density, asked).mesh));
    // A lower bound asked does not take the defaults' 30 degrees away.
    asked.min_angle_deg = 20.0;
    EXPECT_TRUE(same_mesh(r.mesh, generate_mesh(lc.domain, lc.rc.density, asked).mesh));
    // With the last resort off (a request's explicit min_angle_deg 0) nothing is refined:
    // the repair's 29.6 degrees stay, and the mesh is still valid.
    MeshOptions off = lc.options;
    off.sharp_last_resort = false;
    const MeshResult o = generate_mesh(lc.domain, lc.rc.density, off);
    EXPECT_EQ(o.stats.refinement_points, 0u);
    EXPECT_TRUE(check_mesh(o.mesh, false).empty());
    EXPECT_LT(smallest_free_angle(o.mesh).first, 30.0);
    EXPECT_LT(o.mesh.point_count(), r.mesh.point_count());
    const LayeredCase fine = layered_case(148);
    const MeshResult f = generate_mesh(fine.domain, fine.rc.density, fine.options);
    EXPECT_GE(smallest_free_angle(f.mesh).first, 30.0);
    EXPECT_EQ(f.stats.refinement_points, 0u);
}

// Where the refinement cannot put a triangle's circumcentre in, it puts a point beside the
// sharp corner: seed 145352 with layers leaves a triangle of three fixed points at 25.3
// degrees in a narrow gap between two holes' layers (two layer tops and an embedded line's
// free end), whose centre lies past the layers' outer edge, which is never split. A point in
// the triangle across one of the corner's edges, placed for the best smallest angle of the
// triangles it makes, takes that edge and the sharp wedge away.
TEST(RandomDomains, ACentreBeyondTheLayersGivesWayToAPointBesideTheSharpCorner) {
    EXPECT_GT(expect_refined_to_thirty(145352).stats.layer_rounds, 0);
}

// A spoke's foot on a circle near the circle's start point: the corner cap at the foot asks
// for the spoke's length there, but the short arc between the two named points, 1.2 segments
// under the cap's cone, rounds to one segment 1.9 times the spoke (seed 2539: 21.3 degrees).
// A corner capped before and still apart is now capped lower by the ratio left over (seeds
// 2539, 1794, 2106 and 2760: 21.3, 28.6, 26.4 and 28.0 degrees before), and by a third at
// least: a hole's side of one segment, 1.51 times the embedded line leaving its end, stayed
// one segment under a cap lowered by the 6% left over (seed 2478: 29.7 degrees; 2102 with
// layers: 29.97).
TEST(RandomDomains, ACornerStillApartAfterItsCapIsCappedLower) {
    expect_thirty_degrees_without_layers({2539u, 1794u, 2106u, 2760u, 2478u});
    expect_thirty_degrees_with_layers({2102u});
}

// Two columns' rays that cross stop both columns short of the crossing. Where one ray passes
// over the other column's foot, that rule flattened the other: a spline's sharp tip under a
// fan of columns 0.9 tall, crossed 0.045 from the tip by the ray of a column 2.8 away, was cut
// to 0.03, and the outer edge fell from the walls' columns to the tip over one long segment
// beside the fan's small triangles (seed 2311 with layers: 18.25 degrees; 6763: 29.75). Now the
// passing column is cut as by a boundary at the foot, and the foot's column stands whole where
// it stays a strip clear of that cut top (else both are cut as before: seed 2730's narrow gap).
// Seeds 2870, 2012 and 5842 (24.4, 26.6 and 27.4 degrees as first grown) needed the rounds
// that lower columns beside sharp triangles before, and none now.
TEST(RandomDomains, ARayPassingOverAColumnsFootCutsThePassingColumn) {
    expect_thirty_degrees_with_layers({2311u, 6763u});
    for (const std::uint64_t seed : {2870u, 2012u, 5842u}) {
        const LayeredCase lc = layered_case(seed);
        const MeshResult r = generate_mesh(lc.domain, lc.rc.density, lc.options);
        EXPECT_EQ(r.stats.layer_rounds, 0) << seed;
        const auto [angle, where] = smallest_free_angle(r.mesh);
        EXPECT_GE(angle, 30.0) << "seed " << seed << " at (" << where.x << ", " << where.y << ")";
    }
}

// The same at a fan's corner, where the foot's column is too tall to stand whole: cut to its
// few steps to the crossing, the whole fan went (every column of it meets the ray there). A
// hole's 60-degree corner 0.08 from the ray of another hole's column 2.7 away kept 5 of its 25
// layers, the outer edge fell from the wall's columns beside it in one segment 0.65 long, and
// the interior's triangle on it had 27.1 degrees; the lowering rounds made it worse (seed
// 48759). The fan now keeps what stays a strip below the room the cut passing column leaves.
TEST(RandomDomains, ARayOverAFansCornerLeavesTheFanTheRoomAlongTheRay) {
    expect_thirty_degrees_with_layers({48759u});
    const LayeredCase lc = layered_case(48759u);
    EXPECT_EQ(generate_mesh(lc.domain, lc.rc.density, lc.options).stats.layer_rounds, 0);
}

// A gap between two curves about the field's size: too small for the interior to put a point
// in, it is closed by a triangle of the curves' points alone, which neither the smoothing nor
// any interior point can mend (seed 7186 without layers: a square hole's side against a
// triangular hole's corner, 23.6 degrees; with layers, 12209: two holes' bare walls and a
// layer top, 28.7; 12797: a spoke's free end beside another hole's layers, 23.5). The mesh
// made shows such a triangle, and the curves at its corners are placed again finer, which
// makes the interior finer beside them: everything is made again once, and then at 30 degrees
// (and 9262, 13485 and 13840 without layers: 28.1, 28.4 and 26.2 before; 22922 with layers,
// 23.9).
TEST(RandomDomains, ASharpTriangleOfFixedPointsAlonePlacesTheCurvesAgainFinerThere) {
    expect_thirty_degrees_without_layers({7186u, 9262u, 13485u, 13840u});
    expect_thirty_degrees_with_layers({12209u, 12797u, 22922u});
    {
        const RandomCase rc = random_case(7186u);
        const MeshResult r = generate_mesh(build_domain(rc.domain), rc.density, MeshOptions{});
        EXPECT_EQ(r.stats.closing_rounds, 1);
    }
    for (const std::uint64_t seed : {12209u, 12797u}) {
        const LayeredCase lc = layered_case(seed);
        EXPECT_EQ(generate_mesh(lc.domain, lc.rc.density, lc.options).stats.closing_rounds, 1) << seed;
    }
    // A mesh near max_points takes no round: the finer curves' few points more (401 here
    // against 392) could have it refused, where the first mesh met the limit. 392 points
    // against a limit of 440 (the estimate before the interior says 436) is above 80% of it.
    {
        const RandomCase rc = random_case(7186u);
        MeshOptions tight;
        tight.max_points = 440;
        const MeshResult r = generate_mesh(build_domain(rc.domain), rc.density, tight);
        EXPECT_EQ(r.stats.closing_rounds, 0);
        EXPECT_LE(r.quality.points, 440u);
    }
    // Nor one that would not fit in the time left (Observer::seconds_left): the mesh made is
    // kept rather than lost to the limit.
    {
        struct NoTimeLeft : Observer {
            double seconds_left() override { return 0.0; }
        } late;
        const RandomCase rc = random_case(7186u);
        const MeshResult r = generate_mesh(build_domain(rc.domain), rc.density, MeshOptions{}, &late);
        EXPECT_EQ(r.stats.closing_rounds, 0);
    }
    // Without the curves' agreement (an option the tests of the paper's pure method use), the
    // curves stay where rho puts them.
    const RandomCase rc = random_case(7186u);
    MeshOptions pure;
    pure.curve_agreement = false;
    EXPECT_EQ(generate_mesh(build_domain(rc.domain), rc.density, pure).stats.closing_rounds, 0);
}

// The same with one interior point in the gap: a triangular hole's 60-degree corner, a small
// octagonal hole beside it, and the one interior point between them, which the smoothing's
// repair could not move far enough (28.5 degrees at the corner, seed 75459 without layers).
TEST(RandomDomains, ASharpTriangleWithOneInteriorPointAcrossAGapPlacesTheCurvesAgain) {
    expect_thirty_degrees_without_layers({75459u});
    const RandomCase rc = random_case(75459u);
    EXPECT_EQ(generate_mesh(build_domain(rc.domain), rc.density, MeshOptions{}).stats.closing_rounds, 1);
}

// Two embedded lines whose free ends face each other 0.55 of the field apart: a triangle of
// the two ends and an interior point had 27.9 degrees (seed 24033 with layers). Two free ends
// closer than their end segments over 1.5 are now a narrow gap, both lines spaced at its
// width there (Mesher.TwoFreeEndsCloseTogetherAreAGapAsNarrow).
TEST(RandomDomains, TwoFreeEndsCloseTogetherAreSpacedForTheirGap) {
    expect_thirty_degrees_with_layers({24033u});
}

// Two neighbouring segments at a domain point that a triangle of the two alone closes: the
// ratio of 1.5 the corner caps allowed closes a right angle at 33.7 degrees, one of 112 at
// 27.8 (a spoke leaving a coarse circle, seed 2544). The corner is now capped where that
// triangle would have an angle below 31 degrees at its angle (seeds 2544 and 2024: 27.8 and
// 27.4 degrees before).
TEST(RandomDomains, ACornerThatTwoSegmentsCloseIsSpacedForItsAngle) {
    expect_thirty_degrees_without_layers({2544u, 2024u});
}

// A square hole almost touching a side of the outer polygon: triangles across the gap had 20
// degrees (18.7 with layers on the hole). Boundaries facing each other across a gap narrower
// than their segments are now spaced at its width (Mesher.BoundariesFacingAcrossANarrowGap...).
TEST(RandomDomains, AHoleAlmostTouchingTheOuterLoopIsSpacedForTheGap) {
    expect_thirty_degrees_without_layers({2730u});
    expect_thirty_degrees_with_layers({2730u});
}

// An embedded line whose free end comes near a hole's layers from the side, between two of
// their columns: the columns there are cut back as for a cross of the local size at the end,
// so the triangles at the end keep 30 degrees (seeds 67 and 72: 17.5 and 14.9 before).
TEST(RandomDomains, LayersLeaveRoomBesideAnEmbeddedCurvesFreeEnd) {
    for (const std::uint64_t seed : {67u, 72u}) {
        const LayeredCase lc = layered_case(seed);
        const Domain& domain = lc.domain;
        const MeshResult r = generate_mesh(domain, lc.rc.density, lc.options);
        const Mesh& m = r.mesh;
        EXPECT_TRUE(check_mesh(m, false).empty()) << seed;
        std::set<VertexId> on_loop, free_ends;
        for (const MeshEdge& e : m.edges)
            if (!e.embedded) on_loop.insert({e.a, e.b});
        for (const CurveId c : domain.embedded())
            for (const VertexId v : m.curve_ends[c])
                if (v != kNoVertex && !on_loop.count(v)) free_ends.insert(v);
        ASSERT_FALSE(free_ends.empty()) << seed;
        size_t seen = 0;
        for (const Triangle& t : m.triangles) {
            if (t.layer || std::none_of(t.v.begin(), t.v.end(), [&](VertexId v) { return free_ends.count(v) > 0; }))
                continue;
            ++seen;
            for (std::uint32_t i = 0; i < 3; ++i) {
                const Vec2 a = m.point(t.v[i]), b = m.point(t.v[(i + 1) % 3]), c = m.point(t.v[(i + 2) % 3]);
                EXPECT_GE(std::atan2(cross(b - a, c - a), dot(b - a, c - a)) * 180.0 / std::numbers::pi, 30.0)
                    << "seed " << seed << " at (" << a.x << ", " << a.y << ")";
            }
        }
        EXPECT_GT(seen, 0u) << seed;
    }
}

// A spoke that leaves a layered circle close to the circle's own start point cuts off a wall
// segment 10 to 70 times shorter than those beside it. The corner caps reach walls too, so
// the walls are graded away from it like any curves meeting at a point: at the circles' named
// points the wall edges differ by at most 2 (the placement rounds to whole segments), and the
// triangles keep 30 degrees (seeds 672, 910, 505 and 384: 6.7, 15.5, 17.3 and 19.7 degrees,
// neighbouring wall edges up to 70 times apart, before). Not at corners where a wall turns
// by more than kFanTurnDeg (a polygon's): the layers fan or bunch there.
TEST(RandomDomains, AShortWallSegmentBetweenNamedPointsGradesTheWallsBesideIt) {
    for (const std::uint64_t seed : {672u, 910u, 505u, 384u}) {
        const LayeredCase lc = layered_case(seed);
        const MeshResult r = generate_mesh(lc.domain, lc.rc.density, lc.options);
        const Mesh& m = r.mesh;
        EXPECT_TRUE(check_mesh(m, false).empty()) << seed;
        // Per named point: the hole edges ending and starting there.
        std::map<VertexId, std::pair<const MeshEdge*, const MeshEdge*>> at;
        for (const MeshEdge& e : m.edges) {
            if (e.embedded || m.tags[e.tag] != "hole") continue;
            if (m.kind[e.b] == PointKind::Corner) at[e.b].first = &e;
            if (m.kind[e.a] == PointKind::Corner) at[e.a].second = &e;
        }
        size_t seen = 0;
        for (const auto& [v, edges] : at) {
            const auto [in, out] = edges;
            ASSERT_TRUE(in && out) << seed;
            const Vec2 t0 = m.point(in->b) - m.point(in->a), t1 = m.point(out->b) - m.point(out->a);
            if (std::fabs(std::atan2(cross(t0, t1), dot(t0, t1))) > kFanTurnDeg * std::numbers::pi / 180.0) continue;
            ++seen;
            EXPECT_LE(std::max(norm(t0), norm(t1)) / std::min(norm(t0), norm(t1)), 2.0)
                << "seed " << seed << " at (" << m.x[v] << ", " << m.y[v] << ")";
        }
        EXPECT_GE(seen, 2u) << seed;
        const auto [angle, where] = smallest_free_angle(m);
        EXPECT_GE(angle, 30.0) << "seed " << seed << " at (" << where.x << ", " << where.y << ")";
    }
}

// What no rule of the layers foresaw (a narrow gap between two walls' layers, a steep fall of
// the outer edge from a tall column to a short fan): a triangle beside the layers still below
// 30 degrees after the smoothing's repair lowers the columns at its corners, the highest of
// them, and the layers are grown again and the interior meshed again on their outer edge
// (seeds 2749 and 3456: 28.0 and 25.3 degrees as first grown). Only the columns named lose
// layers (and their neighbours, whose outer edge rises from them at most half the way
// across), and the walls stay where they were. A round takes a third of a column's layers: a
// quarter left seeds 10860 and 10903 (26.5 and 18.7 degrees, two holes' layers across a
// narrow gap) below 30 after the three rounds.
TEST(RandomDomains, ASharpTriangleBesideTheLayersLowersTheColumnsAtItsCorners) {
    for (const std::uint64_t seed : {2749u, 3456u, 10860u, 10903u}) {
        const LayeredCase lc = layered_case(seed);
        const MeshResult r = generate_mesh(lc.domain, lc.rc.density, lc.options);
        EXPECT_GT(r.stats.layer_rounds, 0) << seed;
        EXPECT_TRUE(check_mesh(r.mesh, false).empty()) << seed;
        const auto [angle, where] = smallest_free_angle(r.mesh);
        EXPECT_GE(angle, 30.0) << "seed " << seed << " at (" << where.x << ", " << where.y << ")";
        // Against the layers as first grown (without the smoothing, which alone can find a
        // triangle still sharp): few columns more are cut back.
        MeshOptions once = lc.options;
        once.smoothing_iterations = 0;
        const MeshResult first = generate_mesh(lc.domain, lc.rc.density, once);
        EXPECT_EQ(first.stats.layer_rounds, 0) << seed;
        const auto& lowered = r.quality.boundary_layers.front();
        const auto& grown = first.quality.boundary_layers.front();
        EXPECT_LE(lowered.cut_back, grown.cut_back + grown.columns / 10) << seed;
    }
}

// A round of the layers costs a whole mesh: none is begun where one would not fit in the time
// left before the job's limit (Observer::seconds_left, the server's deadline). The mesh made
// is kept, with the layers as first grown, rather than lost to the limit.
TEST(RandomDomains, NoLayersRoundWhereTheTimeLeftWouldNotHoldOne) {
    struct NoTimeLeft : Observer {
        double seconds_left() override { return 0.0; }
    };
    struct PlentyOfTime : Observer {
        double seconds_left() override { return 3600.0; }
    };
    for (const std::uint64_t seed : {2749u, 3456u}) {
        const LayeredCase lc = layered_case(seed);
        NoTimeLeft late;
        const MeshResult r = generate_mesh(lc.domain, lc.rc.density, lc.options, &late);
        EXPECT_EQ(r.stats.layer_rounds, 0) << seed;
        EXPECT_EQ(r.stats.closing_rounds, 0) << seed;
        EXPECT_TRUE(check_mesh(r.mesh, false).empty()) << seed;
        // The layers as first grown: those of the mesh without the smoothing's look.
        MeshOptions once = lc.options;
        once.smoothing_iterations = 0;
        const MeshResult first = generate_mesh(lc.domain, lc.rc.density, once);
        EXPECT_EQ(r.quality.boundary_layers.front().cut_back, first.quality.boundary_layers.front().cut_back) << seed;
        // The same cells where they stand (their corners' numbers can differ: the points the
        // last resort's refinement adds come before the layers' hidden ones).
        auto corners = [](const Mesh& m) {
            std::vector<std::array<Vec2, 4>> out;
            for (const auto& q : m.quads) out.push_back({m.point(q[0]), m.point(q[1]), m.point(q[2]), m.point(q[3])});
            return out;
        };
        EXPECT_TRUE(corners(r.mesh) == corners(first.mesh)) << seed;
        // An observer with time to spare changes nothing.
        PlentyOfTime early;
        EXPECT_GT(generate_mesh(lc.domain, lc.rc.density, lc.options, &early).stats.layer_rounds, 0) << seed;
    }
}

// Where no lowered round leaves every triangle at 30 degrees, the layers are grown once more
// as at first: the user's layers are thinned only where that mends every angle. They are then
// those of a mesh without the smoothing, which grows them once. Seed 12797 (a spoke's free end
// beside another hole's layers) is such a domain; with the defaults its curves are then placed
// again for the triangle of fixed points it leaves (ASharpTriangleOfFixedPointsAlone...), so
// the rounds are seen here without the curves' agreement, which that placing belongs to.
TEST(RandomDomains, LayersNoRoundMendsStandAsFirstGrown) {
    LayeredCase lc = layered_case(12797);
    lc.options.curve_agreement = false;
    const MeshResult r = generate_mesh(lc.domain, lc.rc.density, lc.options);
    EXPECT_EQ(r.stats.layer_rounds, 4);  // three lowered, then as at first
    EXPECT_EQ(r.stats.closing_rounds, 0);
    EXPECT_TRUE(check_mesh(r.mesh, false).empty());
    MeshOptions once = lc.options;
    once.smoothing_iterations = 0;
    const MeshResult first = generate_mesh(lc.domain, lc.rc.density, once);
    const auto& a = r.quality.boundary_layers.front();
    const auto& b = first.quality.boundary_layers.front();
    EXPECT_EQ(a.columns, b.columns);
    EXPECT_EQ(a.cut_back, b.cut_back);
    EXPECT_EQ(a.layers_min, b.layers_min);
    EXPECT_EQ(r.mesh.quads, first.mesh.quads);
}

// Two layered holes close together, their columns radial: columns of the two walls pass
// beside each other at a slant, so the rays (which keep a strip of the local size only along
// each column) left tops of the two walls 0.6 rho apart, joined by triangles of layer tops
// alone. Tops of different walls now keep that strip between them too (seeds 829, 884, 885
// and 412: 18.6, 20.3, 21.8 and 24.1 degrees before).
TEST(RandomDomains, FacingLayersKeepAStripBetweenTheirTops) {
    for (const std::uint64_t seed : {829u, 884u, 885u, 412u}) {
        const LayeredCase lc = layered_case(seed);
        ASSERT_GE(lc.rc.domain.loops.size(), 3u) << seed;  // the outer loop and two holes
        const MeshResult r = generate_mesh(lc.domain, lc.rc.density, lc.options);
        EXPECT_TRUE(check_mesh(r.mesh, false).empty()) << seed;
        EXPECT_GT(r.mesh.quads.size() + static_cast<size_t>(std::count_if(r.mesh.triangles.begin(), r.mesh.triangles.end(),
                                                                            [](const Triangle& t) { return t.layer; })),
                  0u)
            << seed;  // the holes keep layers
        const auto [angle, where] = smallest_free_angle(r.mesh);
        EXPECT_GE(angle, 30.0) << "seed " << seed << " at (" << where.x << ", " << where.y << ")";
    }
}

// A fan planned on the first walls and then placed among walls spaced for it may be cut
// shorter than planned (its neighbours now stand closer), its tops closer together than the
// walls beside it were spaced for: the outer edge then slopes down to it over one long wall
// segment while the interior is capped fine at its tops. The fans are planned again on the
// walls placed for them, and the walls placed again where a fan came out narrower (seeds 83
// and 481 with a polygonal hole: 22.3 and 20.5 degrees before).
TEST(RandomDomains, FansCutShorterThanPlannedAreSpacedForAgain) {
    expect_thirty_degrees_with_layers({83u, 481u});
}

// A fan the first walls left no room for (a polygonal hole's corner whose columns the coarse
// first walls cut back entirely) stands on the walls placed for the other fans: it is planned
// then, and the walls beside it graded down to its tops. Before, the wall's first segment
// beside such a fan was up to 25 times as long as its tops were apart (seeds 358, 960 and
// 222: 21.2, 16.1 and 21.2 degrees).
TEST(RandomDomains, AFanTheFirstWallsCutAwayIsSpacedForOnceItStands) {
    expect_thirty_degrees_with_layers({358u, 960u, 222u});
}

// A short embedded line leaving a layered hole, beside outer-edge segments up to twice its
// length: the corner's triangle, of fixed points alone, had no interior point to mend it, as
// the field beside the line (probed half its length away) was just under 1.5 times its
// length. Such a line now caps the interior around it whatever the field (seeds 503, 767,
// 101 and 293: 22.9, 28.3, 28.5 and 28.1 degrees before).
TEST(RandomDomains, AShortLineLeavingTheLayersGetsInteriorPointsAroundIt) {
    expect_thirty_degrees_with_layers({503u, 767u, 101u, 293u}, true);
}

// A spoke about as short as the layered hole's segments beside its base: the column sliding
// up it took 0.3 of it, and the spoke's free part, the slide column's top and the next
// column's top closed a triangle of fixed points alone with sides 0.85 : 2.4 : 2.4 (seeds 46,
// 203, 87 and 554: 24.8, 26.4, 25.7 and 27.9 degrees). A fixed share of 2/3 of the longer
// wall segment beside the spoke left free did for a spoke square to the wall, not for one at
// 100 degrees or more to it (seeds 1446, 654, 1801, 1381 and 1329: 29.2, 29.1, 29.6, 29.8 and
// 29.9 degrees). The column now leaves free what that triangle needs at the spoke's angle to
// the wall segment on either side, and after the cut-backs loses layers while the triangle
// with its neighbours' actual tops still needs it (a taller neighbour, a free part of two
// segments: seed 1738, 29.3 degrees).
TEST(RandomDomains, AColumnSlidingUpAShortSpokeLeavesFreeWhatTheCornersTriangleNeeds) {
    expect_thirty_degrees_with_layers({46u, 203u, 87u, 554u, 1446u, 654u, 1801u, 1381u, 1329u, 1738u}, true);
}

// A layered side of the outer polygon ending on an unlayered side at 150 degrees or so: its
// end column slid down that side leaning 60 degrees off the wall's normal, its top 1.3 times
// the layers' height from the next column's, and the outer edge between them one segment six
// times the interior's size. Such an end now turns a fan round to the side (seeds 770, 72 and
// 184: 25.4, 25.9 and 25.2 degrees before).
TEST(RandomDomains, AWallEndingOnALineAtABluntAngleFansRoundToIt) {
    expect_thirty_degrees_with_layers({770u, 72u, 184u});
}

// A wall's end column sliding down the line the wall ends on leans along it, up to 30
// degrees off the wall's normal, and under thick layers stands its top 2 H sin(lean / 2) from
// the next column's: 1.4 to 1.9 times the field there, beside the line spaced at the field,
// four triangles of 29.8 degrees at the end's top (seeds 1725, 1811 and 1680). Columns on the
// end's base now fill that gap until the tops are about the field apart.
TEST(RandomDomains, AWallsEndLeaningAlongItsLineGainsColumnsUntilItsTopIsTheFieldFromTheNext) {
    expect_thirty_degrees_with_layers({1725u, 1811u, 1680u});
}

// The fans are planned on walls that are not yet final, and planning them again on the walls
// spaced for them need not settle: a square hole's corner that every plan cut back stood a
// fan on the final walls with tops 613 apart between wall tops 18,000 apart (seed 349). A fan
// the plan lacks now stands no column above its corner (seeds 349, 186 and 784: 26.2, 29.1
// and 28.1 degrees before).
TEST(RandomDomains, AFanNoPlanHadStandsNoColumns) {
    expect_thirty_degrees_with_layers({349u, 186u, 784u});
}

// The curves' agreement with the interior field comes after the fans' plan and caps the field
// beside fine curves: a hole's fan planned 27,000 tall stood 760 on the agreed walls, its tops
// 317 apart beside wall tops 9,000 apart (seed 728). The fans are planned again after the
// agreement (seeds 728 and 82: 24.6 and 16.8 degrees before).
TEST(RandomDomains, FansArePlannedAgainAfterTheCurvesAgreeWithTheField) {
    expect_thirty_degrees_with_layers({728u, 82u});
}

// A wall's columns spread their tops by (R + H) / R on a convex wall: a small circle under
// layers twice its radius thick stood tops 165 apart beside interior triangles of 40 (seed
// 663), and a circle's coarse tops faced a square's fan across a narrow gap (617). Tops more
// than 1.5 times the field apart now cap the wall below them (seeds 663, 617, 201 and 452:
// 26.0, 26.2, 29.1 and 28.9 degrees before).
TEST(RandomDomains, NeighbouringTopsFarApartForTheFieldSpaceTheirWallFiner) {
    expect_thirty_degrees_with_layers({663u, 617u, 201u, 452u});
}

// Layers on a whole outer loop: its tops, drawn together by (R - H) / R on the concave wall,
// stood 1.5 times finer than the field inside. The interior took its first row from them and
// then no point at all (its proposals too close to one another): the isotropic triangles
// inside reached 6.5 times rho (seed 364, a constant density) and 27.3 degrees (429). The
// interior's front now closes on its neighbours there (interior.cpp, close_on).
TEST(RandomDomains, AFrontFinerThanTheFieldStillFillsTheInteriorAtTheField) {
    expect_thirty_degrees_with_layers({364u, 429u});
    const LayeredCase lc = layered_case(364);
    const double* size = std::get_if<double>(&*lc.rc.density.size);
    ASSERT_NE(size, nullptr) << "seed 364's density is no longer constant";
    const MeshResult r = generate_mesh(lc.domain, lc.rc.density, lc.options);
    double longest = 0.0, sum = 0.0;
    size_t edges = 0;
    for (const Triangle& t : r.mesh.triangles) {
        if (t.layer) continue;
        for (std::uint32_t i = 0; i < 3; ++i) {
            const double l = distance(r.mesh.point(t.v[i]), r.mesh.point(t.v[(i + 1) % 3]));
            longest = std::max(longest, l);
            sum += l;
            ++edges;
        }
    }
    // Isotropic triangles at rho: their mean edge within 15% of it, none twice as long.
    EXPECT_NEAR(sum / static_cast<double>(edges), *size, 0.15 * *size);
    EXPECT_LT(longest, 2.0 * *size);
}

// Asking for a smallest angle never makes the smallest angle smaller beside boundary layers:
// with min_angle_deg 28 the first three went from 24.6, 21.1 and 26.4 degrees to 6.8, 2.9 and
// 5.2, the refinement's circumcentres landing next to the layers' column tops, in notches of
// their outer edge that it cannot split; the last from 21.9 to 17.8, an embedded edge split
// beside a point that the refinement left where it was.
TEST(RandomDomains, AskingForASmallestAngleBesideLayersNeverLowersIt) {
    for (const std::uint64_t seed : {83u, 222u, 224u, 225u}) {
        LayeredCase lc = layered_case(seed);
        const double without = smallest_free_angle(generate_mesh(lc.domain, lc.rc.density, lc.options).mesh).first;
        lc.options.min_angle_deg = 28.0;
        const MeshResult r = generate_mesh(lc.domain, lc.rc.density, lc.options);
        EXPECT_TRUE(check_mesh(r.mesh, false).empty()) << seed;
        const auto [with, at] = smallest_free_angle(r.mesh);
        EXPECT_GE(with, without) << "seed " << seed << " at (" << at.x << ", " << at.y << ")";
    }
}

// A fan turns by 30 degrees a step, so its tops stand 0.52 times its height apart: under
// layers several times the field thick, the outer edge across a step was three times the
// field beside it (seed 1234: a fan at a wall's end round to the line it ends on, 28.0
// degrees beside it). The fan gains columns between its own there until its tops are about
// the field apart: every segment of the layers' outer edge is then within twice the target
// size at its ends (it was 3.6 times).
TEST(RandomDomains, AFanUnderLayersThickForTheFieldGainsColumnsUntilItsTopsAreTheFieldApart) {
    expect_thirty_degrees_with_layers({1234u});
    const LayeredCase lc = layered_case(1234);
    const MeshResult r = generate_mesh(lc.domain, lc.rc.density, lc.options);
    const Mesh& m = r.mesh;
    // The outer edge: an isotropic triangle's sides between two layer points.
    double worst = 0.0;
    size_t outer = 0;
    for (const Triangle& t : m.triangles) {
        if (t.layer) continue;
        for (std::uint32_t i = 0; i < 3; ++i) {
            const VertexId a = t.v[i], b = t.v[(i + 1) % 3];
            if (m.kind[a] != PointKind::Layer || m.kind[b] != PointKind::Layer) continue;
            const double ratio = distance(m.point(a), m.point(b)) / (0.5 * (m.target_size[a] + m.target_size[b]));
            worst = std::max(worst, ratio);
            ++outer;
        }
    }
    std::printf("[ seed 1234 ] %zu outer-edge segments, the longest %.2f times the target size\n", outer, worst);
    EXPECT_GT(outer, 50u);
    EXPECT_LT(worst, 2.0);
}
