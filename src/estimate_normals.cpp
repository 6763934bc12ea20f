#include "recon/estimate_normals.h"

#include "recon/core/memory_budget.h"
#include "recon/reconstruct_parts.h"  // reconstruct_phase_1, orientation_options

#include <utility>

namespace recon {

std::vector<Vec3> NormalEstimation::normals_in_input_order() const {
  std::vector<Vec3> normals(order.size());
  for (std::size_t j = 0; j < order.size(); ++j) normals[order[j]] = oriented.normals[j];
  return normals;
}

namespace {

// The options of the reconstruct() whose phases I and II these are.
ReconstructionOptions reconstruction_options(const NormalEstimationOptions& options) {
  ReconstructionOptions run;
  run.method = options.method;
  run.planes = options.planes;
  run.orientation = options.orientation;
  run.quadrics = options.quadrics;
  run.max_memory = options.max_memory;
  run.on_phase = options.on_phase;
  run.progress = options.progress;
  return run;
}

}  // namespace

NormalEstimation estimate_normals(PointCloudView cloud, const NormalEstimationOptions& options) {
  const ProgressScope counting(options.progress);
  const ReconstructionOptions run = reconstruction_options(options);
  // Phase I as reconstruct() runs it, on the positions alone.
  Reconstruction r = reconstruct_phase_1(PointCloudView(cloud.positions, {}, {}), run);
  // Phase II as reconstruct() runs it (its options, once phase I had
  // raised k or not), without phase III's share of the work beside it.
  check_memory_planes_and_graph(r.order.size(), r.planes.k, memory_limit_or_default(options.max_memory),
                                options.method == Method::refined);
  if (options.on_phase) options.on_phase("orientation");
  if (options.progress) options.progress->start(3 * r.order.size());
  NormalEstimation result;
  result.oriented = orient_normals<3>(r.planes, orientation_options(r, run));
  result.method = r.method;
  result.offset = r.offset;
  result.order = std::move(r.order);
  result.planes = std::move(r.planes);
  result.quadrics = std::move(r.quadrics);
  if (result.quadrics) result.quadrics->guide = {};  // phase II's, as reconstruct() releases it
  return result;
}

}  // namespace recon
