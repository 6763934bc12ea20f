#pragma once
// An indexed triangle mesh and the topology measures the tests and the
// statistics report (components, boundary loops, Euler characteristic).

#include "recon/core/point_cloud.h"

#include <array>
#include <cstdint>
#include <vector>

namespace recon {

/// Indexed triangle mesh: #V vertices, #F triangles of three vertex indices,
/// counter-clockwise seen from the side the surface normal points to.
/// `colors` is either empty or holds one colour per vertex.
/// `normals` is either empty or holds one unit normal per vertex, on the side
/// the triangles face (made only when asked: ReconstructionOptions::vertex_normals;
/// phase V's own mesh holds (0, 0, 0) where vertex_normals.h fills them in).
struct Mesh {
  std::vector<Vec3> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::vector<Color> colors;
  std::vector<Vec3> normals;

  [[nodiscard]] bool has_colors() const { return !colors.empty(); }
  [[nodiscard]] bool has_normals() const { return !normals.empty(); }
};

/// An undirected edge (a, b) of vertex indices as one number, the same for
/// (b, a): the key of the maps from edges to the triangles on them.
[[nodiscard]] inline std::uint64_t edge_key(std::uint32_t a, std::uint32_t b) {
  return a < b ? (std::uint64_t{a} << 32) | b : (std::uint64_t{b} << 32) | a;
}

/// Topology of a mesh. "Edge" means an undirected pair of vertices used by
/// at least one triangle.
struct MeshTopology {
  std::size_t vertices = 0;  ///< vertices used by a triangle
  std::size_t edges = 0;
  std::size_t triangles = 0;
  std::size_t components = 0;            ///< connected through shared edges
  std::size_t boundary_edges = 0;        ///< used by exactly one triangle
  std::size_t boundary_loops = 0;        ///< closed chains of boundary edges
  std::size_t non_manifold_edges = 0;    ///< used by three or more triangles
  std::size_t inconsistent_edges = 0;    ///< two triangles traverse it the same way
  std::size_t degenerate_triangles = 0;  ///< zero area or repeated vertex
  long euler_characteristic = 0;         ///< V - E + F over the used vertices
  double signed_volume = 0.0;            ///< > 0 when closed and facing outward
  double area = 0.0;
  /// Per component: number of triangles and Euler characteristic, and
  /// whether it is closed (no boundary edge).
  struct Component {
    std::size_t triangles = 0;
    long euler_characteristic = 0;
    std::size_t boundary_edges = 0;
    double signed_volume = 0.0;
  };
  std::vector<Component> component_list;

  /// Closed, edge-manifold and consistently oriented.
  [[nodiscard]] bool watertight() const {
    return boundary_edges == 0 && non_manifold_edges == 0 && inconsistent_edges == 0;
  }
};

/// The topology of `mesh` (#V vertices, #F triangles): the counts above, its components and boundary loops.
/// Cost: O(V + F); here the half-edges are counted out by vertex and each vertex's d of them ordered by
/// insertion (O(d^2) there), and the components and the boundary's ends are sorted (O(F log F) at most).
/// Throws: InvalidInputError for a vertex index past the end, or more than 2^32 - 1 triangles.
/// Pre: none.
[[nodiscard]] MeshTopology analyze_topology(const Mesh& mesh);

/// The edges used by exactly one triangle (collapsed triangles left out, as
/// in analyze_topology), each as it is traversed by its triangle, sorted.
/// Cost: O(F log F), a sort of the 3F directed edges.
/// Throws: nothing.
/// Pre: none (indices are not read as vertices).
[[nodiscard]] std::vector<std::array<std::uint32_t, 2>> boundary_edges(const Mesh& mesh);

/// Euclidean distance from p to the triangle abc (to its closest point,
/// found by the regions of the triangle's plane: interior, edges, corners).
/// Cost: O(1).
/// Throws: nothing.
/// Pre: none.
[[nodiscard]] double point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace recon
