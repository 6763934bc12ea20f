// Phase II on what a range scanner gives (scan() in shapes.h): a few
// views, holes where none of them sees the surface (the underside, the
// insides of holes), noise along the rays, views slightly out of
// register. The walk must carry one side across every view and around
// the holes' rims; the oracle is the true normal of each return.

#include "recon/core/shapes.h"
#include "recon/estimate_normals.h"

#include <gtest/gtest.h>

#include <ostream>
#include <string>

namespace recon {
namespace {

struct ScanCase {
  std::string shape;
  std::size_t views;
  double noise;  // along the rays, a fraction of the diagonal
};

void PrintTo(const ScanCase& c, std::ostream* out) {
  *out << c.shape << ", " << c.views << " views, noise " << c.noise;
}

// The share of the estimated normals on the true normal's side.
double share_right(const PointCloud& cloud, Method method) {
  NormalEstimationOptions options;
  options.method = method;
  const std::vector<Vec3> normals = estimate_normals(cloud, options).normals_in_input_order();
  std::size_t right = 0;
  for (std::size_t i = 0; i < cloud.size(); ++i) right += normals[i].dot(cloud.normals[i]) > 0.0 ? 1u : 0u;
  return static_cast<double>(right) / static_cast<double>(cloud.size());
}

class ScanOrientation : public ::testing::TestWithParam<ScanCase> {};

// Issue 27 measured as few as 49 % right on such clouds; the refined walk
// must give at least 90 %. Each piece of the conics must be decided on
// its own returns (its underside is missing, the tall cone's apex is a
// tip); the part's hole walls are seen only in patches.
TEST_P(ScanOrientation, AtLeastNinetyPercentOfTheNormalsFaceOut) {
  const ScanCase& c = GetParam();
  ScanOptions options;
  options.views = c.views;
  options.points = 12000;
  options.noise = c.noise;
  options.misregistration = 0.0005;
  options.seed = 3;
  const PointCloud cloud = scan(*make_shape(c.shape), options);
  ASSERT_GT(cloud.size(), 8000u);
  const double share = share_right(cloud, Method::refined);
  RecordProperty("share_right", std::to_string(share));
  EXPECT_GE(share, 0.9);
}

INSTANTIATE_TEST_SUITE_P(Scans, ScanOrientation,
                         ::testing::Values(ScanCase{"part", 3, 0.005}, ScanCase{"conics", 4, 0.005},
                                           ScanCase{"torus", 6, 0.002}),
                         [](const ::testing::TestParamInfo<ScanCase>& c) { return c.param.shape; });

}  // namespace
}  // namespace recon
