// A request body, as the server would get it: parsed, validated, its size forecast, and when
// the forecast is small, meshed, the mesh held to check_mesh. Any answer but a 4xx problem
// (a 500, an escaped exception, a broken mesh) or a sanitizer report is a finding; so is a
// hang (libFuzzer's -timeout), a mesh that comes out different without the interior's
// crossing proof (InteriorOptions::crossing_proof) where the proof was used, and a segment
// the proof passed over that its premise does not cover (InteriorOptions::check_crossing_proof).

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string_view>

#include "meshd/api/problem.hpp"
#include "meshd/api/request.hpp"
#include "meshd/core/mesher.hpp"
#include "pipeline/estimate.hpp"

using namespace meshd;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view body(reinterpret_cast<const char*>(data), size);
    try {
        api::MeshRequest req = api::parse_request(body);
        const core::Domain domain = core::build_domain(req.geometry);
        core::ForecastBudget budget;
        budget.boundary_samples = 2048;
        budget.interior_samples = 4096;
        const core::PointForecast f = core::forecast_points(domain, req.density, budget);
        if (f.total() < 3000.0) {
            core::MeshOptions o = req.options;
            o.max_points = 6000;  // what the forecast missed stops here
            if (o.min_angle_deg > 0.0) o.min_angle_deg = std::min(o.min_angle_deg, 25.0);
            const core::MeshResult r = core::generate_mesh(domain, req.density, o);
            const auto broken = core::check_mesh(r.mesh, o.min_angle_deg == 0.0 && o.smoothing_iterations == 0);
            if (!broken.empty()) {
                std::fprintf(stderr, "broken mesh: %s\n", broken.front().c_str());
                std::abort();
            }
            if (r.stats.interior.crossings_proven > 0 || r.stats.interior.blocks_proven > 0) {
                if (r.stats.interior.blocks_proven > 0) {
                    // Every segment the block-by-block proof passed over, against its premise.
                    o.interior.check_crossing_proof = true;
                    const core::MeshResult checked = core::generate_mesh(domain, req.density, o);
                    if (checked.stats.interior.proof_violations != 0) {
                        std::fprintf(stderr, "a segment the crossing proof passed over is not covered by its premise\n");
                        std::abort();
                    }
                    o.interior.check_crossing_proof = false;
                }
                o.interior.crossing_proof = false;
                const core::MeshResult whole = core::generate_mesh(domain, req.density, o);
                bool same = whole.mesh.point_count() == r.mesh.point_count() &&
                            whole.mesh.triangles.size() == r.mesh.triangles.size();
                for (size_t i = 0; same && i < r.mesh.point_count(); ++i)
                    same = whole.mesh.x[i] == r.mesh.x[i] && whole.mesh.y[i] == r.mesh.y[i];
                for (size_t t = 0; same && t < r.mesh.triangles.size(); ++t)
                    same = whole.mesh.triangles[t].v == r.mesh.triangles[t].v;
                if (!same) {
                    std::fprintf(stderr, "the crossing proof changed the mesh\n");
                    std::abort();
                }
            }
        }
    } catch (...) {
        std::string log;
        const api::Problem p = api::problem_of(std::current_exception(), &log);
        if (p.status >= 500) {
            std::fprintf(stderr, "status %d: %s\n", p.status, log.c_str());
            std::abort();
        }
    }
    return 0;
}
