// Far-apart clusters (reconstruct.h): a cloud too wide for one lattice is
// contoured on a lattice per cluster, each as if reconstructed alone with the
// whole cloud's choices; a cluster too wide by itself is refused, saying so.

#include "io/io_test_helpers.h"
#include "mesh_compare.h"
#include "recon/core/errors.h"
#include "recon/core/shapes.h"
#include "recon/reconstruct.h"
#include "recon/structures/lattice.h"
#include "recon/structures/mesh.h"
#include "recon/tiles/tiles.h"

#include <gtest/gtest.h>
#include <Eigen/Geometry>  // cross

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

namespace recon {
namespace {

PointCloud spheres(const std::vector<Vec3>& centres, std::size_t per_sphere, double radius = 1.0) {
  PointCloud cloud;
  std::uint64_t seed = 40;
  for (const Vec3& c : centres) {
    const PointCloud one = make_sphere(radius, c)->sample(per_sphere, ++seed);
    cloud.positions.insert(cloud.positions.end(), one.positions.begin(), one.positions.end());
  }
  return cloud;
}

PointCloud part_of(const PointCloud& cloud, std::size_t first, std::size_t count) {
  PointCloud part;
  part.positions.assign(cloud.positions.begin() + static_cast<std::ptrdiff_t>(first),
                        cloud.positions.begin() + static_cast<std::ptrdiff_t>(first + count));
  return part;
}

// The whole cloud's choices, as a tile of it is given them (tiles/step1_plan.cpp).
ReconstructionOptions whole_cloud_choices(const Reconstruction& whole) {
  ReconstructionOptions o;
  o.planes.k = whole.planes.k;
  o.planes.adapt_k = false;
  o.planes.cloud = whole.planes.spacing();
  if (whole.quadrics) o.quadrics.cloud = whole.quadrics->medians;
  o.method = whole.method;
  o.cell = whole.contour.cell;
  o.offset = whole.offset;
  o.distance.delta = whole.delta;
  return o;
}

void append(Mesh& all, const Mesh& part) {
  const auto first = static_cast<std::uint32_t>(all.vertices.size());
  all.vertices.insert(all.vertices.end(), part.vertices.begin(), part.vertices.end());
  for (const auto& t : part.triangles) all.triangles.push_back({t[0] + first, t[1] + first, t[2] + first});
}

// Two unit spheres 1e9 apart: no lattice of 2^21 cubes an axis spans both.
// Analytic check: two closed genus-0 surfaces, each near its own sphere and
// facing away from its centre. (Coordinates near 1e9 are held to about 1e-7;
// the reconstruction's own error, `tolerance`, is far larger: hoppe92's cell
// of rho is coarser.)
void expect_two_spheres_a_billion_apart(Method method, double tolerance) {
  const Vec3 far(1e9, 0.0, 0.0);
  ReconstructionOptions options;
  options.method = method;
  const Reconstruction r = reconstruct(spheres({Vec3::Zero(), far}, 1500), options);
  ASSERT_EQ(r.clusters.size(), 2u);
  EXPECT_FALSE(lattice_fits<3>(bounding_box<3>(r.points()), r.contour.cell)) << "one lattice would have fitted";
  EXPECT_EQ(r.clusters[0].points + r.clusters[1].points, 3000u);
  EXPECT_EQ(r.clusters[0].triangles + r.clusters[1].triangles, r.contour.mesh.triangles.size());
  const Mesh& mesh = r.mesh();
  const MeshTopology t = analyze_topology(mesh);
  EXPECT_TRUE(t.watertight()) << "boundary " << t.boundary_edges << ", non-manifold " << t.non_manifold_edges;
  ASSERT_EQ(t.components, 2u);
  for (const auto& c : t.component_list) EXPECT_EQ(c.euler_characteristic, 2);
  std::size_t near_far = 0;
  double worst = 0.0;
  for (const Vec3& v : mesh.vertices) {
    const bool second = v.x() > 0.5e9;
    near_far += second ? 1 : 0;
    worst = std::max(worst, std::abs((v - (second ? far : Vec3::Zero())).norm() - 1.0));
  }
  EXPECT_LT(worst, tolerance);
  EXPECT_GT(near_far, mesh.vertices.size() / 3);
  EXPECT_LT(near_far, 2 * mesh.vertices.size() / 3);
  std::size_t inward = 0;
  for (const auto& tri : mesh.triangles) {
    const Vec3 &a = mesh.vertices[tri[0]], &b = mesh.vertices[tri[1]], &c = mesh.vertices[tri[2]];
    const Vec3 centre = a.x() > 0.5e9 ? far : Vec3::Zero();
    if ((b - a).cross(c - a).dot(a - centre) <= 0.0) ++inward;
  }
  EXPECT_EQ(inward, 0u) << "triangles facing their sphere's centre";
}

TEST(FarClusters, TwoSpheresABillionApartAreTwoClosedSpheres) {
  expect_two_spheres_a_billion_apart(Method::refined, 0.01);
}

TEST(FarClusters, TwoSpheresABillionApartAreTwoClosedSpheresInHoppe92) {
  expect_two_spheres_a_billion_apart(Method::hoppe92, 0.04);
}

// Stray samples far from everything (isolated: they draw no surface) are
// clusters of their own that get no lattice.
TEST(FarClusters, FarStraysGetNoLattice) {
  PointCloud cloud = spheres({Vec3::Zero(), Vec3(1e9, 0.0, 0.0)}, 1500);
  cloud.positions.emplace_back(0.0, 1e9, 0.0);
  cloud.positions.emplace_back(0.0, 0.0, -1e9);
  const Reconstruction r = reconstruct(cloud);
  EXPECT_EQ(r.planes.isolated, 2u);
  ASSERT_EQ(r.clusters.size(), 2u);
  EXPECT_EQ(r.clusters[0].points + r.clusters[1].points, 3000u);
  EXPECT_EQ(analyze_topology(r.mesh()).components, 2u);
}

// Three spheres a million apart along x and z (two levels of splitting):
// each cluster's mesh, phase IV's and the final one, is that of the cluster
// reconstructed alone with the whole cloud's choices, to 1e-9 of the cell.
TEST(FarClusters, EachClusterIsMeshedAsIfAlone) {
  const std::vector<Vec3> centres{Vec3::Zero(), Vec3(1e6, 0.0, 0.0), Vec3(0.0, 0.0, 1e6)};
  constexpr std::size_t per_sphere = 1000;
  const PointCloud cloud = spheres(centres, per_sphere);
  const Reconstruction whole = reconstruct(cloud);
  ASSERT_EQ(whole.clusters.size(), 3u);
  const ReconstructionOptions alone_options = whole_cloud_choices(whole);
  Mesh contoured, refined;
  std::vector<std::size_t> triangles;
  for (std::size_t s = 0; s < centres.size(); ++s) {
    const Reconstruction alone = reconstruct(part_of(cloud, s * per_sphere, per_sphere), alone_options);
    EXPECT_TRUE(alone.clusters.empty());
    append(contoured, alone.contour.mesh);
    append(refined, alone.mesh());
    triangles.push_back(alone.contour.mesh.triangles.size());
  }
  const double tolerance = 1e-9 * whole.contour.cell;
  EXPECT_TRUE(same_mesh(whole.contour.mesh, contoured, tolerance));
  EXPECT_TRUE(same_mesh(whole.mesh(), refined, tolerance));
  for (const ClusterLattice& c : whole.clusters) {
    EXPECT_EQ(c.points, per_sphere);
    EXPECT_NE(std::find(triangles.begin(), triangles.end(), c.triangles), triangles.end());
    EXPECT_LT(c.size[0], 200) << "a lattice over one sphere";
  }
  EXPECT_EQ(analyze_topology(whole.mesh()).components, 3u);
}

// Samples closer than the phases' reach stay one cluster, whatever their
// own gaps: a flat patch sampled in rows 0.05 apart (wider apart than a
// cell of 0.03), beside a sphere 1e9 away, is one open patch, not strips meshed on
// lattices of their own that overlap.
TEST(FarClusters, RowsCloserThanTheReachAreOneCluster) {
  PointCloud cloud = spheres({Vec3(1e9, 0.0, 0.0)}, 1500);
  for (int i = 0; i < 40; ++i)
    for (int j = 0; j < 40; ++j) cloud.positions.emplace_back(0.05 * i, 0.05 * j, 0.0);
  ReconstructionOptions options;
  options.cell = 0.03;
  const Reconstruction r = reconstruct(cloud, options);
  ASSERT_EQ(r.clusters.size(), 2u);
  const MeshTopology t = analyze_topology(r.mesh());
  EXPECT_EQ(t.components, 2u);
  EXPECT_EQ(t.non_manifold_edges, 0u);
  EXPECT_EQ(t.boundary_loops, 1u) << "the patch's";
}

// Two spheres a kilometre apart fit one lattice: nothing is split.
TEST(FarClusters, OneLatticeThatFitsIsNotSplit) {
  const Reconstruction r = reconstruct(spheres({Vec3::Zero(), Vec3(1000.0, 0.0, 0.0)}, 1500));
  EXPECT_TRUE(r.clusters.empty());
  EXPECT_GT(r.contour.size[0], 1000);
}

// A cluster too wide for a lattice by itself (a sphere of radius 2e5 at the
// unit sphere's cell) is refused, and the message says it is one cluster of
// several.
TEST(FarClusters, AClusterTooWideForOneLatticeIsRefusedSayingSo) {
  PointCloud cloud = spheres({Vec3::Zero()}, 3000);
  const PointCloud wide = make_sphere(2e5, Vec3(1e9, 0.0, 0.0))->sample(1000, 7);
  cloud.positions.insert(cloud.positions.end(), wide.positions.begin(), wide.positions.end());
  const std::string message = io::testing::message_of<ResourceLimitError>([&] { (void)reconstruct(cloud); });
  EXPECT_CONTAINS(message, "a cluster of 1000 points (of 2 separated by empty gaps wider than");
  EXPECT_CONTAINS(message, "is too wide for one lattice: the lattice would need");
  EXPECT_CONTAINS(message, "use a larger --cell");
}

// A tiled run lays one lattice over the whole cloud: far-apart clusters too
// wide for it are refused, saying that an in-memory run meshes them.
TEST(FarClusters, ATiledRunRefusesThemSayingWhereTheyRun) {
  const auto dir = std::filesystem::path(::testing::TempDir()) / "recon-far-clusters-tiled";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  TilingOptions options;
  options.tile_size = 1.0;
  const PointCloud cloud = spheres({Vec3::Zero(), Vec3(1e9, 0.0, 0.0)}, 1000);
  const std::string message =
      io::testing::message_of<ResourceLimitError>([&] { (void)plan_tiles(pass_over(cloud), options, dir); });
  EXPECT_CONTAINS(message, "a tiled run lays one lattice over the whole cloud, and the lattice would need");
  EXPECT_CONTAINS(message, "or reconstruct it in memory (not tiled), which meshes far-apart clusters");
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace recon
