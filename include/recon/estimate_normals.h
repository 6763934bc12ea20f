#pragma once
// Phases I and II in one call: consistently oriented normals for a cloud,
// as `recon normals` and the Python package's estimate_normals() give them.
//
//   planes   = estimate_tangent_planes(points)   phase I: k neighbours, centroid, PCA normal
//   oriented = orient_normals(planes)            phase II: Riemannian graph, MST, propagation
//
// The points are moved near the origin first (working_offset in
// reconstruct.h) and worked on in the kd-tree's leaf order, as reconstruct()
// does; normals_in_input_order() gives the result back in the input's order.
//
// Cost: O(n k log n) for n points at k: phase I's neighbour searches and fits, phase II's graph and its
// spanning tree (Prim, O(E log n) for its E ~ n k edges).

#include "recon/core/point_cloud.h"
#include "recon/core/progress.h"
#include "recon/phase1_planes/tangent_planes.h"
#include "recon/phase2_orientation/orientation.h"

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

namespace recon {

struct NormalEstimationOptions {
  TangentPlaneOptions planes{};      ///< phase I: k (raised for noise unless adapt_k is off), rho
  OrientationOptions orientation{};  ///< phase II
  /// Refuse, before allocating, work estimated to need more memory (bytes);
  /// 0: default_memory_limit().
  std::size_t max_memory = 0;
  /// Called as each phase starts ("tangent planes", "orientation").
  std::function<void(const char* phase)> on_phase;
  /// Counts each phase's work, as ReconstructionOptions::progress does
  /// (points, then 3 per point); null: nothing is counted.
  ProgressCounter* progress = nullptr;
};

struct NormalEstimation {
  Vec3 offset = Vec3::Zero();        ///< subtracted from the input before phase I
  std::vector<std::uint32_t> order;  ///< input index of each point, in spatial order
  TangentPlanes<3> planes;           ///< phase I, in spatial order (relative to offset)
  OrientedNormals<3> oriented;       ///< phase II, in spatial order

  /// The input positions in spatial order, minus offset.
  [[nodiscard]] std::span<const Vec3> points() const { return planes.point_tree.points(); }
  /// The oriented normals, entry i for input point i.
  /// Cost: O(n).
  /// Throws: nothing.
  /// Pre: none.
  [[nodiscard]] std::vector<Vec3> normals_in_input_order() const;
};

/// Phases I and II on `cloud` (its positions; colours and normals are not read): planes and oriented normals,
/// in spatial order.
/// Cost: O(n k log n) (see above).
/// Throws: InvalidInputError for unusable data or parameters (what phases I and II throw); ResourceLimitError when
/// phases I-II are estimated to need more than max_memory; what on_phase or an interruption check throws.
/// Pre: none.
[[nodiscard]] NormalEstimation estimate_normals(PointCloudView cloud, const NormalEstimationOptions& options = {});

}  // namespace recon
