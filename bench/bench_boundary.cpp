// Boundary generation and the interior density (eq. 6.1): size sweeps with complexity fits.
//
// - BM_SpacingInterval: Lo's spacing on [0, 1] alone, uniform rho, n points.
// - BM_CircleBoundary: one full circle, uniform rho, n points: the floor cost per point of the
//   point generator (density samples, march, mapping onto the curve).
// - BM_AirfoilBoundary: NACA 0012 in a far field with the paper's Fig. 10 density divided by
//   a scale factor, so the point count grows as the factor: graded, with a numerical
//   arc-length inversion per point; the case of the product.
// - BM_InverseDistance<M>: eq. 6.1 queries against the boundary of the previous case: <0> as
//   the pipeline asks (term by term up to kDirectSources sources), <1> the naive scalar sum,
//   <2> the treecode.
// - BM_InterpolatedField<C>: eq. 6.1 as the pipeline asks it on examples/fig9.json's domain
//   (378 sources, through the query cells): at the midpoints of the mesh's edges, in the
//   order measure_quality asks them (neighbours one after another), per query. <0> the
//   field alone, <1> after the curves' agreement, as the pipeline has it (the curves placed
//   again and the interior capped by cones from the boundary points).

#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>
#include <random>

#include "boundary/boundary.hpp"
#include "density/size_field.hpp"
#include "meshd/core/mesher.hpp"
#include "pipeline/agreement.hpp"
#include "boundary/spacing.hpp"
#include "naca_case.hpp"

using namespace meshd::core;

namespace {

DomainSpec circle_domain() {
    DomainSpec s;
    s.points = {{"P", {1.0, 0.0}}};
    s.curves.push_back({"c", ArcShape{{0.0, 0.0}, ArcDirection::Ccw}, "P", "P", std::nullopt});
    s.loops = {{{"c", false}}};
    return s;
}

// The timed loop of the boundary benchmarks, with the point count and rate as counters.
void discretise_repeatedly(benchmark::State& state, const Domain& dom, const SizeField& rho) {
    size_t points = 0;
    for (auto _ : state) {
        const Discretisation d = discretise_boundary(dom, rho);
        points = d.size();
        benchmark::DoNotOptimize(d.x.data());
    }
    state.SetComplexityN(static_cast<int64_t>(points));
    state.counters["points"] = static_cast<double>(points);
    state.counters["points/s"] = benchmark::Counter(static_cast<double>(points) * state.iterations(),
                                                    benchmark::Counter::kIsRate);
}

void BM_CircleBoundary(benchmark::State& state) {
    const Domain dom = build_domain(circle_domain());
    DensitySpec spec;
    spec.size = 2 * std::numbers::pi / static_cast<double>(state.range(0));
    SizeField rho(spec, dom);
    discretise_repeatedly(state, dom, rho);
}
// Lo's spacing on an interval alone (boundary/spacing.hpp), uniform rho, n points: samples
// of rho and the march, without a curve.
void BM_SpacingInterval(benchmark::State& state) {
    const double h = 1.0 / static_cast<double>(state.range(0));
    size_t points = 0, calls = 0;
    for (auto _ : state) {
        calls = 0;
        const DensityProfile prof = sample_density(1.0, [&](double) { ++calls; return h; }, 1e-12, size_t{1} << 26);
        const std::vector<double> x = graded_stations(prof);
        points = x.size();
        benchmark::DoNotOptimize(x.data());
    }
    state.SetComplexityN(static_cast<int64_t>(points));
    state.counters["samples_per_point"] = static_cast<double>(calls) / static_cast<double>(points);
}
BENCHMARK(BM_SpacingInterval)->RangeMultiplier(10)->Range(1000, 1000000)->Unit(benchmark::kMillisecond)->Complexity(benchmark::oN);

BENCHMARK(BM_CircleBoundary)->RangeMultiplier(10)->Range(1000, 1000000)->Unit(benchmark::kMillisecond)->Complexity(benchmark::oN);

void BM_AirfoilBoundary(benchmark::State& state) {
    const Domain dom = build_domain(meshd::bench::naca_case_domain());
    DensitySpec spec;
    const double scale = 1.0 / static_cast<double>(state.range(0));
    spec.size = meshd::bench::naca_case_density(scale);
    spec.min = 1e-9;
    SizeField rho(spec, dom);
    discretise_repeatedly(state, dom, rho);
}
BENCHMARK(BM_AirfoilBoundary)->RangeMultiplier(10)->Range(1, 10000)->Unit(benchmark::kMillisecond)->Complexity(benchmark::oN);

// kMode 0: as the pipeline asks (term by term below kDirectSources), 1: the naive scalar
// sum, 2: the treecode.
template <int kMode>
void BM_InverseDistance(benchmark::State& state) {
    const Domain dom = build_domain(meshd::bench::naca_case_domain());
    DensitySpec spec;
    spec.size = meshd::bench::naca_case_density(1.0 / static_cast<double>(state.range(0)));
    SizeField rho(spec, dom);
    const Discretisation d = discretise_boundary(dom, rho);
    std::vector<Vec2> a;
    std::vector<double> len;
    for (const auto& s : d.segments) {
        a.push_back(d.point(s.a));
        len.push_back(distance(d.point(s.a), d.point(s.b)));
    }
    const InverseDistanceField field(a, len);
    std::mt19937_64 rng(1);
    std::uniform_real_distribution<double> u(-1.0, 2.0);
    std::vector<Vec2> probes(1024);
    for (auto& p : probes) p = {u(rng), 0.5 * u(rng)};
    size_t i = 0;
    for (auto _ : state) {
        const Vec2 p = probes[i++ & 1023];
        benchmark::DoNotOptimize(kMode == 0 ? field(p) : kMode == 1 ? field.exact(p) : field.treecode(p));
    }
    state.SetComplexityN(static_cast<int64_t>(a.size()));
    state.counters["sources"] = static_cast<double>(a.size());
}
BENCHMARK_TEMPLATE(BM_InverseDistance, 0)->RangeMultiplier(10)->Range(1, 1000);
BENCHMARK_TEMPLATE(BM_InverseDistance, 1)->RangeMultiplier(10)->Range(1, 100)->Complexity(benchmark::oN);
BENCHMARK_TEMPLATE(BM_InverseDistance, 2)->RangeMultiplier(10)->Range(1, 1000)->Complexity(benchmark::oLogN);

template <int kAgreed>
void BM_InterpolatedField(benchmark::State& state) {
    // examples/fig9.json: NACA 0012 in a far field of radius 5, eq. 6.1 inside.
    const Domain dom = build_domain(meshd::bench::naca_case_domain(5.0));
    DensitySpec density;
    density.curves = {{"farfield", std::string("0.4*sqrt(x^2+y^2)+0.2")},
                      {"wing", std::string("0.05*sqrt((x+0.01)^2+y^2)")}};
    density.interior = InteriorMode::Interpolate;
    density.min = 0.002;
    const MeshResult mesh = generate_mesh(dom, density);
    const Mesh& m = mesh.mesh;
    std::vector<Vec2> mid;
    for (TriangleId t = 0; t < m.triangles.size(); ++t)
        for (std::uint32_t i = 0; i < 3; ++i) {
            const Triangle& T = m.triangles[t];
            if (T.n[i] != kNoTriangle && T.n[i] < t) continue;
            mid.push_back(0.5 * (m.point(T.v[(i + 1) % 3]) + m.point(T.v[(i + 2) % 3])));
        }
    SizeField rho(density, dom);
    Discretisation d = discretise_boundary(dom, rho);
    set_interpolation_sources(rho, d);
    if (kAgreed) agree_with_interior(dom, rho, BoundaryOptions{}, d);
    std::vector<double> out(mid.size());
    rho.interior(mid.data(), mid.size(), out.data());  // the query cells made
    for (auto _ : state) {
        rho.interior(mid.data(), mid.size(), out.data());
        benchmark::DoNotOptimize(out.data());
    }
    state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * mid.size()));
    state.counters["queries"] = static_cast<double>(mid.size());
}
BENCHMARK_TEMPLATE(BM_InterpolatedField, 0)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_InterpolatedField, 1)->Unit(benchmark::kMillisecond);

}  // namespace
