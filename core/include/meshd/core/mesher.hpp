#pragma once
/// The front door of the core: a domain and a density in, a mesh and its figures out.
///
///   boundary      graded points on the curves (section 3)             src/boundary/
///   interior      points by the advancing front (section 4)           src/interior/
///   triangulation constrained Delaunay triangulation of all points     src/triangulation/
///   improve       smoothing, angle repair, min_angle_deg refinement    src/improve/
///   quality       the figures of QualityMetrics                        src/improve/
///
/// The server, the CLI, the benchmarks and the tests all call generate_mesh().

#include <cstdint>
#include <string>
#include <vector>

#include "meshd/core/density.hpp"
#include "meshd/core/domain.hpp"
#include "meshd/core/mesh.hpp"
#include "meshd/core/observer.hpp"

namespace meshd::core {

enum class Triangulator {
    Delaunay,        ///< incremental insertion, constraint recovery, flood fill (default)
    AdvancingFront,  ///< the paper's Delaunay advancing front (section 5)
};

/// How points are spread along a B-spline (other curves always use arc length).
enum class SplineSpacing {
    ArcLength,       ///< true arc length, inverted by Newton (the default: measured better)
    ControlPolygon,  ///< the paper's section 3.3: length along the control polygon
};

/// A candidate point whose size is more than this many times larger or smaller than both ends
/// of its segment is a jump of the size field: one element cannot follow it (MeshOptions::
/// jump_gradation).
inline constexpr double kFieldJump = 3.0;

/// The advancing front of the interior points (section 4).
struct InteriorOptions {
    /// Correct C so that |AC| = (rho(A) + rho(C)) / 2 and |BC| = (rho(B) + rho(C)) / 2 (4.4).
    bool newton = true;
    /// Factor on the distance of (4.22); 1 is the paper's criterion. With 1 the points end
    /// up about 16% farther apart than rho asks (each accepted point keeps a disk of radius
    /// rho free around it, and the front leaves gaps of nearly that size); 0.8 brings the
    /// edges to within a few percent of rho and raises the mean radius ratio from 0.954 to
    /// 0.972 on the NACA 0012 benchmark case (measured: docs/method.md).
    double proximity = 0.8;
    /// Where the sizes stay within two neighbouring size classes and every two points are
    /// spaced as (4.22) asks, the front's short segments are left out of the crossing test,
    /// which a proof shows they cannot fail (interior/crossing_proof.hpp): the same points,
    /// sooner. Elsewhere the proof is made block by block of the segments' grid, from the
    /// sizes and size classes of the short segments each block holds. false: every segment is
    /// tested (the tests compare the two).
    bool crossing_proof = true;
    /// For the tests: every block the proof would pass over is tested all the same, and each
    /// of its segments is checked against the proof's premise (InteriorStats::proof_violations).
    bool check_crossing_proof = false;
};

/// The most points one mesh may have, whatever max_points says: vertex and triangle ids are
/// 32 bits, and the smoothing stage packs a triangle id and a corner into one 32-bit word,
/// which holds for fewer than 2^30 triangles (about twice the points).
inline constexpr size_t kMaxPointsLimit = size_t{1} << 28;

/// The peak memory of generate_mesh for a mesh of `points` points: a fixed part and a part
/// per point, measured on uniform squares of 0.29, 1.2 and 4.6 million points (docs/
/// benchmarks.md: 177 and 202 bytes per point at the larger two, 246 at the smallest, where
/// the stages' arrays rounded up to whole 2 MiB pages weigh most; 219 to 283 before the
/// stages let their arrays go earlier) and rounded up; the caller's copy of the result
/// (MeshResult) is included, a writer's output is not.
inline constexpr size_t kPeakBytesBase = size_t{32} << 20;
inline constexpr size_t kPeakBytesPerPoint = 256;
inline size_t peak_bytes_for(double points) {
    const double capped = points < static_cast<double>(kMaxPointsLimit) ? points : static_cast<double>(kMaxPointsLimit);
    return kPeakBytesBase + static_cast<size_t>(capped > 0.0 ? capped : 0.0) * kPeakBytesPerPoint;
}

/// Boundary layers (docs/api.md, "boundary_layers"): columns of thin cells grown from the
/// graded points of wall curves, heights first_height * growth^k, until `layers` layers, the
/// `thickness`, or a cell as tall as rho; cut back where they would meet another boundary or
/// other layers.
struct BoundaryLayerSpec {
    /// Curve names or tags of loop curves (the layers grow on the domain's side).
    std::vector<std::string> curves;
    double first_height = 0.0;
    double growth = 1.2;
    int layers = 0;          ///< 0: not given (then thickness bounds them)
    double thickness = 0.0;  ///< 0: not given
    bool quads = true;       ///< false: each quad split along its shorter diagonal
};

/// The most layers one column may have (a request may ask for fewer).
inline constexpr int kMaxLayers = 200;

struct MeshOptions {
    int smoothing_iterations = 5;
    Triangulator triangulator = Triangulator::Delaunay;
    /// Refuse (GeometryError TooManyPoints) beyond this many points, before the interior
    /// work when the estimate already exceeds it. 0, or anything above kMaxPointsLimit:
    /// kMaxPointsLimit.
    size_t max_points = 0;
    SplineSpacing spline_spacing = SplineSpacing::ArcLength;
    InteriorOptions interior;
    /// Quality refinement after smoothing: no angle below this (degrees) except between two
    /// constrained edges and in triangles far below the local size; 0 keeps the paper's
    /// method. The request layer accepts up to 34 (Ruppert-style refinement is proven to end
    /// up to about 20.7 degrees and in practice ends well beyond 30).
    double min_angle_deg = 0.0;
    /// The defaults' last resort for 30 degrees: a finished mesh that still has a triangle
    /// below 30 degrees away from a corner between two constrained edges (a few in 100,000 of
    /// the random domains) is refined as min_angle_deg 30 would refine it, with the curves'
    /// agreement and the smoothing on. Off: no refinement but the one min_angle_deg asks (a
    /// request's explicit min_angle_deg 0, "off, the paper's pure method").
    bool sharp_last_resort = true;
    /// Curves spaced far more coarsely than the interior field beside them are spaced again
    /// to agree with it (pipeline/agreement.hpp). Off: the curves keep their own density
    /// (the paper's placement, slivers included), what the tests of min_angle_deg start from.
    bool curve_agreement = true;
    /// Where the request gives no gradation and the interior stage finds the size field
    /// jumping (kFieldJump) at 16 candidates and more (one more per 1,024 made), the mesh is
    /// made again from the boundary with this gradation (MeshStats::gradation_applied): a
    /// refinement box or strip whose size changes tenfold across a line leaves triangles
    /// below 30 degrees that no smoothing lifts. 0: never; nor with curve_agreement off (the
    /// gradation places the curves again, along the limited field).
    double jump_gradation = 1.5;
    /// 1: straight 3-node triangles; 2: 6-node triangles whose edge nodes on the curves lie
    /// on the curves (Mesh::edge_nodes).
    int order = 1;
    std::vector<BoundaryLayerSpec> boundary_layers;
};

struct StageTimings {
    double boundary_ms = 0, interior_ms = 0, triangulation_ms = 0, smoothing_ms = 0, total_ms = 0;
};

struct InteriorStats {
    std::uint64_t candidates = 0;
    std::uint64_t accepted = 0;
    std::uint64_t rejected_near = 0;      ///< (4.22)
    std::uint64_t rejected_crossing = 0;  ///< AC or BC crosses the front
    /// Candidates whose crossing test left the short segments to the proof
    /// (InteriorOptions::crossing_proof).
    std::uint64_t crossings_proven = 0;
    /// Blocks of short segments the crossing test passed over by the proof made block by block.
    std::uint64_t blocks_proven = 0;
    /// Segments the block-by-block proof passed over that its premise does not cover, found by
    /// InteriorOptions::check_crossing_proof: 0 unless the proof's bookkeeping is wrong.
    std::uint64_t proof_violations = 0;
    std::uint64_t rejected_outside = 0;   ///< outside the domain or across a constraint
    /// Candidates whose size is more than kFieldJump times off both ends of their segment (the
    /// field changes faster than one element can follow).
    std::uint64_t jumps = 0;
};

struct TriangulationStats {
    std::uint64_t flips = 0;
    std::uint64_t walk_steps = 0;
    std::uint64_t duplicates = 0;
};

/// The curves spaced again to agree with the interior field (MeshOptions::curve_agreement).
struct AgreementStats {
    int rounds = 0;       ///< placements of the curve points after the first
    size_t probes = 0;    ///< samples of the interior field that cap the curves
    size_t curves_kept = 0;  ///< curves a round left where they were (no new cap reached them)
};

struct MeshStats {
    /// Points forecast from the domain and density before any work (the admission check).
    double forecast_points = 0.0;
    AgreementStats agreement;
    InteriorStats interior;
    TriangulationStats triangulation;
    std::uint64_t smoothing_moves = 0, smoothing_flips = 0;
    std::uint64_t refinement_points = 0;
    /// Times the boundary layers were grown again, lower beside triangles below 30 degrees,
    /// and the interior meshed again on their outer edge: at most 3, and once more as first
    /// grown when none of those left every triangle at 30 degrees or more. Only where the
    /// observer's time left (Observer::seconds_left) holds another round as long as the last.
    int layer_rounds = 0;
    /// Times the curves were placed again, finer where the mesh had a triangle below 30
    /// degrees made of fixed points alone (curve points, layer tops: a gap between curves too
    /// small for an interior point) or of two of them and one interior point, and everything after
    /// them made again: at most 2, with
    /// the curves' agreement and the smoothing on, for a mesh below 80% of max_points, and
    /// where the observer's time left (Observer::seconds_left) holds another round.
    int closing_rounds = 0;
    /// The gradation the mesh was made with where the request gave none and its size field
    /// jumped (MeshOptions::jump_gradation); 0 when none was applied.
    double gradation_applied = 0.0;
    /// Predicate calls the floating-point filter could not settle (exact stage).
    std::uint64_t orient_exact = 0, incircle_exact = 0;
};

struct MeshResult {
    Mesh mesh;
    QualityMetrics quality;
    StageTimings timings;
    MeshStats stats;
};

/// Meshes the domain with the density. Inputs are only read: one domain may be meshed by
/// several threads at once. Throws GeometryError (the density does not fit the domain, the
/// mesh would be too large), Cancelled (the observer asked to stop) or InternalError.
MeshResult generate_mesh(const Domain& domain, const DensitySpec& density, const MeshOptions& options = {},
                         Observer* observer = nullptr);

/// The same from the description: build_domain() first (GeometryError when the description
/// is not a valid domain).
MeshResult generate_mesh(const DomainSpec& geometry, const DensitySpec& density, const MeshOptions& options = {},
                         Observer* observer = nullptr);

}  // namespace meshd::core
