#pragma once
// The files of a tiled run (tiles.h) and their records; private to src/.

#include "recon/detail/binary_file.h"
#include "recon/tiles.h"

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>

namespace recon::tile_files {

inline std::filesystem::path plan(const std::filesystem::path& dir) { return dir / "plan.bin"; }
inline std::filesystem::path flips(const std::filesystem::path& dir) { return dir / "flips.bin"; }
inline std::filesystem::path of_tile(const std::filesystem::path& dir, std::size_t tile, const char* kind) {
  char name[64];
  std::snprintf(name, sizeof name, "tile-%06zu.%s", tile, kind);
  return dir / name;
}

/// A point of a tile: its index in the input and its position (input coordinates).
struct PointRecord {
  std::uint64_t index = 0;
  double x = 0.0, y = 0.0, z = 0.0;
};

/// An oriented sample near a tile's border, for the reconciliation.
struct BorderRecord {
  std::uint64_t index = 0;   ///< in the input
  std::uint32_t node = 0;    ///< the tile's piece (made global by the reconciliation)
  float normal[3] = {0.0f, 0.0f, 0.0f};
};

/// A piece's highest core sample (z in working coordinates; index in the input).
struct PieceTop {
  double z = -1e300;
  std::uint64_t index = UINT64_MAX;
};

/// A vertex of a tile's mesh: its position (input coordinates) and lattice edge.
struct MeshVertex {
  double x = 0.0, y = 0.0, z = 0.0;
  std::uint64_t corner = 0;
  std::uint32_t axis = 0, unused = 0;
};

inline constexpr char plan_magic[9] = "RCNPLAN1";
inline constexpr char points_magic[9] = "RCNPTS01";
inline constexpr char orient_magic[9] = "RCNORI01";
inline constexpr char flips_magic[9] = "RCNFLIP1";
inline constexpr char mesh_magic[9] = "RCNMESH1";
inline constexpr char planes_magic[9] = "RCNPLNS1";

/// The tile's core, in cubes: [lo, hi) per axis.
struct CoreBox {
  Lattice<3>::Index lo{}, hi{};
};
[[nodiscard]] CoreBox core_of(const TilePlan& plan, std::size_t tile);
/// The core of the tile at `grid` in the grid of tiles.
[[nodiscard]] CoreBox core_at(const TilePlan& plan, const Lattice<3>::Index& grid);
/// How far a point (working coordinates) lies outside a core: the largest
/// overshoot over the axes; negative inside, by the depth.
[[nodiscard]] double outside_core(const TilePlan& plan, const CoreBox& core, const Vec3& w);
/// The options every tile's phase I runs with (the cloud-wide choices of the plan).
[[nodiscard]] ReconstructionOptions tile_options(const TilePlan& plan);

}  // namespace recon::tile_files
