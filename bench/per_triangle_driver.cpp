// What a triangle costs in one request against another, the two meshed in turn in one
// process (issue 15: eq. 6.1 within 1.5 times an expression per triangle). Usage:
//   meshd_per_triangle BASE.json OTHER.json [RUNS]
// e.g. examples/naca0012.json examples/fig9.json 16. Alternating keeps both in the same
// minutes of a virtual machine whose speed drifts; the least of the runs is the figure least
// disturbed by other load, the median the typical one. Prints, per request, the least and the
// median time of each stage and of the whole pipeline, and the ratios of OTHER's time per
// triangle to BASE's, least against least and median against median.

#include <malloc.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "meshd/api/request.hpp"
#include "meshd/core/domain.hpp"
#include "meshd/core/mesher.hpp"

using namespace meshd;

namespace {

struct Request {
    std::string name;
    api::MeshRequest req;
    core::Domain domain;
    size_t triangles = 0;
    std::vector<std::vector<double>> times;  // per run: total, boundary, interior, triangulation, smoothing
};

Request load(const char* path) {
    std::ifstream in(path);
    std::stringstream ss;
    ss << in.rdbuf();
    std::string name = path;
    if (const auto slash = name.rfind('/'); slash != std::string::npos) name = name.substr(slash + 1);
    api::MeshRequest req = api::parse_request(ss.str());
    core::Domain domain = core::build_domain(req.geometry);
    return {name, std::move(req), std::move(domain), 0, {}};
}

void run(Request& r) {
    const core::MeshResult m = core::generate_mesh(r.domain, r.req.density, r.req.options);
    r.triangles = m.mesh.triangles.size();
    const core::StageTimings& t = m.timings;
    r.times.push_back({t.total_ms, t.boundary_ms, t.interior_ms, t.triangulation_ms, t.smoothing_ms});
}

double least(std::vector<double> v) { return *std::min_element(v.begin(), v.end()); }

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::vector<double> column(const Request& r, size_t k) {
    std::vector<double> out;
    for (const auto& t : r.times) out.push_back(t[k]);
    return out;
}

void report(const Request& r) {
    static const char* stages[] = {"total", "boundary", "interior", "triangulation", "smoothing"};
    std::printf("%s: %zu triangles, %zu runs\n", r.name.c_str(), r.triangles, r.times.size());
    for (size_t k = 0; k < 5; ++k)
        std::printf("  %-14s least %8.2f ms  median %8.2f ms\n", stages[k], least(column(r, k)), median(column(r, k)));
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: %s BASE.json OTHER.json [RUNS]\n", argv[0]);
        return 2;
    }
    const int runs = argc > 3 ? std::max(1, std::atoi(argv[3])) : 16;
    // The server's allocator settings (server/src/main.cpp), as in bench_pipeline.cpp.
    mallopt(M_MMAP_THRESHOLD, 32 << 20);
    mallopt(M_TRIM_THRESHOLD, 64 << 20);
    Request base = load(argv[1]), other = load(argv[2]);
    for (int i = 0; i < runs; ++i) {
        run(base);
        run(other);
    }
    report(base);
    report(other);
    auto per_triangle = [](const Request& r, double ms) { return ms / static_cast<double>(r.triangles); };
    const std::vector<double> b = column(base, 0), o = column(other, 0);
    std::printf("%s per triangle against %s: %.2fx least against least, %.2fx median against median\n",
                other.name.c_str(), base.name.c_str(), per_triangle(other, least(o)) / per_triangle(base, least(b)),
                per_triangle(other, median(o)) / per_triangle(base, median(b)));
}
