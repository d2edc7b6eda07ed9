#pragma once
/// Errors of the core library.
///
/// - GeometryError: a request that is well formed but describes no valid domain or
///   density. It names the model objects involved (curve, loop, point names; the
///   density entry) so that the layer which built the model from its input can point
///   at the offending field. The core never sees JSON pointers.
/// - InternalError: a broken invariant (a bug). Carries file and line; the input that
///   caused it should be kept and turned into a regression test.
/// - Cancelled: the observer asked the pipeline to stop.

#include <stdexcept>
#include <string>
#include <vector>

#include "meshd/core/vec2.hpp"

namespace meshd::core {

/// Base of every exception thrown by the core.
class Error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// What part of the model an error is about.
struct Subject {
    enum class Kind { None, Point, Curve, Loop, Embedded, Density, Layers };
    Kind kind = Kind::None;
    /// Point or curve name; for Density the entry ("size", "interior", a curve or tag
    /// name of the per-curve table, "min", "max", "gradation").
    std::string name;
    /// Loop, embedded-list or boundary_layers index, when kind is Loop, Embedded or Layers
    /// (else -1).
    int index = -1;
    /// Path below the object, e.g. {"control_points", "3"} or {"code"}; may be empty.
    std::vector<std::string> field;

    static Subject point(std::string n) { return {Kind::Point, std::move(n), -1, {}}; }
    static Subject curve(std::string n, std::vector<std::string> f = {}) {
        return {Kind::Curve, std::move(n), -1, std::move(f)};
    }
    static Subject loop(int i, std::vector<std::string> f = {}) {
        return {Kind::Loop, {}, i, std::move(f)};
    }
    static Subject embedded(int i) { return {Kind::Embedded, {}, i, {}}; }
    static Subject layers(int i, std::vector<std::string> f = {}) { return {Kind::Layers, {}, i, std::move(f)}; }
    static Subject density(std::string entry, std::vector<std::string> f = {}) {
        return {Kind::Density, std::move(entry), -1, std::move(f)};
    }
};

enum class GeometryErrorKind {
    UnknownPoint,         ///< a curve names a point that does not exist
    UnknownCurve,         ///< a loop or the embedded list names a curve that does not exist
    NonFinite,            ///< a coordinate or parameter is NaN or infinite
    CoincidentPoints,     ///< two distinct named points at the same place
    ZeroLength,           ///< a curve of zero length
    ArcEndsOffCircle,     ///< an arc whose ends are at different distances from its centre
    TooFewControlPoints,  ///< B-spline with fewer than degree + 1 control points, spline < 2
    BadDegree,            ///< B-spline degree below 1
    BadKnots,             ///< knot vector of the wrong size, decreasing or not clamped
    EndsMismatch,         ///< a curve's geometric ends differ from its named `from`/`to`
    BadNaca,              ///< a NACA code that is not a valid 4- or 5-digit designation
    BadAirfoil,           ///< airfoil text that is not a Selig or Lednicer airfoil
    BadParameter,         ///< a parameter out of range (chord <= 0, ...)
    LoopNotClosed,        ///< consecutive curves of a loop do not share their ends
    EmptyLoop,            ///< a loop with no curves
    CurveReused,          ///< a curve used twice in loops or embedded
    UnusedCurve,          ///< a curve in no loop and not embedded
    NoOuterLoop,          ///< no loop encloses all the others
    HoleOutside,          ///< a hole not inside the outer loop
    HolesOverlap,         ///< two holes overlap or one holds the other
    CurvesCross,          ///< two curves cross or touch away from a shared end
    SelfIntersection,     ///< a curve or loop crosses itself
    EmbeddedOutside,      ///< an embedded curve leaves the domain
    DiscretisationCrosses,///< the polygon of the discretised boundary crosses itself
    DensityExpression,    ///< a density expression does not parse
    DensityInvalid,       ///< density not finite and positive at some point
    DensityMissing,       ///< no density given for some curve
    TooManyPoints,        ///< the discretisation would exceed the point limit
};

/// Stable lower-case name of an error kind ("curves-cross"), for problem types.
const char* to_string(GeometryErrorKind kind);

class GeometryError : public Error {
public:
    GeometryError(GeometryErrorKind kind, std::string message, std::vector<Subject> subjects = {})
        : Error(std::move(message)), kind_(kind), subjects_(std::move(subjects)) {}

    GeometryErrorKind kind() const { return kind_; }
    /// The model objects involved, most specific first. May be empty.
    const std::vector<Subject>& subjects() const { return subjects_; }
    /// Where the error happened, when it is about a place in the plane (density errors).
    const Vec2* where() const { return has_where_ ? &where_ : nullptr; }

    GeometryError&& at(Vec2 p) && {
        where_ = p;
        has_where_ = true;
        return std::move(*this);
    }

private:
    GeometryErrorKind kind_;
    std::vector<Subject> subjects_;
    Vec2 where_{};
    bool has_where_ = false;
};

class InternalError : public Error {
public:
    InternalError(const std::string& what, const char* file, int line)
        : Error(what + " (" + file + ":" + std::to_string(line) + ")"), message_(what) {}
    /// What broke, without the source location (what() has both): for answers to clients.
    const std::string& message() const { return message_; }

private:
    std::string message_;
};

class Cancelled : public Error {
public:
    Cancelled() : Error("cancelled") {}
};

#define MESHD_INTERNAL_CHECK(cond, msg)                                          \
    do {                                                                         \
        if (!(cond)) throw ::meshd::core::InternalError((msg), __FILE__, __LINE__); \
    } while (false)

}  // namespace meshd::core
