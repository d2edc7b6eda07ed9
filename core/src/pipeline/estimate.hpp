#pragma once
// What the pipeline learns about the domain from the triangulation of its boundary before
// the interior work: the expected number of points, and samples of rho at about the local
// size for the gradation envelope.

#include <cmath>

#include "boundary/boundary.hpp"
#include "density/size_field.hpp"
#include "meshd/core/observer.hpp"

namespace meshd::core {

/// Points per rho^2 of area: 2 / sqrt(3) for a perfect equilateral mesh (two triangles of
/// side rho per point); the advancing front with its default proximity places about 14%
/// fewer.
inline constexpr double kPointsPerArea = 0.86 * 2.0 / 1.7320508075688772;

/// How many points the mesh will have, forecast from the domain and the density alone,
/// before any discretisation (forecast.cpp): the boundary's from the integral of 1/rho along
/// the curves, the interior's from the integral of rho^-2 over the outlines of the loops.
/// Costs at most the budget's samples of rho (and the outline's segments), whatever rho is.
/// Without the gradation (which only adds points), so a lower estimate where one is given.
struct ForecastBudget {
    size_t boundary_samples = size_t{1} << 13;
    size_t interior_samples = size_t{1} << 14;
    /// Forecast the curves spaced again to agree with the interior field, as the mesh will
    /// be (MeshOptions::curve_agreement; pipeline/agreement.hpp).
    bool curve_agreement = true;
};
struct PointForecast {
    double boundary = 0.0, interior = 0.0;
    size_t boundary_samples = 0, interior_samples = 0;
    double total() const { return boundary + interior; }
};
/// Throws GeometryError for a density that does not fit the domain (as SizeField does), or
/// that is invalid on a curve; Cancelled.
PointForecast forecast_points(const Domain& domain, const DensitySpec& density,
                              const ForecastBudget& budget = {}, Observer* observer = nullptr);

/// Expected number of points of the mesh (boundary plus interior), from the integral of
/// rho^-2 over the domain; stops counting once past `limit`, or after about 16 samples per
/// point of the limit (a lower count then). Within about 10% on smooth densities. `rho` must
/// be ready for interior queries.
double estimate_point_count(const Discretisation& boundary, const BoundaryTriangulation& walls,
                            const SizeField& rho, double limit = HUGE_VAL,
                            Observer* observer = nullptr);

/// Throws GeometryError TooManyPoints: the mesh would have about `estimate` points, more
/// than `limit`.
[[noreturn]] void refuse_too_many(double estimate, size_t limit);

/// The memory a gradation source takes while the sources are gathered and the field's tree is
/// built (the gathered arrays, grown by doubling, beside the field's copy and its nodes): an
/// upper bound of what it keeps.
inline constexpr size_t kGradationBytesPerSource = 96;

/// Limits the growth of rho inside the domain to its gradation (density/gradation.hpp):
/// samples the boundary points and the interior (the centres of square cells of one lattice,
/// split while larger than the local size), then sets them as the gradation sources.
/// The samples follow the field before the limit, so a field that would give more than
/// max_points points is refused (refuse_too_many) as soon as the sampling shows it.
/// The samples' memory stays with the field to the end of the run, beside the peak that
/// `forecast_points` makes (peak_bytes_for): the observer hears the two together as the
/// samples grow (Observer::on_forecast), from 2^16 samples and at each doubling after.
/// Returns the bytes the samples take, kGradationBytesPerSource each (for the interior
/// stage's reports: InteriorBudget).
size_t set_gradation_sources(SizeField& rho, const Discretisation& boundary, const BoundaryTriangulation& walls,
                             size_t max_points, Observer* observer = nullptr, double forecast_points = 0.0);

}  // namespace meshd::core
