#pragma once
/// Every tolerance the core applies when it constructs or checks geometry for the user.
/// Topological decisions of the mesher use exact predicates instead and need none.
/// Lengths are relative to the extent (bounding-box diagonal) of the domain unless
/// stated otherwise.

namespace meshd::core::tol {

/// Arc ends must be on one circle: | |B - S| - |A - S| | <= kArcRadius * |A - S|.
inline constexpr double kArcRadius = 1e-9;

/// A curve whose length is below this fraction of the domain extent is zero-length.
inline constexpr double kMinCurveLength = 1e-12;

/// Distinct named points closer than this fraction of the extent are refused as
/// coincident; so are a curve's geometric ends that differ from its named points by more.
inline constexpr double kPointMatch = 1e-9;

/// Curves are flattened into polylines for the crossing and containment checks with this
/// chordal deviation (fraction of the extent).
inline constexpr double kFlattenDeviation = 1e-5;

/// Relative accuracy of the piecewise-linear model of rho along a curve that the
/// point generator of section 3.1 marches on.
inline constexpr double kDensityInterpolation = 1e-3;

/// Accuracy of the numerical arc length model (Gauss-Legendre integrals, piecewise cubic in
/// the parameter), relative to the curve's length.
inline constexpr double kArcLength = 1e-10;

/// Default lower clamp of the density, as a fraction of the domain extent, used when the
/// request gives no `min`: a density tending to zero cannot ask for endless refinement.
inline constexpr double kDefaultMinSize = 1e-6;

/// A corner of a curve is a break where the tangent direction turns by more than this
/// (radians); corners are always points of the discretisation.
inline constexpr double kCornerAngle = 1e-6;

/// The most a boundary segment may turn the curve's tangent (radians): sizes are capped at
/// this times the local radius of curvature, whatever the density asks, so that a coarse
/// density keeps every curve's shape (a closed curve gets at least six segments).
inline constexpr double kMaxSegmentTurn = 1.5707963267948966;  // 90 degrees
/// The cap above holds where rho is sampled; a segment whose tangent still turns by more than
/// this (a density jumping from sizes beyond the curve to fine ones next to a leading edge) is
/// halved until none does. Set above kMaxSegmentTurn so that segments the cap sized (a
/// little over 90 degrees between its samples) are left alone.
inline constexpr double kMaxStepTurn = 2.356194490192345;  // 135 degrees

/// Largest coordinate magnitude accepted (absolute). Exact predicates multiply up to four
/// coordinates; this keeps every product far from overflow and underflow.
inline constexpr double kMaxCoordinate = 1e30;
/// Smallest extent of a domain: the in-circle determinant multiplies four coordinate
/// differences, which must stay far above the smallest normal double (1e-308) for the exact
/// predicates to be exact (they assume no underflow).
inline constexpr double kMinExtent = 1e-30;

}  // namespace meshd::core::tol
