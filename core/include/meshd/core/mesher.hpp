#pragma once
/// The front door of the core: a domain and a density in, a mesh and its figures out.
///
///   boundary      graded points on the curves (section 3)
///   interior      points by the advancing front (section 4)
///   triangulation constrained Delaunay triangulation of all points (section 5)
///   smoothing     Laplacian smoothing that never inverts nor worsens a star, then flips
///   quality       the figures of quality.hpp
///
/// The server, the CLI and the tests all call generate_mesh().

#include <cmath>
#include <cstdint>

#include "meshd/core/boundary.hpp"
#include "meshd/core/density.hpp"
#include "meshd/core/interior.hpp"
#include "meshd/core/mesh.hpp"
#include "meshd/core/observer.hpp"
#include "meshd/core/quality.hpp"

namespace meshd::core {

enum class Triangulator {
    Delaunay,        ///< incremental insertion, constraint recovery, flood fill (default)
    AdvancingFront,  ///< the paper's Delaunay advancing front
};

struct MeshOptions {
    int smoothing_iterations = 5;
    Triangulator triangulator = Triangulator::Delaunay;
    /// Refuse (TooManyPoints) beyond this many points. 0: no limit.
    size_t max_points = 0;
    SplineSpacing spline_spacing = SplineSpacing::ArcLength;
    InteriorOptions interior;
    /// Quality refinement after smoothing: no angle below this (degrees) except input
    /// corners; 0 keeps the paper's method. Up to about 30 degrees.
    double min_angle_deg = 0.0;
};

struct StageTimings {
    double boundary_ms = 0, interior_ms = 0, triangulation_ms = 0, smoothing_ms = 0, total_ms = 0;
};

struct MeshStats {
    InteriorStats interior;
    TriangulationStats triangulation;
    std::uint64_t smoothing_moves = 0, smoothing_flips = 0;
    std::uint64_t refinement_points = 0;
    /// Predicate calls the floating-point filter could not settle (exact stage).
    std::uint64_t orient_exact = 0, incircle_exact = 0;
};

struct MeshResult {
    Mesh mesh;
    QualityMetrics quality;
    StageTimings timings;
    MeshStats stats;
};

/// Meshes the domain. rho is completed here (eq. 6.1 sources) and must not be shared with
/// other threads. Throws GeometryError, Cancelled or InternalError.
MeshResult generate_mesh(const Domain& domain, SizeField& rho, const MeshOptions& options = {},
                         Observer* observer = nullptr);

/// Expected number of points of the mesh (boundary plus interior), from the integral of
/// rho^-2 over the domain; stops counting once past `limit`. Within about 10% on smooth
/// densities. `rho` must be ready for interior queries.
double estimate_point_count(const Discretisation& boundary, const SizeField& rho, double limit = HUGE_VAL,
                            Observer* observer = nullptr);

/// Limits the growth of rho inside the domain to its gradation (gradation.hpp): samples the
/// boundary and the interior, then sets them as the gradation sources of rho.
void set_gradation_sources(SizeField& rho, const Discretisation& boundary,
                           Observer* observer = nullptr);

/// Inserts circumcentres (or splits constrained edges they encroach) until no triangle has
/// an angle below min_angle_deg, except at input corners and below a tenth of the local size;
/// keeps the mesh constrained Delaunay. Stops at max_points (0: no limit). Returns the number
/// of points added.
std::uint64_t refine_min_angle(Mesh& mesh, const SizeField& rho, double min_angle_deg, size_t max_points = 0,
                               Observer* observer = nullptr);

/// Laplacian smoothing of the interior points (section 5 of ALGORITHM.md): each sweep moves
/// the interior points that are still settling to the mean of their neighbours (or half way)
/// unless that inverts a triangle of the star or lowers the star's worst mean ratio; then
/// the Delaunay property is restored by flips of unconstrained edges. Last, the interior
/// corners of triangles with an angle below 34 degrees are placed where the smallest angle
/// of their star is largest (a pattern search), again followed by flips. Returns the number
/// of moves made.
std::uint64_t smooth(Mesh& mesh, int iterations, std::uint64_t* flips = nullptr, Observer* observer = nullptr);

}  // namespace meshd::core
