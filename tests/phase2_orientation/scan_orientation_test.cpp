// Phase II on what a range scanner gives (scan() in shapes.h): a few
// views, holes where none of them sees the surface (the underside, the
// insides of holes), noise along the rays, views slightly out of
// register. The walk must carry one side across every view and around
// the holes' rims; the oracle is the true normal of each return.

#include "recon/core/shapes.h"
#include "recon/estimate_normals.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <ostream>
#include <string>

namespace recon {
namespace {

struct ScanCase {
  std::string shape;
  std::size_t views;
  double noise;  // along the rays, a fraction of the diagonal
  std::size_t points = 12000;
  double misregistration = 0.0005;
  std::uint64_t seed = 3;
  std::string name;  // of the test
};

void PrintTo(const ScanCase& c, std::ostream* out) {
  *out << c.shape << ", " << c.views << " views, noise " << c.noise << ", " << c.points << " points";
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
  options.points = c.points;
  options.noise = c.noise;
  options.misregistration = c.misregistration;
  options.seed = c.seed;
  const PointCloud cloud = scan(*make_shape(c.shape), options);
  ASSERT_GT(cloud.size(), c.points * 2 / 3);
  const double share = share_right(cloud, Method::refined);
  RecordProperty("share_right", std::to_string(share));
  EXPECT_GE(share, 0.9);
}

// The last case turned the tall cone inside out (5 % right) when one
// sample decided a piece's side: the best-aligned normal near its extreme
// happened to be one of the few the walk got wrong (noise of 0.5 % of the
// diagonal is a sixth of the cone's radius).
INSTANTIATE_TEST_SUITE_P(Scans, ScanOrientation,
                         ::testing::Values(ScanCase{"part", 3, 0.005, 12000, 0.0005, 3, "part"},
                                           ScanCase{"conics", 4, 0.005, 12000, 0.0005, 3, "conics"},
                                           ScanCase{"torus", 6, 0.002, 12000, 0.0005, 3, "torus"},
                                           ScanCase{"conics", 4, 0.005, 20000, 0.0, 1, "conics_noisy_cone"}),
                         [](const ::testing::TestParamInfo<ScanCase>& c) { return c.param.name; });

// A closed plate 1.5 to 2 rho thick: within two neighbourhood radii of its
// top lie samples of its bottom sheet, rightly pointing down, and when the
// best-aligned of them decided the side the whole plate came out inside
// out (0.1 % right).
TEST(ThinPlateSide, TheTopSheetDecidesNotTheOneBeneathIt) {
  const PointCloud cloud = make_plate(0.05)->sample(40000, 1);  // rho about 0.025: 2 rho thick
  EXPECT_GE(share_right(cloud, Method::refined), 0.99);
}

}  // namespace
}  // namespace recon
