// Step 2 of a tiled run (tiles.h): phases I and II on each tile with its
// border, the planes written for step 4 and the border samples' signs for
// step 3.
#include "recon/core/timer.h"
#include "recon/reconstruct_parts.h"
#include "recon/tiles/tiles.h"
#include "tiles/files.h"
#include "tiles/tile_input.h"

namespace recon {

using tile_files::BorderRecord;
using tile_files::CoreBox;
using tile_files::DipoleRecord;
using tile_files::Orientation;
using tile_files::outside_core;
using tile_files::PieceTop;
using tile_files::TilePoints;
using namespace tile_input;

namespace {
// Sample j (spatial order) as its piece's winding number reads it.
DipoleRecord dipole(const Reconstruction& r, std::size_t j, std::uint32_t piece) {
  const Vec3& x = r.planes.origins[j];
  const Vec3 an = sample_area<3>(r.planes.radius[j], r.planes.k) * r.oriented->normals[j];
  return {{static_cast<float>(x.x()), static_cast<float>(x.y()), static_cast<float>(x.z())},
          {static_cast<float>(an.x()), static_cast<float>(an.y()), static_cast<float>(an.z())},
          piece};
}

// What the reconciliation needs of one oriented sample j (spatial order).
void note_sample(const TilePlan& plan, const CoreBox& core, const Reconstruction& r, const TilePoints& points,
                 std::size_t j, Orientation& o) {
  const Vec3 w = r.points()[j];
  const std::uint32_t t = r.order[j];
  const double out = outside_core(plan, core, w);
  const std::uint32_t piece = o.piece[t];
  if (out <= 0.0) {  // a core sample: each is one tile's
    PieceTop& top = o.tops[piece];
    if (std::tie(w.z(), top.index) > std::tie(top.z, points.index[t]) || top.index == UINT64_MAX)
      top = {w.z(), points.index[t]};
    if (r.planes.local_rho[j] > 0.0f) o.dipoles.push_back(dipole(r, j, piece));
  }
  if (out > plan.exact_margin) return;
  if (r.planes.local_rho[j] > 0.0f && out + 2.0 * static_cast<double>(r.planes.radius[j]) > plan.halo) ++o.inexact;
  if (out < -plan.exact_margin) return;
  const Vec3 n = r.oriented->normals[j];
  o.border.push_back(
      {points.index[t], piece, {static_cast<float>(n.x()), static_cast<float>(n.y()), static_cast<float>(n.z())}});
}

Orientation orient_points(const TilePlan& plan, const CoreBox& core, Reconstruction& r, const TilePoints& points) {
  const ReconstructionOptions options = tile_files::tile_options(plan);
  OrientationOptions orientation = orientation_options(r, options);
  orientation.turn_nested = false;  // (decided over all tiles: step3_reconcile.cpp)
  RiemannianGraph<3> graph = build_riemannian_graph<3>(r.planes, orientation.graph);
  r.planes.neighbors = {};
  r.oriented = orient_normals<3>(r.planes, std::move(graph), orientation);
  Orientation o;
  const std::size_t n = points.positions.size();
  o.sign.resize(n);
  o.piece.resize(n);
  o.tops.resize(r.oriented->component_count());
  for (std::size_t j = 0; j < n; ++j) {
    o.sign[r.order[j]] = r.oriented->normals[j].dot(r.planes.normals[j]) >= 0.0 ? 1 : -1;
    o.piece[r.order[j]] = r.oriented->graph.components.label[j];
  }
  for (std::size_t j = 0; j < n; ++j) note_sample(plan, core, r, points, j, o);
  std::sort(o.border.begin(), o.border.end(),
            [](const BorderRecord& a, const BorderRecord& b) { return a.index < b.index; });
  return o;
}

// What step 4 needs of phase I, so that it does not run it again: per
// sample (spatial order) the plane, rho_i and the crease band, and for
// phase V the curvature and spacing; and the order that the kd-tree over
// the tile's points gives (step 4 builds the same tree, and checks it is
// the same).
void write_planes(const std::filesystem::path& path, const Reconstruction& r) {
  detail::BinaryWriter out(path, tile_files::planes_magic);
  out.put_vector<std::uint32_t>(r.order);
  std::vector<double> coordinates;
  coordinates.reserve(6 * r.order.size());
  for (const auto* vectors : {&r.planes.origins, &r.planes.normals})
    for (const Vec3& v : *vectors) coordinates.insert(coordinates.end(), {v.x(), v.y(), v.z()});
  out.put_vector<double>(coordinates);
  out.put_vector<float>(r.planes.local_rho);
  out.put_vector<std::uint8_t>(r.quadrics ? std::span<const std::uint8_t>(r.quadrics->near_crease)
                                          : std::span<const std::uint8_t>());
  out.put(r.planes.noise);
  std::vector<float> curvature;
  if (r.quadrics) {
    curvature.reserve(3 * r.quadrics->curvature.size());
    for (const Curvature& c : r.quadrics->curvature) curvature.insert(curvature.end(), {c.p, c.q, c.r});
  }
  out.put_vector<float>(curvature);
  out.put_vector<float>(r.planes.local_gap);
  out.put(r.planes.rho);
  out.commit();
}

TileOrientation orient_one_tile(const std::filesystem::path& work_dir, std::size_t tile) {
  Timer timer;
  const auto& [plan, info, points] = load_tile(work_dir, tile);
  std::optional<Reconstruction> r = tile_phase_1(plan, points);
  Orientation o;
  if (r) {
    o = orient_points(plan, tile_files::core_of(plan, tile), *r, points);
    write_planes(tile_files::of_tile(work_dir, info.id, "planes"), *r);
  }
  tile_files::write_orientation(tile_files::of_tile(work_dir, info.id, "orient"), o);
  TileOrientation result;
  result.points = points.positions.size();
  result.pieces = o.tops.size();
  result.border_samples = o.border.size();
  result.inexact_samples = o.inexact;
  result.seconds = timer.elapsed();
  return result;
}

}  // namespace

TileOrientation orient_tile(const std::filesystem::path& work_dir, std::size_t tile) {
  return naming_tile("orienting", tile, [&] { return orient_one_tile(work_dir, tile); });
}

}  // namespace recon
