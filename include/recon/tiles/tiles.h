#pragma once
// Clouds larger than memory: the same reconstruction, tile by tile.
//
// The plain idea. Phases I, III and IV are local, and most of V: a
// sample's plane depends on its k nearest neighbours, f at a lattice
// corner on the planes and samples within a few neighbourhoods of it, a
// cube's triangles on its 8 corners, and where phase V moves a vertex on
// the planes and triangles a few cubes around it. So cut space into tiles
// (boxes of whole lattice cubes), give each tile its points plus a halo of
// the points around it, run the phases there, and keep only the triangles
// of the tile's own cubes (its core):
// every cube belongs to one tile, and where the halo is wide enough the
// tile sees the same neighbourhoods and nearest planes as the whole cloud,
// so the pieces meet exactly on the lattice edges of the tiles' borders.
// Phase II is global: each tile orients its own pieces, and the signs are
// then made to agree through the halos, where two tiles orient the same
// samples; so is phase V's last step (trimming, fragments), decided over
// the whole mesh as it is stitched. In steps:
//
//   1. plan_tiles: stream the input (never held whole): its bounding box
//      and count; then the cloud-wide choices, made once as reconstruct()
//      makes them (k raised for noise, the medians behind rho and delta,
//      the cell, the lattice and the working offset), from phase I over
//      the whole cloud when it fits within statistics_points; then bin the
//      points into tile files (core + halo) on disk. A larger cloud is
//      first measured on spatial patches of it that fit, which make a
//      first plan; its tiles then measure the whole cloud, each its own
//      samples, and the measures come out exactly reconstruct()'s
//      (src/tiles/statistics.h); the points are binned again under the
//      plan they make.
//   2. orient_tile, for every tile: phases I-II on its points; its planes
//      are written, and the signs of its pieces' normals at the samples
//      near its border.
//   3. reconcile_tiles: a small graph whose nodes are (tile, piece), joined
//      where two tiles orient the same samples, weighted by how many of them
//      agree; its maximum spanning forest, walked from the piece holding
//      each object's highest sample (phase II's own rule), turns the
//      pieces that disagree. Separate objects stay separate. For the
//      refined method, an object nested in others then faces as phase II
//      turns nested pieces (orientation.h): step 2 wrote each core
//      sample's origin and area-weighted normal, so the winding numbers
//      are summed over the tiles, where one object's box holds another's.
//   4. contour_tile, for every tile: the planes step 2 wrote, their
//      normals signed as reconciled, f, and marching cubes over the tile's
//      own cubes and a ring of cubes around them on the one global lattice,
//      in the cubes' order (sort_by_cube); for the refined method, phase V's
//      local steps over all of it (refine_patch); then the triangles of its
//      own cubes are kept, each vertex named by the lattice edge it comes
//      from (or the two, for a vertex phase V put on a crease), and
//      coloured from the samples' colours when the cloud has them; with
//      vertex normals, each keeps phase V's fitted normal (or none).
//   5. stitch_tiles: the tiles' triangles into one PLY file, written as
//      they come; vertices other tiles use too are welded by name, so there
//      are no cracks and no doubled triangles. Phase V's last step (trim
//      open boundaries, drop strays and fragments) is decided over the
//      whole mesh first, from what each tile marked (step5_stitch.cpp);
//      the vertices without a fitted normal get their kept faces' mean.
//
// Each step is a source of its own in src/tiles/ (step1_plan.cpp to
// step5_stitch.cpp), and reconstruct_tiled (driver.cpp) runs them in a row;
// the tiles' files are private to that folder (files.h).
//
// Steps 2 and 4 read and write only their tile's files in the work
// directory: they can run in any order, in parallel, on other machines
// sharing the directory (python -m recon.distributed runs them as Dask
// tasks), and rerun after a failure: each output file appears whole or not
// at all, and carries a checksum that every reader checks, as it checks
// every index in it (src/tiles/files.h): a damaged file is a ParseError
// naming it, and the step's error names its tile. Every step is
// deterministic, so the mesh does not depend on who ran which tile.
//
// What a tiled mesh is. On clouds that fit in memory it has the same
// triangles as reconstruct()'s final mesh on clean data, phase V's for the
// refined method (tests/tiles/tiles_test.cpp), when the cloud-wide measures come
// from the whole cloud. Phase V's few order-dependent choices (which crease
// vertex comes first, which sliver flips) see the same triangles in the same
// order in a tile, as far as the ring reaches. A component's object (for
// fragments) is voted by its vertices, each counted once, those that only
// peeled triangles use included (in memory they are gone by then): a tie
// could go the other way. Where samples lie on an exact grid, a k-th
// neighbour can be a tie between equidistant samples, which the kd-tree
// breaks by its own numbering: a tile's tree may break it another way than
// the whole cloud's, and a few planes differ (Hoppe's cactus: 120 of a
// tile's 2698 samples, most in its halo; the same triangles, 67 of 5313
// vertices up to a quarter of a cell apart). Colours: each tile blends its
// own vertices' colours from its samples' (vertex_colors.h), as
// reconstruct() does.
//
// Halo. A sample's plane is exact when its k-NN ball lies inside the tile's
// points, and its neighbours' balls too (their spacing, their fits); a
// corner's f is exact when the planes and samples within f's reach of it
// are. The halo is the walk margin (the ring plus 2 cubes) plus f's reach
// (1.5 rho + delta + 2 cells) plus three neighbourhood radii (one to the
// nearest plane's sample, two for its neighbourhood and its neighbours'),
// and for the refined method at least the walk margin plus phase V's reach
// for strays (5 rho + delta), with rho at its 99.9th percentile over
// the statistics run and the radius at 1.5 times its own; each tile counts
// the samples near its core (isolated ones aside) whose neighbourhood may
// reach past its points (TileOrientation::inexact_samples), which should be 0.
//
// Cost: reconstruct()'s, O(n k log n) for n points at k, spread over the tiles (the halos' points counted again),
// one tile in memory at a time; plus three or four streamed passes over the input, and the tiles' files.

#include "recon/core/progress.h"
#include "recon/io/point_io.h"
#include "recon/reconstruct.h"

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace recon {

/// A pass over an input cloud: calls `take` with consecutive chunks of its
/// points, in order, from the first (chunk valid during the call only;
/// `first` is the index of its first point). Called once per pass.
using ChunkTaker = std::function<void(PointCloudView chunk, std::size_t first)>;
using PointPass = std::function<void(const ChunkTaker& take)>;

struct TilingOptions {
  /// The reconstruction asked for. Honoured: method, planes.k and adapt_k,
  /// planes.rho, cell or resolution, distance.delta, orientation's
  /// vote_rounds and graph options. max_memory bounds each tile's run and the
  /// plan's statistics (0: default_memory_limit()).
  ReconstructionOptions reconstruction;
  double tile_size = 0.0;  ///< edge of a tile's core (a length); 0: the largest that fits max_memory
  /// Phase I for the cloud-wide measures runs on at most this many points
  /// at once: the whole cloud when it has no more, else over the tiles
  /// (step 1 below); 0: what fits in a quarter of max_memory.
  std::size_t statistics_points = 0;
  std::uint64_t seed = 1;  ///< picks the spatial patches of the first plan when the cloud is larger
  /// Counts the points of the plan's passes over the input (progress.h):
  /// the first without a total, the next two with the cloud's count.
  ProgressCounter* progress = nullptr;
};

struct TileInfo {
  std::array<std::int32_t, 3> index{};  ///< position in the grid of tiles
  std::uint32_t id = 0;                 ///< names its files (tile-<id>.*)
  std::uint64_t points = 0;             ///< in its file, halo included
  std::uint64_t core_points = 0;        ///< of which in its core
};

struct TilePlan {
  Method method = Method::refined;
  int k = 0;             ///< phase I's k for every tile (raised for noise once, for the whole cloud)
  CloudSpacing spacing;  ///< the cloud-wide measures of phase I
  bool has_quadric_medians = false;
  QuadricMedians quadric_medians;  ///< of the refined fits
  std::optional<double> rho;       ///< given by the user
  std::optional<double> delta;     ///< given by the user
  int vote_rounds = 3;
  double gap_factor = 1.5;
  int min_component_points = 0;
  Vec3 offset = Vec3::Zero();    ///< the working offset (reconstruct.h)
  Box<3> box;                    ///< of the input, in working coordinates
  Lattice<3> lattice;            ///< the one lattice of every tile (working coordinates)
  std::int32_t tile_cubes = 0;   ///< a tile's core is tile_cubes^3 cubes
  double halo = 0.0;             ///< a length (see the header)
  double exact_margin = 0.0;     ///< around the core, where planes and f are exact
  std::int32_t walk_margin = 2;  ///< cubes around the core the walk may cross
  /// Cubes around the core whose triangles a tile makes too, to see the
  /// triangles its own meet (1), and for phase V (the refined method) the
  /// neighbours its choices depend on (3). The walk goes 2 cubes further.
  std::int32_t ring = 1;
  RefinementOptions refinement;    ///< phase V's options (max_move 0: the cell)
  bool colors = false;             ///< the cloud has colours, and the mesh gets them (mesh_colors)
  VertexColorOptions color_blend;  ///< how (vertex_colors.h)
  /// The mesh gets vertex normals (ReconstructionOptions::vertex_normals):
  /// each tile writes phase V's fitted ones, the stitch fills the rest from
  /// the faces it keeps, as reconstruct() does (vertex_normals.h).
  bool normals = false;
  double radius_q = 0.0, rho_q = 0.0;  ///< 99.9th percentiles of the neighbourhood radius and of rho_i
  std::uint64_t input_points = 0;
  std::uint64_t statistics_points = 0;  ///< points phase I ran on for the cloud-wide measures
  /// Whether phase I measured them over the tiles, each tile its own
  /// samples (a cloud larger than TilingOptions::statistics_points), and
  /// of those samples the ones whose neighbourhood may have reached past
  /// their tile's points (0 when the measures are exact). Not kept in the
  /// plan's file.
  bool statistics_over_tiles = false;
  std::uint64_t statistics_inexact = 0;
  std::vector<TileInfo> tiles;  ///< the non-empty tiles, in grid order
  double seconds_statistics = 0.0, seconds_binning = 0.0, seconds_bounds = 0.0;
};

/// What orient_tile found.
struct TileOrientation {
  std::size_t points = 0;
  std::size_t pieces = 0;           ///< pieces of the data in the tile (phase II's components)
  std::size_t border_samples = 0;   ///< samples written for the reconciliation
  std::size_t inexact_samples = 0;  ///< samples near the core whose neighbourhood reached past the halo
  double seconds = 0.0;
};

struct TileReconciliation {
  std::size_t nodes = 0;           ///< (tile, piece) pairs
  std::size_t edges = 0;           ///< pairs that share samples
  std::size_t objects = 0;         ///< components of the graph with a sample in some tile's core
  std::size_t turned = 0;          ///< pieces turned round
  std::size_t shared_samples = 0;  ///< sample pairs compared
  std::size_t disagreeing = 0;     ///< of which still disagree after the turns (0 on clean data)
  std::size_t objects_nested = 0;  ///< objects inside another (the refined method; orientation.h)
  std::size_t nested_turned = 0;   ///< of which turned round: inside an odd number of others
  double seconds = 0.0;
};

struct TileContour {
  std::size_t vertices = 0, triangles = 0;  ///< of the tile's own cubes
  std::size_t visited_cubes = 0;
  double seconds = 0.0;
};

struct StitchedMesh {
  std::size_t vertices = 0, triangles = 0;
  std::size_t welded = 0;  ///< vertices on tile borders met more than once
  /// Phase V's (refinement.h): vertices added on creases, and step 4 over the whole mesh.
  std::size_t crease_vertices = 0, trimmed = 0, stray_triangles = 0, fragments = 0, fragment_triangles = 0;
  double seconds = 0.0;
};

/// Step 1. Creates `work_dir` and fills it: the plan, and each tile's points (core and halo).
/// Cost: O(n) per pass over the input: three (the bounds, the statistics' sample, the binning), four for a cloud
/// beyond statistics_points (binned again once phase I has measured it over the tiles); phase I on up to
/// statistics_points.
/// Throws: InvalidInputError when `work_dir` holds a plan already, for an empty cloud, a coordinate not finite or
/// beyond +-max_coordinate, a tile size that is not a finite positive length, or bad options; ResourceLimitError
/// when the one lattice over the cloud is too large or the statistics or the densest tile cannot fit max_memory;
/// what the pass throws (reading errors); IoError for the files (std::filesystem::filesystem_error when `work_dir`
/// cannot be made); what an interruption check throws.
/// Pre: every pass gives the same points in the same order.
TilePlan plan_tiles(const PointPass& pass, const TilingOptions& options, const std::filesystem::path& work_dir);
/// The plan written in `work_dir`.
/// Cost: O(tiles).
/// Throws: ParseError/IoError when absent or damaged.
/// Pre: none.
[[nodiscard]] TilePlan read_tile_plan(const std::filesystem::path& work_dir);
/// Step 2 for tile `tile` (an index into plan.tiles): writes its planes and its pieces' signs near its border.
/// Cost: phases I-II on the tile's m points, O(m k log m).
/// Throws: InvalidInputError for a tile index out of range; ParseError/IoError when a file it reads is absent or
/// damaged, IoError when it cannot write; each message names the step and the tile. What an interruption check
/// throws.
/// Pre: plan_tiles done in `work_dir`.
TileOrientation orient_tile(const std::filesystem::path& work_dir, std::size_t tile);
/// Step 3, once every tile is oriented: writes each piece's sign.
/// Cost: O(B log B) for the B border samples of all tiles (a sort), and Kruskal over the pieces' graph; where one
/// object's box holds another's (the refined method), the tiles' orientation files read again and O(|Q|) per such
/// pair (P, Q).
/// Throws: ParseError/IoError when a file is absent or damaged, IoError when it cannot write; ResourceLimitError
/// for more than 2^32 pieces in all.
/// Pre: every tile oriented.
TileReconciliation reconcile_tiles(const std::filesystem::path& work_dir);
/// Step 4 for tile `tile`, once reconciled: writes the triangles of its own cubes.
/// Cost: phases III-V on the tile: O(c log m) for the c cubes its walk visits (a nearest-plane query per corner),
/// phase V O(V log m).
/// Throws: as orient_tile, and ResourceLimitError when the walk would pass what max_memory allows (named alike).
/// Pre: reconcile_tiles done.
TileContour contour_tile(const std::filesystem::path& work_dir, std::size_t tile);
/// Step 5, once every tile is contoured: the mesh into `output` (binary
/// PLY, written to a temporary file and renamed).
/// Cost: O(F log F) at most for the F triangles of all tiles (a hash welds the vertices, ordered maps count votes);
/// each tile's mesh file read two or three times, never all at once.
/// Throws: ParseError/IoError when a tile's file is absent or damaged; IoError when `output` cannot be written;
/// InvalidInputError when no tile holds a triangle.
/// Pre: every tile contoured.
StitchedMesh stitch_tiles(const std::filesystem::path& work_dir, const std::filesystem::path& output);

/// The whole tiled run in this process, steps 1 to 5, the tiles one after
/// the other on every thread, or two at a time on half the threads each
/// when two fit the memory limit (the same files either way). `on_tile(step, done, total)`
/// is called before each step ("planning", "orienting", "reconciling",
/// "contouring", "stitching") and after each tile, for progress displays.
struct TiledRun {
  TilePlan plan;
  std::vector<TileOrientation> orientations;
  TileReconciliation reconciliation;
  std::vector<TileContour> contours;
  StitchedMesh mesh;
  double seconds = 0.0;
};
/// Cost: the steps' (see the header).
/// Throws: what the steps throw (the first failure, once the tiles running are done), and what on_tile throws.
/// Pre: as plan_tiles.
TiledRun reconstruct_tiled(
    const PointPass& pass, const TilingOptions& options, const std::filesystem::path& work_dir,
    const std::filesystem::path& output,
    const std::function<void(const char* step, std::size_t done, std::size_t total)>& on_tile = {});

/// A pass over the points of an in-memory cloud, in chunks of `chunk`.
/// Cost: O(1); each pass O(n / chunk) chunk views.
/// Throws: nothing; a pass throws what `take` throws.
/// Pre: the cloud outlives the pass (it is viewed, not copied); chunk > 0.
[[nodiscard]] PointPass pass_over(PointCloudView cloud, std::size_t chunk = std::size_t{1} << 20);
/// A pass over a point file, read as it streams by (io/point_stream.h):
/// never held whole for the formats that stream (PLY, XYZ/CSV, LAS).
/// Cost: O(1); each pass reads the file, O(n).
/// Throws: nothing; a pass throws what io::read_points_in_chunks throws (IoError, ParseError, InvalidInputError)
/// and what `take` throws.
/// Pre: the file does not change between passes.
[[nodiscard]] PointPass pass_over_file(const std::filesystem::path& path, const io::ReadPointsOptions& options = {});

/// A directory for a tiled run's files: `parent`/recon-tiles-XXXXXX, made
/// now by mkdtemp (so never another run's, even one with the same process
/// id in another container), locked for its life (flock on the file
/// recon-tiles.lock inside it), and removed with everything in it when
/// destroyed (also when unwinding from an error or an interruption). First
/// removes the stale workspaces in `parent` (remove_stale_tile_workspaces).
inline constexpr std::size_t max_workspace_path = 4000;  ///< characters of a workspace's path
class TileWorkspace {
 public:
  /// Cost: a mkdtemp, an open and flock, and remove_stale_tile_workspaces(parent).
  /// Throws: InvalidInputError when `parent`'s path is longer than max_workspace_path allows (a signal handler
  /// must be able to clean it); IoError when the folder or its lock cannot be made (no `parent`, say).
  /// Pre: none.
  explicit TileWorkspace(const std::filesystem::path& parent);
  ~TileWorkspace();
  TileWorkspace(const TileWorkspace&) = delete;
  TileWorkspace& operator=(const TileWorkspace&) = delete;
  [[nodiscard]] const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
  int slot_ = -1;  // in the registry remove_tile_workspaces reads
  int lock_ = -1;  // the descriptor holding the folder's lock
};

/// Removes the workspaces in `parent` that no live run holds: folders (not
/// links) named recon-tiles-*, holding a recon-tiles.lock whose lock is
/// free, as a run killed by SIGKILL leaves them. Never touches anything
/// else (a folder without the lock file, another program's). Returns how
/// many it removed; errors (a parent it cannot read) are ignored.
/// Cost: a listing of `parent` and an open and flock per workspace found.
/// Throws: nothing.
/// Pre: none.
std::size_t remove_stale_tile_workspaces(const std::filesystem::path& parent) noexcept;

/// Removes every file of every TileWorkspace alive, and the folders, also
/// while other threads are still committing files into them. Async-signal-safe:
/// for the handlers of SIGINT, SIGTERM, SIGBUS of a program about to end.
/// Cost: a listing and an unlink per file of each live workspace.
/// Throws: nothing.
/// Pre: none (the runs still using them fail then: call it only when the program ends).
void remove_tile_workspaces() noexcept;

}  // namespace recon
