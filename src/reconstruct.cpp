#include "recon/reconstruct.h"

#include "recon/errors.h"
#include "recon/resource_usage.h"
#include "recon/spatial_order.h"  // permuted
#include "recon/timer.h"

#include <cmath>
#include <sstream>


namespace recon {

double lattice_cell(std::span<const Vec3> points, const TangentPlanes<3>& planes, const ReconstructionOptions& options) {
  if (options.cell && options.resolution)
    throw InvalidInputError("give either a cell size or a resolution, not both");
  if (options.cell) {
    if (!(*options.cell > 0.0) || !std::isfinite(*options.cell))
      throw InvalidInputError("the cell size must be a positive length");
    return *options.cell;
  }
  if (options.resolution) {
    if (*options.resolution < 1) throw InvalidInputError("the resolution must be at least 1 cube");
    const Box<3> box = bounding_box<3>(points);
    return box.extent().maxCoeff() / *options.resolution;
  }
  return planes.rho;
}

namespace {
constexpr double bytes_per_cube = 250.0;  // corner and edge hash entries, visited set, mesh share

std::size_t default_max_cubes() {
  const std::size_t physical = physical_memory_bytes();
  const double memory = physical > 0 ? static_cast<double>(physical) : 8e9;
  return static_cast<std::size_t>(0.5 * memory / bytes_per_cube);
}
}  // namespace

Reconstruction reconstruct(const PointCloud& cloud, const ReconstructionOptions& options) {
  return reconstruct(PointCloud(cloud), options);
}

Reconstruction reconstruct(PointCloud&& cloud, const ReconstructionOptions& options) {
  if (options.use_input_normals && !cloud.has_normals())
    throw InvalidInputError("the input has no normals to use; run without the option to estimate them");
  auto starting = [&](const char* phase) {
    if (options.on_phase) options.on_phase(phase);
  };
  Reconstruction r;
  starting("tangent planes");
  Timer tree_timer;
  KdTree<3> tree(cloud.positions, options.planes.tree);
  cloud.positions = {};
  r.order = tree.renumber_by_leaf_order();
  if (options.use_input_normals) r.input_normals = permuted<Vec3>(cloud.normals, r.order);
  cloud.normals = {};
  const double seconds_tree = tree_timer.lap();
  r.planes = estimate_tangent_planes<3>(std::move(tree), options.planes);
  r.planes.seconds_tree += seconds_tree;

  // Refuse a lattice that would not fit before building anything large.
  const double cell = lattice_cell(r.points(), r.planes, options);
  const std::size_t max_cubes = options.max_cubes > 0 ? options.max_cubes : default_max_cubes();
  const double cubes = estimate_visited_cubes(r.order.size(), r.planes.rho, cell);
  if (cubes > static_cast<double>(max_cubes)) {
    std::ostringstream message;
    message.precision(3);
    message << "a cell of " << cell << " would visit about " << cubes << " lattice cubes, about "
            << cubes * bytes_per_cube / 1e9 << " GB, more than the " << static_cast<double>(max_cubes) * bytes_per_cube / 1e9
            << " GB allowed (half the memory): use a larger --cell or a smaller --resolution";
    throw ResourceLimitError(message.str());
  }

  if (options.use_input_normals) {
    for (Vec3& n : r.input_normals) {
      const double norm = n.norm();
      if (!(norm > 0.0) || !std::isfinite(norm))
        throw InvalidInputError("the input normals include a zero or non-finite one; run without using them");
      n /= norm;
    }
    r.planes.neighbors = {};
  } else {
    starting("orientation");
    RiemannianGraph<3> graph = build_riemannian_graph<3>(r.planes, options.orientation.graph);
    r.planes.neighbors = {};  // the graph's source, no longer needed
    r.oriented = orient_normals<3>(r.planes, std::move(graph), options.orientation);
    if (!options.keep_graph) {
      r.oriented->graph.graph = {};
      r.oriented->graph.emst = {};
      r.oriented->tree = {};
    }
  }

  starting("signed distance");
  Timer timer;
  // Built only now that phase II's graph is complete: its memory and the
  // graph's need not add up.
  r.origin_tree = KdTree<3>(std::span<const Vec3>(r.planes.origins));
  const SignedDistance<3> f = make_signed_distance<3>(r.planes, r.normals(), r.origin_tree, options.distance);
  r.delta = f.delta();
  r.delta_given = f.delta_given();
  r.seconds_distance_setup = timer.lap();

  starting("contouring");
  MarchingCubesOptions mc;
  mc.cell = cell;
  mc.max_cubes = max_cubes;
  r.contour = marching_cubes(std::cref(f), r.points(), mc, options.keep_corners);
  return r;
}

}  // namespace recon
