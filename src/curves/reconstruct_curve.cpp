#include "recon/curves/reconstruct_curve.h"

#include "recon/core/timer.h"
#include "recon/reconstruct_parts.h"  // chosen_cell

#include <functional>
#include <vector>

namespace recon {

double curve_lattice_cell(std::span<const Vec2> points, double rho, const CurveReconstructionOptions& options) {
  return chosen_cell(
      options.cell, options.resolution, [&] { return bounding_box<2>(points).extent().maxCoeff(); }, 0.5 * rho);
}

CurveReconstruction reconstruct_curve(std::span<const Vec2> points, const CurveReconstructionOptions& options) {
  CurveReconstruction r;
  r.planes = estimate_tangent_planes<2>(points, options.planes);
  const double cell = curve_lattice_cell(points, r.planes.rho, options);
  r.oriented = orient_normals<2>(
      r.planes, build_orientation_graph<2>(r.planes, options.graph, options.orientation.graph), options.orientation);

  Timer timer;
  r.origin_tree = r.planes.point_tree.refit(r.planes.origins);
  const SignedDistance<2> f =
      make_signed_distance<2>(r.planes, std::span<const Vec2>(r.oriented.normals), r.origin_tree, options.distance);
  r.delta = f.delta();
  r.delta_given = f.delta_given();
  r.seconds_distance_setup = timer.lap();

  MarchingSquaresOptions squares;
  squares.cell = cell;
  squares.max_slope = options.max_slope;
  squares.max_squares = options.max_squares;
  // Seeds: the samples, and the tangent lines' origins, where f vanishes
  // (each origin is its own nearest): with few samples around a tight bend
  // the lines pass a square or more inside the samples, and a walk started
  // from the samples alone would not find them.
  std::vector<Vec2> seeds(points.begin(), points.end());
  seeds.insert(seeds.end(), r.planes.origins.begin(), r.planes.origins.end());
  squares.keep_corners = options.keep_corners;
  r.contour = marching_squares(std::cref(f), seeds, squares);
  return r;
}

}  // namespace recon
