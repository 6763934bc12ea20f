#pragma once
// The whole of Hoppe's algorithm in one call: phases I to IV, keeping every
// phase's result (the visual feedback and the statistics read them).

#include "recon/marching_cubes.h"
#include "recon/orientation.h"
#include "recon/signed_distance.h"
#include "recon/tangent_planes.h"

#include <functional>
#include <optional>

namespace recon {

struct ReconstructionOptions {
  TangentPlaneOptions planes{};            ///< phase I: k, rho
  OrientationOptions orientation{};        ///< phase II (its k is the k phase I used)
  SignedDistanceOptions distance{};        ///< phase III: delta
  std::optional<double> cell;              ///< phase IV cube side; default rho (as in Hoppe's paper)
  std::optional<int> resolution;           ///< or: cubes along the longest side of the bounding box
  bool use_input_normals = false;          ///< orient with the cloud's own normals, skipping phase II
  std::size_t max_cubes = 0;               ///< refuse larger lattice walks; 0: what half the physical memory holds
                                           ///< at about 250 bytes a cube
  bool keep_corners = false;               ///< keep the evaluated lattice corners in the result
  /// Called as each phase starts, with its name ("tangent planes",
  /// "orientation", "signed distance", "contouring"): for progress displays.
  std::function<void(const char* phase)> on_phase;
};

/// Per-point results (planes, normals, graph vertices) are indexed in
/// spatial order (spatial_order.h): entry j is input point order[j], at
/// position points[j].
struct Reconstruction {
  std::vector<std::uint32_t> order;            ///< spatial order of the input points
  std::vector<Vec3> points;                    ///< the input positions in that order
  TangentPlanes<3> planes;
  std::optional<OrientedNormals<3>> oriented;  ///< absent when the input normals were used
  std::vector<Vec3> normals;                   ///< the oriented normals used by phase III
  std::optional<KdTree<3>> origin_tree;        ///< built here when phase II did not
  double delta = 0.0;
  bool delta_given = false;
  MarchingCubesResult contour;                 ///< the mesh and the lattice statistics
  double seconds_distance_setup = 0.0;
};

/// Throws what the phases throw (InvalidInputError for unusable data or
/// parameters, ResourceLimitError for a lattice too large), and
/// InvalidInputError when use_input_normals is set but the cloud has none.
[[nodiscard]] Reconstruction reconstruct(const PointCloud& cloud, const ReconstructionOptions& options = {});

/// The cube side that `options` asks for, given the phase I result.
[[nodiscard]] double lattice_cell(const PointCloud& cloud, const TangentPlanes<3>& planes,
                                  const ReconstructionOptions& options);

}  // namespace recon
