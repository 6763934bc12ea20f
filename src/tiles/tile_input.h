#pragma once
// What steps 2 and 4 of a tiled run (step2_orient.cpp, step4_contour.cpp)
// start from: the plan, a tile and its points, phase I over them with the
// plan's cloud-wide choices, and the tile's name on the errors they throw.

#include "recon/core/errors.h"
#include "recon/reconstruct.h"
#include "recon/tiles/tiles.h"
#include "tiles/files.h"

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>

namespace recon::tile_input {

struct TileInput {
  TilePlan plan;
  TileInfo info;
  tile_files::TilePoints points;
};

/// The plan of `dir`, tile `tile`'s entry and its points. Throws ParseError
/// or IoError for a damaged or missing file, InvalidInputError for a tile
/// the plan does not have.
[[nodiscard]] TileInput load_tile(const std::filesystem::path& dir, std::size_t tile);

/// Phase I over a tile, with the plan's cloud-wide choices. Empty when the
/// tile's points make no plane: fewer than k + 1 of them, or no k + 1
/// distinct ones, or only degenerate neighbourhoods (a tile of strays or of
/// copies of one point, which draw nothing in the whole cloud either).
[[nodiscard]] std::optional<Reconstruction> tile_phase_1(const TilePlan& plan, const tile_files::TilePoints& points);

/// Runs a step of tile `tile`; a recon error from it (a damaged file, a
/// limit) comes out with the same type, its message naming the step and
/// the tile: from a Dask task that message is all the user sees.
template <class Step>
auto naming_tile(const char* step, std::size_t tile, const Step& run) -> decltype(run()) {
  const std::string where = std::string(step) + " tile " + std::to_string(tile) + ": ";
  try {
    return run();
  } catch (const ParseError& e) {
    throw ParseError(where + e.what());
  } catch (const IoError& e) {
    throw IoError(where + e.what(), e.error_code());
  } catch (const ResourceLimitError& e) {
    throw ResourceLimitError(where + e.what());
  } catch (const InvalidInputError& e) {
    throw InvalidInputError(where + e.what());
  }
}

}  // namespace recon::tile_input
