#include "recon/estimate_normals.h"

#include "recon/core/memory_budget.h"
#include "recon/reconstruct_parts.h"  // working_tree

namespace recon {

std::vector<Vec3> NormalEstimation::normals_in_input_order() const {
  std::vector<Vec3> normals(order.size());
  for (std::size_t j = 0; j < order.size(); ++j) normals[order[j]] = oriented.normals[j];
  return normals;
}

NormalEstimation estimate_normals(PointCloudView cloud, const NormalEstimationOptions& options) {
  const ProgressScope counting(options.progress);
  auto starting = [&](const char* phase, std::uint64_t work) {
    if (options.on_phase) options.on_phase(phase);
    if (options.progress) options.progress->start(work);
  };
  check_memory_planes_and_graph(cloud.size(), options.planes.k, memory_limit_or_default(options.max_memory));
  NormalEstimation result;
  starting("tangent planes", cloud.size());
  WorkingTree working = working_tree(cloud.positions, options.planes.tree);
  result.offset = working.offset;
  result.order = std::move(working.order);
  result.planes = estimate_tangent_planes<3>(std::move(working.tree), options.planes);
  starting("orientation", 3 * cloud.size());
  result.oriented = orient_normals<3>(result.planes, options.orientation);
  return result;
}

}  // namespace recon
