// A tiled run of a cloud larger than one phase I may measure
// (TilingOptions::statistics_points): the cloud-wide measures taken over
// its tiles (src/tiles/statistics.h) are the in-memory run's exactly, and so
// is the mesh. Before, they came from spatial patches of the cloud, and a
// tiled run was not the in-memory run (issue 28: 9,596,770 triangles
// against 9,664,462 on a 4M-point terrain).

#include "recon/tiles/tiles.h"

#include "mesh_compare.h"
#include "recon/core/shapes.h"
#include "recon/io/mesh_io.h"
#include "tile_cases.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace recon {
namespace {

using namespace tile_testing;

struct Case {
  const char* shape;
  std::size_t points;
  Method method;
  double noise = 0.0;  // of the sample spacing
  std::optional<double> rho = std::nullopt;
  std::size_t copies = 0;    // of one sample (a scanner's repeated point: no spacing, no plane there)
  std::size_t in_a_row = 1;  // samples of the shape, 3 apart along x (a sparse shape's halo spans it whole)
};

void PrintTo(const Case& c, std::ostream* os) { *os << c.shape << " " << c.points << " " << method_name(c.method); }

PointCloud cloud_of(const Case& c) {
  PointCloud cloud = noisy_sample(c.shape, c.points, c.noise, 23, 7);
  for (std::size_t i = 0; i < c.copies; ++i) cloud.positions.push_back(cloud.positions[c.points / 3]);
  for (std::size_t r = 1; r < c.in_a_row; ++r)
    for (const Vec3& p : noisy_sample(c.shape, c.points, c.noise, 23 + r, 7).positions)
      cloud.positions.push_back(p + Vec3(3.0 * static_cast<double>(r), 0.0, 0.0));
  return cloud;
}

class MeasuredOverTiles : public ::testing::TestWithParam<Case> {};

TEST_P(MeasuredOverTiles, MeasuresAndMeshAreTheInMemoryOnes) {
  const Case& c = GetParam();
  const PointCloud cloud = cloud_of(c);
  ReconstructionOptions options;
  options.method = c.method;
  options.planes.rho = c.rho;
  const Reconstruction whole = reconstruct(cloud, options);

  TilingOptions tiling;
  tiling.reconstruction = options;
  tiling.statistics_points = cloud.size() / 5;  // patches only: the measures come from the tiles
  tiling.tile_size = 0.3 * bounding_box<3>(cloud.positions).extent().maxCoeff();
  const auto dir = scratch_folder("recon-tile-statistics-" + std::string(c.shape));
  const TiledRun run = reconstruct_tiled(pass_over(cloud, 4096), tiling, dir / "work", dir / "mesh.ply");
  const Mesh mesh = io::read_mesh(dir / "mesh.ply");
  std::filesystem::remove_all(dir);

  const TilePlan& plan = run.plan;
  ASSERT_GT(plan.tiles.size(), 1u);
  if (c.noise > 0.0) {
    EXPECT_GT(whole.planes.k, whole.planes.k_requested) << "the case must raise k";
  }
  EXPECT_TRUE(plan.statistics_over_tiles);
  EXPECT_EQ(plan.statistics_points, cloud.size());
  EXPECT_EQ(plan.statistics_inexact, 0u);
  EXPECT_EQ(plan.k, whole.planes.k);
  const CloudSpacing a = plan.spacing, b = whole.planes.spacing();
  EXPECT_EQ(a.irregularity, b.irregularity);
  EXPECT_EQ(a.rho, b.rho);
  EXPECT_EQ(a.gap, b.gap);
  EXPECT_EQ(a.noise, b.noise);
  EXPECT_EQ(plan.has_quadric_medians, whole.quadrics.has_value());
  if (whole.quadrics) {
    EXPECT_EQ(plan.quadric_medians.fit_residual, whole.quadrics->medians.fit_residual);
    EXPECT_EQ(plan.quadric_medians.radius, whole.quadrics->medians.radius);
    EXPECT_EQ(plan.quadric_medians.noise, whole.quadrics->medians.noise);
    EXPECT_EQ(plan.quadric_medians.fit_residual_quartile, whole.quadrics->medians.fit_residual_quartile);
  }
  EXPECT_EQ(plan.lattice.cell, whole.contour.cell);
  for (const TileOrientation& o : run.orientations) EXPECT_EQ(o.inexact_samples, 0u);
  if (c.noise == 0.0) {
    EXPECT_TRUE(same_mesh(mesh, whole.mesh(), 1e-9 * whole.contour.cell));
  } else {  // (noisy: the same neighbourhoods, but the walk may differ; see tiles_test.cpp)
    const MeshTopology x = analyze_topology(mesh), y = analyze_topology(whole.mesh());
    EXPECT_EQ(x.components, y.components);
    EXPECT_EQ(x.euler_characteristic, y.euler_characteristic);
  }
}

// Clean data in both methods (the refined one measures its fits too), the
// terrain with 40 copies of one sample (their gap, 0, is left out of the
// median); a noisy cloud, on which phase I raises k; a given rho; sparse
// CAD parts, whose crease fits look for better ones by the residuals'
// lower quartile (local_quadrics.h).
INSTANTIATE_TEST_SUITE_P(Clouds, MeasuredOverTiles,
                         ::testing::Values(Case{"terrain", 12000, Method::refined, 0.0, std::nullopt, 40},
                                           Case{"torus", 10000, Method::hoppe92},
                                           Case{"box", 40000, Method::refined, 1.2},
                                           Case{"two", 10000, Method::refined, 0.0, 0.05},
                                           Case{"part", 4100, Method::refined, 0.0, std::nullopt, 0, 3}),
                         [](const auto& p) {
                           return std::string(p.param.shape) + "_" + method_name(p.param.method) +
                                  (p.param.noise > 0.0 ? "_noisy" : "") + (p.param.rho ? "_rho" : "") +
                                  (p.param.copies > 0 ? "_copies" : "") + (p.param.in_a_row > 1 ? "_in_a_row" : "");
                         });

// Samples a tile cannot measure exactly are counted, not hidden: five
// strays far from the rest make a tile of their own, too few for a
// neighbourhood of k (the in-memory run measures them with the sphere's
// samples, 3 away).
TEST(MeasuredOverTiles, SamplesATileCannotMeasureAreCounted) {
  PointCloud cloud = make_shape("sphere")->sample(8000, 3);
  for (int i = 0; i < 5; ++i) cloud.positions.emplace_back(4.0 + 0.01 * i, 0.0, 0.0);
  TilingOptions tiling;
  tiling.statistics_points = 2000;
  tiling.tile_size = 0.5;
  const auto dir = std::filesystem::path(::testing::TempDir()) / "recon-tile-statistics-strays";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const TiledRun run = reconstruct_tiled(pass_over(cloud, 4096), tiling, dir / "work", dir / "mesh.ply");
  std::filesystem::remove_all(dir);
  EXPECT_TRUE(run.plan.statistics_over_tiles);
  EXPECT_EQ(run.plan.statistics_inexact, 5u);
}

}  // namespace
}  // namespace recon
