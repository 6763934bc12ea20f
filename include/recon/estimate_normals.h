#pragma once
// Phases I and II in one call: consistently oriented normals for a cloud,
// as `recon normals` and the Python package's estimate_normals() give them.
// They are the normals reconstruct() of the same method orients and phase
// III then reads (Reconstruction::normals()), bit for bit: the same code
// runs (reconstruct_phase_1, then phase II with orientation_options).
//
// The textbook version (Method::hoppe92), the paper's phases I and II:
//   planes   = estimate_tangent_planes(points)   phase I: k neighbours, centroid, PCA normal
//   oriented = orient_normals(planes)            phase II: Riemannian graph, MST, propagation from the top
// What the refined method (the default) changes, and why:
//   - phase I fits a quadric per neighbourhood and moves each plane onto it
//     (local_quadrics.h): its origin lies on the surface, its normal is the
//     fitted surface's, which tells two facing sheets apart;
//   - phase II decides each piece's side at its best extreme rather than at
//     its highest point (a tall cone's top is its apex, whose normal is
//     nearly horizontal: there the 1992 rule turns the whole cone inside
//     out), walks with phase I's PCA normals as a guide around sharp
//     creases, carries the orientation reversed between facing sheets and
//     turns faces found inside out across a crease (orientation.h).
// The fits tell two sheets apart from 1.5 lattice cells; the cell is
// reconstruct()'s default, rho / sqrt 2 (quadrics.min_sheet_separation
// sets the distance itself).
//
// The points are moved near the origin first (working_offset in
// reconstruct_parts.h) and worked on in the kd-tree's leaf order, as
// reconstruct() does; normals_in_input_order() gives the result back in the
// input's order.
//
// Cost: O(n k log n) for n points at k: phase I's neighbour searches and fits, phase II's graph and its
// spanning tree (Prim, O(E log n) for its E ~ n k edges); the refined method adds a quadric fit per
// neighbourhood, O(n k).

#include "recon/core/point_cloud.h"
#include "recon/core/progress.h"
#include "recon/phase1_planes/local_quadrics.h"
#include "recon/phase1_planes/tangent_planes.h"
#include "recon/phase2_orientation/orientation.h"
#include "recon/reconstruct.h"  // Method

#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <vector>

namespace recon {

struct NormalEstimationOptions {
  Method method = Method::refined;   ///< refined (the default) or hoppe92 (the 1992 phases, see above)
  TangentPlaneOptions planes{};      ///< phase I: k (raised for noise unless adapt_k is off), rho
  OrientationOptions orientation{};  ///< phase II (the refined method adds its own parts, as reconstruct())
  LocalQuadricOptions quadrics{};    ///< phase I's second-order fits (refined only)
  /// Refuse, before allocating, work estimated to need more memory (bytes);
  /// 0: default_memory_limit().
  std::size_t max_memory = 0;
  /// Called as each phase starts ("tangent planes", "orientation").
  std::function<void(const char* phase)> on_phase;
  /// Counts each phase's work, as ReconstructionOptions::progress does
  /// (points, twice over in the refined method, then 3 per point); null: nothing is counted.
  ProgressCounter* progress = nullptr;
};

struct NormalEstimation {
  Method method = Method::refined;   ///< the method that ran
  Vec3 offset = Vec3::Zero();        ///< subtracted from the input before phase I
  std::vector<std::uint32_t> order;  ///< input index of each point, in spatial order
  /// Phase I, in spatial order (relative to offset); in the refined method
  /// the planes moved onto the fits (their origins and normals).
  TangentPlanes<3> planes;
  /// Phase I's second-order fits (refined only): their figures, curvature and residuals.
  std::optional<LocalQuadrics> quadrics;
  OrientedNormals<3> oriented;  ///< phase II, in spatial order, with its graph and spanning tree

  /// The input positions in spatial order, minus offset.
  [[nodiscard]] std::span<const Vec3> points() const { return planes.point_tree.points(); }
  /// The oriented normals, entry i for input point i.
  /// Cost: O(n).
  /// Throws: nothing.
  /// Pre: none.
  [[nodiscard]] std::vector<Vec3> normals_in_input_order() const;
};

/// Phases I and II of options.method on `cloud` (its positions; colours and normals are not read): planes and
/// oriented normals, in spatial order; the normals reconstruct() of that method orients, bit for bit.
/// Cost: O(n k log n) (see above).
/// Throws: InvalidInputError for unusable data or parameters (what reconstruct() throws before and in phases
/// I and II); ResourceLimitError when phases I-II are estimated to need more than max_memory (checked before
/// phase I, and again when phase I raised k); what on_phase or an interruption check throws.
/// Pre: none.
[[nodiscard]] NormalEstimation estimate_normals(PointCloudView cloud, const NormalEstimationOptions& options = {});

}  // namespace recon
