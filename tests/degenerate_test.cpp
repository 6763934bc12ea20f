// Degenerate clouds: each is reconstructed correctly or refused with a
// message that says what to change (docs/robustness.md lists them).

#include "io/io_test_helpers.h"
#include "recon/core/errors.h"
#include "recon/core/shapes.h"
#include "recon/reconstruct.h"
#include "recon/structures/mesh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <random>
#include <string>

namespace recon {
namespace {

template <typename E = InvalidInputError>
std::string refusal(const PointCloud& cloud, const ReconstructionOptions& options = {}) {
  return io::testing::message_of<E>([&] { (void)reconstruct(cloud, options); });
}

PointCloud sphere_cloud(std::size_t n, std::uint64_t seed, double radius = 1.0, Vec3 centre = Vec3::Zero()) {
  PointCloud cloud = make_sphere(radius, centre)->sample(n, seed);
  cloud.normals.clear();
  return cloud;
}

// The mesh is `pieces` closed spheres facing outward, every vertex within
// `tolerance` of the true surface.
void expect_closed_spheres(const Reconstruction& r, const Shape& truth, std::size_t pieces, double tolerance) {
  const MeshTopology t = analyze_topology(r.mesh());
  EXPECT_TRUE(t.watertight()) << "boundary " << t.boundary_edges << ", non-manifold " << t.non_manifold_edges;
  EXPECT_EQ(t.components, pieces);
  EXPECT_EQ(t.euler_characteristic, 2 * static_cast<long>(pieces));
  for (const auto& c : t.component_list) EXPECT_GT(c.signed_volume, 0.0) << "a component faces inward";
  double worst = 0.0;
  for (const Vec3& v : r.mesh().vertices) worst = std::max(worst, truth.distance(v));
  EXPECT_LT(worst, tolerance);
}

TEST(DegenerateClouds, FewerDistinctPointsThanKPlusOneSayToLowerK) {
  PointCloud cloud;
  for (int copy = 0; copy < 10; ++copy)
    for (int i = 0; i < 5; ++i) cloud.positions.emplace_back(i, i * i, 1.0 / (i + 1));
  const std::string message = refusal(cloud);
  EXPECT_CONTAINS(message, "only 5 distinct points (of 50)");
  EXPECT_CONTAINS(message, "k = 20 needs at least 21 (lower --k)");
}

TEST(DegenerateClouds, IdenticalPointsAreRefused) {
  PointCloud cloud;
  cloud.positions.assign(100, Vec3(1, 2, 3));
  EXPECT_CONTAINS(refusal(cloud), "only 1 distinct point (of 100); k = 20 needs at least 21: too few to fit a surface");
}

TEST(DegenerateClouds, CollinearPointsAreRefused) {
  PointCloud cloud;
  for (int i = 0; i < 500; ++i) cloud.positions.emplace_back(0.01 * i, 0.02 * i + 1, -0.03 * i);
  EXPECT_CONTAINS(refusal(cloud), "all points lie on one line");
}

// All points on a plane is a valid surface, an open flat mesh:
// Reconstruct.PlanePatchWithHoleStaysOpen (reconstruct_test.cpp).

TEST(DegenerateClouds, HalfTheCloudDuplicatedStillGivesTheSurface) {
  const auto sphere = make_sphere();
  PointCloud cloud = sphere_cloud(6000, 8);
  const std::size_t n = cloud.size();
  for (std::size_t i = 0; i < n; ++i) cloud.positions.push_back(cloud.positions[i]);
  const Reconstruction r = reconstruct(cloud);
  EXPECT_EQ(r.planes.distinct_points, n);
  expect_closed_spheres(r, *sphere, 1, 0.01);
}

// A geo-referenced scan: a 10 cm sphere sampled about 2.5 mm apart, at
// coordinates of ten million. The mesh must be the one of the same points
// near the origin, moved there, to far better than the spacing.
// A scanner that writes "no return" as 0 0 0: copies of one point beside a
// sphere 10 units away. The copies have no plane and draw no surface; the
// searches among them stay logarithmic (before, every k-NN and EMST query
// among the copies visited all of them: hours for 100,000). Timed: ten
// times the copies must not take anywhere near a hundred times as long
// (linear growth gives at most 10, the quadratic searches gave 100).
TEST(DegenerateClouds, MassOfIdenticalPointsDrawsNothingAndStaysFast) {
  const auto sphere = make_sphere(1.0, Vec3(10, 10, 10));
  const PointCloud base = sphere_cloud(5000, 14, 1.0, Vec3(10, 10, 10));
  auto run = [&](std::size_t copies, Reconstruction& r) {
    PointCloud cloud = base;
    cloud.positions.insert(cloud.positions.end(), copies, Vec3::Zero());
    double fastest = std::numeric_limits<double>::infinity();
    for (int round = 0; round < 2; ++round) {  // the faster of two: a busy machine slows one run, not both
      const auto start = std::chrono::steady_clock::now();
      r = reconstruct(cloud);
      fastest = std::min(fastest, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
    return fastest;
  };
  Reconstruction few, many;
  const double seconds_few = run(10000, few), seconds_many = run(100000, many);
  EXPECT_LT(seconds_many, 20.0 * seconds_few)
      << seconds_few << " s with 10,000 copies, " << seconds_many << " s with 100,000";
  EXPECT_EQ(many.planes.distinct_points, 5001u);
  expect_closed_spheres(many, *sphere, 1, 0.01);
}

TEST(DegenerateClouds, GeoReferencedCoordinatesKeepTheirPrecision) {
  const Vec3 far(4512345.678, 5412345.123, 1.0e7);
  const PointCloud local = sphere_cloud(20000, 3, 0.1);
  PointCloud geo = local;
  for (Vec3& p : geo.positions) p += far;
  const Reconstruction near_origin = reconstruct(local);
  const Reconstruction moved = reconstruct(geo);
  EXPECT_EQ(near_origin.offset, Vec3::Zero());
  EXPECT_LT((moved.offset - far).norm(), 0.1);
  expect_closed_spheres(moved, *make_sphere(0.1, far), 1, 0.001);
  const Mesh& a = near_origin.mesh();
  const Mesh& b = moved.mesh();
  ASSERT_EQ(a.vertices.size(), b.vertices.size());
  ASSERT_EQ(a.triangles, b.triangles);
  double worst = 0.0;
  for (std::size_t i = 0; i < a.vertices.size(); ++i)
    worst = std::max(worst, (b.vertices[i] - far - a.vertices[i]).norm());
  // The input itself is rounded to 2e-9 at 1e7; the mesh differs by at most
  // a thousandth of a millimetre (single precision anywhere would cost a metre).
  EXPECT_LT(worst, 1e-5);
}

TEST(DegenerateClouds, HugeOrNonFiniteCoordinatesAreRefusedWithCountAndFirst) {
  PointCloud cloud = sphere_cloud(500, 4);
  cloud.positions[7].y() = std::numeric_limits<double>::quiet_NaN();
  cloud.positions[9].x() = 1e30;
  cloud.positions[12].z() = -std::numeric_limits<double>::infinity();
  const std::string message = refusal(cloud);
  EXPECT_CONTAINS(message, "3 points have a coordinate that is not finite or beyond +-1e+15; the first is point 7");
}

TEST(DegenerateClouds, OneFarOutlierDrawsNoSurface) {
  const auto sphere = make_sphere();
  PointCloud cloud = sphere_cloud(5000, 6);
  cloud.positions.emplace_back(1e4, 2e4, -3e4);  // the bounding box grows 30,000-fold
  const Reconstruction r = reconstruct(cloud);
  EXPECT_EQ(r.planes.isolated, 1u);
  const auto outlier = static_cast<std::size_t>(std::find(r.order.begin(), r.order.end(), 5000u) - r.order.begin());
  EXPECT_EQ(r.planes.local_rho[outlier], 0.0f);
  expect_closed_spheres(r, *sphere, 1, 0.01);
}

// Stray points: a pair and a cluster of five far out, then thirty
// scattered around; no surface grows from any of them (before, the pair's
// plane spread a sheet hundreds of units wide, and the run took minutes).
TEST(DegenerateClouds, StrayPointsAndSmallClustersDrawNoSurface) {
  const auto sphere = make_sphere();
  PointCloud cloud = sphere_cloud(5000, 7);
  cloud.positions.emplace_back(100, 200, -300);
  cloud.positions.emplace_back(100.01, 200, -300);
  for (int i = 0; i < 5; ++i) cloud.positions.emplace_back(50 + 0.01 * i, 20 + 0.001 * i * i, -30);
  const Reconstruction r = reconstruct(cloud);
  EXPECT_EQ(r.planes.isolated, 7u);
  for (std::size_t j = 0; j < r.order.size(); ++j)
    EXPECT_EQ(r.planes.local_rho[j] == 0.0f, r.order[j] >= 5000) << r.order[j];
  expect_closed_spheres(r, *sphere, 1, 0.01);

  // Scattered points whose neighbours are mostly other scattered points need
  // not be isolated (a sparse cloud of strays looks like sparse data); the
  // walk starts only in cubes of samples that f crosses, and these strays'
  // planes, fitted to distant neighbours, miss them. Still one sphere, and no
  // sample of it is isolated.
  std::mt19937_64 random(3);
  std::uniform_real_distribution<double> around(-50.0, 50.0);
  for (int i = 0; i < 30; ++i) cloud.positions.emplace_back(around(random), around(random), around(random));
  const Reconstruction scattered = reconstruct(cloud);
  for (std::size_t j = 0; j < scattered.order.size(); ++j)
    if (scattered.order[j] < 5000) {
      EXPECT_GT(scattered.planes.local_rho[j], 0.0f);
    }
  expect_closed_spheres(scattered, *sphere, 1, 0.01);
}

TEST(DegenerateClouds, TwoClustersAKilometreApartAreTwoClosedSurfaces) {
  PointCloud cloud = sphere_cloud(5000, 9);
  const PointCloud second = sphere_cloud(5000, 10, 1.0, Vec3(1000.0, 0.0, 0.0));
  cloud.positions.insert(cloud.positions.end(), second.positions.begin(), second.positions.end());
  const Reconstruction r = reconstruct(cloud);
  EXPECT_EQ(r.planes.isolated, 0u);
  ASSERT_TRUE(r.oriented);
  EXPECT_EQ(r.oriented->component_count(), 2u);
  const auto first_sphere = make_sphere();
  const auto second_sphere = make_sphere(1.0, Vec3(1000.0, 0.0, 0.0));
  struct Both : Shape {
    const Shape *a, *b;
    Both(const Shape* x, const Shape* y) : a(x), b(y) {}
    PointCloud sample(std::size_t, std::uint64_t) const override { return {}; }
    double distance(const Vec3& p) const override { return std::min(a->distance(p), b->distance(p)); }
    double area() const override { return a->area() + b->area(); }
    int euler_characteristic() const override { return 4; }
  } both(first_sphere.get(), second_sphere.get());
  expect_closed_spheres(r, both, 2, 0.01);
  EXPECT_LT(r.contour.visited_cubes, 20000u) << "the walk stays near the data, however large the box";
}

// Thirteen times denser on a cap than elsewhere: one closed surface, and no
// sample of the sparse part is taken for a stray one.
TEST(DegenerateClouds, VeryNonUniformDensityStaysClosed) {
  const auto sphere = make_sphere();
  const PointCloud dense = sphere_cloud(40000, 11);
  const PointCloud sparse = sphere_cloud(3000, 12);
  PointCloud cloud;
  for (const Vec3& p : dense.positions)
    if (p.z() > 0.3) cloud.positions.push_back(p);
  for (const Vec3& p : sparse.positions)
    if (p.z() <= 0.3) cloud.positions.push_back(p);
  const Reconstruction r = reconstruct(cloud);
  EXPECT_EQ(r.planes.isolated, 0u);
  expect_closed_spheres(r, *sphere, 1, 0.02);
}

TEST(DegenerateClouds, MemoryLimitRefusesBeforeAllocatingAndSaysWhatToChange) {
  const PointCloud cloud = sphere_cloud(20000, 13);
  ReconstructionOptions options;
  options.max_memory = 2'000'000;  // 2 MB: phases I-II need about 8 MB here (7.4 by the 1992 method)
  const std::string planes = refusal<ResourceLimitError>(cloud, options);
  EXPECT_CONTAINS(planes, "tangent planes and orientation of 20000 points at k = 20 would need about 8.2 MB");
  EXPECT_CONTAINS(planes, "more than the 2 MB allowed (--max-memory");
  EXPECT_CONTAINS(planes, "lower --k or thin the cloud, or raise --max-memory");
  options.max_memory = 100'000'000;  // enough for the points, not for a lattice of cell 1e-4
  options.cell = 1e-4;
  const std::string lattice = refusal<ResourceLimitError>(cloud, options);
  EXPECT_CONTAINS(lattice, "a lattice cell of 0.0001");
  EXPECT_CONTAINS(lattice, "use a larger --cell or a smaller --resolution, or raise --max-memory");
  options.cell.reset();
  const Reconstruction r = reconstruct(cloud, options);  // the default cell fits
  EXPECT_GT(r.mesh().triangles.size(), 1000u);
}

}  // namespace
}  // namespace recon
