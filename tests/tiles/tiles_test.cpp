// Tiled runs (tiles.h) against the in-memory one: on clean data the same
// triangles for several tile sizes, down to tiles smaller than an object;
// on noisy data the same topology within a cell; the steps' files rerun to
// the same bytes, and damaged ones are errors that name them.

#include "recon/tiles/tiles.h"

#include "conics_truth.h"
#include "mesh_compare.h"
#include "recon/core/errors.h"
#include "recon/core/shapes.h"
#include "recon/io/mesh_io.h"
#include "test_data.h"
#include "tile_cases.h"
#include "tiles/files.h"  // (the tiles' files, made by hand below)

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <iterator>
#include <map>
#include <memory>
#include <numbers>
#include <string>

namespace recon {
namespace {

using namespace tile_testing;

std::filesystem::path scratch(const std::string& name) { return scratch_folder("recon-tiles-test-" + name); }

struct Case {
  const char* shape;
  std::size_t points;
  Method method;
  double tile_size;
  double noise = 0.0;  // of the sample spacing
};

std::string name_of(const Case& c) {
  return std::string(c.shape) + "_" + method_name(c.method) + "_" +
         std::to_string(static_cast<int>(c.tile_size * 100)) + (c.noise > 0.0 ? "_noisy" : "");
}

PointCloud cloud_of(const Case& c) { return noisy_sample(c.shape, c.points, c.noise, 11, 5); }

// The in-memory run a tiled one is compared with, by the case's method.
Reconstruction in_memory(const PointCloud& cloud, const Case& c) {
  ReconstructionOptions options;
  options.method = c.method;
  return reconstruct(cloud, options);
}

// The in-memory mesh the tiled one must equal: the final one (phase V's
// for the refined method, phase IV's for hoppe92).
const Mesh& contoured(const Reconstruction& r) { return r.mesh(); }

struct Tiled {
  TiledRun run;
  Mesh mesh;
};

Tiled run_tiled(const PointCloud& cloud, const Case& c) {
  TilingOptions options;
  options.reconstruction.method = c.method;
  options.tile_size = c.tile_size;
  const auto dir = scratch(name_of(c));
  Tiled t;
  t.run = reconstruct_tiled(pass_over(cloud, 4096), options, dir / "work", dir / "mesh.ply");
  t.mesh = io::read_mesh(dir / "mesh.ply");
  std::filesystem::remove_all(dir);
  return t;
}

class TiledRunOnCleanData : public ::testing::TestWithParam<Case> {};

TEST_P(TiledRunOnCleanData, SameTrianglesAsInMemory) {
  const Case& c = GetParam();
  const PointCloud cloud = cloud_of(c);
  const Reconstruction whole = in_memory(cloud, c);
  const Tiled tiled = run_tiled(cloud, c);
  ASSERT_GT(tiled.run.plan.tiles.size(), 1u) << "the case must cut the cloud";
  EXPECT_EQ(tiled.run.plan.statistics_points, cloud.size());
  EXPECT_EQ(tiled.run.plan.k, whole.planes.k);
  EXPECT_EQ(tiled.run.plan.lattice.cell, whole.contour.cell);
  for (const TileOrientation& o : tiled.run.orientations) EXPECT_EQ(o.inexact_samples, 0u);
  EXPECT_EQ(tiled.run.reconciliation.disagreeing, 0u);
  EXPECT_TRUE(same_mesh(tiled.mesh, contoured(whole), 1e-9 * whole.contour.cell));
  EXPECT_GT(tiled.mesh.triangles.size(), 1000u);
  if (whole.refinement) {  // phase V's step 4, decided over the whole mesh in both
    EXPECT_EQ(tiled.run.mesh.trimmed, whole.refinement->trimmed);
    EXPECT_EQ(tiled.run.mesh.stray_triangles, whole.refinement->stray_triangles);
    EXPECT_EQ(tiled.run.mesh.fragments, whole.refinement->fragments);
    EXPECT_EQ(tiled.run.mesh.fragment_triangles, whole.refinement->fragment_triangles);
    EXPECT_EQ(tiled.run.mesh.crease_vertices > 0, whole.refinement->crease_vertices > 0);
  }
}

// Colours come through tiles as in memory: each vertex the same blend of
// the same samples' colours (a cloud coloured in stripes across the tiles).
TEST(TiledRun, ColoursAreTheInMemoryOnes) {
  const Case c{"torus", 12000, Method::refined, 0.9};
  PointCloud cloud = cloud_of(c);
  for (const Vec3& p : cloud.positions)
    cloud.colors.push_back({static_cast<std::uint8_t>(128.0 + 127.0 * std::sin(7.0 * p.x())),
                            static_cast<std::uint8_t>(128.0 + 127.0 * std::cos(5.0 * p.y())),
                            static_cast<std::uint8_t>(p.z() > 0.0 ? 200 : 30)});
  const Reconstruction whole = reconstruct(cloud);
  const Tiled tiled = run_tiled(cloud, c);
  ASSERT_GT(tiled.run.plan.tiles.size(), 1u);
  EXPECT_TRUE(tiled.run.plan.colors);
  ASSERT_TRUE(same_mesh(tiled.mesh, whole.mesh(), 1e-9 * whole.contour.cell));
  ASSERT_EQ(tiled.mesh.colors.size(), tiled.mesh.vertices.size());
  const KdTree<3> tree(whole.mesh().vertices);
  std::size_t same = 0;
  for (std::size_t v = 0; v < tiled.mesh.vertices.size(); ++v)
    same += tiled.mesh.colors[v] == whole.mesh().colors[tree.nearest(tiled.mesh.vertices[v]).index] ? 1u : 0u;
  EXPECT_EQ(same, tiled.mesh.vertices.size());
  // Without colours asked for, none.
  TilingOptions options;
  options.reconstruction.mesh_colors = false;
  options.tile_size = c.tile_size;
  const auto dir = scratch("no-colours");
  reconstruct_tiled(pass_over(cloud, 4096), options, dir / "work", dir / "mesh.ply");
  EXPECT_FALSE(io::read_mesh(dir / "mesh.ply").has_colors());
  std::filesystem::remove_all(dir);
}

// Vertex normals come through tiles as in memory: phase V's fitted ones
// travel in the tiles' mesh files, the others are summed from the kept
// faces by the stitch (in another order: the same floats, or within one
// rounding of them). The box has creases and corners (face-weighted), the
// hoppe92 torus only face-weighted normals.
// x rounded to float, as the files hold normals. (Through a volatile: at
// -O3, GCC 12 folded a vectorised double -> float -> double round trip.)
double as_float(double x) {
  volatile float f = static_cast<float>(x);
  return static_cast<double>(f);
}

TEST(TiledRun, NormalsAreTheInMemoryOnes) {
  for (const Case& c : {Case{"box", 12000, Method::refined, 0.45}, Case{"torus", 8000, Method::hoppe92, 0.9}}) {
    const PointCloud cloud = cloud_of(c);
    ReconstructionOptions in_memory;
    in_memory.method = c.method;
    in_memory.vertex_normals = true;
    const Reconstruction whole = reconstruct(cloud, in_memory);
    TilingOptions options;
    options.reconstruction = in_memory;
    options.tile_size = c.tile_size;
    const auto dir = scratch(std::string("normals-") + c.shape);
    const TiledRun run = reconstruct_tiled(pass_over(cloud, 4096), options, dir / "work", dir / "mesh.ply");
    const Mesh tiled = io::read_mesh(dir / "mesh.ply");
    std::filesystem::remove_all(dir);
    ASSERT_GT(run.plan.tiles.size(), 1u) << c.shape;
    ASSERT_TRUE(same_mesh(tiled, whole.mesh(), 1e-9 * whole.contour.cell)) << c.shape;
    ASSERT_EQ(tiled.normals.size(), tiled.vertices.size());
    const KdTree<3> tree(whole.mesh().vertices);
    std::size_t exact = 0;
    double worst = 0.0;
    for (std::size_t v = 0; v < tiled.vertices.size(); ++v) {
      const Vec3& n = whole.mesh().normals[tree.nearest(tiled.vertices[v]).index];
      const Vec3 expected(as_float(n.x()), as_float(n.y()), as_float(n.z()));  // as written
      exact += tiled.normals[v] == expected ? 1u : 0u;
      worst = std::max(worst, (tiled.normals[v] - expected).norm());
    }
    EXPECT_LT(worst, 1e-6) << c.shape;
    EXPECT_GT(exact, tiled.vertices.size() * 9 / 10) << c.shape;
  }
}

// Real scans, cut into tiles a quarter of their extent wide (or the least
// the halo allows): the bunny into 16 tiles, distcap with its open boundary
// trimmed, its strays and fragments dropped across tiles, the kitten's
// creases. (Hoppe's cactus is left out: its samples lie on a grid, and
// where neighbours are exactly as far, a tile's kd-tree breaks the tie
// for the k-th one another way than the whole cloud's; see tiles.h.)
TEST(TiledRun, RealScansSameAsInMemory) {
  for (const char* file : {"stanford_bunny/bun_zipper.ply", "hoppe_distcap/distcap.pts", "cgal_kitten/kitten.xyz"}) {
    const auto path = testing::shared_data(file);
    RECON_REQUIRE_DATA(path);
    PointCloud cloud = io::read_points(path);
    cloud.normals.clear();
    const Reconstruction whole = reconstruct(cloud);
    const std::string name = path.stem().string();
    const Case c{name.c_str(), cloud.size(), Method::refined,
                 0.25 * bounding_box<3>(cloud.positions).extent().maxCoeff()};
    const Tiled tiled = run_tiled(cloud, c);
    EXPECT_GT(tiled.run.plan.tiles.size(), 1u) << file;
    EXPECT_TRUE(same_mesh(tiled.mesh, whole.mesh(), 1e-9 * whole.contour.cell)) << file;
    EXPECT_EQ(tiled.run.mesh.trimmed, whole.refinement->trimmed) << file;
    EXPECT_EQ(tiled.run.mesh.fragments, whole.refinement->fragments) << file;
  }
}

// Tile cores from a quarter of an object to about the whole; the sphere and
// torus are two objects a tile border may cut both of. The refined method's
// phase V: the box's creases and corners (cut by the borders of 12 tiles in
// the larger box), the terrain's open boundary trimmed across tiles.
INSTANTIATE_TEST_SUITE_P(
    Shapes, TiledRunOnCleanData,
    ::testing::Values(Case{"sphere", 12000, Method::hoppe92, 0.8}, Case{"torus", 12000, Method::refined, 0.9},
                      Case{"two", 15000, Method::hoppe92, 1.0}, Case{"two", 15000, Method::refined, 1.4},
                      Case{"terrain", 15000, Method::refined, 0.5}, Case{"box", 12000, Method::refined, 0.5},
                      Case{"box", 60000, Method::refined, 0.3}),
    [](const auto& p) { return name_of(p.param); });

TEST(TiledRun, SeparateObjectsStaySeparate) {
  const Case c{"two", 15000, Method::refined, 1.0};
  const Tiled tiled = run_tiled(cloud_of(c), c);
  EXPECT_EQ(tiled.run.reconciliation.objects, 2u);
  const MeshTopology topology = analyze_topology(tiled.mesh);
  EXPECT_EQ(topology.components, 2u);
  EXPECT_TRUE(topology.watertight());
  EXPECT_GT(topology.signed_volume, 0.0) << "facing outward";
}

// Issue 27: a hollow ball with a ball in its cavity, cut into tiles: the
// cavity's wall (an object inside one other) faces into the cavity and the
// ball (inside two) out, as in memory, from winding numbers summed over
// the tiles. Every triangle is the in-memory one, oriented the same way.
TEST(TiledRun, NestedObjectsFaceAsInMemory) {
  const Case c{"nested", 20000, Method::refined, 0.8};
  const PointCloud cloud = cloud_of(c);
  const Reconstruction whole = in_memory(cloud, c);
  ASSERT_EQ(whole.oriented->nested_turned, 1u);
  const Tiled tiled = run_tiled(cloud, c);
  ASSERT_GT(tiled.run.plan.tiles.size(), 1u);
  EXPECT_EQ(tiled.run.reconciliation.objects, 3u);
  EXPECT_EQ(tiled.run.reconciliation.objects_nested, 2u);
  EXPECT_EQ(tiled.run.reconciliation.nested_turned, 1u);
  EXPECT_EQ(tiled.run.reconciliation.disagreeing, 0u);
  EXPECT_TRUE(same_mesh(tiled.mesh, whole.mesh(), 1e-9 * whole.contour.cell));
  const double volume = 4.0 / 3.0 * std::numbers::pi * (1.0 - 0.7 * 0.7 * 0.7 + 0.3 * 0.3 * 0.3);
  EXPECT_NEAR(analyze_topology(tiled.mesh).signed_volume, volume, 0.02 * volume) << "every wall the true way";
}

// A ball in a bowl: the bowl's box holds the ball's, and its winding
// number there exceeds 1/2, but its samples, summed over the tiles, close
// no surface: nothing is turned, as in memory.
TEST(TiledRun, ABallInABowlFacesAsInMemory) {
  const Case c{"ball-in-bowl", 24000, Method::refined, 0.8};
  const PointCloud cloud = testing::ball_in_bowl(20000, 4000, 24);
  const Reconstruction whole = in_memory(cloud, c);
  ASSERT_EQ(whole.oriented->pieces_nested, 0u);
  const Tiled tiled = run_tiled(cloud, c);
  ASSERT_GT(tiled.run.plan.tiles.size(), 1u);
  EXPECT_EQ(tiled.run.reconciliation.objects_nested, 0u);
  EXPECT_EQ(tiled.run.reconciliation.nested_turned, 0u);
  EXPECT_TRUE(same_mesh(tiled.mesh, whole.mesh(), 1e-9 * whole.contour.cell));
}

// Noisy data: a sample's neighbourhood is the same in a tile, but the
// orientation's walk may differ; the meshes have the same topology and lie
// within a cell of each other.
TEST(TiledRun, NoisyDataSameTopologyWithinACell) {
  const Case c{"torus", 15000, Method::refined, 1.0, 0.5};
  const PointCloud cloud = cloud_of(c);
  const Reconstruction whole = reconstruct(cloud, {});
  const Tiled tiled = run_tiled(cloud, c);
  const MeshTopology a = analyze_topology(tiled.mesh), b = analyze_topology(contoured(whole));
  EXPECT_EQ(a.components, b.components);
  EXPECT_EQ(a.euler_characteristic, b.euler_characteristic);
  EXPECT_EQ(a.boundary_loops, b.boundary_loops);
  const KdTree<3> to_whole(contoured(whole).vertices), to_tiled(tiled.mesh.vertices);
  double farthest = 0.0;
  for (const Vec3& v : tiled.mesh.vertices) farthest = std::max(farthest, to_whole.nearest(v).distance2);
  for (const Vec3& v : contoured(whole).vertices) farthest = std::max(farthest, to_tiled.nearest(v).distance2);
  EXPECT_LE(std::sqrt(farthest), whole.contour.cell);
}

std::string bytes_of(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

// A step run again (a task rerun after a worker died) writes the same bytes,
// and the steps can run in any order of tiles.
TEST(TiledRun, StepsRerunToTheSameFiles) {
  const Case c{"sphere", 20000, Method::refined, 0.7};
  const PointCloud cloud = cloud_of(c);
  const auto dir = scratch("rerun");
  TilingOptions options;
  options.tile_size = c.tile_size;
  const TilePlan plan = plan_tiles(pass_over(cloud), options, dir);
  ASSERT_GT(plan.tiles.size(), 2u);
  for (std::size_t t = plan.tiles.size(); t-- > 0;) orient_tile(dir, t);
  reconcile_tiles(dir);
  for (std::size_t t = 0; t < plan.tiles.size(); ++t) contour_tile(dir, t);
  stitch_tiles(dir, dir / "a.ply");
  const std::string mesh_1 = bytes_of(dir / "tile-000001.mesh");
  orient_tile(dir, 1);
  reconcile_tiles(dir);
  contour_tile(dir, 1);
  EXPECT_EQ(bytes_of(dir / "tile-000001.mesh"), mesh_1);
  stitch_tiles(dir, dir / "b.ply");
  EXPECT_EQ(bytes_of(dir / "a.ply"), bytes_of(dir / "b.ply"));
  std::filesystem::remove_all(dir);
}

TEST(TiledRun, DamagedFilesAreErrorsNamingThem) {
  const Case c{"sphere", 4000, Method::hoppe92, 0.8};
  const auto dir = scratch("damaged");
  TilingOptions options;
  options.reconstruction.method = c.method;
  options.tile_size = c.tile_size;
  plan_tiles(pass_over(cloud_of(c)), options, dir);
  EXPECT_THROW(plan_tiles(pass_over(cloud_of(c)), options, dir), InvalidInputError) << "a plan is there already";
  const auto points = dir / "tile-000000.points";
  std::filesystem::resize_file(points, std::filesystem::file_size(points) - 5);
  try {
    orient_tile(dir, 0);
    ADD_FAILURE() << "a truncated tile was read";
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("tile-000000.points"), std::string::npos) << e.what();
  }
  EXPECT_THROW(orient_tile(dir, 1000), InvalidInputError);
  EXPECT_THROW(reconcile_tiles(dir), IoError) << "no tile was oriented";
  std::filesystem::remove(dir / "plan.bin");
  EXPECT_THROW(read_tile_plan(dir), IoError);
  std::filesystem::remove_all(dir);
}

// A tile's mesh naming a vertex it does not have, and a tile's colours
// fewer than its points, are errors naming the file.
TEST(TiledRun, DamagedMeshesAndColoursAreErrorsNamingThem) {
  const Case c{"sphere", 20000, Method::refined, 0.7};
  PointCloud cloud = cloud_of(c);
  cloud.colors.assign(cloud.size(), Color{10, 20, 30});
  const auto dir = scratch("damaged-mesh");
  TilingOptions options;
  options.tile_size = c.tile_size;
  const TilePlan plan = plan_tiles(pass_over(cloud), options, dir);
  ASSERT_TRUE(plan.colors);
  for (std::size_t t = 0; t < plan.tiles.size(); ++t) orient_tile(dir, t);
  reconcile_tiles(dir);
  for (std::size_t t = 0; t < plan.tiles.size(); ++t) contour_tile(dir, t);
  ASSERT_GT(plan.tiles.size(), 1u);
  const auto name_of_file = [&](std::size_t tile, const char* kind) {
    char name[64];
    std::snprintf(name, sizeof name, "tile-%06u.%s", static_cast<unsigned>(plan.tiles[tile].id), kind);
    return std::string(name);
  };
  const auto mesh = dir / name_of_file(0, "mesh");
  {
    std::fstream file(mesh, std::ios::in | std::ios::out | std::ios::binary);
    std::uint64_t vertices = 0;
    file.seekg(8);
    file.read(reinterpret_cast<char*>(&vertices), sizeof vertices);
    ASSERT_GT(vertices, 0u);
    file.seekp(static_cast<std::streamoff>(8 + 8 + vertices * 64 + 8));  // the first triangle's first vertex
    const std::uint32_t wrong = 0xFFFFFFF0u;
    file.write(reinterpret_cast<const char*>(&wrong), sizeof wrong);
  }
  try {
    stitch_tiles(dir, dir / "out.ply");
    ADD_FAILURE() << "a damaged mesh was stitched";
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find(name_of_file(0, "mesh")), std::string::npos) << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "out.ply"));
  const auto colors = dir / name_of_file(1, "colors");
  std::filesystem::resize_file(colors, std::filesystem::file_size(colors) - 3);
  try {
    contour_tile(dir, 1);
    ADD_FAILURE() << "colours fewer than the points were read";
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find(name_of_file(1, "colors")), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(dir);
}

// Phase V's last step across tiles, on tile meshes made by hand (the
// clouds above rarely need it: a peelable strip there reaches the open
// boundary in every tile it crosses, and every part of a component is
// large). Tile A holds a fan of 100 lasting triangles and a peelable
// triangle with no open edge, and another on the fan's edge; tile B a
// peelable triangle across an edge from the first that is on the open
// boundary, a triangle hanging on the fan by a vertex, and a lone
// triangle, and a fan of 5 triangles. The first two peelable triangles go
// (joined across the border), the one on the fan stays with it, as does the
// hanging triangle (their component is the fan's); the lone one (1 % of the
// fan) goes as a fragment, the small fan (5 %) stays.
TEST(TiledRun, StitchDecidesTrimmingAndFragmentsAcrossTiles) {
  const Case c{"sphere", 20000, Method::refined, 0.7};
  const auto dir = scratch("stitch-by-hand");
  TilingOptions options;
  options.tile_size = c.tile_size;
  const TilePlan plan = plan_tiles(pass_over(cloud_of(c)), options, dir);
  ASSERT_GT(plan.tiles.size(), 1u);
  using tile_files::MeshTriangle;
  using tile_files::MeshVertex;
  auto vertex = [](std::uint64_t name, bool shared, std::uint32_t atom) {
    MeshVertex v;
    v.x = static_cast<double>(name);
    v.corner[0] = name;
    v.shared = shared ? 1 : 0;
    v.atom = atom;
    v.object = 0;
    return v;
  };
  auto triangle = [](std::uint32_t p, std::uint32_t q, std::uint32_t r, std::uint32_t peel) {
    MeshTriangle t;
    t.v[0] = p;
    t.v[1] = q;
    t.v[2] = r;
    t.peel = peel;
    return t;
  };
  tile_files::TileMesh a;  // names: fan 1000..1101 (1000 shared), peelable 2000 and 2001-2002 (shared)
  for (std::uint64_t v = 0; v < 102; ++v) a.vertices.push_back(vertex(1000 + v, v == 0, 0));
  for (std::uint32_t t = 1; t <= 100; ++t) a.triangles.push_back(triangle(0, t, t + 1, tile_files::none));
  a.atom_triangles = {100, 0, 0, 0, 0, 0};
  a.vertices.push_back(vertex(2000, false, 1));
  a.vertices.push_back(vertex(2001, true, 2));
  a.vertices.push_back(vertex(2002, true, 3));
  a.triangles.push_back(triangle(102, 103, 104, 0));
  a.vertices.push_back(vertex(2100, false, 4));  // a peelable triangle on the fan that reaches no open edge
  a.vertices.push_back(vertex(2101, false, 5));
  a.triangles.push_back(triangle(105, 106, 5, 1));
  a.peel_open = {0, 0};
  a.votes = {{0, 0, 101}, {1, 0, 1}};
  tile_files::TileMesh b;
  b.vertices = {vertex(2002, true, 0),  vertex(2001, true, 1),  vertex(2003, false, 2),   // peelable
                vertex(1000, true, 3),  vertex(3001, false, 3), vertex(3002, false, 3),   // hanging on the fan
                vertex(4000, false, 4), vertex(4001, false, 4), vertex(4002, false, 4)};  // alone
  b.triangles = {triangle(0, 1, 2, 0), triangle(3, 4, 5, tile_files::none), triangle(6, 7, 8, tile_files::none)};
  for (std::uint64_t v = 0; v < 7; ++v) b.vertices.push_back(vertex(5000 + v, false, 5));  // a fan of 5
  for (std::uint32_t t = 10; t < 15; ++t) b.triangles.push_back(triangle(9, t, t + 1, tile_files::none));
  b.peel_open = {1};
  b.atom_triangles = {0, 0, 0, 1, 1, 5};
  b.votes = {{2, 0, 1}, {3, 0, 2}, {4, 0, 3}, {5, 0, 7}};
  for (std::size_t t = 0; t < plan.tiles.size(); ++t) {
    char name[64];
    std::snprintf(name, sizeof name, "tile-%06u.mesh", static_cast<unsigned>(plan.tiles[t].id));
    tile_files::write_mesh(dir / name, t == 0 ? a : t == 1 ? b : tile_files::TileMesh{});
  }
  const StitchedMesh m = stitch_tiles(dir, dir / "out.ply");
  EXPECT_EQ(m.trimmed, 2u) << "the peelable triangle without an open edge goes with the one across the border";
  EXPECT_EQ(m.fragments, 1u) << "the lone triangle (1 % of the fan's 102) goes, the fan of 5 (5 %) stays";
  EXPECT_EQ(m.fragment_triangles, 1u) << "the triangles on the fan, by a vertex or a shared vertex, are part of it";
  EXPECT_EQ(m.triangles, 107u);
  EXPECT_EQ(m.vertices, 113u);  // the fan's 102, 2 of each triangle on it (1000 welded), the small fan's 7
  EXPECT_EQ(io::read_mesh(dir / "out.ply").triangles.size(), 107u);
  std::filesystem::remove_all(dir);
}

TEST(TiledRun, WorkspaceIsRemovedAlsoOnErrors) {
  std::filesystem::path path;
  try {
    TileWorkspace workspace(::testing::TempDir());
    path = workspace.path();
    std::ofstream(path / "a") << "x";
    throw InvalidInputError("stop");
  } catch (const InvalidInputError&) {
  }
  EXPECT_FALSE(path.empty());
  EXPECT_FALSE(std::filesystem::exists(path));
}

// A tile of copies of one point (a scanner's "no return" written as one
// position many times) makes no plane, as in the whole cloud: the run goes
// on, and the mesh is the same.
TEST(TiledRun, ATileOfCopiesMakesNoPlane) {
  const Case c{"sphere", 8000, Method::hoppe92, 1.0};
  PointCloud cloud = cloud_of(c);
  for (int i = 0; i < 50; ++i) cloud.positions.emplace_back(0.0, 0.0, 6.0);
  const Reconstruction whole = in_memory(cloud, c);
  const Tiled tiled = run_tiled(cloud, c);
  EXPECT_TRUE(same_mesh(tiled.mesh, contoured(whole), 1e-9 * whole.contour.cell));
  EXPECT_EQ(analyze_topology(tiled.mesh).components, 1u);
}

TEST(TiledRun, EmptyCloudIsRefused) {
  const auto dir = scratch("empty");
  EXPECT_THROW(plan_tiles(pass_over(PointCloud{}), {}, dir), InvalidInputError);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace recon
