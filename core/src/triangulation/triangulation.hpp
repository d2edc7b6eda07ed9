#pragma once
/// Constrained Delaunay triangulation (CDT) of a point set with constraint segments and
/// holes, built incrementally.
///
/// Every in-circle decision goes through incircle_perturbed() with the vertex index as rank,
/// so the result is the unique CDT under that perturbation: cocircular input gives the same
/// triangles whatever the insertion order or algorithm.

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "meshd/core/mesh.hpp"
#include "meshd/core/mesher.hpp"
#include "meshd/core/observer.hpp"

namespace meshd::core {


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
    Array<Triangle> triangles;
    /// Points of the input that coincide are merged into the one of them inserted first:
    /// alias[i] = i for every kept point.
    Array<std::uint32_t> alias;
    TriangulationStats stats;
};
TriangulationResult triangulate_delaunay(std::span<const Vec2> points,
                                         const std::vector<Constraint>& constraints,
                                         Observer* observer = nullptr);

/// The paper's triangulator (section 5, after Lo 1989): the Delaunay advancing front. For
/// the last front edge AB, the visible point C on its left whose circle through A, B, C
/// holds no other visible candidate forms ABC; the candidate search is local (a k-d tree) and
/// widens until a point is found. Gives the same triangles as triangulate_delaunay(). Its
/// points must be distinct (InternalError if two coincide; alias is the identity).
TriangulationResult triangulate_advancing_front(std::span<const Vec2> points,
                                                const std::vector<Constraint>& constraints,
                                                Observer* observer = nullptr);

}  // namespace meshd::core
