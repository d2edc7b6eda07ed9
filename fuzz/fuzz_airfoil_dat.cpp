// An airfoil file (.dat, Selig or Lednicer): parsed, and when it parses, made into the curve
// meshd would mesh and evaluated along it. BadAirfoil (a GeometryError) is the only refusal.

#include <cstdint>
#include <cstdio>
#include <cmath>
#include <cstdlib>
#include <string>
#include <string_view>

#include "geometry/curve.hpp"
#include "meshd/core/errors.hpp"

using namespace meshd::core;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    try {
        const AirfoilPoints pts = parse_airfoil_dat(text);
        for (TrailingEdge te : {TrailingEdge::Open, TrailingEdge::Closed}) {
            AirfoilSpec spec;
            spec.coordinates = std::string(text);
            spec.trailing_edge = te;
            const std::unique_ptr<Curve> c = make_airfoil(spec);
            for (int i = 0; i <= 64; ++i) {
                const double t = c->t_begin() + (c->t_end() - c->t_begin()) * i / 64.0;
                const Vec2 p = c->point(t);
                if (!std::isfinite(p.x) || !std::isfinite(p.y)) {
                    std::fprintf(stderr, "not finite at t = %g\n", t);
                    std::abort();
                }
            }
        }
        (void)pts;
    } catch (const GeometryError&) {
    }
    return 0;
}
