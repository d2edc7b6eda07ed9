#pragma once
// What the pipeline learns about the domain from the triangulation of its boundary before
// the interior work: the expected number of points, and samples of rho at about the local
// size for the gradation envelope.

#include <cmath>

#include "boundary/boundary.hpp"
#include "density/size_field.hpp"
#include "meshd/core/observer.hpp"

namespace meshd::core {

/// Expected number of points of the mesh (boundary plus interior), from the integral of
/// rho^-2 over the domain; stops counting once past `limit`. Within about 10% on smooth
/// densities. `rho` must be ready for interior queries.
double estimate_point_count(const Discretisation& boundary, const BoundaryTriangulation& walls,
                            const SizeField& rho, double limit = HUGE_VAL,
                            Observer* observer = nullptr);

/// Throws GeometryError TooManyPoints: the mesh would have about `estimate` points, more
/// than `limit`.
[[noreturn]] void refuse_too_many(double estimate, size_t limit);

/// Limits the growth of rho inside the domain to its gradation (density/gradation.hpp):
/// samples the boundary points and the interior, then sets them as the gradation sources.
/// The samples follow the field before the limit, so a field that would give more than
/// max_points points is refused (refuse_too_many) as soon as the sampling shows it.
void set_gradation_sources(SizeField& rho, const Discretisation& boundary, const BoundaryTriangulation& walls,
                           size_t max_points, Observer* observer = nullptr);

}  // namespace meshd::core
