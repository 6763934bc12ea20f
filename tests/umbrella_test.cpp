// recon/recon.h: one include gives every layer's public names.
#include "recon/recon.h"

#include <gtest/gtest.h>

#include <string>

namespace recon {
namespace {

TEST(UmbrellaHeader, GivesEveryLayer) {
  // A name from each of several layers, used: a data structure, a phase,
  // the front door.
  const PointCloud cloud = make_sphere()->sample(2000, 1);
  const KdTree<3> tree(cloud.positions);
  EXPECT_EQ(tree.size(), cloud.size());
  EXPECT_EQ(std::string(method_name(Method::hoppe92)), "hoppe92");
  const Reconstruction r = reconstruct(cloud);
  EXPECT_GT(r.mesh().triangles.size(), 1000u);
}

}  // namespace
}  // namespace recon
