#pragma once
// The files of a tiled run (tiles.h) and their records; private to src/.

#include "recon/tiles/tiles.h"
#include "tiles/binary_file.h"

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

namespace recon::tile_files {

inline std::filesystem::path plan(const std::filesystem::path& dir) { return dir / "plan.bin"; }
inline std::filesystem::path flips(const std::filesystem::path& dir) { return dir / "flips.bin"; }
/// "tile-<id>.<kind>", the id in at least six digits (tile-000042.mesh),
/// into `out`. Async-signal-safe; `kind` is cut to fit.
inline constexpr std::size_t tile_name_size = 48;
void format_tile_name(char (&out)[tile_name_size], std::uint64_t id, const char* kind) noexcept;
inline std::filesystem::path of_tile(const std::filesystem::path& dir, std::size_t tile, const char* kind) {
  char name[tile_name_size];
  format_tile_name(name, tile, kind);
  return dir / name;
}

/// A point of a tile: its index in the input and its position (input coordinates).
struct PointRecord {
  std::uint64_t index = 0;
  double x = 0.0, y = 0.0, z = 0.0;
};

/// An oriented sample near a tile's border, for the reconciliation.
struct BorderRecord {
  std::uint64_t index = 0;  ///< in the input
  std::uint32_t node = 0;   ///< the tile's piece (made global by the reconciliation)
  float normal[3] = {0.0f, 0.0f, 0.0f};
};

/// A piece's highest core sample (z in working coordinates; index in the input).
struct PieceTop {
  double z = -1e300;
  std::uint64_t index = UINT64_MAX;
};

/// A core sample of a tile as the winding number of its piece reads it
/// (nested pieces, orientation.h): its plane's origin (working coordinates)
/// and its area times its normal, as the tile oriented it (floats: a
/// winding number is asked only whether it passes 1/2).
struct DipoleRecord {
  float origin[3] = {0.0f, 0.0f, 0.0f};
  float area_normal[3] = {0.0f, 0.0f, 0.0f};
  std::uint32_t piece = 0;  ///< the tile's piece
};

inline constexpr std::uint32_t none = UINT32_MAX;

/// A vertex of a tile's mesh: its position (input coordinates) and its name
/// in the whole mesh: the lattice edge it was contoured on, or for a vertex
/// phase V added on a crease the two edges whose vertices it lies between
/// (the lesser first; corner[1] = UINT64_MAX for one). Shared: other
/// tiles' triangles use it too. Atom and object: step 4 of phase V (see
/// step4_contour.cpp), none where not needed.
struct MeshVertex {
  double x = 0.0, y = 0.0, z = 0.0;
  std::uint64_t corner[2] = {0, UINT64_MAX};
  std::uint32_t axis[2] = {0, 0};
  std::uint32_t shared = 0;
  std::uint32_t atom = none;
  std::uint32_t object = none;
  std::uint32_t color = 0;  ///< r | g << 8 | b << 16 (when the plan has colours)
  /// Phase V's fitted normal (when the plan has normals), or 0 0 0 where
  /// there is none (the stitch fills those from the faces): floats, as
  /// the mesh files hold normals.
  float normal[3] = {0.0f, 0.0f, 0.0f};
  std::uint32_t unused = 0;  ///< (keeps the record free of padding, which would be written unset)
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

// Every reader below checks the file's checksum first (binary_file.h), then
// that every count matches and every index names something the file (or
// the plan) has, and that coordinates are finite: ParseError naming the
// file and the record otherwise. Cost: linear in the file.
[[nodiscard]] TileMesh read_mesh(const std::filesystem::path& path);

/// What step 2 writes of a tile (tile-N.orient) and steps 3 and 4 read.
struct Orientation {
  std::vector<std::int8_t> sign;      ///< per tile point (file order): +1 or -1, its normal against phase I's
  std::vector<std::uint32_t> piece;   ///< per tile point: its piece (< tops.size())
  std::vector<PieceTop> tops;         ///< per piece
  std::vector<BorderRecord> border;   ///< node: the piece (< tops.size())
  std::vector<DipoleRecord> dipoles;  ///< per core sample with a surface (not isolated), in spatial order
  std::uint64_t inexact = 0;
};
void write_orientation(const std::filesystem::path& path, const Orientation& o);
[[nodiscard]] Orientation read_orientation(const std::filesystem::path& path);

/// What step 3 writes (flips.bin) and step 4 reads: the pieces of all tiles
/// numbered one after the other (tile t's from first_node[t]), each with
/// its sign and its object (a piece).
struct Flips {
  std::vector<std::uint64_t> first_node;  ///< per tile, ascending, <= flip.size()
  std::vector<std::int8_t> flip;          ///< per piece: +1 kept, -1 turned round
  std::vector<std::uint32_t> object;      ///< per piece: the piece its object was walked from
  /// Tile `tile`'s pieces: [first, end). Precondition: tile < first_node.size().
  [[nodiscard]] std::pair<std::uint64_t, std::uint64_t> pieces_of(std::size_t tile) const;
};
void write_flips(const std::filesystem::path& dir, const Flips& flips);
[[nodiscard]] Flips read_flips(const std::filesystem::path& dir);

/// A tile's points (tile-N.points; coordinates finite) and colours.
[[nodiscard]] std::vector<PointRecord> read_point_records(const std::filesystem::path& path);
[[nodiscard]] std::vector<Color> read_colors(const std::filesystem::path& path);

/// The plan (plan.bin). The reader checks what the steps index or divide
/// by: the method, k, the lattice, each tile's place in the grid, its id.
void write_plan(const TilePlan& plan, const std::filesystem::path& dir);
[[nodiscard]] TilePlan read_plan_file(const std::filesystem::path& path);

inline constexpr char plan_magic[9] = "RCNPLAN5";
inline constexpr char points_magic[9] = "RCNPTS02";
inline constexpr char colors_magic[9] = "RCNCOL02";
inline constexpr char orient_magic[9] = "RCNORI03";
inline constexpr char flips_magic[9] = "RCNFLIP3";
inline constexpr char mesh_magic[9] = "RCNMESH4";
inline constexpr char planes_magic[9] = "RCNPLNS3";

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
