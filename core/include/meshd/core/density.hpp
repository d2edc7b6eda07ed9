#pragma once
/// The mesh density function rho (the target edge length) of the paper: given by
/// expressions in x and y, per curve or tag on the boundary, and inside either by an
/// expression or by the paper's inverse-distance interpolation of the boundary segment
/// lengths (eq. 6.1), with lower and upper clamps.

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "meshd/core/domain.hpp"
#include "meshd/core/errors.hpp"
#include "meshd/core/gradation.hpp"
#include "meshd/core/idw.hpp"

namespace meshd::core {

/// A compiled expression in x and y: numbers, x, y, _pi, _e, operators + - * / ^ (right
/// associative, above unary minus: -x^2 = -(x^2)), comparisons < > <= >= == != (1 or 0),
/// && ||, c ? a : b, and the functions sqrt abs exp log (natural) ln log2 log10 sin cos tan
/// asin acos atan sinh cosh tanh floor ceil rint sign pow atan2, and min max sum avg of one
/// or more arguments. Compiled to a small stack machine with constants folded; evaluation
/// keeps no state, so one object may be shared between threads.
class Expression {
public:
    /// Throws GeometryError(DensityExpression) naming what is wrong and where.
    explicit Expression(const std::string& text);
    Expression(const Expression& other);
    Expression& operator=(const Expression& other);
    Expression(Expression&&) noexcept;
    Expression& operator=(Expression&&) noexcept;
    ~Expression();

    double operator()(double x, double y) const;
    const std::string& text() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

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
    /// Largest ratio of neighbouring sizes (> 1); applied by the interior stage (Core II).
    std::optional<double> gradation;
    std::optional<double> min, max;
};

/// rho over a domain. Not thread-safe (expressions carry evaluation state): one per job.
class SizeField {
public:
    /// Compiles and checks the spec against the domain: every used curve must get a density,
    /// every per-curve key must name a curve or a tag. Throws GeometryError.
    SizeField(const DensitySpec& spec, const Domain& domain);

    /// rho at a point of curve c, clamped to [min, max]. Throws DensityInvalid when the raw
    /// value is not finite and positive.
    double on_curve(CurveId c, Vec2 p) const;

    /// rho inside the domain. In interpolation mode set_boundary_segments() must come first.
    double interior(Vec2 p) const;

    bool interpolates() const { return interpolate_; }
    /// Sources of eq. 6.1: the start A_i of each boundary segment and its length rho_i.
    void set_boundary_segments(std::vector<Vec2> starts, std::vector<double> lengths);

    /// Limits the field (on curves and inside) to the gradation envelope over these samples
    /// (gradation.hpp).
    void set_gradation_sources(std::vector<Vec2> points, std::vector<double> sizes);
    bool graded() const { return graded_ != nullptr; }

    double min_size() const { return min_; }
    double max_size() const { return max_; }
    std::optional<double> gradation() const { return gradation_; }

private:
    struct Source {
        std::optional<double> constant;
        std::optional<Expression> expr;
        Subject subject;  // where it came from, for error messages
    };
    double eval(const Source& s, Vec2 p) const;

    std::vector<std::optional<size_t>> curve_source_;  // per curve: index into sources_
    std::vector<Source> sources_;
    std::optional<size_t> size_source_, interior_source_;
    bool interpolate_ = false;
    std::unique_ptr<InverseDistanceField> idw_;
    std::unique_ptr<GradationField> graded_;
    double min_ = 0.0, max_ = 0.0;
    std::optional<double> gradation_;
};

}  // namespace meshd::core
