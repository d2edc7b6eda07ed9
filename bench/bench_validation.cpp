// Parsing and validating requests with many curves: a plate with n x n circular holes, each
// a named point, an arc and a loop. Both stages must grow like n^2 (the number of holes),
// not its square: nlohmann's callback parser and the holes' containment checks did.

#include <benchmark/benchmark.h>

#include <string>

#include "meshd/api/request.hpp"
#include "meshd/core/domain.hpp"

namespace {

std::string plate(int n) {
    std::string points = "\"A\": [0, 0], \"B\": [" + std::to_string(2 * n) + ", 0], \"C\": [" + std::to_string(2 * n) + ", " +
                         std::to_string(2 * n) + "], \"D\": [0, " + std::to_string(2 * n) + "]";
    std::string curves = "\"b\": {\"type\": \"line\", \"from\": \"A\", \"to\": \"B\"}, \"r\": {\"type\": \"line\", \"from\": \"B\", \"to\": \"C\"}, "
                         "\"t\": {\"type\": \"line\", \"from\": \"C\", \"to\": \"D\"}, \"l\": {\"type\": \"line\", \"from\": \"D\", \"to\": \"A\"}";
    std::string loops = "[\"b\", \"r\", \"t\", \"l\"]";
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const std::string h = "h" + std::to_string(i * n + j), x = std::to_string(2 * i + 1), y = std::to_string(2 * j + 1);
            points += ", \"" + h + "\": [" + x + ".3, " + y + "]";
            curves += ", \"" + h + "\": {\"type\": \"arc\", \"from\": \"" + h + "\", \"to\": \"" + h + "\", \"center\": [" + x + ", " + y + "]}";
            loops += ", [\"" + h + "\"]";
        }
    return "{\"geometry\": {\"points\": {" + points + "}, \"curves\": {" + curves + "}, \"loops\": [" + loops +
           "]}, \"density\": {\"size\": 0.1}}";
}

void BM_ParseHoles(benchmark::State& state) {
    const std::string body = plate(static_cast<int>(state.range(0)));
    for (auto _ : state) benchmark::DoNotOptimize(meshd::api::parse_request(body));
    state.counters["holes"] = static_cast<double>(state.range(0) * state.range(0));
    state.SetComplexityN(state.range(0) * state.range(0));
}
BENCHMARK(BM_ParseHoles)->RangeMultiplier(2)->Range(16, 128)->Unit(benchmark::kMillisecond)->Complexity();

void BM_ValidateHoles(benchmark::State& state) {
    const meshd::api::MeshRequest req = meshd::api::parse_request(plate(static_cast<int>(state.range(0))));
    for (auto _ : state) benchmark::DoNotOptimize(meshd::core::build_domain(req.geometry));
    state.counters["holes"] = static_cast<double>(state.range(0) * state.range(0));
    state.SetComplexityN(state.range(0) * state.range(0));
}
BENCHMARK(BM_ValidateHoles)->RangeMultiplier(2)->Range(16, 128)->Unit(benchmark::kMillisecond)->Complexity();

}  // namespace
