#pragma once
// Phase IV: contour tracing. The zero set of the signed distance f becomes
// a triangle mesh by marching cubes over a lattice (lattice.h).
//
// The textbook algorithm (Lorensen and Cline 1987): for every cube of a
// lattice over the bounding box, evaluate f at its 8 corners, note which
// corners are inside (f < 0), look the 8 bits up in a case table
// (marching_cubes_table.h) and emit its triangles, each vertex on a cube
// edge where f changes sign.
//
// This walk visits only the cubes near the surface (continuation). It
// starts from the cubes that contain a seed (a sample) and moves to a
// neighbouring cube only across a face whose four corners do not all have
// the same sign: the surface goes through that face, so it continues in the
// neighbour. Corner values are computed once and kept in a hash table
// (lattice_table.h), so time and memory grow with the area of the surface,
// not the volume of the box. It goes breadth-first, one wave of cubes at a
// time, in five steps per batch of a wave: find the corners already met,
// add the new ones, evaluate f at those (in parallel), classify each cube,
// and emit its triangles and the next wave. The mesh is the same for any
// number of threads, and the same as reference.h's plain serial walk over
// a std::unordered_map (tests/alternatives/reference_test.cpp).
//
// Per cube: if a corner is undefined (phase III), the cube yields nothing and
// the walk does not go on through it: the surface stays open there.
// Otherwise the case table gives the triangles; each vertex sits on a
// lattice edge where f changes sign, at the linear interpolation of the two
// corner values, and is shared by every triangle using that edge: the mesh
// is indexed. A corner where f = 0 counts as outside; a vertex is kept at
// least 1/1000 of the edge away from the corners so that no triangle has
// zero area.
//
// Cost: textbook O(N^3) evaluations of f for a lattice of N^3 cubes; here
// O(c) for the c cubes visited (about 1.5 A / cell^2 for a surface of area A).

#include "recon/core/point_cloud.h"
#include "recon/structures/lattice.h"
#include "recon/structures/mesh.h"

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <vector>

namespace recon {

/// A walk over part of a lattice laid out beforehand (the tiles of a large
/// cloud, tiles.h): the lattice is this one, not one over the seeds; the
/// walk starts from the seeds in [walk_lo, walk_hi) and visits only cubes
/// there, and emits the triangles of the cubes in [own_lo, own_hi) alone.
/// Cubes are named by their lowest corner; the boxes are half-open.
struct LatticeRegion {
  Lattice<3> lattice;
  Lattice<3>::Index walk_lo{}, walk_hi{};
  Lattice<3>::Index own_lo{}, own_hi{};
  [[nodiscard]] static bool inside(const Lattice<3>::Index& i, const Lattice<3>::Index& lo,
                                   const Lattice<3>::Index& hi) {
    for (std::size_t a = 0; a < 3; ++a)
      if (i[a] < lo[a] || i[a] >= hi[a]) return false;
    return true;
  }
};

struct MarchingCubesOptions {
  double cell = 0.0;                    ///< cube side (a length); must be > 0
  std::size_t max_cubes = 200'000'000;  ///< refuse lattices that would visit more (memory guard)
  bool keep_corners = false;            ///< keep every evaluated corner in the result
  std::optional<LatticeRegion> region;  ///< walk part of this lattice (see above); its cell must be `cell`
  bool keep_vertex_edges = false;       ///< name each vertex's lattice edge in the result
  bool keep_triangle_cubes = false;     ///< name each triangle's cube in the result (triangle_cube finds it too)
};

/// The lattice edge a vertex lies on: the key of the edge's lower corner
/// (Lattice<3>::key) and its axis (0, 1, 2). A vertex at the centre of a
/// cube's loop has axis 3 and its cube's key: no other cube shares it.
struct VertexEdge {
  std::uint64_t corner = 0;
  std::uint32_t axis = 0;
  friend bool operator==(const VertexEdge&, const VertexEdge&) = default;
};

using LatticeCorner = Lattice<3>::Corner;

struct MarchingCubesResult {
  Mesh mesh;
  double cell = 0.0;
  Vec3 origin = Vec3::Zero();          ///< position of lattice corner (0, 0, 0)
  std::array<std::int32_t, 3> size{};  ///< cubes along each axis
  std::size_t seed_cubes = 0;          ///< cubes containing a sample
  std::size_t visited_cubes = 0;       ///< cubes whose corners were looked at
  std::size_t undefined_cubes = 0;     ///< visited cubes with an undefined corner
  std::size_t evaluated_corners = 0;
  std::size_t undefined_corners = 0;
  std::vector<LatticeCorner> corners;    ///< every evaluated corner (if keep_corners)
  std::vector<VertexEdge> vertex_edges;  ///< per mesh vertex, its edge (if keep_vertex_edges)
  std::vector<std::uint64_t>
      triangle_cubes;          ///< per triangle, its cube's key (Lattice<3>::key; if keep_triangle_cubes)
  double seconds = 0.0;        ///< the whole walk, evaluations of f included
  double seconds_field = 0.0;  ///< of which evaluating f (phase III's share)
};

/// The function contoured: its value at a point, or nullopt where undefined.
/// It is called from several threads at once (one wave of corners at a time).
using ScalarField = std::function<std::optional<double>(const Vec3&)>;

/// Estimated cubes a walk will visit for `samples` points on a surface
/// where each sample stands for a spacing x spacing square, at cube side
/// `cell` (used to refuse before allocating): an upper estimate, at least
/// `samples`.
/// Cost: O(1).
/// Throws: nothing.
/// Pre: cell > 0.
[[nodiscard]] double estimate_visited_cubes(std::size_t samples, double spacing, double cell);
/// The same as expected rather than at most: a surface of area A crosses
/// about 1.5 A / cell^2 cubes on average over its orientations (the estimate
/// above takes the diagonal's 3 A / cell^2). A progress display's total.
/// Cost: O(1).
/// Throws: nothing.
/// Pre: cell > 0.
[[nodiscard]] inline double expected_visited_cubes(std::size_t samples, double spacing, double cell) {
  return 1.5 * static_cast<double>(samples) * spacing * spacing / (cell * cell);
}

/// The triangle mesh of f = 0, walked from the cubes that contain `seeds`
/// (normally the input points), in the seeds' coordinates. No seeds: an empty mesh.
/// Cost: O(N^3) for the whole N^3 lattice; here O(c) evaluations of f and expected O(1) table work per cube visited.
/// Throws: InvalidInputError when the cell is not a positive, finite length or options.region's cell is another;
/// ResourceLimitError when an axis needs more than Lattice<3>::max_cells_per_axis cubes or the walk passes
/// max_cubes; whatever f or an interruption check (interruption.h) throws.
/// Pre: finite seeds; f safe to call from several threads at once.
[[nodiscard]] MarchingCubesResult marching_cubes(const ScalarField& f, std::span<const Vec3> seeds,
                                                 const MarchingCubesOptions& options);

/// The key (Lattice<3>::key) of the cube a triangle of the result was
/// emitted for: the cube its centroid lies in. (A triangle's vertices lie on
/// edges of its cube, or at its centre, never all three on one face
/// (tests/phase4_contour/marching_cubes_test.cpp), and at least a thousandth of an edge
/// from a corner, so the centroid lies inside, by a margin rounding cannot
/// cross.)
/// Cost: O(1).
/// Throws: nothing.
/// Pre: `triangle` < result.mesh.triangles.size(); the result as marching_cubes() made it.
[[nodiscard]] std::uint64_t triangle_cube(const MarchingCubesResult& result, std::size_t triangle);

/// Reorders the result's triangles by their cubes' keys (each cube's in
/// the case table's order) and renumbers the vertices in the order the
/// triangles first use them. The walk's order depends on where
/// it started; this one does not, so a part of the lattice walked on its own
/// (a tile, tiles.h) lists its triangles in the same order, relative to one
/// another, as a walk over the whole: phase V, whose few order-dependent
/// choices (which crease vertex comes first) follow the triangles' order,
/// then makes the same choices in both. Vertex edges and triangle cubes,
/// if kept, follow.
/// Cost: O(T log T) for T triangles (a sort of the runs of triangles by cube), O(V) to renumber.
/// Throws: nothing.
/// Pre: the result as marching_cubes() made it (each cube's triangles in one run).
void sort_by_cube(MarchingCubesResult& result);

}  // namespace recon
