#pragma once
/// Constrained Delaunay triangulation (CDT) of a point set with constraint segments and
/// holes, built incrementally.
///
/* Triangle t stores its vertices counter-clockwise and, for each vertex i, the neighbour
   across the opposite edge and whether that edge is constrained:

                  v[2]
                  /  \
       n[1]      /    \      n[0]
    (edge v2-v0)/  t   \(edge v1-v2)
               /        \
            v[0] ------ v[1]
                  n[2]
              (edge v0-v1)

   Edge i of t runs from v[(i+1)%3] to v[(i+2)%3], so t lies on its left. */

/// Every in-circle decision goes through incircle_perturbed() with the vertex index as rank,
/// so the result is the unique CDT under that perturbation: cocircular input gives the same
/// triangles whatever the insertion order or algorithm.

#include <array>
#include <cstdint>
#include <vector>

#include "meshd/core/vec2.hpp"

namespace meshd::core {

using TriangleId = std::uint32_t;
inline constexpr TriangleId kNoTriangle = UINT32_MAX;

struct Triangle {
    std::array<std::uint32_t, 3> v;
    std::array<TriangleId, 3> n;
    std::uint8_t constrained = 0;  ///< bit i: edge i is a constraint
    std::uint8_t boundary = 0;     ///< bit i: edge i is a loop segment (holes stop at it)
};

/// Bit i of an edge flag byte.
inline bool edge_bit(std::uint8_t flags, std::uint32_t i) { return ((static_cast<std::uint32_t>(flags) >> i) & 1u) != 0; }

struct TriangulationStats {
    std::uint64_t flips = 0;
    std::uint64_t walk_steps = 0;
    std::uint64_t duplicates = 0;
};

/// A constraint: a -> b. Loop segments have the domain on their left and bound the flood
/// fill that removes holes; embedded segments are kept as edges but do not bound anything.
struct Constraint {
    std::uint32_t a, b;
    bool loop;
};

/// The triangles of the CDT of `points` that lie inside the loops, with their adjacency
/// (kNoTriangle across loop segments). Points in insertion-independent order; every
/// constraint is an edge of the result (a constraint through another input point is split
/// there). Throws InternalError on a broken invariant. O(n log n) expected.
struct TriangulationResult {
    std::vector<Triangle> triangles;
    /// Points of the input that coincide with an earlier point are merged into it:
    /// alias[i] = i for every kept point.
    std::vector<std::uint32_t> alias;
    TriangulationStats stats;
};
TriangulationResult triangulate_delaunay(const std::vector<Vec2>& points,
                                         const std::vector<Constraint>& constraints,
                                         class Observer* observer = nullptr);

/// The paper's triangulator (section 5, after Lo 1989): the Delaunay advancing front. For
/// the last front edge AB, the visible point C on its left whose circle through A, B, C
/// holds no other visible candidate forms ABC; the candidate search is local (a grid) and
/// widens until a point is found. Gives the same triangles as triangulate_delaunay().
TriangulationResult triangulate_advancing_front(const std::vector<Vec2>& points,
                                                const std::vector<Constraint>& constraints,
                                                class Observer* observer = nullptr);

/// Restores the constrained Delaunay property by flipping unconstrained edges (after
/// smoothing moved points). Returns the number of flips.
std::uint64_t make_delaunay(const std::vector<Vec2>& points, std::vector<Triangle>& triangles);

}  // namespace meshd::core
