#pragma once
/// The finished mesh: flat arrays that writers consume, its quality figures and its checker.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "meshd/core/array.hpp"
#include "meshd/core/domain.hpp"

namespace meshd::core {

using VertexId = std::uint32_t;
inline constexpr VertexId kNoVertex = UINT32_MAX;
using TriangleId = std::uint32_t;
inline constexpr TriangleId kNoTriangle = UINT32_MAX;

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
struct Triangle {
    std::array<VertexId, 3> v;
    std::array<TriangleId, 3> n;
    std::uint8_t constrained = 0;  ///< bit i: edge i is a constraint (loop or embedded segment)
    std::uint8_t boundary = 0;     ///< bit i: edge i is a loop segment (holes stop at it)
    std::uint8_t layer = 0;        ///< 1: a cell of the boundary layers (a fan or a step)
};

/// Bit i of an edge flag byte.
inline bool edge_bit(std::uint8_t flags, std::uint32_t i) {
    return ((static_cast<std::uint32_t>(flags) >> i) & 1u) != 0;
}

enum class PointKind : std::uint8_t {
    Corner,    ///< an end of a curve (a named point)
    Boundary,  ///< on a loop curve
    Embedded,  ///< on an embedded curve
    Interior,  ///< made by the advancing front or the refinement (may move in smoothing)
    Layer,     ///< made by the boundary layers (never moves)
};

struct MeshEdge {
    VertexId a, b;  ///< loop edges have the domain on their left
    TagId tag;
    CurveId curve;  ///< the domain curve the edge lies on
    bool embedded;
};

struct Mesh {
    // The arrays that grow with the mesh are Arrays (array.hpp): std::vectors on huge pages.
    Array<double> x, y;
    Array<PointKind> kind;
    /// The curve a Boundary or Embedded point lies on and its parameter there (the curve's
    /// own t); kNoCurve and 0 for corners and interior points.
    Array<CurveId> curve;
    Array<double> param;
    /// Counter-clockwise, with neighbours (kNoTriangle across loop edges and edges shared
    /// with a quad) and constraint bits. The boundary layers' triangles (fans at sharp
    /// corners, steps where the layer count changes, or every layer cell when quads are
    /// split) come after the others, marked `layer`.
    Array<Triangle> triangles;
    /// The boundary layers' quadrilaterals, counter-clockwise, strictly convex.
    std::vector<std::array<VertexId, 4>> quads;
    /// Loop edges in loop order, then embedded edges.
    std::vector<MeshEdge> edges;
    std::vector<std::string> tags;
    size_t holes = 0;
    /// The domain's curves as the mesh follows them (the topology file formats keep): per
    /// domain curve, the mesh points at its start and end in its own direction (kNoVertex for
    /// a curve the mesh does not follow), and each loop (outer first) as the curves it runs
    /// along, with `reversed` set where it runs a curve from end to start.
    std::vector<std::array<VertexId, 2>> curve_ends;
    struct LoopCurve {
        CurveId curve;
        bool reversed;
    };
    std::vector<std::vector<LoopCurve>> loops;
    /// rho at each point (the interior density), for writers that carry the target size.
    Array<double> target_size;
    /// Second order (MeshOptions::order 2): one node on each edge, numbered after the
    /// vertices (edge node k is point point_count() + k in the files). On a curve's edge it
    /// lies on the curve (at the parameter halfway between the ends'), elsewhere halfway
    /// along the chord. `edge_node[t][i]` is the node on edge i of triangle t (from v[(i+1)%3]
    /// to v[(i+2)%3]); `edge_node_of_edge[k]` the node on edges[k]. All empty at order 1.
    std::vector<Vec2> edge_nodes;
    std::vector<std::array<std::uint32_t, 3>> edge_node;
    std::vector<std::uint32_t> edge_node_of_edge;

    int order() const { return edge_nodes.empty() ? 1 : 2; }

    size_t point_count() const { return x.size(); }
    Vec2 point(VertexId v) const { return {x[v], y[v]}; }
};

/// The figures of a mesh, as the service reports them (docs/api.md, "metrics").
struct QualityMetrics {
    size_t points = 0, boundary_points = 0, interior_points = 0, triangles = 0, quads = 0;
    /// The angles, radius ratios and size ratios below are those of the isotropic triangles
    /// (not the boundary layers' cells, which `boundary_layers` describes).
    double angle_min = 0, angle_max = 0, angle_mean = 0;  ///< degrees
    /// Radius ratio 2 r_in / r_circ: 1 for an equilateral triangle.
    double quality_min = 0, quality_mean = 0;
    std::array<std::uint64_t, 10> quality_histogram{};  ///< 10 equal bins over [0, 1]
    /// Edge length / rho at the edge's midpoint, over all edges.
    double size_ratio_mean = 0;
    double size_ratio_within_sqrt2 = 0;  ///< fraction with a ratio in [1/sqrt 2, sqrt 2]
    /// Order 2 only: boundary and embedded edges whose middle node lies on their curve, those
    /// left straight because the curve would have folded a triangle, and the smallest scaled
    /// Jacobian of any triangle (at its six nodes; 1 for a straight one).
    std::uint64_t curved_edges = 0, straightened_edges = 0;
    double scaled_jacobian_min = 1.0;
    /// Per entry of MeshOptions::boundary_layers, the layers it made.
    struct Layers {
        int layers_min = 0, layers_max = 0;             ///< over its columns
        double first_height_min = 0, first_height_max = 0;
        double aspect_ratio_max = 0;                    ///< longest over shortest side, quads
        double scaled_jacobian_min = 1;                 ///< quads, at their corners
        double skew_max = 0;                            ///< quads: the largest |corner - 90 deg| / 90 deg
        std::uint64_t columns = 0, cut_back = 0;        ///< columns; those with fewer layers than asked
        std::vector<Vec2> cut_back_at;                  ///< the middle of each run of cut-back columns (at most 16)
    };
    std::vector<Layers> boundary_layers;
};

/// Radius ratio 2 r_in / r_circ of a triangle: 1 when equilateral, 0 when degenerate.
double radius_ratio(Vec2 a, Vec2 b, Vec2 c);

/// Checks the invariants every mesh must satisfy and returns what is violated (empty when
/// all hold): indices in range, counter-clockwise triangles of positive area (exact),
/// symmetric adjacency, every edge of `edges` present (and only those edges without a
/// neighbour), Euler characteristic V - E + F = 1 - holes, and empty circumcircles (exact
/// in-circle) across every unconstrained edge when `delaunay` is set. With quads: each
/// strictly convex and counter-clockwise, every edge shared by at most two cells in opposite
/// directions (conforming, no overlap), F counting triangles and quads; layer triangles are
/// not held to the in-circle test. The tests call it on
/// every mesh they make.
std::vector<std::string> check_mesh(const Mesh& mesh, bool delaunay = true);

}  // namespace meshd::core
