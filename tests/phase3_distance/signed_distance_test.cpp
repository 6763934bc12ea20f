// Phase III (signed_distance.h): f against analytic surfaces, the rule that
// makes f undefined away from the data, and the hint's contract (the answer
// does not depend on it).

#include "recon/phase3_distance/signed_distance.h"

#include "recon/core/errors.h"
#include "recon/core/shapes.h"
#include "recon/phase1_planes/tangent_planes.h"
#include "recon/structures/kdtree.h"

#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <random>
#include <vector>

namespace recon {
namespace {

// Planes through given samples with given unit normals and rho_i, as phase
// I would make them on exact data: each origin its own sample.
TangentPlanes<3> planes_through(const std::vector<Vec3>& samples, const std::vector<Vec3>& normals, float rho) {
  TangentPlanes<3> planes;
  planes.origins = samples;
  planes.normals = normals;
  planes.local_rho.assign(samples.size(), rho);
  planes.rho = rho;
  planes.point_tree = KdTree<3>(samples);
  return planes;
}

// The flat patch z = 0 sampled on a grid of step h over [0, 1]^2, normals +z.
struct FlatPatch {
  static constexpr double h = 0.1;
  std::vector<Vec3> samples, normals;
  TangentPlanes<3> planes;
  KdTree<3> origin_tree;
  FlatPatch() {
    for (int j = 0; j <= 10; ++j)
      for (int i = 0; i <= 10; ++i) {
        samples.emplace_back(i * h, j * h, 0.0);
        normals.emplace_back(0.0, 0.0, 1.0);
      }
    planes = planes_through(samples, normals, static_cast<float>(h));
    origin_tree = KdTree<3>(planes.origins);
  }
};

TEST(SignedDistance, IsTheHeightAboveAPlane) {
  const FlatPatch patch;
  SignedDistanceOptions options;
  options.delta = 0.0;
  const SignedDistance<3> f = make_signed_distance<3>(patch.planes, patch.normals, patch.origin_tree, options);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> inside(0.0, 1.0), height(-0.1, 0.1);
  for (int n = 0; n < 2000; ++n) {
    const Vec3 p(inside(rng), inside(rng), height(rng));
    const std::optional<double> value = f(p);
    ASSERT_TRUE(value.has_value()) << p.transpose();  // over the data: defined
    EXPECT_NEAR(*value, p.z(), 1e-15);
  }
}

// A sphere through phase I's own planes (normals turned outward by hand):
// f approaches |p| - 1, positive outside and negative inside.
TEST(SignedDistance, ApproachesTheDistanceToASphere) {
  const PointCloud cloud = make_sphere()->sample(4000, 12);
  TangentPlanes<3> planes = estimate_tangent_planes<3>(cloud.positions);
  std::vector<Vec3> normals = planes.normals;
  for (std::size_t i = 0; i < normals.size(); ++i)
    if (normals[i].dot(planes.origins[i]) < 0.0) normals[i] = -normals[i];
  const KdTree<3> origin_tree(planes.origins);
  const SignedDistance<3> f = make_signed_distance<3>(planes, normals, origin_tree);
  std::mt19937 rng(13);
  std::normal_distribution<double> direction(0.0, 1.0);
  std::uniform_real_distribution<double> radius(0.9, 1.1);
  for (int n = 0; n < 2000; ++n) {
    const double r = radius(rng);
    const Vec3 p = r * Vec3(direction(rng), direction(rng), direction(rng)).normalized();
    const std::optional<double> value = f(p);
    ASSERT_TRUE(value.has_value()) << p.transpose();
    EXPECT_NEAR(*value, r - 1.0, 0.01) << p.transpose();
    if (std::abs(r - 1.0) > 0.01) {
      EXPECT_EQ(*value > 0.0, r > 1.0);
    }
  }
}

// f is undefined exactly where no sample lies within 1.5 rho_i + delta +
// |f(p)| of p (the header's rule: Hoppe's foot-point test, rho_i + delta
// around p's foot point, and the ball around p itself, which contains it).
// Beyond the edge x = 1 of the patch, the nearest sample is (1, y, 0).
TEST(SignedDistance, IsUndefinedExactlyBeyondItsReachOfTheData) {
  const FlatPatch patch;
  SignedDistanceOptions options;
  options.delta = 0.02;
  const SignedDistance<3> f = make_signed_distance<3>(patch.planes, patch.normals, patch.origin_tree, options);
  const double rho = static_cast<double>(static_cast<float>(FlatPatch::h));
  for (const double z : {0.0, 0.05, -0.03}) {
    const double reach = 1.5 * rho + *options.delta + std::abs(z);
    const double beyond = std::sqrt(reach * reach - z * z);  // distance past the edge at which p is `reach` away
    const Vec3 just_inside(1.0 + beyond - 1e-9, 0.5, z), just_outside(1.0 + beyond + 1e-9, 0.5, z);
    const std::optional<double> in = f(just_inside), out = f(just_outside);
    ASSERT_TRUE(in.has_value()) << z;
    EXPECT_NEAR(*in, z, 1e-15);
    EXPECT_FALSE(out.has_value()) << z;
    // Hoppe's test alone (the foot point within rho + delta of a sample) ends
    // sooner: between the two, p is defined by the ball around itself.
    const Vec3 past_foot_reach(1.0 + rho + *options.delta + 1e-6, 0.5, z);
    EXPECT_TRUE(f(past_foot_reach).has_value()) << z;
  }
  // Over the data: always defined, however far above it (the foot point is
  // on the data).
  EXPECT_TRUE(f(Vec3(0.55, 0.45, 3.0)).has_value());
  // A larger delta reaches further.
  options.delta = 0.2;
  const SignedDistance<3> wide = make_signed_distance<3>(patch.planes, patch.normals, patch.origin_tree, options);
  EXPECT_TRUE(wide(Vec3(1.3, 0.5, 0.0)).has_value());
  EXPECT_FALSE(f(Vec3(1.3, 0.5, 0.0)).has_value());
}

// The hint bounds the search only: with a good hint (the plane f uses), a
// bad one (any other plane), none, or one out of range, the evaluation is
// the same, with one candidate (Hoppe's nearest origin) and with several.
// The data: a sphere without its cap above z = 0.6, so that f is undefined
// over the opening.
TEST(SignedDistance, AnswersTheSameWithAGoodBadOrAbsentHint) {
  const PointCloud sphere = make_sphere()->sample(4000, 14);
  std::vector<Vec3> samples;
  for (const Vec3& p : sphere.positions)
    if (p.z() <= 0.6) samples.push_back(p);
  TangentPlanes<3> planes = estimate_tangent_planes<3>(samples);
  const KdTree<3> origin_tree(planes.origins);
  std::mt19937 rng(15);
  std::uniform_real_distribution<double> box(-1.3, 1.3);
  std::uniform_int_distribution<std::uint32_t> any_plane(0, static_cast<std::uint32_t>(planes.origins.size() - 1));
  for (const int candidates : {1, 8}) {
    SignedDistanceOptions options;
    options.candidates = candidates;
    const SignedDistance<3> f = make_signed_distance<3>(planes, planes.normals, origin_tree, options);
    std::size_t defined = 0, undefined = 0;
    for (int n = 0; n < 3000; ++n) {
      const Vec3 p(box(rng), box(rng), box(rng));
      const auto plain = f.evaluate(p);
      if (candidates == 1) {
        EXPECT_EQ(plain.plane, origin_tree.nearest(p).index);  // Hoppe's rule
      }
      EXPECT_EQ(f.plane_for(p), plain.plane);
      (plain.value ? defined : undefined) += 1;
      for (const std::uint32_t hint : {plain.plane, any_plane(rng), SignedDistance<3>::no_hint,
                                       static_cast<std::uint32_t>(planes.origins.size())}) {
        const auto hinted = f.evaluate(p, hint);
        ASSERT_EQ(hinted.plane, plain.plane) << hint;
        ASSERT_EQ(hinted.value, plain.value) << hint;
        ASSERT_EQ(hinted.by_orientation, plain.by_orientation) << hint;
        ASSERT_EQ(f.plane_for(p, hint), plain.plane) << hint;
      }
    }
    EXPECT_GT(defined, 100u);
    EXPECT_GT(undefined, 100u);
  }
}

TEST(SignedDistance, EstimatesDeltaFromTheNoiseAndRefusesBadOptions) {
  const FlatPatch patch;
  TangentPlanes<3> planes = planes_through(patch.samples, patch.normals, static_cast<float>(FlatPatch::h));
  planes.noise = 0.003;
  const SignedDistance<3> f = make_signed_distance<3>(planes, patch.normals, patch.origin_tree);
  EXPECT_EQ(f.delta(), 0.006);  // twice phase I's noise
  EXPECT_FALSE(f.delta_given());
  SignedDistanceOptions options;
  options.delta = -1.0;
  EXPECT_THROW((void)make_signed_distance<3>(planes, patch.normals, patch.origin_tree, options), InvalidInputError);
  options.delta = 0.01;
  options.candidates = 33;
  EXPECT_THROW((void)make_signed_distance<3>(planes, patch.normals, patch.origin_tree, options), InvalidInputError);
  const std::vector<Vec3> too_few(patch.normals.begin(), patch.normals.end() - 1);
  EXPECT_THROW((void)make_signed_distance<3>(planes, too_few, patch.origin_tree), InvalidInputError);
}

}  // namespace
}  // namespace recon
