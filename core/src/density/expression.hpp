#pragma once
// Density expressions: parsed and compiled once, evaluated at many points.

#include <cstddef>
#include <memory>
#include <string>

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
    /// out[i] = (*this)(x[i], y[i]) for i < n, to the bit, with the machine's dispatch paid
    /// once per instruction for a batch of points instead of once per point.
    void evaluate(const double* x, const double* y, double* out, size_t n) const;
    const std::string& text() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace meshd::core
