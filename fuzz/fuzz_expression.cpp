// A density expression: compiled, then evaluated over a few points. Compilation may refuse
// the text (GeometryError); nothing else may escape, and evaluation never throws.

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>

#include "density/expression.hpp"
#include "meshd/core/errors.hpp"

using namespace meshd::core;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    std::optional<Expression> e;
    try {
        e.emplace(text);
    } catch (const GeometryError&) {
        return 0;
    }
    const double xs[] = {0.0, 1.0, -2.5, 1e-300, 1e300, -0.0};
    double sink = 0.0;
    for (double x : xs)
        for (double y : xs) sink += (*e)(x, y);
    // Copies evaluate alike (the server copies densities between jobs).
    const Expression copy = *e;
    for (double x : xs) {
        const double a = (*e)(x, 0.5), b = copy(x, 0.5);
        if (!(a == b || (a != a && b != b))) {
            std::fprintf(stderr, "a copy evaluates differently: %.17g vs %.17g\n", a, b);
            std::abort();
        }
    }
    (void)sink;
    return 0;
}
