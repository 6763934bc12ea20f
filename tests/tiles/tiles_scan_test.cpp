// A generated scan-like cloud through tiles, against the in-memory run: an
// open terrain (its boundary trimmed across tile borders) with outliers
// scattered above it, which grow sheets that phase V drops as strays and
// fragments, some cut by tile borders. Phase V's last step is decided over
// the whole mesh in both runs (tiles/step5_stitch.cpp), so the meshes must be the
// same. Runs everywhere (the real scans' test skips without ../shared/data).

#include "recon/tiles/tiles.h"

#include "mesh_compare.h"
#include "recon/core/shapes.h"
#include "recon/io/mesh_io.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <random>

namespace recon {
namespace {

PointCloud scan_with_outliers() {
  constexpr std::size_t points = 15000, outliers = 80;
  const auto terrain = make_shape("terrain");
  PointCloud cloud = terrain->sample(points, 5);
  const double spacing = 2.0 / std::ceil(std::sqrt(static_cast<double>(points)));
  std::mt19937_64 random(1);
  std::uniform_int_distribution<std::size_t> which(0, points - 1);
  std::uniform_real_distribution<double> height(3.0 * spacing, 6.0 * spacing);
  for (std::size_t i = 0; i < outliers; ++i)
    cloud.positions.push_back(cloud.positions[which(random)] + Vec3(0.0, 0.0, height(random)));
  return cloud;
}

TEST(TiledScan, OutliersStraysAndFragmentsAreDroppedAsInMemory) {
  const PointCloud cloud = scan_with_outliers();
  const Reconstruction whole = reconstruct(cloud);
  ASSERT_TRUE(whole.refinement);
  ASSERT_GT(whole.refinement->trimmed, 0u) << "the case must trim";
  ASSERT_GT(whole.refinement->stray_triangles, 0u) << "the case must drop strays";
  ASSERT_GT(whole.refinement->fragments, 0u) << "the case must drop fragments";

  const auto dir = std::filesystem::path(::testing::TempDir()) / "recon-tiled-scan";
  std::filesystem::remove_all(dir);
  TilingOptions options;
  options.tile_size = 0.5;
  const TiledRun run = reconstruct_tiled(pass_over(cloud, 4096), options, dir / "work", dir / "mesh.ply");
  const Mesh mesh = io::read_mesh(dir / "mesh.ply");
  std::filesystem::remove_all(dir);
  ASSERT_GT(run.plan.tiles.size(), 1u);
  EXPECT_EQ(run.mesh.trimmed, whole.refinement->trimmed);
  EXPECT_EQ(run.mesh.stray_triangles, whole.refinement->stray_triangles);
  EXPECT_EQ(run.mesh.fragments, whole.refinement->fragments);
  EXPECT_EQ(run.mesh.fragment_triangles, whole.refinement->fragment_triangles);
  EXPECT_TRUE(same_mesh(mesh, whole.mesh(), 1e-9 * whole.contour.cell));
}

}  // namespace
}  // namespace recon
