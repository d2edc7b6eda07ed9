// How close the forecast of a mesh's size (pipeline/estimate.hpp) comes to the mesh, and
// what admission costs. Usage: meshd_forecast_report REQUEST.json...
// For each request: parsing, validation and forecast times, the forecast (and its boundary
// part), its samples, the estimate after the boundary stage, the points of the mesh made (or
// the refusal), and the ratios. FORECAST_SAMPLES sets the interior budget.

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include "boundary/boundary.hpp"
#include "meshd/api/request.hpp"
#include "meshd/core/domain.hpp"
#include "meshd/core/errors.hpp"
#include "meshd/core/mesher.hpp"
#include "pipeline/agreement.hpp"
#include "pipeline/estimate.hpp"

using namespace meshd;
using Clock = std::chrono::steady_clock;

namespace {

double ms_since(Clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

}  // namespace

int main(int argc, char** argv) {
    std::setvbuf(stdout, nullptr, _IOLBF, 0);
    std::printf("%-22s %8s %8s %8s %12s %10s %7s %10s %10s %7s %7s\n", "request", "parse", "domain", "forecast",
                "forecast", "(boundary)", "samples", "after-bdy", "points", "f/n", "a/n");
    std::printf("%-22s %8s %8s %8s\n", "", "ms", "ms", "ms");
    for (int i = 1; i < argc; ++i) {
        std::ifstream in(argv[i]);
        std::stringstream ss;
        ss << in.rdbuf();
        std::string name = argv[i];
        if (const auto slash = name.rfind('/'); slash != std::string::npos) name = name.substr(slash + 1);
        auto t0 = Clock::now();
        const api::MeshRequest req = api::parse_request(ss.str());
        const double parse_ms = ms_since(t0);
        t0 = Clock::now();
        const core::Domain dom = core::build_domain(req.geometry);
        const double domain_ms = ms_since(t0);
        core::ForecastBudget budget;
        if (const char* b = std::getenv("FORECAST_SAMPLES")) budget.interior_samples = std::stoul(b);
        t0 = Clock::now();
        const core::PointForecast f = core::forecast_points(dom, req.density, budget);
        const double forecast_ms = ms_since(t0);
        std::printf("%-22s %8.2f %8.2f %8.2f %12.4g %10.4g %7zu", name.c_str(), parse_ms, domain_ms, forecast_ms,
                    f.total(), f.boundary, f.boundary_samples + f.interior_samples);
        const double limit = req.options.max_points ? static_cast<double>(req.options.max_points) : 5e6;
        if (f.total() > limit) {
            std::printf(" %10s %10s\n", "-", "refused");
            continue;
        }
        try {
            core::SizeField rho(req.density, dom);
            core::Discretisation d = core::discretise_boundary(dom, rho);
            if (rho.interpolates()) core::set_interpolation_sources(rho, d);
            core::agree_with_interior(dom, rho, {}, d);  // as the pipeline does
            const double after = core::estimate_point_count(d, core::triangulate_boundary(d), rho);
            const core::MeshResult r = core::generate_mesh(dom, req.density, req.options);
            const double n = static_cast<double>(r.mesh.point_count());
            std::printf(" %10.0f %10.0f %7.3f %7.3f\n", after, n, f.total() / n, after / n);
        } catch (const core::GeometryError& e) {
            std::printf(" %10s %10s  (%s)\n", "-", "error", e.what());
        }
    }
}
