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

/// Limits the growth of rho inside the domain to its gradation (density/gradation.hpp):
/// samples the boundary points and the interior, then sets them as the gradation sources.
void set_gradation_sources(SizeField& rho, const Discretisation& boundary,
                           const BoundaryTriangulation& walls, Observer* observer = nullptr);

}  // namespace meshd::core
