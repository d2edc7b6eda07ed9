#pragma once
// Curves spaced far more coarsely than the interior field beside them: a far field's long
// segments next to the small sizes eq. 6.1 spreads from an airfoil's many short ones, or a
// coarse curve density under a fine interior expression. No placement of interior points next
// to such a segment gives fair angles (the paper's Fig. 9 had 11 degrees at its far field),
// so the pipeline makes the two agree before the interior: it caps rho on the curves at the
// interior field found just inside their segments and places the curve points again.

#include "boundary/boundary.hpp"
#include "density/size_field.hpp"
#include "meshd/core/mesher.hpp"
#include "meshd/core/observer.hpp"

namespace meshd::core {

/// A boundary segment at most this many times the interior field beside it is left alone (a
/// smooth field differs by less over half a segment; Lo's spacing puts segments within a few
/// percent of rho).
inline constexpr double kAgreementRatio = 1.5;
/// The caps grow by at most this ratio per element away from a probe (gradation cones).
inline constexpr double kAgreementCapRatio = 1.5;
/// The interior cap grows more gently from the boundary layers' outer edge (agree_interior_
/// with_front) and, under eq. 6.1, from every boundary point: where the field grows fast
/// away from fixed points, a first-row interior point may come to stand over three short
/// segments at once (29 degrees; NACA sections with layers, Fig. 9's leading edge).
inline constexpr double kFrontCapRatio = 1.25;
/// Rounds of probing and placing the curve points again, at most.
inline constexpr int kAgreementRounds = 4;

/// rho inside at p, or NaN where the interior density is not defined there (a probe that fell
/// outside a narrow part of the domain, where an expression may be invalid): no cap from it.
double probe_interior(const SizeField& rho, Vec2 p);

/// Probes the interior field just inside every segment of `d` (half a segment off its middle,
/// on the domain's side of loop segments, on both sides of embedded ones). Where a segment is
/// longer than kAgreementRatio times the field there, caps rho on the curves at that field
/// (SizeField::set_curve_cap) and places the curve points again (and the eq. 6.1 sources with
/// them). Where the field is more than kAgreementRatio times the segment (a curve spaced
/// finely among coarser ones: an airfoil's leading edge under eq. 6.1, which averages in the
/// longer segments further along; a blunt trailing edge's short base under any field), caps
/// the interior field at the segment's length there (SizeField::set_interior_cap). Both caps
/// are cones growing by kAgreementCapRatio per element (the interior's by kFrontCapRatio from
/// the boundary's points under eq. 6.1); rounds repeat while either grows, a
/// few at most, since each changes what the other sees. Where curves meet at a domain point
/// and their first segments differ by more than kAgreementRatio, or two neighbouring ones
/// would close a triangle of the two alone with an angle below kClosingAngleDeg
/// (kernel/constructions.hpp), the curves are capped at the shorter there too (the triangle
/// that closes such a corner is often made of the two segments alone; at a wall with layers
/// the outer edge repeats the wall's spacing, so walls take part, but not where one turns by
/// more than kFanTurnDeg and the layers fan or bunch); a corner still apart after its cap
/// (a short curve there rounded its count of segments down) is capped lower the next round.
/// Sources are only made where the two
/// disagree, so a mesh whose curves and field agree pays one probe per segment. Throws what
/// discretise_boundary throws (too many points, Cancelled).
///
/// `walls` (per curve, may be empty): curves with boundary layers, whose fine segments cap no
/// interior field: the interior meets the layers' outer edge instead (agree_interior_with_front).
/// `closing`: caps of the curves known before the first probe (a mesh made before showed
/// sharp triangles of curve points alone there); they make the first round's placement.
AgreementStats agree_with_interior(const Domain& domain, SizeField& rho, const BoundaryOptions& options,
                                   Discretisation& d, Observer* observer = nullptr,
                                   const std::vector<bool>& walls = {}, const SizeCaps& closing = {});

/// The interior cap of agree_with_interior made again from `front`, the discretisation the
/// interior is meshed up to when boundary layers stand on the walls: their outer edge is
/// spaced like the walls but lies a layer's thickness out, where the field (and under eq.
/// 6.1 the cones from the walls' points) is already coarser. Replaces the cap from the walls.
/// An embedded segment of the front beside a front segment more than kAgreementRatio times
/// as long is capped too, whatever the field: the walls' spacing at a short line leaving
/// them was agreed on before a column slid up the line, and the triangle closing that
/// corner needs an interior point.
void agree_interior_with_front(SizeField& rho, const Discretisation& front);

}  // namespace meshd::core
