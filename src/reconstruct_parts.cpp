// The parts of reconstruct() that its callers repeat (reconstruct_parts.h):
// the lattice cell, the refusal of an empty contour, each phase's options,
// phase V's input and phase I's working tree.
#include "recon/reconstruct_parts.h"

#include "recon/core/errors.h"
#include "recon/core/point_cloud.h"  // check_coordinates

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

namespace recon {

double chosen_cell(std::optional<double> cell, std::optional<int> resolution,
                   const std::function<double()>& longest_side, double fallback) {
  if (cell && resolution) throw InvalidInputError("give either a cell size or a resolution, not both");
  if (cell) {
    if (!std::isfinite(*cell) || !(*cell > 0.0)) throw InvalidInputError("the cell size must be a positive length");
    return *cell;
  }
  if (resolution) {
    if (*resolution < 1) throw InvalidInputError("the resolution must be at least 1 cell");
    return longest_side() / *resolution;
  }
  return fallback;
}

double lattice_cell(std::span<const Vec3> points, const TangentPlanes<3>& planes,
                    const ReconstructionOptions& options) {
  return lattice_cell([&] { return bounding_box<3>(points).extent().maxCoeff(); }, planes.rho, options);
}

double lattice_cell(const std::function<double()>& longest_side, double rho, const ReconstructionOptions& options) {
  const double fallback = options.method == Method::hoppe92 ? rho : rho / std::numbers::sqrt2;
  return chosen_cell(options.cell, options.resolution, longest_side, fallback);
}

void refuse_no_surface(const std::string& figures, double cell, double longest_side, const std::string& smaller_cell) {
  std::ostringstream why;
  why.precision(3);
  why << "no surface found: " << figures << "; the cloud's longest side is " << longest_side;
  if (cell >= 0.5 * longest_side)
    why << ": the cell is not smaller than half the cloud, so its cubes are too coarse to see a surface; use a cell "
           "under about "
        << 0.25 * longest_side << " (" << smaller_cell << ")";
  throw InvalidInputError(why.str());
}

SignedDistanceOptions signed_distance_options(Method method, const SignedDistanceOptions& given,
                                              const std::optional<LocalQuadrics>& quadrics) {
  SignedDistanceOptions options = given;
  if (!options.candidates) options.candidates = method == Method::refined ? 8 : 1;
  if (quadrics && options.near_crease.empty()) options.near_crease = quadrics->near_crease;
  return options;
}

RefinementInput refinement_input(const TangentPlanes<3>& planes, std::span<const Vec3> oriented,
                                 std::span<const Curvature> curvature, std::span<const std::uint32_t> piece,
                                 const SignedDistance<3>& f, const KdTree<3>& origin_tree) {
  RefinementInput input;
  input.origins = planes.origins;
  input.normals = planes.normals;
  input.oriented = oriented;
  input.curvature = curvature;
  input.distance = &f;
  input.spacing = planes.local_gap;
  // Noisy data (the fits miss their samples by over a hundredth of the
  // sampling density): blend the quadrics of 8 planes around each vertex.
  if (planes.noise > 0.01 * planes.rho) {
    input.blend = 8;
    input.origin_tree = &origin_tree;
  }
  input.piece = piece;
  input.sample_tree = &planes.point_tree;
  input.local_rho = planes.local_rho;
  input.delta = f.delta();
  return input;
}

RefinementInput refinement_input_of(const Reconstruction& r, const SignedDistance<3>& f) {
  if (!r.quadrics)
    throw InvalidInputError("refinement_input_of: the reconstruction has no second-order fits (hoppe92)");
  const std::span<const std::uint32_t> piece = r.oriented
                                                   ? std::span<const std::uint32_t>(r.oriented->graph.components.label)
                                                   : std::span<const std::uint32_t>();
  return refinement_input(r.planes, r.normals(), r.quadrics->curvature, piece, f, r.origin_tree);
}

RefinementOptions refinement_options(const RefinementOptions& given, double cell) {
  RefinementOptions options = given;
  if (options.max_move <= 0.0) options.max_move = cell;
  return options;
}

SignedDistance<3> signed_distance_of(const Reconstruction& r) {
  SignedDistanceOptions given;
  given.delta = r.delta;
  return make_signed_distance<3>(r.planes, r.normals(), r.origin_tree,
                                 signed_distance_options(r.method, given, r.quadrics));
}

Vec3 working_offset(std::span<const Vec3> points) { return working_offset(bounding_box<3>(points)); }

Vec3 working_offset(const Box<3>& box) {
  if (box.empty()) return Vec3::Zero();
  const Vec3 centre = 0.5 * (box.min + box.max);
  // Near the origin already (within its own size): nothing to gain.
  if (centre.cwiseAbs().maxCoeff() <= box.diagonal()) return Vec3::Zero();
  return centre;
}

namespace {
WorkingTree checked_working_tree(std::span<const Vec3> points, const KdTreeOptions& options, const Vec3& offset) {
  WorkingTree w;
  w.offset = offset;
  w.tree = KdTree<3>(points, options, w.offset);
  w.order = w.tree.renumber_by_leaf_order();
  return w;
}
}  // namespace

WorkingTree working_tree(std::span<const Vec3> points, const KdTreeOptions& options) {
  check_coordinates<3>(points);  // before the bounding box of working_offset
  return checked_working_tree(points, options, working_offset(points));
}

WorkingTree working_tree(std::span<const Vec3> points, const KdTreeOptions& options, const Vec3& offset) {
  check_coordinates<3>(points);
  return checked_working_tree(points, options, offset);
}

OrientationOptions orientation_options(const Reconstruction& r, const ReconstructionOptions& options) {
  OrientationOptions orientation = options.orientation;
  if (options.method == Method::refined) orientation.sign_by_extremes = true;
  if (r.quadrics) {
    orientation.sheet_misfit = r.quadrics->residual;
    orientation.guide = r.quadrics->guide;
  }
  return orientation;
}

}  // namespace recon
