// What steps 2 and 4 of a tiled run start from (tile_input.h).
#include "tiles/tile_input.h"

#include "recon/reconstruct_parts.h"

namespace recon::tile_input {

namespace {

const TileInfo& tile_info(const TilePlan& plan, std::size_t tile) {
  if (tile >= plan.tiles.size())
    throw InvalidInputError("tile " + std::to_string(tile) + " of a plan of " + std::to_string(plan.tiles.size()) +
                            " tiles");
  return plan.tiles[tile];
}

}  // namespace

TileInput load_tile(const std::filesystem::path& dir, std::size_t tile) {
  TileInput in;
  in.plan = read_tile_plan(dir);
  in.info = tile_info(in.plan, tile);
  in.points = tile_files::read_points(dir, in.plan, in.info);
  return in;
}

std::optional<Reconstruction> tile_phase_1(const TilePlan& plan, const tile_files::TilePoints& points) {
  if (points.positions.size() <= static_cast<std::size_t>(plan.k)) return std::nullopt;
  const ReconstructionOptions options = tile_files::tile_options(plan);
  try {
    return reconstruct_phase_1(PointCloudView(points.positions, {}, {}), options);
  } catch (const InvalidInputError&) {  // (the plan's options passed the statistics' run already)
    return std::nullopt;
  }
}

}  // namespace recon::tile_input
