// meshd-cli: meshes a request file offline, with the same core and api as the server.
//
//   meshd-cli REQUEST.json [-o OUT] [--format json|vtk|su2|msh|cgns|foam|svg] [--view X0,Y0,X1,Y1] [--quiet]
//
// The format comes from --format, else from the extension of OUT, else json. Without -o the
// mesh goes to standard output. Metrics and, on a terminal, a progress bar go to stderr.
// Exit status: 0 done, 1 usage, 2 the request is malformed, 3 it describes no valid domain or
// density (the problem is printed as JSON), 4 internal error, 5 cancelled by the timeout.

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

#include "meshd/api/problem.hpp"
#include "meshd/api/request.hpp"
#include "meshd/api/writers.hpp"

namespace {

using namespace meshd;

void usage() {
    std::fprintf(stderr,
                 "usage: meshd-cli REQUEST.json [-o OUT] [--format json|vtk|su2|msh|cgns|foam|svg] [--view X0,Y0,X1,Y1] [--quiet]\n"
                 "Meshes the request (see docs/api.md) and writes the mesh; '-' reads standard input.\n"
                 "--view draws only that window of the plane (svg).\n");
}

class Progress : public core::Observer {
public:
    Progress(bool tty, std::optional<double> timeout_s) : tty_(tty) {
        if (timeout_s) deadline_ = std::chrono::steady_clock::now() + std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(*timeout_s));
    }
    void on_progress(core::Stage stage, double fraction) override {
        if (!tty_) return;
        const auto now = std::chrono::steady_clock::now();
        if (stage == last_stage_ && now - last_ < std::chrono::milliseconds(100)) return;
        last_ = now;
        last_stage_ = stage;
        const int width = 30, done = static_cast<int>(fraction * width);
        std::fprintf(stderr, "\r%-13s [%s%s] %3d%%", core::to_string(stage), std::string(static_cast<size_t>(done), '#').c_str(),
                     std::string(static_cast<size_t>(width - done), ' ').c_str(), static_cast<int>(fraction * 100));
        std::fflush(stderr);
    }
    bool should_stop() override { return deadline_ && std::chrono::steady_clock::now() > *deadline_; }
    void finish() {
        if (tty_) std::fprintf(stderr, "\r%60s\r", "");
    }

private:
    bool tty_;
    std::optional<std::chrono::steady_clock::time_point> deadline_;
    std::chrono::steady_clock::time_point last_{};
    core::Stage last_stage_ = core::Stage::Quality;
};

}  // namespace

int main(int argc, char** argv) {
    std::string input, output, format_name;
    bool quiet = false;
    std::optional<core::Box> view;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if ((a == "-o" || a == "--output") && i + 1 < argc) output = argv[++i];
        else if (a == "--format" && i + 1 < argc) format_name = argv[++i];
        else if (a == "--quiet" || a == "-q") quiet = true;
        else if (a == "--view" && i + 1 < argc) {
            double v[4];
            if (std::sscanf(argv[++i], "%lf,%lf,%lf,%lf", &v[0], &v[1], &v[2], &v[3]) != 4 || !(v[2] > v[0]) || !(v[3] > v[1])) {
                std::fprintf(stderr, "meshd-cli: --view wants X0,Y0,X1,Y1 with X1 > X0 and Y1 > Y0\n");
                return 1;
            }
            core::Box b;
            b.add(core::Vec2{v[0], v[1]});
            b.add(core::Vec2{v[2], v[3]});
            view = b;
        }
        else if (a == "-h" || a == "--help") { usage(); return 0; }
        else if (input.empty()) input = a;
        else { usage(); return 1; }
    }
    if (input.empty()) { usage(); return 1; }
    if (format_name.empty() && !output.empty()) {
        const auto dot = output.rfind('.');
        if (dot != std::string::npos) format_name = output.substr(dot + 1);
    }
    if (format_name.empty()) format_name = "json";
    const auto format = api::parse_format(format_name);
    if (!format) {
        std::fprintf(stderr, "meshd-cli: unknown format \"%s\" (%s)\n", format_name.c_str(), api::format_list().c_str());
        return 1;
    }
    std::string body;
    {
        std::ostringstream ss;
        if (input == "-") {
            ss << std::cin.rdbuf();
        } else {
            std::ifstream f(input, std::ios::binary);
            if (!f) { std::fprintf(stderr, "meshd-cli: cannot read %s\n", input.c_str()); return 1; }
            ss << f.rdbuf();
        }
        body = ss.str();
    }
    try {
        const api::MeshRequest req = api::parse_request(body);
        if (req.options.order == 2)
            if (auto why = api::second_order_refusal(*format)) {
                std::fprintf(stderr, "%s\n",
                             api::Problem{422, "/v1/problems/format-cannot-hold-order", "Format cannot hold this mesh", *why,
                                          "/options/order"}
                                 .to_json()
                                 .c_str());
                return 3;
            }
        Progress progress(!quiet && isatty(2), req.timeout_s);
        const core::MeshResult r = core::generate_mesh(req.geometry, req.density, req.options, &progress);
        progress.finish();
        auto write = [&](std::ostream& os) {
            if (*format == api::Format::Svg) api::write_svg(r, os, view);
            else api::write_mesh(*format, r, os, req.foam);
        };
        if (output.empty()) {
            write(std::cout);
            std::cout.flush();
        } else {
            std::ofstream f(output, std::ios::binary);
            if (!f) { std::fprintf(stderr, "meshd-cli: cannot write %s\n", output.c_str()); return 1; }
            write(f);
            if (!f) { std::fprintf(stderr, "meshd-cli: writing %s failed\n", output.c_str()); return 1; }
        }
        if (!quiet) {
            const auto& q = r.quality;
            const std::string quads = q.quads ? ", " + std::to_string(q.quads) + " quads" : "";
            std::fprintf(stderr,
                         "%zu points (%zu boundary), %zu triangles%s; angles %.1f..%.1f deg; radius ratio min %.3f "
                         "mean %.4f; edges within sqrt2 of rho %.4f; %.1f ms (boundary %.1f, interior %.1f, "
                         "triangulation %.1f, smoothing %.1f)%s%s\n",
                         q.points, q.boundary_points, q.triangles, quads.c_str(), q.angle_min, q.angle_max, q.quality_min,
                         q.quality_mean, q.size_ratio_within_sqrt2, r.timings.total_ms, r.timings.boundary_ms,
                         r.timings.interior_ms, r.timings.triangulation_ms, r.timings.smoothing_ms,
                         output.empty() ? "" : " -> ", output.c_str());
        }
        return 0;
    } catch (...) {
        const api::Problem p = api::problem_of(std::current_exception());
        if (api::is_cancellation(p)) {
            std::fprintf(stderr, "meshd-cli: stopped by the timeout\n");
            return 5;
        }
        std::fprintf(stderr, "%s\n", p.to_json().c_str());
        return p.status == 400 ? 2 : (p.status >= 500 ? 4 : 3);
    }
}
