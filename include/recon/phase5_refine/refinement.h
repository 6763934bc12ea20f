#pragma once
// Phase V (the default method): the contoured mesh moved onto the surface
// the samples describe. Hoppe's own next step (1993) optimised the mesh
// against the points; this is its local, one-pass form.
//
// The textbook idea. Marching cubes puts each vertex on a lattice edge,
// where the linear interpolation of f between two corners vanishes, and cuts
// every crease with flat triangles. Instead:
//   1. Project. Each vertex goes onto the osculating quadric of the tangent
//      plane f takes there (signed_distance.h; local_quadrics.h): the surface
//      as the samples around it curve, not the plane, nor the lattice edge.
//      On noisy data (blend), onto a weighted average of the quadrics of the
//      planes around it, which averages their noise out.
//   2. Sharpen. Where the two ends of a mesh edge lie on surfaces that meet
//      at a crease (their normals differ by more than crease_angle, far more
//      than the curvature between them explains), an end projected past the
//      crease (onto its face's plane beyond the other face) is brought back
//      onto the crease line, and the edge is split where it crosses the
//      crease, on the line where the two tangent planes meet; where three
//      faces' planes meet near a triangle, the nearest vertex moves onto
//      that corner. The crease is then drawn by mesh edges, not cut off.
//   3. Balance. A flat triangle with its corners on a curved surface lies
//      inside it (on the concave side) by up to |e|^2 kappa / 8. Each vertex
//      moves out by chord_balance times the mean sag of its edges, |e|^2
//      kappa / 12 (kappa from the normals at both ends), so that the mesh
//      crosses the surface instead of lying under it: the mesh then
//      approximates the surface in the least-squares sense, as Hoppe's 1993
//      mesh optimisation would fit it to the points. Crease edges are left
//      out of the mean, and vertices on a crease do not move.
//   Untangle (after step 3). Moving vertices can make triangles cross: a
//      vertex projected past a neighbour's plane, a crease vertex pulled
//      across a thin triangle, a fold on a sharp edge (407 crossing pairs
//      counted on a fandisk-like part, 233 on a turned box). The textbook
//      remedies are to refuse each move that would flip a neighbour
//      (checked as it is made) or to repair afterwards. Here: repair, by
//      retreat, since the contoured mesh is embedded. The exact check
//      (mesh_embedding.h) lists the triangles that cross, have no area (or
//      were made numerically flat by a retreat) and the pinched vertices;
//      each offence's vertices go halfway back to where phase IV had them,
//      then all the way (a crease vertex to the middle of the edge it split),
//      and the check runs again, until none is left or every vertex
//      concerned is home (at most 12 rounds; 2-6 on the shapes tried).
//      Plain vertices go first; crease vertices only where an offence has
//      no plain vertex left to move, and corners last, so the creases stay
//      drawn where they can. Each decision reads only the triangles around
//      the offence, so a tile (whose patch reaches a ring of cells past its
//      core) decides as the whole mesh does: the tiled tests give the same
//      mesh. What it costs: the check is O(F log F) a round (a 200k-point
//      torus, nothing to untangle: phase V 43 -> 182 ms, the run 0.54 ->
//      0.65 s), and the vertices put back lose their fit (the turned box's
//      edge passes up to 0.3 cell off at the spots that crossed; Chamfer
//      +13 % on the part, Hausdorff-95 +24 % on the conics; phase VI then
//      leaves 38 triangles of a box, not 12). So it is asked for
//      (keep_embedding, `recon reconstruct --embedded`), not the default,
//      until the crossings are avoided where they are made (step 2's crease
//      splits) and the check is local.
//   4. Clean. An open boundary is cut back to the data: f reaches about
//      1.5 rho + delta past the last samples, so the contoured surface runs
//      on past an open edge; triangles whose vertices all lie farther than
//      the local spacing from the samples are peeled off, from the boundary
//      inwards only (closed surfaces lose nothing, no hole is made inside).
//      Triangles far beyond f's reach (all three vertices farther than
//      5 rho_i + delta from every sample: fins drawn where two sheets lie
//      closer than a cell) are dropped. Fragments are dropped: a mesh component smaller than
//      fragment_fraction of the largest component drawn from the same piece
//      of data (phase II's components). Every piece keeps its largest
//      component, so a separate object is never dropped however small: only
//      debris next to a larger surface of the same piece is.
//
// Steps 1 to 3 are local: a vertex's new place depends on the planes and
// triangles around it. Step 4 is not (a peeled strip or a component can be
// any size), so refine_patch runs steps 1-3 alone on part of a larger mesh
// (the tiles of tiles.h) and marks what step 4 needs, to be decided over the
// whole; refine_mesh is refine_patch followed by step 4.
//
// Vertices, triangles and their order are the same for any thread count.
//
// Cost: Hoppe's 1993 optimisation iterates a global fit; this one pass is O(V log n) for V vertices over n planes.

#include "recon/phase1_planes/local_quadrics.h"
#include "recon/phase3_distance/signed_distance.h"
#include "recon/structures/mesh.h"

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace recon {

struct RefinementOptions {
  double crease_angle_degrees =
      recon::crease_angle_degrees;  ///< normals further apart (and than curvature explains) meet at a crease
  double chord_balance = 1.5;  ///< multiple of the mean edge sag a vertex moves outward (0: vertices on the surface)
  double fragment_fraction =
      0.02;                     ///< drop components with fewer triangles than this fraction of their piece's largest
  bool keep_fragments = false;  ///< keep every component
  double max_move = 0.0;        ///< a projection moving a vertex further is not trusted (0: unbounded)
  /// Record in mesh.normals each projected vertex's fitted normal (the
  /// quadric's, at the point it was projected to, on the side the
  /// triangles face), and (0, 0, 0) where there is none: crease and corner
  /// vertices, unmoved ones (vertex_normals.h fills those). False: no normals.
  bool fitted_normals = false;
  /// Put back the vertices whose move made triangles cross or a vertex
  /// pinched (see "Untangle" above): an embedded mesh, at its cost. False:
  /// the mesh as steps 1-3 leave it (not embedded in general).
  bool keep_embedding = false;
};

/// What the refinement reads: the surface fits of phase I (origins on the
/// surface, unoriented normals, curvature), phase III's f (which picks the
/// plane a vertex belongs to, as it did for the lattice corners), and the
/// piece of data each plane belongs to.
struct RefinementInput {
  std::span<const Vec3> origins;
  std::span<const Vec3> normals;   ///< unit, as local_quadrics.h gives them (unoriented)
  std::span<const Vec3> oriented;  ///< the same normals oriented (phase II), which tell convex edges from concave
  std::span<const Curvature> curvature;
  const SignedDistance<3>* distance = nullptr;  ///< over these origins
  /// Per plane, the spacing of the samples there (phase I's gap_i); empty:
  /// open boundaries are not cut back (step 4).
  std::span<const float> spacing;
  std::span<const std::uint32_t> piece;  ///< per plane, its component in phase II (empty: one piece)
  /// Noisy data: each vertex is projected onto the quadrics of this many
  /// origins around it and the points averaged (1: its plane's alone).
  int blend = 1;
  const KdTree<3>* origin_tree = nullptr;  ///< over `origins`; needed when blend > 1
  /// The samples: a triangle whose three vertices all lie farther than
  /// reach * rho_i + delta (rho_i of each vertex's plane) from every sample
  /// is no part of the surface but a fin drawn where two sheets lie closer
  /// than a cell (step 4). f itself reaches about 1.5 rho_i + delta past
  /// the data; 5 leaves every mesh of the real scans tried as it was (at 1.5
  /// and 3 the sparse distcap and oni lost triangles of their surface).
  /// Null: not looked for.
  const KdTree<3>* sample_tree = nullptr;
  std::span<const float> local_rho;  ///< per plane, phase I's rho_i (with sample_tree)
  double delta = 0.0;
  double reach = 5.0;
};

struct Refinement {
  Mesh mesh;  ///< the refined mesh (same coordinates as the contoured one)
  /// Per vertex of `mesh`: how far it lies from where the contoured mesh had
  /// it (for a vertex added on a crease, from the midpoint of the edge it split).
  std::vector<float> displacement;
  std::size_t crease_vertices = 0;     ///< vertices added on creases
  std::size_t brought_back = 0;        ///< vertices moved back onto a crease they were projected past
  std::size_t corner_vertices = 0;     ///< vertices added at corners
  std::size_t unmoved = 0;             ///< vertices whose projection moved them further than max_move
  std::size_t put_back = 0;            ///< vertices put back toward the contoured mesh (untangling)
  std::size_t trimmed = 0;             ///< triangles cut off past open boundaries
  std::size_t stray_triangles = 0;     ///< triangles dropped beyond f's reach from every sample (step 4)
  std::size_t fragments = 0;           ///< components dropped (see above)
  std::size_t fragment_triangles = 0;  ///< their triangles
  double seconds = 0.0;
};

/// Steps 1 to 3, and per vertex and triangle what step 4 decides by.
struct RefinedPatch {
  static constexpr std::uint32_t none = UINT32_MAX;
  Mesh mesh;                        ///< nothing removed yet
  std::vector<float> displacement;  ///< per vertex (as Refinement's)
  /// Per vertex, the contoured vertex it was moved from ({v, none}), or for
  /// a vertex added on a crease the two ends of the contoured edge it splits.
  std::vector<std::array<std::uint32_t, 2>> stem;
  std::vector<std::uint8_t> covered;  ///< per vertex: within the local spacing of a sample (4a)
  std::vector<std::uint8_t> far;      ///< per vertex: beyond f's reach from every sample (4b; 0 without sample_tree)
  std::vector<std::uint32_t> piece;   ///< per vertex: the piece of data it stands for (none at a corner)
  std::vector<std::uint32_t> source;  ///< per triangle: the contoured triangle it was cut from
  std::size_t crease_vertices = 0, brought_back = 0, corner_vertices = 0, unmoved = 0, put_back = 0;

  /// Keeps the triangles marked 1 and the vertices they use, in order, with their per-vertex entries.
  /// Cost: O(V + F).
  /// Throws: nothing.
  /// Pre: keep_triangle holds one entry per triangle.
  void keep(const std::vector<std::uint8_t>& keep_triangle);
};

/// Steps 1 to 3 on `contoured` (phase IV's mesh, or part of it), with what step 4 needs marked, nothing removed.
/// Cost: O(V log n) for V vertices over n planes: a nearest-plane query each (and a blend-NN and a sample query
/// when asked), then O(V + F) for the local steps.
/// Throws: InvalidInputError when origins, both normals, curvature and piece (if given) differ in length, there are
/// no planes, f is missing, or blend > 1 without a tree over the origins; what an interruption check throws
/// (interruption.h).
/// Pre: the mesh in the origins' coordinates, its indices in range; spacing and local_rho empty or one per plane.
[[nodiscard]] RefinedPatch refine_patch(const Mesh& contoured, const RefinementInput& input,
                                        const RefinementOptions& options = {});
/// The whole of phase V: refine_patch, then step 4 over the whole mesh.
/// Cost: as refine_patch, plus O(V + F) for step 4.
/// Throws: as refine_patch.
/// Pre: as refine_patch.
[[nodiscard]] Refinement refine_mesh(const Mesh& contoured, const RefinementInput& input,
                                     const RefinementOptions& options = {});

}  // namespace recon
