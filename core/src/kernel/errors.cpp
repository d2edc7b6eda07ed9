#include "meshd/core/errors.hpp"

namespace meshd::core {

const char* to_string(GeometryErrorKind kind) {
    using K = GeometryErrorKind;
    switch (kind) {
        case K::UnknownPoint: return "unknown-point";
        case K::UnknownCurve: return "unknown-curve";
        case K::NonFinite: return "non-finite";
        case K::CoincidentPoints: return "coincident-points";
        case K::ZeroLength: return "zero-length";
        case K::ArcEndsOffCircle: return "arc-ends-off-circle";
        case K::TooFewControlPoints: return "too-few-control-points";
        case K::BadDegree: return "bad-degree";
        case K::BadKnots: return "bad-knots";
        case K::EndsMismatch: return "ends-mismatch";
        case K::BadNaca: return "bad-naca-code";
        case K::BadAirfoil: return "bad-airfoil";
        case K::BadParameter: return "bad-parameter";
        case K::LoopNotClosed: return "loop-not-closed";
        case K::EmptyLoop: return "empty-loop";
        case K::CurveReused: return "curve-reused";
        case K::UnusedCurve: return "unused-curve";
        case K::NoOuterLoop: return "no-outer-loop";
        case K::HoleOutside: return "hole-outside";
        case K::HolesOverlap: return "holes-overlap";
        case K::CurvesCross: return "curves-cross";
        case K::SelfIntersection: return "self-intersection";
        case K::EmbeddedOutside: return "embedded-outside";
        case K::DiscretisationCrosses: return "discretisation-crosses";
        case K::DensityExpression: return "density-expression";
        case K::DensityInvalid: return "density-invalid";
        case K::DensityMissing: return "density-missing";
        case K::TooManyPoints: return "too-many-points";
    }
    return "unknown";
}

}  // namespace meshd::core
