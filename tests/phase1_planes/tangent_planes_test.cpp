#include "recon/phase1_planes/tangent_planes.h"

#include "recon/core/errors.h"
#include "recon/core/shapes.h"

#include <gtest/gtest.h>

#include <optional>
#include <vector>

namespace recon {
namespace {

TEST(TangentPlanes, NormalsOfASphereAreRadial) {
  const PointCloud cloud = make_sphere()->sample(5000, 1);
  const auto planes = estimate_tangent_planes<3>(cloud.positions);
  ASSERT_EQ(planes.normals.size(), cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    EXPECT_GT(std::abs(planes.normals[i].dot(cloud.normals[i])), 0.99) << i;
    // Centroids lie just inside the sphere (chords), by about r_k^2 / (4R).
    EXPECT_LT(std::abs(planes.origins[i].norm() - 1.0), 0.01);
    EXPECT_LT(planes.surface_variation(i), 0.01);
  }
  EXPECT_EQ(planes.distinct_points, cloud.size());
  // 5000 random samples on area 4 pi: a disc holding k = 15 of them has
  // radius sqrt(15 * 4 pi / (5000 pi)) = 0.110; for random data that is rho.
  EXPECT_GT(planes.irregularity, 0.45);
  EXPECT_NEAR(planes.rho, 0.110, 0.015);
  // The widest gap to a nearest neighbour is shorter, about the spacing.
  EXPECT_GT(planes.gap, 0.03);
  EXPECT_LT(planes.gap, planes.rho);
}

// Isolation must find the stray samples and only them: none on real
// surfaces (random, grid-like, creased, of varying density, with copies),
// exactly the outliers added to a sphere.
TEST(TangentPlanes, OnlyStraySamplesAreIsolated) {
  for (const char* name : {"sphere", "torus", "box", "terrain", "two"}) {
    PointCloud cloud = make_shape(name)->sample(20000, 3);
    for (std::size_t i = 0; i < 2000; ++i) cloud.positions.push_back(cloud.positions[i]);
    const auto planes = estimate_tangent_planes<3>(cloud.positions);
    EXPECT_EQ(planes.isolated, 0u) << name;
  }
  PointCloud cloud = make_sphere()->sample(3000, 4);
  const std::vector<Vec3> stray = {Vec3(30, 0, 0), Vec3(0, -40, 7), Vec3(0, -40.001, 7), Vec3(5, 5, 5)};
  cloud.positions.insert(cloud.positions.end(), stray.begin(), stray.end());
  for (const auto& given : {std::optional<double>(), std::optional<double>(0.2)}) {
    TangentPlaneOptions options;
    options.rho = given;
    const auto planes = estimate_tangent_planes<3>(cloud.positions, options);
    EXPECT_EQ(planes.isolated, stray.size());
    for (std::size_t i = 0; i < cloud.size(); ++i) EXPECT_EQ(planes.local_rho[i] == 0.0f, i >= 3000) << i;
  }
}

TEST(TangentPlanes, CountsDuplicatesAndGivenRho) {
  PointCloud cloud = make_sphere()->sample(500, 2);
  for (std::size_t i = 0; i < 100; ++i) cloud.positions.push_back(cloud.positions[i]);
  TangentPlaneOptions options;
  options.rho = 0.25;
  const auto planes = estimate_tangent_planes<3>(cloud.positions, options);
  EXPECT_EQ(planes.distinct_points, 500u);
  EXPECT_EQ(planes.rho, 0.25);
  EXPECT_TRUE(planes.rho_given);
  for (const float r : planes.local_rho) EXPECT_EQ(r, 0.25f);
}

TEST(TangentPlanes, RefusesDegenerateInput) {
  std::vector<Vec3> few(10, Vec3::Zero());
  for (int i = 0; i < 10; ++i) few[static_cast<std::size_t>(i)] = Vec3(i, i * i, 1);
  EXPECT_THROW((void)estimate_tangent_planes<3>(few), InvalidInputError);  // fewer than k + 1

  std::vector<Vec3> same(100, Vec3(1, 2, 3));
  try {
    (void)estimate_tangent_planes<3>(same);
    FAIL();
  } catch (const InvalidInputError& e) {
    EXPECT_NE(std::string(e.what()).find("distinct"), std::string::npos) << e.what();
  }

  std::vector<Vec3> line;
  for (int i = 0; i < 100; ++i) line.emplace_back(i, 2.0 * i, 3.0 * i);
  try {
    (void)estimate_tangent_planes<3>(line);
    FAIL();
  } catch (const InvalidInputError& e) {
    EXPECT_NE(std::string(e.what()).find("line"), std::string::npos) << e.what();
  }

  std::vector<Vec3> nan_cloud = make_sphere()->sample(100, 3).positions;
  nan_cloud[42].y() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW((void)estimate_tangent_planes<3>(nan_cloud), InvalidInputError);

  TangentPlaneOptions small_k;
  small_k.k = 2;
  EXPECT_THROW((void)estimate_tangent_planes<3>(make_sphere()->sample(100, 3).positions, small_k), InvalidInputError);
}

TEST(TangentPlanes, FlatPatchIsExactlyPlanar) {
  std::vector<Vec3> grid;
  for (int i = 0; i < 30; ++i)
    for (int j = 0; j < 30; ++j) grid.emplace_back(i * 0.1, j * 0.1, 2.0);
  const auto planes = estimate_tangent_planes<3>(grid);
  for (const Vec3& n : planes.normals) EXPECT_NEAR(std::abs(n.z()), 1.0, 1e-12);
  // gap_i and rho_i are stored as float: exact to float's 7 digits.
  EXPECT_NEAR(planes.gap, 0.1, 1e-7);  // the grid spacing
  // A perfectly regular grid: rho is 1.5 spacings (below the radius of the
  // 15-neighbourhood, sqrt(5) spacings).
  EXPECT_NEAR(planes.irregularity, 0.0, 0.05);
  EXPECT_NEAR(planes.rho, 0.15, 1e-7);
}

}  // namespace
}  // namespace recon
