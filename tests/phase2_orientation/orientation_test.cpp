#include "recon/phase2_orientation/orientation.h"

#include "recon/core/shapes.h"
#include "recon/io/point_io.h"
#include "test_data.h"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace recon
