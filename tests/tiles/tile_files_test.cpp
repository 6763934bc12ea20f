// The files of a tiled run (tiles/files.h, binary_file.h) and its workspace
// (TileWorkspace): damaged files are errors naming the file and the tile,
// never a crash or a hole in the mesh; a piece oriented the other way in a
// tile's file is turned by the reconciliation; workspaces are exclusive,
// locked, cleaned after runs that died, and by the signal handlers also
// while other threads still write into them.

#include "recon/tiles/tiles.h"

#include "mesh_compare.h"
#include "recon/core/errors.h"
#include "recon/core/shapes.h"
#include "recon/io/mesh_io.h"
#include "tile_cases.h"
#include "tiles/files.h"  // (the tiles' files, changed by hand below)

#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <csignal>
#include <cstring>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <string>
#include <thread>
#include <vector>

namespace recon {
namespace {

namespace fs = std::filesystem;

fs::path scratch(const std::string& name) { return tile_testing::scratch_folder("recon-tile-files-test-" + name); }

std::string bytes_of(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_bytes(const fs::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

// A file changed by hand, given a checksum that matches again: what a
// writer that lies (or a forger) would make. Past the checksum, the
// reader's own checks must catch it.
void reseal(const fs::path& path) {
  std::string bytes = bytes_of(path);
  bytes.resize(bytes.size() - sizeof(detail::ChecksumTrailer));
  detail::Checksum sum;
  sum.add(bytes.data(), bytes.size());
  const detail::ChecksumTrailer trailer = sum.trailer();
  bytes.append(reinterpret_cast<const char*>(&trailer), sizeof trailer);
  write_bytes(path, bytes);
}

template <class T>
void overwrite(const fs::path& path, std::size_t at, const T& value) {
  std::string bytes = bytes_of(path);
  ASSERT_LE(at + sizeof(T), bytes.size());
  std::memcpy(bytes.data() + at, &value, sizeof(T));
  write_bytes(path, bytes);
}

PointCloud sphere(std::size_t points) { return make_shape("sphere")->sample(points, 11); }

TilingOptions tiling(Method method, double tile_size) {
  TilingOptions options;
  options.reconstruction.method = method;
  options.tile_size = tile_size;
  return options;
}

// Steps 1 and 2 over a sphere cut in several tiles.
TilePlan oriented_sphere(const fs::path& dir) {
  const TilePlan plan = plan_tiles(pass_over(sphere(12000)), tiling(Method::hoppe92, 0.8), dir);
  for (std::size_t t = 0; t < plan.tiles.size(); ++t) orient_tile(dir, t);
  return plan;
}

template <class Step>
std::string error_of(const Step& step) {
  try {
    step();
  } catch (const ParseError& e) {
    return e.what();
  }
  return "(no ParseError)";
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// ---------------------------------------------------------------------------
// Item 7: damaged files.

// One flipped bit anywhere in a tile's orientation once crashed the
// reconciliation (an index past its arrays): now the checksum refuses it.
TEST(TileFiles, AFlippedBitIsAnErrorNamingTheFile) {
  const auto dir = scratch("bit");
  const TilePlan plan = oriented_sphere(dir);
  ASSERT_GT(plan.tiles.size(), 1u);
  const fs::path orient = tile_files::of_tile(dir, plan.tiles[0].id, "orient");
  const std::string whole = bytes_of(orient);
  for (const std::size_t at : {std::size_t{9}, whole.size() / 3, whole.size() / 2, whole.size() - 20}) {
    std::string damaged = whole;
    damaged[at] = static_cast<char>(damaged[at] ^ 0x10);
    write_bytes(orient, damaged);
    const std::string error = error_of([&] { reconcile_tiles(dir); });
    EXPECT_TRUE(has(error, orient.string() + ": damaged")) << "byte " << at << ": " << error;
  }
  write_bytes(orient, whole.substr(0, whole.size() - 1));
  EXPECT_TRUE(has(error_of([&] { reconcile_tiles(dir); }), orient.string() + ": damaged")) << "truncated";
  write_bytes(orient, whole);
  EXPECT_NO_THROW(reconcile_tiles(dir));
  fs::remove_all(dir);
}

// Every kind of file a run writes carries the checksum: a byte changed in
// each is refused by the step that reads it.
TEST(TileFiles, EveryKindOfFileIsChecked) {
  const auto dir = scratch("kinds");
  PointCloud cloud = sphere(4000);
  cloud.colors.assign(cloud.size(), Color{1, 2, 3});
  const TilePlan plan = plan_tiles(pass_over(cloud), tiling(Method::refined, 0.8), dir);
  ASSERT_TRUE(plan.colors);
  for (std::size_t t = 0; t < plan.tiles.size(); ++t) orient_tile(dir, t);
  reconcile_tiles(dir);
  for (std::size_t t = 0; t < plan.tiles.size(); ++t) contour_tile(dir, t);
  const auto tile = [&](const char* kind) { return tile_files::of_tile(dir, plan.tiles[0].id, kind); };
  const std::vector<std::pair<fs::path, std::function<void()>>> files = {
      {tile_files::plan(dir), [&] { static_cast<void>(read_tile_plan(dir)); }},
      {tile("points"), [&] { orient_tile(dir, 0); }},
      {tile("colors"), [&] { contour_tile(dir, 0); }},
      {tile("orient"), [&] { reconcile_tiles(dir); }},
      {tile("planes"), [&] { contour_tile(dir, 0); }},
      {tile_files::flips(dir), [&] { contour_tile(dir, 0); }},
      {tile("mesh"), [&] { stitch_tiles(dir, dir / "out.ply"); }},
  };
  for (const auto& [path, read] : files) {
    const std::string whole = bytes_of(path);
    std::string damaged = whole;
    damaged[whole.size() / 2] = static_cast<char>(damaged[whole.size() / 2] + 1);
    write_bytes(path, damaged);
    const std::string error = error_of(read);
    EXPECT_TRUE(has(error, path.string() + ": damaged: its CRC-32")) << error;
    write_bytes(path, whole);
  }
  EXPECT_NO_THROW(stitch_tiles(dir, dir / "out.ply"));
  fs::remove_all(dir);
}

// Past the checksum (a file resealed after the change), every index is
// still checked: a piece or a border sample naming a piece the tile does
// not have, a sign that is neither +1 nor -1.
TEST(TileFiles, IndicesAreCheckedBeyondTheChecksum) {
  const auto dir = scratch("indices");
  const TilePlan plan = oriented_sphere(dir);
  const fs::path orient = tile_files::of_tile(dir, plan.tiles[0].id, "orient");
  const tile_files::Orientation o = tile_files::read_orientation(orient);
  ASSERT_FALSE(o.sign.empty());
  ASSERT_FALSE(o.border.empty());
  const std::string whole = bytes_of(orient);
  // The file: magic, then sign (count, values), piece (count, values), tops, border.
  const std::size_t sign_at = 8 + 8, piece_at = sign_at + o.sign.size() + 8;
  const std::size_t border_at = piece_at + 4 * o.piece.size() + 8 + sizeof(tile_files::PieceTop) * o.tops.size() + 8;
  const auto refused = [&](std::size_t at, auto value, const std::string& why) {
    write_bytes(orient, whole);
    overwrite(orient, at, value);
    reseal(orient);
    const std::string error = error_of([&] { reconcile_tiles(dir); });
    EXPECT_TRUE(has(error, orient.string() + ": ") && has(error, why)) << error;
  };
  refused(piece_at + 4 * (o.piece.size() / 2), std::uint32_t{0xFFFFFF00u}, "names a piece the tile does not have");
  refused(border_at + offsetof(tile_files::BorderRecord, node), std::uint32_t{1u << 30},
          "names a piece the tile does not have");
  refused(sign_at + o.sign.size() / 2, std::int8_t{5}, "a sign other than +1 or -1");
  refused(8, std::uint64_t{1} << 60, "truncated");
  write_bytes(orient, whole);
  EXPECT_NO_THROW(reconcile_tiles(dir));
  fs::remove_all(dir);
}

// A tile mesh's vertex normal (phase V's fitted one) must be unit or zero.
TEST(TileFiles, AVertexNormalNeitherUnitNorZeroIsRefused) {
  const auto dir = scratch("normals");
  fs::create_directories(dir);
  const fs::path path = dir / "tile-000000.mesh";
  tile_files::TileMesh mesh;
  mesh.vertices.resize(3);
  mesh.vertices[1].normal[2] = 1.0f;
  tile_files::write_mesh(path, mesh);
  EXPECT_NO_THROW((void)tile_files::read_mesh(path));
  mesh.vertices[2].normal[0] = 2.0f;
  tile_files::write_mesh(path, mesh);
  const std::string error = error_of([&] { (void)tile_files::read_mesh(path); });
  EXPECT_TRUE(has(error, path.string() + ": vertex 2: its normal is neither unit nor zero")) << error;
  fs::remove_all(dir);
}

// A NaN in a tile's points once made that tile orient to no piece and draw
// nothing (a hole, exit status 0). Now it is an error naming the file and
// the tile, with or without a matching checksum.
TEST(TileFiles, ANotANumberInATilesPointsIsAnErrorNamingTheTile) {
  const auto dir = scratch("nan");
  const TilePlan plan = plan_tiles(pass_over(sphere(12000)), tiling(Method::hoppe92, 0.8), dir);
  ASSERT_GT(plan.tiles.size(), 1u);
  const fs::path points = tile_files::of_tile(dir, plan.tiles[1].id, "points");
  overwrite(points, 8 + 5 * sizeof(tile_files::PointRecord) + offsetof(tile_files::PointRecord, y),
            std::numeric_limits<double>::quiet_NaN());
  EXPECT_TRUE(has(error_of([&] { orient_tile(dir, 1); }), "orienting tile 1: " + points.string() + ": damaged"));
  reseal(points);
  const std::string error = error_of([&] { orient_tile(dir, 1); });
  EXPECT_TRUE(has(error, "orienting tile 1: " + points.string() + ": point 5: a coordinate is not a finite number"))
      << error;
  fs::remove_all(dir);
}

// Reconciliation signs from a file of another plan: tile 0's pieces in it
// are not those of tile 0's orientation.
TEST(TileFiles, FlipsThatAreNotThePlansAreRefused) {
  const auto dir = scratch("flips");
  const TilePlan plan = oriented_sphere(dir);
  reconcile_tiles(dir);
  tile_files::Flips flips = tile_files::read_flips(dir);
  flips.first_node.assign(flips.first_node.size(), 0);
  flips.first_node.back() = flips.flip.size();
  tile_files::write_flips(dir, flips);
  const std::string error = error_of([&] { contour_tile(dir, 0); });
  EXPECT_TRUE(has(error, "contouring tile 0: " + tile_files::flips(dir).string() + ": its pieces of tile 0")) << error;
  fs::remove_all(dir);
}

// ---------------------------------------------------------------------------
// Item 24a: the reconciliation must turn a piece that disagrees.

// Triangles facing the sphere's centre (the shape is the unit sphere).
std::size_t inward_triangles(const Mesh& mesh) {
  std::size_t inward = 0;
  for (const auto& t : mesh.triangles) {
    const Vec3 a = mesh.vertices[t[0]], b = mesh.vertices[t[1]], c = mesh.vertices[t[2]];
    const Vec3 u = b - a, v = c - a;
    const Vec3 normal(u.y() * v.z() - u.z() * v.y(), u.z() * v.x() - u.x() * v.z(), u.x() * v.y() - u.y() * v.x());
    if (normal.dot(a + b + c) < 0.0) ++inward;
  }
  return inward;
}

// A tile's orientation file made by hand with every piece of the tile the
// other way round (its signs and its border normals negated), as a tile's
// own phase II would leave it had it started from the other side. The
// tile holding the object's highest sample keeps its sign (phase II's
// rule), so another tile is turned: the reconciliation must turn its
// pieces back, and the mesh must be the in-memory one, every triangle
// facing out.
TEST(TileFiles, APieceOrientedTheOtherWayIsTurned) {
  const auto dir = scratch("turned");
  const PointCloud cloud = sphere(12000);
  const TilePlan plan = plan_tiles(pass_over(cloud), tiling(Method::hoppe92, 0.8), dir);
  ASSERT_GT(plan.tiles.size(), 2u);
  for (std::size_t t = 0; t < plan.tiles.size(); ++t) orient_tile(dir, t);
  ASSERT_EQ(reconcile_tiles(dir).turned, 0u) << "the clean run needs no turn";
  // The tile with the highest sample, and another with pieces and border samples (the lowest).
  std::size_t top_tile = 0, turned_tile = 0;
  double top = -1e300, bottom = 1e300;
  for (std::size_t t = 0; t < plan.tiles.size(); ++t) {
    const tile_files::Orientation o =
        tile_files::read_orientation(tile_files::of_tile(dir, plan.tiles[t].id, "orient"));
    for (const tile_files::PieceTop& p : o.tops) {
      if (p.index == UINT64_MAX) continue;
      if (p.z > top) {
        top = p.z;
        top_tile = t;
      }
      if (p.z < bottom && !o.border.empty()) {
        bottom = p.z;
        turned_tile = t;
      }
    }
  }
  ASSERT_NE(top_tile, turned_tile);
  const fs::path orient = tile_files::of_tile(dir, plan.tiles[turned_tile].id, "orient");
  tile_files::Orientation o = tile_files::read_orientation(orient);
  for (std::int8_t& s : o.sign) s = static_cast<std::int8_t>(-s);
  for (tile_files::BorderRecord& b : o.border)
    for (float& c : b.normal) c = -c;
  tile_files::write_orientation(orient, o);
  const TileReconciliation reconciled = reconcile_tiles(dir);
  EXPECT_EQ(reconciled.turned, o.tops.size()) << "every piece of tile " << turned_tile << " turned back";
  EXPECT_EQ(reconciled.disagreeing, 0u);
  for (std::size_t t = 0; t < plan.tiles.size(); ++t) contour_tile(dir, t);
  stitch_tiles(dir, dir / "mesh.ply");
  const Mesh tiled = io::read_mesh(dir / "mesh.ply");
  ReconstructionOptions options;
  options.method = Method::hoppe92;
  const Reconstruction whole = reconstruct(cloud, options);
  EXPECT_EQ(inward_triangles(tiled), 0u);
  EXPECT_TRUE(same_mesh(tiled, whole.mesh(), 1e-9 * whole.contour.cell));
  fs::remove_all(dir);
}

// ---------------------------------------------------------------------------
// Item 5: workspaces.

bool locked_by_someone(const fs::path& lock) {
  const int fd = ::open(lock.c_str(), O_RDWR | O_CLOEXEC);
  if (fd < 0) return false;
  const bool taken = ::flock(fd, LOCK_EX | LOCK_NB) != 0;
  ::close(fd);
  return taken;
}

TEST(TileWorkspaces, AreDistinctAndLockedInOneParent) {
  const auto parent = scratch("workspaces");
  {
    TileWorkspace a(parent), b(parent);
    EXPECT_NE(a.path(), b.path());
    EXPECT_TRUE(a.path().filename().string().starts_with("recon-tiles-"));
    EXPECT_TRUE(locked_by_someone(a.path() / "recon-tiles.lock"));
    EXPECT_TRUE(locked_by_someone(b.path() / "recon-tiles.lock"));
    EXPECT_EQ(remove_stale_tile_workspaces(parent), 0u) << "live workspaces are not stale";
    EXPECT_TRUE(fs::exists(a.path()) && fs::exists(b.path()));
  }
  EXPECT_TRUE(fs::is_empty(parent));
  fs::remove_all(parent);
}

// A run killed by SIGKILL leaves its folder with a lock nobody holds: the
// next run in the same parent removes it. Nothing else goes: a folder
// without the lock file, one whose lock is held (by another process's
// descriptor: a second open file description stands for it here), one not
// named recon-tiles-*, a link to a stale folder (the folder stays too).
TEST(TileWorkspaces, StaleOnesAreRemovedAndNothingElse) {
  const auto parent = scratch("stale");
  const auto folder = [&](const std::string& name, bool lock) {
    fs::create_directories(parent / name);
    std::ofstream(parent / name / "tile-000000.points") << "x";
    if (lock) std::ofstream(parent / name / "recon-tiles.lock");
    return parent / name;
  };
  const fs::path stale = folder("recon-tiles-dead01", true);
  const fs::path unlocked = folder("recon-tiles-nolock", false);
  const fs::path held = folder("recon-tiles-held01", true);
  const fs::path other = folder("other-tiles", true);
  const fs::path elsewhere = scratch("stale-elsewhere");
  std::ofstream(elsewhere / "recon-tiles.lock");
  fs::create_directory_symlink(elsewhere, parent / "recon-tiles-link01");
  const int holder = ::open((held / "recon-tiles.lock").c_str(), O_RDWR | O_CLOEXEC);
  ASSERT_EQ(::flock(holder, LOCK_EX | LOCK_NB), 0);
  {
    TileWorkspace next(parent);
    EXPECT_FALSE(fs::exists(stale));
    for (const fs::path& kept : {unlocked, held, other, elsewhere, parent / "recon-tiles-link01"})
      EXPECT_TRUE(fs::exists(kept / "recon-tiles.lock") || fs::exists(kept / "tile-000000.points")) << kept;
  }
  ::close(holder);
  EXPECT_EQ(remove_stale_tile_workspaces(parent), 1u) << "once its holder is gone";
  EXPECT_FALSE(fs::exists(held));
  fs::remove_all(parent);
  fs::remove_all(elsewhere);
}

// Item 23c: a parent whose path leaves no room within what the signal
// handler can hold is refused up front, with a message saying why.
TEST(TileWorkspaces, ATooLongParentIsRefused) {
  const fs::path parent = fs::path(::testing::TempDir()) / std::string(max_workspace_path, 'd');
  try {
    TileWorkspace workspace(parent);
    ADD_FAILURE() << "a workspace the handler cannot clean was made";
  } catch (const InvalidInputError& e) {
    EXPECT_TRUE(has(e.what(), "must have a path of at most")) << e.what();
  }
}

// Item 23b: the handler removes every file of a workspace whatever its
// name: tiles numbered past 999,999, temporaries, the lock.
TEST(TileWorkspaces, TheHandlerRemovesEveryFile) {
  const auto parent = scratch("handler");
  TileWorkspace workspace(parent);
  for (const std::uint64_t id : {std::uint64_t{0}, std::uint64_t{999999}, std::uint64_t{1234567}})
    std::ofstream(tile_files::of_tile(workspace.path(), id, "mesh")) << "x";
  EXPECT_TRUE(fs::exists(workspace.path() / "tile-1234567.mesh"));
  std::ofstream(workspace.path() / ".tile-000001.mesh.tmp-12-34") << "x";
  remove_tile_workspaces();
  EXPECT_FALSE(fs::exists(workspace.path()));
  fs::remove_all(parent);
}

// Item 21: Ctrl-C while tiles are being contoured. The handler runs while
// other threads still commit tile files; the workspace must be gone when it
// returns, whatever they do meanwhile (five times over).
bool removed_while_threads_commit(const fs::path& parent) {
  TileWorkspace workspace(parent);
  std::atomic<int> committed{0};
  const auto writer = [&](std::uint64_t first) {
    for (std::uint64_t id = first; id < first + 100000; ++id) {
      try {
        detail::BinaryWriter out(tile_files::of_tile(workspace.path(), id, "mesh"), tile_files::mesh_magic);
        out.commit();
        ++committed;
      } catch (const IoError&) {
        return;  // (the folder is gone)
      }
    }
  };
  std::vector<std::thread> writers;
  for (std::uint64_t w = 0; w < 3; ++w) writers.emplace_back(writer, w * 200000);
  while (committed.load() < 30) std::this_thread::yield();
  remove_tile_workspaces();
  const bool gone = !fs::exists(workspace.path());
  for (std::thread& w : writers) w.join();
  return gone && !fs::exists(workspace.path());
}

TEST(TileWorkspaces, TheHandlerRemovesTheFolderWhileThreadsCommit) {
  const auto parent = scratch("handler-race");
  int left = 0;
  for (int attempt = 0; attempt < 5; ++attempt) left += removed_while_threads_commit(parent) ? 0 : 1;
  EXPECT_EQ(left, 0) << "of 5 workspaces were left behind";
  fs::remove_all(parent);
}

// ---------------------------------------------------------------------------
// The program: items 22 and 23c.

#ifdef RECON_CLI_PATH
std::string quoted(const fs::path& path) {
  std::string out = "'";
  for (const char c : path.string()) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

// The input shortened while a tiled run reads it (SIGBUS: it is mapped):
// the error names the input, as in memory, and the tiles' folder goes too.
TEST(TiledProgram, AnInputShortenedWhileTiledLeavesNoTiles) {
  const auto dir = scratch("sigbus");
  fs::create_directories(dir / "tmp");
  {
    std::ofstream big(dir / "big.xyz");
    std::string block;
    for (int i = 0; i < 1000; ++i) block += std::to_string(i % 100) + " " + std::to_string(i % 37) + " 0.5\n";
    for (int i = 0; i < 8000; ++i) big << block;  // about 80 MB
  }
  // Start recon, wait until its tiles' folder exists and the input is mapped, cut the input to one page.
  const std::string command =
      "cd " + quoted(dir) + " && { " + quoted(RECON_CLI_PATH) +
      " reconstruct big.xyz -o out.ply --tile-size 10 --tmpdir tmp </dev/null >/dev/null 2>stderr.txt & pid=$!; " +
      "while [ -e /proc/$pid ] && ! { ls tmp | grep -q recon-tiles- && grep -q big.xyz /proc/$pid/maps; } "
      "2>/dev/null; " +
      "do :; done; truncate -s 4096 big.xyz; wait $pid; exit $?; }";
  const int status = std::system(command.c_str());
  ASSERT_TRUE(status != -1 && WIFEXITED(status)) << status;
  const std::string message = bytes_of(dir / "stderr.txt");
  EXPECT_EQ(WEXITSTATUS(status), 1) << message;
  EXPECT_EQ(message,
            "recon: error: big.xyz: the file was shortened, or could not be read, while recon was reading it\n");
  EXPECT_TRUE(fs::is_empty(dir / "tmp")) << "the tiles' folder was left behind";
  EXPECT_FALSE(fs::exists(dir / "out.ply"));
  fs::remove_all(dir);
}

// Item 21, end to end: SIGINT once the first tile's mesh is written, while
// the two lanes of tiles still contour and commit theirs (was: tile-N.mesh
// files left behind, 5 of 5 tries). Twice.
TEST(TiledProgram, AnInterruptWhileContouringLeavesNoTiles) {
  const auto dir = scratch("sigint-contour");
  const std::string cli = quoted(RECON_CLI_PATH);
  ASSERT_EQ(std::system(("cd " + quoted(dir) + " && " + cli + " --quiet generate terrain -n 40000 -o t.ply").c_str()),
            0);
  for (int attempt = 0; attempt < 2; ++attempt) {
    fs::create_directories(dir / "tmp");
    const std::string command =
        "cd " + quoted(dir) + " && { " + cli +
        " --quiet reconstruct t.ply -o m.ply --tile-size 0.3 --tmpdir tmp </dev/null >/dev/null 2>/dev/null & "
        "pid=$!; " +
        "while [ -e /proc/$pid ] && ! ls tmp/recon-tiles-*/tile-*.mesh >/dev/null 2>&1; do :; done; " +
        "kill -INT $pid; wait $pid; exit $?; }";
    const int status = std::system(command.c_str());
    ASSERT_TRUE(status != -1 && WIFEXITED(status)) << status;
    EXPECT_EQ(WEXITSTATUS(status), 128 + SIGINT) << "the run must end by the interrupt, not finish";
    EXPECT_TRUE(fs::is_empty(dir / "tmp")) << "attempt " << attempt << ": tiles were left behind";
    EXPECT_FALSE(fs::exists(dir / "m.ply"));
    fs::remove_all(dir / "tmp");
  }
  fs::remove_all(dir);
}

TEST(TiledProgram, ATooLongTmpdirIsRefusedUpFront) {
  const auto dir = scratch("long-tmpdir");
  std::ofstream(dir / "in.xyz") << "0 0 0\n1 0 0\n0 1 0\n";
  std::string tmpdir;  // (an existing folder, within PATH_MAX, too long for a workspace's path)
  for (int level = 0; level < 16; ++level) tmpdir += (level > 0 ? "/" : "") + std::string(250, 'd');
  fs::create_directories(dir / tmpdir);
  const std::string command = "cd " + quoted(dir) + " && " + quoted(RECON_CLI_PATH) +
                              " reconstruct in.xyz -o out.ply --tile-size 1 --tmpdir " + tmpdir +
                              " </dev/null >/dev/null 2>stderr.txt";
  const int status = std::system(command.c_str());
  ASSERT_TRUE(status != -1 && WIFEXITED(status)) << status;
  const std::string message = bytes_of(dir / "stderr.txt");
  EXPECT_EQ(WEXITSTATUS(status), 1) << message;
  EXPECT_TRUE(message.starts_with("recon: error: dddd")) << message;
  EXPECT_TRUE(has(message, "must have a path of at most")) << message;
  EXPECT_EQ(std::count(message.begin(), message.end(), '\n'), 1) << message;
  fs::remove_all(dir);
}
#endif

}  // namespace
}  // namespace recon
