#pragma once
// The files of a tiled run (tiles.h) and their records; private to src/.

#include "recon/detail/binary_file.h"
#include "recon/tiles.h"

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

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

inline constexpr std::uint32_t none = UINT32_MAX;

/// A vertex of a tile's mesh: its position (input coordinates) and its name
/// in the whole mesh: the lattice edge it was contoured on, or for a vertex
/// phase V added on a crease the two edges whose vertices it lies between
/// (the lesser first; corner[1] = UINT64_MAX for one). Shared: other
/// tiles' triangles use it too. Atom and object: step 4 of phase V (see
/// tiles.cpp), none where not needed.
struct MeshVertex {
  double x = 0.0, y = 0.0, z = 0.0;
  std::uint64_t corner[2] = {0, UINT64_MAX};
  std::uint32_t axis[2] = {0, 0};
  std::uint32_t shared = 0;
  std::uint32_t atom = none;
  std::uint32_t object = none;
  std::uint32_t color = 0;  ///< r | g << 8 | b << 16 (when the plan has colours)
};

/// A triangle of a tile's own cubes, and what step 4 of phase V decides
/// it by: the peelable component it is in (none: not peelable), and
/// whether it lies beyond f's reach (stray).
struct MeshTriangle {
  std::uint32_t v[3] = {0, 0, 0};
  std::uint32_t peel = none;
  std::uint32_t stray = 0;
};

/// Vertices of an atom that vote for an object (step 4's fragments).
struct AtomVote {
  std::uint32_t atom = 0, object = 0;
  std::uint64_t count = 0;
};

/// What step 4 writes of a tile (tile-N.mesh) and step 5 reads.
struct TileMesh {
  std::vector<MeshVertex> vertices;
  std::vector<MeshTriangle> triangles;
  std::vector<std::uint8_t> peel_open;        ///< per peelable component: on the mesh's open boundary
  std::vector<std::uint64_t> atom_triangles;  ///< per atom: its triangles
  std::vector<AtomVote> votes;
};
void write_mesh(const std::filesystem::path& path, const TileMesh& mesh);
/// Checks that every index names something (ParseError naming the file).
[[nodiscard]] TileMesh read_mesh(const std::filesystem::path& path);

inline constexpr char plan_magic[9] = "RCNPLAN2";
inline constexpr char points_magic[9] = "RCNPTS01";
inline constexpr char colors_magic[9] = "RCNCOL01";
inline constexpr char orient_magic[9] = "RCNORI01";
inline constexpr char flips_magic[9] = "RCNFLIP2";
inline constexpr char mesh_magic[9] = "RCNMESH2";
inline constexpr char planes_magic[9] = "RCNPLNS2";

/// A tile's points as its file holds them, in input order.
struct TilePoints {
  std::vector<Vec3> positions;
  std::vector<std::uint64_t> index;  ///< in the input
  std::vector<Color> colors;         ///< (when the plan has colours)
};
/// The points (and colours) of a tile (ParseError/IoError naming a damaged file).
[[nodiscard]] TilePoints read_points(const std::filesystem::path& dir, const TilePlan& plan, const TileInfo& info);

/// The tile whose core holds w (working coordinates), in the grid of
/// tiles: each point is one tile's (points beyond the lattice go to the
/// nearest tile).
[[nodiscard]] Lattice<3>::Index tile_at(const TilePlan& plan, const Vec3& w);

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
