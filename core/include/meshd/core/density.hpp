#pragma once
/// The mesh density function rho (the target edge length) of the paper: given by
/// expressions in x and y, per curve or tag on the boundary, and inside either by an
/// expression or by the paper's inverse-distance interpolation of the boundary segment
/// lengths (eq. 6.1), with lower and upper clamps.

#include <optional>
#include <string>
#include <variant>
#include <vector>


namespace meshd::core {

/// A number or an expression text.
using ScalarSpec = std::variant<double, std::string>;

enum class InteriorMode {
    Default,      ///< `size` when given, else interpolation
    Interpolate,  ///< eq. 6.1
    Expression,   ///< `interior_expression`
};

struct DensitySpec {
    std::optional<ScalarSpec> size;
    /// Curve name or tag -> rho on that curve. A curve's own name wins over its tag.
    std::vector<std::pair<std::string, ScalarSpec>> curves;
    InteriorMode interior = InteriorMode::Default;
    std::optional<std::string> interior_expression;
    /// Largest ratio of neighbouring sizes (> 1): rho is lowered to grow no faster than this.
    std::optional<double> gradation;
    std::optional<double> min, max;
};

}  // namespace meshd::core
