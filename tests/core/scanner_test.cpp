// Tests of the range-scan simulator (scan() in shapes.h). The oracles:
// - without noise or misregistration every return is a point of the true
//   surface with its true normal (distance() 0, the step test of
//   shapes_test);
// - what no view can see gets no points: a box's bottom face (the views
//   stand above it) and a hollow ball's cavity wall (hidden inside);
// - the noise moves points along their rays: their distances to the
//   surface have about the asked spread, never more than the range allows;
// - misregistration moves whole views off the surface; the same options
//   give the same cloud.

#include "recon/core/errors.h"
#include "recon/core/shapes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace recon {
namespace {

ScanOptions options_of(std::size_t views, std::size_t points, double noise = 0.0, double misregistration = 0.0) {
  ScanOptions options;
  options.views = views;
  options.points = points;
  options.noise = noise;
  options.misregistration = misregistration;
  options.seed = 7;
  return options;
}

double diagonal_of(const PointCloud& cloud) { return bounding_box<3>(cloud.positions).diagonal(); }

TEST(Scan, ReturnsLieOnTheSurfaceWithTheirTrueNormals) {
  const auto part = make_machined_part();
  const PointCloud cloud = scan(*part, options_of(4, 8000));
  ASSERT_EQ(cloud.normals.size(), cloud.size());
  const double e = 1e-3;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    ASSERT_LT(part->distance(cloud.positions[i]), 1e-9) << i;
    ASSERT_NEAR(part->distance(cloud.positions[i] + e * cloud.normals[i]), e, 1e-8) << i;
  }
}

TEST(Scan, ReturnsAboutTheAskedNumberOfPoints) {
  for (const char* name : {"torus", "part", "box"}) {
    const PointCloud cloud = scan(*make_shape(name), options_of(3, 10000));
    EXPECT_GT(cloud.size(), 7000u) << name;
    EXPECT_LT(cloud.size(), 13000u) << name;
  }
}

// The views stand 15 to 45 degrees above the centre: the bottom face is
// never seen, the top always; a side face is seen only from its side.
TEST(Scan, TheUndersideGetsNoPoints) {
  const auto box = make_box();
  const PointCloud cloud = scan(*box, options_of(4, 8000));
  std::size_t top = 0;
  for (const Vec3& n : cloud.normals) {
    ASSERT_GT(n.z(), -0.5) << "a point of the bottom face";
    top += n.z() > 0.5 ? 1u : 0u;
  }
  EXPECT_GT(top, cloud.size() / 5);
}

// A cavity's wall is hidden behind the outer wall from every view: a
// z-buffer that let a farther surface through would put points on it.
TEST(Scan, AHiddenCavityGetsNoPoints) {
  const auto shell = make_hollow_ball(1.0, 0.7);
  const PointCloud cloud = scan(*shell, options_of(6, 10000));
  ASSERT_GT(cloud.size(), 5000u);
  for (const Vec3& p : cloud.positions) ASSERT_NEAR(p.norm(), 1.0, 1e-9);
}

// Self-shadowing: a hole's wall is seen only where a view looks down into
// the hole past its rim: far fewer points there than its share of the area.
TEST(Scan, OccludedRegionsAreHoles) {
  const auto part = make_machined_part();
  const PointCloud cloud = scan(*part, options_of(3, 10000));
  std::size_t walls = 0;
  for (const Vec3& n : cloud.normals)
    walls += std::abs(n.z()) < 0.99 && std::abs(n.x()) < 0.99 && std::abs(n.y()) < 0.99;
  const double wall_share = 3.0 * 2.0 * 3.14159 * 0.18 * 0.4 / part->area();  // about 0.28
  EXPECT_LT(static_cast<double>(walls) / static_cast<double>(cloud.size()), 0.5 * wall_share);
}

// Range noise moves a point along its ray: it lands at most |offset| from
// the surface (less when the ray is slanted), and a standard deviation
// sigma x (range / view distance) gives a spread of that order.
TEST(Scan, NoiseHasTheAskedSpreadAlongTheRays) {
  const auto sphere = make_sphere();
  const double noise = 0.004;
  const PointCloud cloud = scan(*sphere, options_of(4, 8000, noise));
  const double sigma = noise * diagonal_of(scan(*sphere, options_of(1, 2000)));
  double sum2 = 0.0;
  for (const Vec3& p : cloud.positions) sum2 += std::pow(sphere->distance(p), 2);
  const double rms = std::sqrt(sum2 / static_cast<double>(cloud.size()));
  // Ranges lie within 1.5 to 3.5 bounding radii (views at 2.5): the
  // spread scales by 0.6 to 1.4, the slant shrinks it by its cosine.
  EXPECT_GT(rms, 0.3 * sigma);
  EXPECT_LT(rms, 1.4 * sigma);
}

TEST(Scan, MisregistrationMovesWholeViewsOffTheSurface) {
  const auto torus = make_torus();
  const PointCloud exact = scan(*torus, options_of(3, 6000));
  const PointCloud moved = scan(*torus, options_of(3, 6000, 0.0, 0.01));
  ASSERT_EQ(exact.size(), moved.size());
  double mean = 0.0;
  for (const Vec3& p : moved.positions) mean += torus->distance(p);
  mean /= static_cast<double>(moved.size());
  EXPECT_GT(mean, 0.002);  // a shift of 0.01 x the diagonal (about 2.9) and a turn of 0.01 radian
  EXPECT_LT(mean, 0.06);
}

TEST(Scan, SameOptionsSameCloudOtherSeedOtherCloud) {
  const auto torus = make_torus();
  ScanOptions options = options_of(4, 4000, 0.002, 0.001);
  const PointCloud a = scan(*torus, options), b = scan(*torus, options);
  EXPECT_EQ(a.positions, b.positions);
  EXPECT_EQ(a.normals, b.normals);
  options.seed = 8;
  EXPECT_NE(scan(*torus, options).positions, a.positions);
}

TEST(Scan, BadOptionsAreRefused) {
  const auto sphere = make_sphere();
  EXPECT_THROW((void)scan(*sphere, options_of(0, 1000)), InvalidInputError);
  EXPECT_THROW((void)scan(*sphere, options_of(65, 1000)), InvalidInputError);
  EXPECT_THROW((void)scan(*sphere, options_of(3, 0)), InvalidInputError);
  EXPECT_THROW((void)scan(*sphere, options_of(3, 1000, -0.1)), InvalidInputError);
  EXPECT_THROW((void)scan(*sphere, options_of(3, 1000, 0.0, 1.0)), InvalidInputError);
}

}  // namespace
}  // namespace recon
