#pragma once
/// The finished mesh: flat arrays that writers consume, and its checker.

#include <cstdint>
#include <string>
#include <vector>

#include "meshd/core/domain.hpp"
#include "meshd/core/triangulation.hpp"

namespace meshd::core {

enum class PointKind : std::uint8_t {
    Corner,    ///< an end of a curve (a named point)
    Boundary,  ///< on a loop curve
    Embedded,  ///< on an embedded curve
    Interior,  ///< made by the advancing front (may move in smoothing)
};

struct MeshEdge {
    std::uint32_t a, b;  ///< loop edges have the domain on their left
    TagId tag;
    bool embedded;
};

struct Mesh {
    std::vector<double> x, y;
    std::vector<PointKind> kind;
    /// Counter-clockwise, with neighbours (kNoTriangle across loop edges) and the constraint
    /// bits of triangulation.hpp.
    std::vector<Triangle> triangles;
    /// Loop edges in loop order, then embedded edges.
    std::vector<MeshEdge> edges;
    std::vector<std::string> tags;
    size_t holes = 0;
    /// rho at each point (the interior density), for writers that carry the target size.
    std::vector<double> target_size;

    size_t point_count() const { return x.size(); }
    Vec2 point(std::uint32_t v) const { return {x[v], y[v]}; }
};

/// Checks the invariants every mesh must satisfy and returns what is violated (empty when
/// all hold): indices in range, counter-clockwise triangles of positive area (exact),
/// symmetric adjacency, every edge of `edges` present (and only those edges without a
/// neighbour), Euler characteristic V - E + F = 1 - holes, and empty circumcircles (exact
/// in-circle) across every unconstrained edge when `delaunay` is set.
std::vector<std::string> check_mesh(const Mesh& mesh, bool delaunay = true);

}  // namespace meshd::core
