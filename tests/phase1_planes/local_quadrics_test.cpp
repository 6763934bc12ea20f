#include "recon/phase1_planes/local_quadrics.h"

#include "recon/core/errors.h"
#include "recon/core/shapes.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace recon {
namespace {

// Phase I over a tree numbered by leaf order, as reconstruct() runs it;
// `truth[j]` is the true normal of point j (in that order) when the cloud had normals.
struct LeafPlanes {
  TangentPlanes<3> planes;
  std::vector<Vec3> truth;
};

LeafPlanes leaf_planes(const PointCloud& cloud, TangentPlaneOptions options = {}) {
  KdTree<3> tree(cloud.positions);
  const std::vector<std::uint32_t> order = tree.renumber_by_leaf_order();
  LeafPlanes out;
  out.planes = estimate_tangent_planes<3>(std::move(tree), options);
  if (cloud.has_normals())
    for (const std::uint32_t i : order) out.truth.push_back(cloud.normals[i]);
  return out;
}

TEST(LocalQuadrics, TangentBasisIsOrthonormal) {
  std::mt19937_64 rng(1);
  std::normal_distribution<double> g;
  for (int trial = 0; trial < 1000; ++trial) {
    Vec3 n(g(rng), g(rng), g(rng));
    if (trial == 0) n = Vec3(0, 0, -1);  // the formula's branch point
    if (trial == 1) n = Vec3(0, 0, 1);
    n.normalize();
    const auto t = tangent_basis(n);
    EXPECT_NEAR(t[0].norm(), 1.0, 1e-12);
    EXPECT_NEAR(t[1].norm(), 1.0, 1e-12);
    EXPECT_NEAR(t[0].dot(t[1]), 0.0, 1e-12);
    EXPECT_NEAR(t[0].dot(n), 0.0, 1e-12);
    EXPECT_NEAR(t[1].dot(n), 0.0, 1e-12);
    EXPECT_NEAR(t[0].cross(t[1]).dot(n), 1.0, 1e-12);  // right-handed
  }
}

// On a sphere of radius R the osculating quadric is the paraboloid of
// curvature 1/R: the origins land on the sphere (the centroids sit about
// r_k^2 / 4R inside it), the normals are radial and h(t) = |t|^2 / 2R
// towards the centre.
TEST(LocalQuadrics, SphereOriginsLieOnTheSurface) {
  const double radius = 2.0;
  const auto sphere = make_sphere(radius);
  const LeafPlanes lp = leaf_planes(sphere->sample(20000, 2));
  const TangentPlanes<3>& planes = lp.planes;
  const LocalQuadrics q = fit_local_quadrics(planes);
  ASSERT_EQ(q.origins.size(), planes.origins.size());
  double centroid_error = 0.0, origin_error = 0.0;
  for (std::size_t i = 0; i < q.origins.size(); ++i) {
    centroid_error += sphere->distance(planes.origins[i]);
    origin_error += sphere->distance(q.origins[i]);
    EXPECT_GT(std::abs(q.normals[i].dot(lp.truth[i])), 1.0 - 1e-6) << i;
    EXPECT_GT(q.normals[i].dot(planes.normals[i]), 0.0) << "the normal keeps phase I's side";
    // Heights along the stored (unoriented) normal: towards the centre when
    // it points out.
    const double expected = (q.normals[i].dot(lp.truth[i]) > 0.0 ? -1.0 : 1.0) * 0.5 / radius;
    EXPECT_NEAR(q.curvature[i].p, expected, 0.02 / radius);
    EXPECT_NEAR(q.curvature[i].r, expected, 0.02 / radius);
    EXPECT_NEAR(q.curvature[i].q, 0.0, 0.02 / radius);
  }
  centroid_error /= static_cast<double>(q.origins.size());
  origin_error /= static_cast<double>(q.origins.size());
  EXPECT_GT(centroid_error, 1e-3);  // r_k^2 / 4R with r_k about 0.09
  EXPECT_LT(origin_error, 1e-6);
  EXPECT_EQ(q.split, 0u);
  for (const auto band : q.near_crease) EXPECT_EQ(band, 0) << "no crease on a sphere";
}

// A point moved onto a quadric lands on it, and a point on it stays.
TEST(LocalQuadrics, ProjectionOntoAQuadric) {
  const Vec3 origin(1, 2, 3), normal = Vec3(1, 1, 1).normalized();
  const Curvature c{0.3f, -0.2f, 0.5f};
  const auto t = tangent_basis(normal);
  auto height = [&](double a, double b) {
    return static_cast<double>(c.p) * a * a + static_cast<double>(c.q) * a * b + static_cast<double>(c.r) * b * b;
  };
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-0.2, 0.2);
  for (int trial = 0; trial < 200; ++trial) {
    const double a = u(rng), b = u(rng);
    const Vec3 on = origin + a * t[0] + b * t[1] + height(a, b) * normal;
    EXPECT_LT((project_onto_quadric(origin, normal, c, on).point - on).norm(), 1e-12);
    const SurfacePoint moved = project_onto_quadric(origin, normal, c, on + 0.05 * Vec3(u(rng), u(rng), u(rng)));
    const Vec3 d = moved.point - origin;
    const double da = d.dot(t[0]), db = d.dot(t[1]);
    EXPECT_NEAR(d.dot(normal), height(da, db), 1e-12);
    EXPECT_GT(moved.normal.dot(normal), 0.0);
  }
}

// Near a sharp edge a neighbourhood straddles two faces: the samples there
// borrow a neighbour's fit of their own face, so every origin lies on the
// box and every normal is its face's.
TEST(LocalQuadrics, BoxSamplesNearEdgesTakeTheirFacesPlane) {
  const auto box = make_box();
  const LeafPlanes lp = leaf_planes(box->sample(30000, 4));
  const LocalQuadrics q = fit_local_quadrics(lp.planes);
  EXPECT_GT(q.borrowed, 500u);
  std::size_t tilted_before = 0, tilted_after = 0, band = 0;
  for (std::size_t i = 0; i < q.origins.size(); ++i) {
    const Vec3& truth = lp.truth[i];  // the face's normal
    tilted_before += std::abs(lp.planes.normals[i].dot(truth)) < 0.999 ? 1u : 0u;
    tilted_after += std::abs(q.normals[i].dot(truth)) < 0.999 ? 1u : 0u;
    EXPECT_LT(box->distance(q.origins[i]), 1e-3) << i;
    band += q.near_crease[i];
  }
  EXPECT_GT(tilted_before, 2000u);
  EXPECT_LT(tilted_after, tilted_before / 20);  // the corners' samples may still lean
  EXPECT_GT(band, tilted_before / 2);           // the band along the edges is marked
}

// Two parallel sheets closer than a neighbourhood: every neighbourhood
// reaching across is fitted to its own sheet.
TEST(LocalQuadrics, TwoSheetsCloserThanANeighbourhoodAreFittedApart) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double gap = 0.03;  // the neighbourhoods' radius is about 0.04
  PointCloud cloud;
  for (int i = 0; i < 20000; ++i) cloud.positions.emplace_back(u(rng), u(rng), i % 2 == 0 ? 0.0 : gap);
  TangentPlaneOptions options;
  options.adapt_k = false;  // (the sheets' distance looks like noise to phase I: see fit_second_order, reconstruct.cpp)
  const LeafPlanes lp = leaf_planes(cloud, options);
  const TangentPlanes<3>& planes = lp.planes;
  ASSERT_GT(static_cast<double>(planes.radius[0]), gap);
  const LocalQuadrics q = fit_local_quadrics(planes);
  EXPECT_GT(q.split, 1000u);
  const auto x = planes.point_tree.points();
  for (std::size_t i = 0; i < q.origins.size(); ++i) {
    EXPECT_NEAR(q.origins[i].z(), x[i].z(), 1e-9) << i;  // not in the empty band between the sheets
    EXPECT_GT(std::abs(q.normals[i].z()), 1.0 - 1e-9);
  }
}

// Two sheets whose distance grows from 0.02 to 0.04 across the cloud: at a
// separation of 0.03 the nearer part is fitted as one surface, the farther
// split. same_fits is exactly the separations that give these fits: the
// same fits just inside either end, other fits just outside.
TEST(LocalQuadrics, SameFitsIsTheRangeOfSeparationsThatGiveThem) {
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  PointCloud cloud;
  for (int i = 0; i < 20000; ++i) {
    const double x = u(rng);
    cloud.positions.emplace_back(x, u(rng), i % 2 == 0 ? 0.0 : 0.03 + 0.01 * x);
  }
  TangentPlaneOptions planes_options;
  planes_options.adapt_k = false;
  const LeafPlanes lp = leaf_planes(cloud, planes_options);
  LocalQuadricOptions options;
  options.min_sheet_separation = 0.03;
  const LocalQuadrics q = fit_local_quadrics(lp.planes, options);
  const SeparationRange range = q.same_fits;
  ASSERT_LT(range.below, 0.03);
  ASSERT_GE(range.up_to, 0.03);
  ASSERT_GT(range.below, 0.02) << "some pairs nearer than 0.03 were measured";
  ASSERT_LT(range.up_to, 0.04) << "and some farther";
  const auto fits_at = [&](double separation) {
    LocalQuadricOptions o = options;
    o.min_sheet_separation = separation;
    return fit_local_quadrics(lp.planes, o);
  };
  const auto same = [&](const LocalQuadrics& other) {
    return other.split == q.split && other.origins == q.origins && other.normals == q.normals;
  };
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(same(fits_at(std::nextafter(range.below, inf))));
  EXPECT_TRUE(same(fits_at(range.up_to)));
  EXPECT_TRUE(range.holds(std::nextafter(range.below, inf)) && range.holds(range.up_to));
  EXPECT_FALSE(same(fits_at(range.below)));
  EXPECT_FALSE(same(fits_at(std::nextafter(range.up_to, inf))));
  EXPECT_FALSE(range.holds(range.below) || range.holds(std::nextafter(range.up_to, inf)));
  // Without a separation no pair is measured: only none gives the same fits.
  const LocalQuadrics unseparated = fits_at(0.0);
  EXPECT_TRUE(unseparated.same_fits.holds(0.0));
  EXPECT_FALSE(unseparated.same_fits.holds(1e-12));
}

// A neighbourhood of copies of one point has no surface; strays scattered
// far from the data reach each other across empty space. Both keep phase
// I's plane, which passes through no sample and so draws nothing.
TEST(LocalQuadrics, StraysAndCopiesKeepPhaseOnesPlane) {
  PointCloud cloud = make_sphere()->sample(3000, 6);
  cloud.normals.clear();
  cloud.positions.insert(cloud.positions.end(), 30, Vec3(0.3, -0.2, 5.0));  // copies of one point
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> around(-50.0, 50.0);
  for (int i = 0; i < 40; ++i) cloud.positions.emplace_back(around(rng), around(rng), around(rng));
  const LeafPlanes lp = leaf_planes(cloud);
  const LocalQuadrics q = fit_local_quadrics(lp.planes);
  const auto x = lp.planes.point_tree.points();
  std::size_t kept = 0;
  for (std::size_t i = 0; i < q.origins.size(); ++i) {
    const bool stray = x[i].norm() > 2.0;
    if (!stray) continue;
    const bool plane_kept = q.origins[i] == lp.planes.origins[i] && q.normals[i] == lp.planes.normals[i];
    kept += plane_kept ? 1u : 0u;
    EXPECT_TRUE(plane_kept) << x[i].transpose();
  }
  EXPECT_EQ(kept, 70u);
  EXPECT_GE(q.flat, 70u);
}

TEST(LocalQuadrics, NeedsTheListsAndTheLeafOrder) {
  const PointCloud cloud = make_sphere()->sample(500, 8);
  const auto planes = estimate_tangent_planes<3>(cloud.positions);  // a tree in its own order
  EXPECT_THROW((void)fit_local_quadrics(planes), InvalidInputError);
}

}  // namespace
}  // namespace recon
