#include "recon/phase2_orientation/orientation.h"

#include "conics_truth.h"
#include "recon/core/parallel.h"
#include "recon/core/shapes.h"
#include "recon/io/point_io.h"
#include "test_data.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace recon {
namespace {

struct OrientationCheck {
  std::size_t outward = 0, total = 0, components = 0;
  std::size_t planar = 0, planar_outward = 0;  // neighbourhoods with a well-defined normal
};

OrientationCheck orient_and_compare(const PointCloud& cloud) {
  const auto planes = estimate_tangent_planes<3>(cloud.positions);
  const auto oriented = orient_normals<3>(planes);
  OrientationCheck check;
  check.total = cloud.size();
  check.components = oriented.component_count();
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const bool outward = oriented.normals[i].dot(cloud.normals[i]) > 0.0;
    check.outward += outward ? 1u : 0u;
    if (planes.surface_variation(i) < 0.02) {
      ++check.planar;
      check.planar_outward += outward ? 1u : 0u;
    }
  }
  return check;
}

// A smooth shape's cloud: `components` trees, every normal facing out.
void expect_all_outward(const PointCloud& cloud, std::size_t components) {
  const auto c = orient_and_compare(cloud);
  EXPECT_EQ(c.components, components);
  EXPECT_EQ(c.outward, c.total);
}

TEST(Orientation, SphereNormalsAllPointOutward) { expect_all_outward(make_sphere()->sample(20000, 11), 1); }

TEST(Orientation, TorusNormalsAllPointOutward) { expect_all_outward(make_torus()->sample(30000, 12), 1); }

TEST(Orientation, EllipsoidNormalsAllPointOutward) { expect_all_outward(make_ellipsoid()->sample(20000, 13), 1); }

TEST(Orientation, TwoSeparateShapesAreTwoComponentsAllOutward) {
  expect_all_outward(make_sphere_and_torus(0.3)->sample(40000, 14), 2);
}

TEST(Orientation, BoxNormalsPointOutwardExceptAtCorners) {
  const auto c = orient_and_compare(make_box()->sample(20000, 15));
  EXPECT_EQ(c.components, 1u);
  // Every neighbourhood that has a normal (away from the edges and corners)
  // faces out. At a corner, PCA's "normal" of three perpendicular faces is
  // an arbitrary diagonal: a few there may face across a face's normal.
  EXPECT_EQ(c.planar_outward, c.planar);
  EXPECT_GT(c.planar, c.total * 8 / 10);
  EXPECT_GE(static_cast<double>(c.outward), 0.999 * static_cast<double>(c.total));
}

TEST(Orientation, EveryTreeEdgeIsConsistentAndRootsPointUp) {
  const PointCloud cloud = make_torus()->sample(5000, 16);
  const auto planes = estimate_tangent_planes<3>(cloud.positions);
  const auto oriented = orient_normals<3>(planes);
  for (std::uint32_t v = 0; v < cloud.size(); ++v) {
    const auto p = oriented.tree.parent[v];
    if (p == SpanningForest::no_parent) {
      EXPECT_GE(oriented.normals[v].z(), 0.0);
      for (std::uint32_t u = 0; u < cloud.size(); ++u) {
        if (oriented.graph.components.label[u] == oriented.graph.components.label[v]) {
          EXPECT_LE(planes.origins[u].z(), planes.origins[v].z());
        }
      }
    } else {
      EXPECT_GE(oriented.normals[v].dot(oriented.normals[p]), 0.0);
    }
  }
}

TEST(Orientation, KittenAgreesWithItsStoredNormals) {
  const auto path = testing::shared_data("cgal_kitten/kitten.xyz");
  RECON_REQUIRE_DATA(path);
  const PointCloud cloud = io::read_points(path);
  ASSERT_TRUE(cloud.has_normals());
  const auto c = orient_and_compare(cloud);
  EXPECT_EQ(c.components, 1u);
  EXPECT_GE(static_cast<double>(c.outward), 0.99 * static_cast<double>(c.total));
}

// Nested pieces (the refined method, sign_by_extremes): each piece is
// first made to face out at its extremes, as if alone; then a piece inside
// an odd number of others is turned round to face into its cavity.
OrientedNormals<3> refined_orientation(const PointCloud& cloud) {
  const auto planes = estimate_tangent_planes<3>(cloud.positions);
  OrientationOptions options;
  options.sign_by_extremes = true;
  return orient_normals<3>(planes, options);
}

PointCloud joined(PointCloud a, const PointCloud& b) {
  a.positions.insert(a.positions.end(), b.positions.begin(), b.positions.end());
  a.normals.insert(a.normals.end(), b.normals.begin(), b.normals.end());
  return a;
}

// Issue 27: the cavity's wall (depth 1) faces into the cavity; the ball in
// it (depth 2) faces out again. Each piece alone would face out.
TEST(Orientation, NestedPiecesFaceIntoTheirCavityAtEveryDepth) {
  for (const std::size_t walls : {2u, 3u}) {
    const PointCloud cloud = (walls == 2 ? make_hollow_ball() : make_nested_balls())->sample(40000, 17);
    const auto oriented = refined_orientation(cloud);
    ASSERT_EQ(oriented.component_count(), walls);
    EXPECT_EQ(oriented.pieces_nested, walls - 1);
    EXPECT_EQ(oriented.nested_turned, 1u) << "the cavity's wall only";
    const std::vector<double> right = testing::right_per_ball(cloud, oriented.normals, walls);
    for (std::size_t w = 0; w < walls; ++w) EXPECT_GE(right[w], 0.99) << walls << " walls, wall " << w;
  }
}

// Pieces side by side are never turned, also where one's bounding box
// holds the other's: a small ball in the corner of a large one's box, but
// outside the ball (its winding number there is about 0).
TEST(Orientation, APieceBesideAnotherIsNeverTurned) {
  const PointCloud corner =
      joined(make_sphere()->sample(30000, 18), make_sphere(0.1, Vec3(0.8, 0.8, 0.8))->sample(1500, 19));
  const PointCloud apart =
      joined(make_sphere()->sample(20000, 20), make_sphere(0.5, Vec3(2.0, 0.3, 0.0))->sample(5000, 21));
  for (const PointCloud& cloud : {corner, apart}) {
    const auto oriented = refined_orientation(cloud);
    ASSERT_EQ(oriented.component_count(), 2u);
    EXPECT_EQ(oriented.pieces_nested, 0u);
    EXPECT_EQ(oriented.nested_turned, 0u);
    for (std::size_t i = 0; i < cloud.size(); ++i) ASSERT_GT(oriented.normals[i].dot(cloud.normals[i]), 0.0) << i;
  }
}

// A ball in a bowl (an open hemisphere): the bowl's winding number at the
// ball is over 1/2, but the bowl bounds no cavity (its area-weighted
// normals add up to its opening, half its area), so the ball stays as it is.
TEST(Orientation, ABallInABowlIsNeverTurned) {
  const PointCloud cloud = testing::ball_in_bowl(20000, 4000, 23);
  double w = 0.0;
  const Vec3 top(0.0, 0.0, -0.5);
  for (std::size_t i = 0; i < 20000; ++i)
    w += winding_term<3>(cloud.positions[i], 2.0 * std::numbers::pi / 20000.0 * cloud.normals[i], top);
  ASSERT_GT(std::abs(w), 0.5) << "a winding number alone would count the ball inside the bowl";
  const auto oriented = refined_orientation(cloud);
  ASSERT_EQ(oriented.component_count(), 2u);
  EXPECT_EQ(oriented.pieces_nested, 0u);
  std::size_t right = 0;
  for (std::size_t i = 20000; i < cloud.size(); ++i) right += oriented.normals[i].dot(cloud.normals[i]) > 0.0 ? 1u : 0u;
  EXPECT_EQ(right, 4000u) << "the ball faces out";
}

// The 1992 method (no sign_by_extremes) decides no nesting; and the
// refined one's turns do not depend on the thread count.
TEST(Orientation, NestingIsTheRefinedMethodsAndTheSameOnAnyThreadCount) {
  const PointCloud cloud = make_nested_balls()->sample(30000, 22);
  const auto plain = orient_normals<3>(estimate_tangent_planes<3>(cloud.positions));
  EXPECT_EQ(plain.pieces_nested, 0u);
  EXPECT_EQ(plain.nested_turned, 0u);
  set_thread_count(4);
  const auto many = refined_orientation(cloud);
  set_thread_count(1);
  const auto one = refined_orientation(cloud);
  set_thread_count(0);
  EXPECT_EQ(many.flipped, one.flipped);
  EXPECT_EQ(many.nested_turned, 1u);
}

}  // namespace
}  // namespace recon
