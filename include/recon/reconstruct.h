#pragma once
// The whole of Hoppe's algorithm in one call: phases I to IV, keeping every
// phase's result (the visual feedback and the statistics read them).
//
// Colours travel: when the cloud has colours, the result keeps them (in
// spatial order, Reconstruction::colors) and the final mesh (phase V's, or
// phase IV's in hoppe92) gets one per vertex, Mesh::colors: a blend of the
// colours of the k samples nearest the vertex, weighted by inverse squared
// distance (vertex_colors.h says why a blend rather than the nearest
// sample). Phase IV's mesh of a refined run, an intermediate, has none.
// ReconstructionOptions::mesh_colors turns this off.
//
// This is the front door: the options, the result and reconstruct(). The
// parts reconstruct() is made of, for callers that repeat some of them on
// their own (the tiles, the 2D curves, estimate_normals()), are in
// reconstruct_parts.h.

#include "recon/core/memory_budget.h"  // what reconstruct() refuses with ResourceLimitError
#include "recon/core/progress.h"
#include "recon/core/resource_usage.h"  // default_memory_limit
#include "recon/phase1_planes/local_quadrics.h"
#include "recon/phase1_planes/tangent_planes.h"
#include "recon/phase2_orientation/orientation.h"
#include "recon/phase3_distance/signed_distance.h"
#include "recon/phase4_contour/marching_cubes.h"
#include "recon/phase5_refine/refinement.h"
#include "recon/phase5_refine/vertex_colors.h"
#include "recon/phase5_refine/vertex_normals.h"
#include "recon/phase6_simplify/simplification.h"

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string_view>

namespace recon {

/// Phase VI, optional (simplification.h): what reconstruct() asks of
/// simplify() after phase V (phase IV in hoppe92), before the colours. Off
/// unless one of the three is given; with several, it stops at whichever
/// comes first.
struct SimplifyStep {
  std::size_t triangles = 0;  ///< stop at this many triangles (0: none)
  double ratio = 0.0;         ///< or at this fraction of them (0 < ratio < 1; 0: none)
  double max_error = 0.0;  ///< a bound on the distance of the unsimplified mesh's vertices, a multiple of rho (0: none)
  [[nodiscard]] bool requested() const { return triangles > 0 || ratio != 0.0 || max_error != 0.0; }
};

/// Which pipeline runs.
/// - refined (the default): phase I fits a quadric per neighbourhood and
///   moves each plane onto it (local_quadrics.h), phase IV contours at
///   rho / sqrt 2, and phase V (refinement.h) moves the mesh onto the
///   quadrics, sharpens creases and drops fragments.
/// - hoppe92: the paper's four phases exactly (planes through centroids, a
///   cell of rho, the contoured mesh as it comes), as the course teaches them.
enum class Method { refined, hoppe92 };

struct ReconstructionOptions {
  Method method = Method::refined;
  TangentPlaneOptions planes{};      ///< phase I: k, rho
  OrientationOptions orientation{};  ///< phase II (its k is the k phase I used)
  SignedDistanceOptions distance{};  ///< phase III: delta
  LocalQuadricOptions quadrics{};    ///< phase I's second-order fits (refined only)
  RefinementOptions refinement{};    ///< phase V (refined only)
  SimplifyStep simplify{};           ///< phase VI, optional (off by default)
  std::optional<double> cell;  ///< phase IV cube side; default rho (hoppe92, as in the paper), rho / sqrt 2 (refined)
  std::optional<int> resolution;   ///< or: cubes along the longest side of the bounding box
  bool use_input_normals = false;  ///< orient with the cloud's own normals, skipping phase II
  /// Refuse, before allocating, work estimated to need more memory (bytes);
  /// 0: default_memory_limit(). The estimates are memory_budget.h's.
  std::size_t max_memory = 0;
  bool keep_corners = false;  ///< keep the evaluated lattice corners in the result
  /// Move the cloud by this instead of working_offset (see Reconstruction):
  /// a tile of a larger cloud takes the whole cloud's (tiles.h).
  std::optional<Vec3> offset;
  /// Keep phase II's graph, EMST and spanning tree in the result (for
  /// inspection); when false they are released once the normals are
  /// oriented, before phases III and IV need their memory (on 10M points,
  /// about 1 GB). Their sizes stay in RiemannianGraph::edge_count.
  bool keep_graph = true;
  /// Give the final mesh the cloud's colours, when it has them (see above);
  /// false: the mesh has none (the colours are still kept in the result).
  bool mesh_colors = true;
  VertexColorOptions colors{};  ///< how the mesh's colours are blended
  /// Give the final mesh a unit normal per vertex (Mesh::normals): phase
  /// V's fitted normal where it has one, the area-weighted mean of the
  /// triangles' elsewhere (vertex_normals.h). False: none (the default, so
  /// outputs that do not ask stay as they were).
  bool vertex_normals = false;
  /// Called as each phase starts, with its name ("tangent planes",
  /// "orientation", "signed distance", "contouring", "refinement" in the
  /// refined method, "simplification" when asked, and "colours" when the
  /// mesh is coloured): for progress
  /// displays.
  std::function<void(const char* phase)> on_phase;
  /// Counts each phase's work as it runs, for a display to read (see
  /// progress.h); null: nothing is counted. Just after on_phase, it is
  /// started with the phase's total: points for "tangent planes" (twice
  /// over in the refined method: planes, then fits), 3 per point for
  /// "orientation" (the EMST's merges, the graph's rows, Prim's vertices),
  /// the cubes the walk is estimated to visit for "contouring", the
  /// vertices for "refinement"; 0 (not counted) for the short ones.
  ProgressCounter* progress = nullptr;
};

/// The method named "refined" or "hoppe92".
/// Cost: O(1).
/// Throws: InvalidInputError for another name.
/// Pre: none.
[[nodiscard]] Method method_from_name(std::string_view name);
/// The method's name, as method_from_name reads it. Cost: O(1). Throws: nothing. Pre: none.
[[nodiscard]] const char* method_name(Method method);

/// One of the far-apart clusters of a cloud too wide for one lattice (see
/// reconstruct()): its samples and the lattice its surface was contoured on.
struct ClusterLattice {
  std::size_t points = 0;              ///< samples in the cluster
  Vec3 origin = Vec3::Zero();          ///< its lattice's corner (0, 0, 0), relative to Reconstruction::offset
  std::array<std::int32_t, 3> size{};  ///< its lattice's cubes along each axis
  std::size_t triangles = 0;           ///< its triangles in phase IV's mesh (the clusters' follow one another)
};

/// Per-point results (planes, normals, graph vertices) are indexed in
/// spatial order, the leaf order of phase I's kd-tree: entry j is input
/// point order[j], at position points()[j]. Nothing is copied twice: the
/// points live in that tree only, and planes.neighbors is released once
/// phase II has built its graph from it (it is the largest array of the run).
///
/// Far from the origin (a geo-referenced scan: coordinates of 1e7 with
/// millimetre spacing) coordinates share a large common part. The phases
/// work on differences of doubles and keep their precision there (measured:
/// the same mesh to 1 um), but anything that stores or multiplies raw
/// coordinates in lower precision would not: single-precision copies for
/// display, lattice corners, products in a plane fit. The cloud is therefore
/// moved near the origin first (by `offset`, see working_offset): every
/// per-point and lattice result below (points, planes, the corners) is
/// relative to `offset`, and only the mesh is moved back to the input's
/// coordinates.
struct Reconstruction {
  Vec3 offset = Vec3::Zero();        ///< subtracted from the input before phase I (see above)
  std::vector<std::uint32_t> order;  ///< input index of each point, in spatial order
  TangentPlanes<3> planes;
  std::optional<OrientedNormals<3>> oriented;  ///< absent when the input normals were used
  std::vector<Vec3> input_normals;             ///< the input's own normals (unit, spatial order), when used
  /// The input's colours in spatial order (colors[j] is input point
  /// order[j]'s); empty when it had none. 3 bytes a point.
  std::vector<Color> colors;
  KdTree<3> origin_tree;  ///< over the plane origins: phase III's nearest-plane queries

  /// The input positions in spatial order.
  [[nodiscard]] std::span<const Vec3> points() const { return planes.point_tree.points(); }  // minus offset
  /// The oriented normals phase III used.
  [[nodiscard]] std::span<const Vec3> normals() const {
    return oriented ? std::span<const Vec3>(oriented->normals) : std::span<const Vec3>(input_normals);
  }
  double delta = 0.0;
  bool delta_given = false;
  Method method = Method::refined;
  /// Phase I's second-order fits (refined): their origins and normals have
  /// moved into `planes` (which the later phases read), phase I's normals
  /// were here while phase II used them (released after); the curvature,
  /// residuals and counts stay here.
  std::optional<LocalQuadrics> quadrics;
  MarchingCubesResult contour;  ///< phase IV's mesh (input coordinates) and the lattice statistics
  /// Empty when one lattice covers the cloud (the usual case). Otherwise
  /// the far-apart clusters that draw a surface, one lattice each, in the
  /// order their meshes follow one another in `contour`; `contour` then
  /// sums their statistics, and its origin and size, which no single
  /// lattice has, are zero, and it keeps no corners (their indices are each
  /// lattice's own).
  std::vector<ClusterLattice> clusters;
  std::optional<Refinement> refinement;  ///< phase V's mesh (input coordinates), refined only
  /// Phase VI's mesh (input coordinates), when options.simplify asked for
  /// it; its vertex_error is in input units (divide by planes.rho for the
  /// multiple of rho).
  std::optional<Simplification> simplification;
  /// The result: phase VI's mesh when there is one, else phase V's, else phase IV's.
  [[nodiscard]] const Mesh& mesh() const {
    return simplification ? simplification->mesh : refinement ? refinement->mesh : contour.mesh;
  }
  [[nodiscard]] Mesh& mesh() {
    return simplification ? simplification->mesh : refinement ? refinement->mesh : contour.mesh;
  }
  /// Phase III's time outside phase II: f's set-up, and the first wave's
  /// corners still to evaluate once the orientation was done.
  double seconds_distance_setup = 0.0;
  /// Phase III's time on a thread of its own beside phase II's Prim: the
  /// tree over the origins, and f at the corners of the lattice cubes that
  /// hold a sample, from the unoriented planes (signs are fixed afterwards).
  double seconds_distance_beside = 0.0;
  double seconds_colors = 0.0;  ///< giving the mesh its colours (0 when it has none)
  FaceNormalFill face_normals;  ///< the normals filled from the faces (vertex_normals)
};

/// A triangle mesh from `cloud`, by the phases in order, keeping every
/// phase's result. alternatives/reference.h writes the same phases out
/// plainly; here, with more than one thread, phase III's values at the
/// corners of the cubes that hold a sample are computed on a thread of
/// their own while phase II's Prim (serial) runs, from the unoriented
/// planes, which gives the same result bit for bit (src/first_wave.h).
///
/// Far-apart clusters. One lattice over the whole cloud needs at most
/// Lattice<3>::max_cells_per_axis cubes along an axis (2^21 - 2: its keys
/// have 21 bits an axis). When the cloud's bounding box needs more (two
/// objects 1e9 apart at a cell of 0.01), phases I-III still run over the
/// whole cloud as always (so k, rho, delta, the cell and the medians are the
/// whole cloud's), and then the cloud is split into clusters at every empty
/// slab along an axis (recursively) wider than twice the farthest reach of
/// any phase (the widest neighbourhood of a sample that draws, f's reach
/// past a plane, phase V's, a lattice's margin): no phase links two of them.
/// Each cluster is contoured (phase IV) on a lattice over its own samples (a
/// cluster of stray points draws nothing and is skipped), as a run over that
/// cluster alone with the same choices would be; phase V refines the meshes,
/// concatenated in the clusters' order (Reconstruction::clusters). This
/// costs a sort of the samples per axis and level of splitting, and nothing
/// when one lattice fits (the usual case, whose result it leaves bit for bit
/// as it was). Phase II's first wave is not computed beside it then.
///
/// Cost: textbook (reference.h) O(n^2) for n points; here O(n k log n)
/// expected at k neighbours (phase I's searches and phase II's Prim
/// dominate), plus O(c) for the c lattice cubes the surface crosses (about
/// n at the default cell), phases I and III-V on all threads.
/// Throws: InvalidInputError for unusable data or parameters, checked
/// before phase I where they can be (a simplify step's values, the cell or
/// resolution, use_input_normals on a cloud without normals, colours not
/// one per point), later what the phases throw, a triangle target above the
/// mesh's triangles, and "no surface found" when phase IV finds none (the
/// message gives the cell, rho, delta and the cloud's size, and says to
/// lower the cell when it is as large as the cloud) rather than return an
/// empty mesh; ResourceLimitError when the memory estimated before phases
/// I-II or before the lattice (memory_budget.h) exceeds max_memory, or a
/// single cluster is too wide for one lattice; whatever the installed
/// interruption check throws (core/interruption.h).
/// Pre: none.
[[nodiscard]] Reconstruction reconstruct(const PointCloud& cloud, const ReconstructionOptions& options = {});
/// The same on a cloud held elsewhere (numpy arrays, a memory map): read in
/// place, never copied; phase I's kd-tree makes the one working copy of the
/// positions (moved by `offset`, in its leaf order), as in every form here.
[[nodiscard]] Reconstruction reconstruct(PointCloudView cloud, const ReconstructionOptions& options = {});
/// The same, consuming the cloud: its arrays are released as soon as phase
/// I's kd-tree holds the points, which lowers the peak memory.
[[nodiscard]] Reconstruction reconstruct(PointCloud&& cloud, const ReconstructionOptions& options = {});
/// The three above: `release` is called as soon as nothing more is read
/// from `cloud` (the caller may free it then). Cost, Throws: reconstruct()'s.
/// Pre: `cloud`'s arrays live until `release` is called.
[[nodiscard]] Reconstruction reconstruct_from(PointCloudView cloud, const ReconstructionOptions& options,
                                              const std::function<void()>& release);

/// reconstruct() in two steps, for a caller that changes the later phases'
/// parameters and runs them again without phases I and II (the web page,
/// web/webapp/): phases I and II, then phases III to VI and the colours on
/// their result, as often as wanted. The mesh is reconstruct()'s bit for
/// bit (phase III's values are computed after phase II rather than beside
/// it, which gives the same values: src/first_wave.h). The graph stays in
/// the result while keep_graph asks for it. Phases I-II read options'
/// method, planes, orientation, quadrics, use_input_normals, max_memory,
/// offset, keep_graph and, in the refined method, the cell (phase I's
/// second-order fits tell two sheets apart at 1.5 cells): a later call with
/// another cell in the refined method gives reconstruct()'s mesh for that
/// cell when phases_1_2_hold_for says so; in hoppe92 it always does.
/// Cost: O(n k log n) expected, as reconstruct()'s phases I-II.
/// Throws: what reconstruct() throws for those phases.
/// Pre: none.
[[nodiscard]] Reconstruction reconstruct_phases_1_2(PointCloudView cloud, const ReconstructionOptions& options);
/// Phase II alone on `r` from reconstruct_phase_1 (below):
/// reconstruct_phases_1_2 is the two in a row (the web page shows phase I's
/// layers between them).
/// Cost: O(n k log n) expected (the graph and Prim).
/// Throws: what reconstruct() throws in phase II.
/// Pre: `r` from reconstruct_phase_1 with the same options, phase II not yet run on it.
void reconstruct_phase_2_on(Reconstruction& r, const ReconstructionOptions& options);
/// Phases III-VI and the colours on `r` (its later results, if any,
/// replaced).
/// Cost: O(n log n + c) expected, as reconstruct()'s phases III-VI.
/// Throws: what reconstruct() throws for those phases; InvalidInputError
/// when options.method is not the method of r's phase I.
/// Pre: `r` from reconstruct_phases_1_2 (or phase 1 then phase 2 on it).
void reconstruct_phases_3_on(Reconstruction& r, const ReconstructionOptions& options);
/// Whether `r`'s phases I-II are those reconstruct() would run with
/// `options`, which differ from the options r was made with in the cell or
/// the resolution at most: always in hoppe92; in the refined method when the
/// new cell's sheet separation (1.5 cells, unless options.quadrics gives one)
/// leaves every second-order fit as it was (LocalQuadrics::same_fits), and
/// never after phase I undid a raised k (its cell came from other planes).
/// Cost: O(n) (the cloud's box, for a resolution); O(1) with a cell.
/// Throws: InvalidInputError for a cell or resolution reconstruct() refuses.
/// Pre: `r` from reconstruct_phases_1_2 (or reconstruct_phase_1) with the same options but the cell and resolution.
[[nodiscard]] bool phases_1_2_hold_for(const Reconstruction& r, const ReconstructionOptions& options);
/// Phase I alone, as reconstruct() runs it: the planes, and in the refined
/// method the second-order fits (with a raised k undone where they find
/// two sheets); r.order, r.offset and r.planes (neighbour lists kept), and
/// r.quadrics. Tiled runs (tiles.h) take the cloud-wide measures from it
/// and run the later phases tile by tile.
/// Cost: O(n k log n) expected (the tree, the searches, the fits).
/// Throws: what reconstruct() throws before and in phase I.
/// Pre: none.
[[nodiscard]] Reconstruction reconstruct_phase_1(PointCloudView cloud, const ReconstructionOptions& options);

}  // namespace recon
