#pragma once
// Laplacian smoothing and the angle repair (paper, section 5; docs/method.md).

#include <cstdint>

#include "meshd/core/mesh.hpp"
#include "meshd/core/observer.hpp"

namespace meshd::core {

/// Each sweep moves the interior points that are still settling to the mean of their
/// neighbours (or half way) unless that inverts a triangle of the star or takes one below
/// both the star's worst mean ratio and 0.8; then the Delaunay property is restored by
/// flips of unconstrained edges.
/// Last, the angle repair: the interior corners of triangles with an angle below 34 degrees
/// are placed where the smallest angle of their star is largest (a pattern search), again
/// followed by flips; a triangle of fixed points only has an edge flipped when the interior
/// point beyond it, placed again, makes a better star; with the domain given, points on
/// curves of triangles still below 30 degrees slide along their curves (between their
/// neighbours there, never off a corner of the curve); and a triangle still between 15 and 30
/// degrees has the edge flipped whose flip does best, with the quad's interior corners placed
/// again, when that mends it.
/// Returns the number of moves made; adds the flips to *flips when given.
std::uint64_t smooth(Mesh& mesh, int iterations, const Domain* domain = nullptr, std::uint64_t* flips = nullptr,
                     Observer* observer = nullptr);

/// The angle repair of smooth() alone, without sweeps: for a mesh that gained points after
/// smoothing (min_angle_deg's refinement). Only points from `first_movable` on move (the
/// refinement's own, in a mesh whose other points were asked to stay where they are).
std::uint64_t repair_angles(Mesh& mesh, const Domain* domain = nullptr, std::uint64_t* flips = nullptr,
                            Observer* observer = nullptr, VertexId first_movable = 0);

}  // namespace meshd::core
