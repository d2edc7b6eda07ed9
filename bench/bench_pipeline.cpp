// The whole pipeline on the small request of the load run (bench/load/small_square.json: a
// unit square, size 0.016 + 0.01 x, about 2,500 points): what a small request costs besides
// HTTP and JSON, stage by stage (counters in ms; "boundary" includes the admission forecast
// and the estimate).

#include <benchmark/benchmark.h>
#include <malloc.h>

#include "meshd/core/mesher.hpp"
#include "triangulation/triangulation.hpp"

using namespace meshd::core;

namespace {

Domain small_square() {
    DomainSpec s;
    s.points = {{"A", {0, 0}}, {"B", {1, 0}}, {"C", {1, 1}}, {"D", {0, 1}}};
    s.curves.push_back({"bottom", LineShape{}, "A", "B", std::nullopt});
    s.curves.push_back({"right", LineShape{}, "B", "C", std::nullopt});
    s.curves.push_back({"top", LineShape{}, "C", "D", std::nullopt});
    s.curves.push_back({"left", LineShape{}, "D", "A", std::nullopt});
    s.loops = {{{"bottom", false}, {"right", false}, {"top", false}, {"left", false}}};
    return build_domain(s);
}

void BM_SmallRequest(benchmark::State& state) {
    const Domain domain = small_square();
    DensitySpec density;
    density.size = "0.016 + 0.01 * x";
    MeshOptions options;
    // The server's allocator settings (server/src/main.cpp): freed memory kept for the next
    // job. Without them each run here would fault in its larger arrays afresh, which the
    // server's jobs do not.
    mallopt(M_MMAP_THRESHOLD, 32 << 20);
    mallopt(M_TRIM_THRESHOLD, 64 << 20);
    StageTimings sum{};
    size_t points = 0;
    for (auto _ : state) {
        const MeshResult r = generate_mesh(domain, density, options);
        points = r.mesh.point_count();
        sum.boundary_ms += r.timings.boundary_ms;
        sum.interior_ms += r.timings.interior_ms;
        sum.triangulation_ms += r.timings.triangulation_ms;
        sum.smoothing_ms += r.timings.smoothing_ms;
    }
    const double n = static_cast<double>(state.iterations());
    state.counters["points"] = static_cast<double>(points);
    state.counters["boundary_ms"] = sum.boundary_ms / n;
    state.counters["interior_ms"] = sum.interior_ms / n;
    state.counters["triangulation_ms"] = sum.triangulation_ms / n;
    state.counters["smoothing_ms"] = sum.smoothing_ms / n;
}
BENCHMARK(BM_SmallRequest)->Unit(benchmark::kMillisecond);

// The triangulation stage alone on the small request's points (as smoothed) and its boundary
// edges: the constrained Delaunay triangulation of about 2,500 points that all fit in cache.
void BM_SmallTriangulation(benchmark::State& state) {
    DensitySpec density;
    density.size = "0.016 + 0.01 * x";
    const MeshResult r = generate_mesh(small_square(), density, MeshOptions{});
    std::vector<Vec2> points;
    for (std::uint32_t v = 0; v < r.mesh.point_count(); ++v) points.push_back(r.mesh.point(v));
    std::vector<Constraint> constraints;
    for (const MeshEdge& e : r.mesh.edges) constraints.push_back({e.a, e.b, !e.embedded});
    TriangulationStats stats{};
    for (auto _ : state) {
        TriangulationResult t = triangulate_delaunay(points, constraints, nullptr);
        stats = t.stats;
        benchmark::DoNotOptimize(t.triangles.data());
    }
    state.counters["points"] = static_cast<double>(points.size());
    state.counters["flips_per_point"] = static_cast<double>(stats.flips) / static_cast<double>(points.size());
    state.counters["walk_per_point"] = static_cast<double>(stats.walk_steps) / static_cast<double>(points.size());
    state.counters["us_per_point"] = benchmark::Counter(static_cast<double>(points.size()),
                                                        benchmark::Counter::kIsIterationInvariantRate |
                                                            benchmark::Counter::kInvert);
}
BENCHMARK(BM_SmallTriangulation)->Unit(benchmark::kMicrosecond);

}  // namespace
