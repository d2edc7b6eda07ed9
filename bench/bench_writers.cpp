// The answer's numbers: the small request's mesh written as JSON (what the load run's
// server writes per request), and a number at a time by the writers' shortest() against
// std::to_chars, on that mesh's coordinates and on doubles uniform in [0, 1).

#include <benchmark/benchmark.h>

#include <charconv>
#include <random>
#include <sstream>
#include <vector>

#include "meshd/api/writers.hpp"
#include "meshd/core/mesher.hpp"
#include "writers/shortest.hpp"

using namespace meshd;

namespace {

const core::MeshResult& small_square_mesh() {
    static const core::MeshResult r = [] {
        core::DomainSpec s;
        s.points = {{"A", {0, 0}}, {"B", {1, 0}}, {"C", {1, 1}}, {"D", {0, 1}}};
        s.curves.push_back({"bottom", core::LineShape{}, "A", "B", std::nullopt});
        s.curves.push_back({"right", core::LineShape{}, "B", "C", std::nullopt});
        s.curves.push_back({"top", core::LineShape{}, "C", "D", std::nullopt});
        s.curves.push_back({"left", core::LineShape{}, "D", "A", std::nullopt});
        s.loops = {{{"bottom", false}, {"right", false}, {"top", false}, {"left", false}}};
        core::DensitySpec density;
        density.size = "0.016 + 0.01 * x";
        return core::generate_mesh(core::build_domain(s), density, core::MeshOptions{});
    }();
    return r;
}

void BM_JsonAnswer(benchmark::State& state) {
    const core::MeshResult& r = small_square_mesh();
    size_t bytes = 0;
    for (auto _ : state) {
        std::ostringstream os;
        api::write_json(r, os);
        bytes = os.str().size();
        benchmark::DoNotOptimize(bytes);
    }
    state.counters["bytes"] = static_cast<double>(bytes);
}
BENCHMARK(BM_JsonAnswer)->Unit(benchmark::kMicrosecond);

std::vector<double> numbers(bool coordinates) {
    std::vector<double> v;
    if (coordinates) {
        const core::Mesh& m = small_square_mesh().mesh;
        v.insert(v.end(), m.x.begin(), m.x.end());
        v.insert(v.end(), m.y.begin(), m.y.end());
    } else {
        std::mt19937_64 rng(1);
        std::uniform_real_distribution<double> u(0.0, 1.0);
        v.resize(1 << 16);
        for (double& x : v) x = u(rng);
    }
    return v;
}

template <bool kOurs>
void BM_Number(benchmark::State& state) {
    const std::vector<double> v = numbers(state.range(0) != 0);
    char buf[api::writers::kShortestMax];
    size_t chars = 0;
    for (auto _ : state) {
        for (const double x : v)
            chars += static_cast<size_t>(
                (kOurs ? api::writers::shortest(buf, x) : std::to_chars(buf, buf + sizeof buf, x).ptr) - buf);
        benchmark::DoNotOptimize(chars);
    }
    state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * v.size()));
}
// Argument 1: the mesh's coordinates; 0: uniform doubles.
BENCHMARK_TEMPLATE(BM_Number, true)->Arg(1)->Arg(0);
BENCHMARK_TEMPLATE(BM_Number, false)->Arg(1)->Arg(0);

}  // namespace
