// The Euclidean minimum spanning tree (emst.h) against its oracle, Prim on
// the complete graph (complete_graph_mst.h), with and without hints.

#include "recon/phase2_orientation/emst.h"

#include "recon/alternatives/complete_graph_mst.h"
#include "recon/core/parallel.h"
#include "recon/core/shapes.h"
#include "recon/phase1_planes/tangent_planes.h"
#include "recon/phase2_orientation/riemannian_graph.h"
#include "search_clouds.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <string>
#include <tuple>
#include <vector>

namespace recon {
namespace {

using testing::Cloud;
using testing::make_cloud;

// Oracle: Prim on the complete graph, O(n^2), with the same
// (length, smaller end, larger end) edge order.
template <int D>
std::vector<Edge> brute_force_emst(const std::vector<Vec<D>>& pts) {
  return complete_graph_minimum_spanning_tree<D>(pts).edges;
}

// The same edge set (endpoints and lengths), whatever the order.
void expect_same_edges(std::vector<Edge> got, std::vector<Edge> expected) {
  ASSERT_EQ(got.size(), expected.size());
  auto by_ends = [](const Edge& a, const Edge& b) { return std::tie(a.u, a.v) < std::tie(b.u, b.v); };
  std::sort(got.begin(), got.end(), by_ends);
  std::sort(expected.begin(), expected.end(), by_ends);
  for (std::size_t e = 0; e < got.size(); ++e) {
    ASSERT_EQ(got[e].u, expected[e].u) << "edge " << e;
    ASSERT_EQ(got[e].v, expected[e].v) << "edge " << e;
    ASSERT_DOUBLE_EQ(got[e].weight, expected[e].weight) << "edge " << e;
  }
}

template <int D>
void check_emst(Cloud cloud, std::size_t n, std::uint32_t seed, bool with_knn) {
  SCOPED_TRACE(testing::name_of(cloud) + ", " + std::to_string(n) + " points" + (with_knn ? "" : ", no hints"));
  const std::vector<Vec<D>> pts = make_cloud<D>(cloud, n, seed);
  const KdTree<D> tree(pts, {4});
  const KnnTable knn = tree.all_knn(static_cast<int>(std::min<std::size_t>(6, n)));
  const auto got =
      with_knn ? euclidean_minimum_spanning_tree<D>(tree, pts, knn) : euclidean_minimum_spanning_tree<D>(tree, pts);
  ASSERT_EQ(got.size(), n - 1);
  expect_same_edges(got, brute_force_emst<D>(pts));
}

// Uniform points, a surface, clusters with far outliers, and an integer
// lattice (copies and equal lengths everywhere, where only the order of
// the edges keeps the tree unique).
TEST(EuclideanMst, EqualsBruteForceMst3D) {
  for (const Cloud cloud : testing::all_clouds) {
    for (const std::size_t n : {2u, 3u, 50u, 500u, 3000u}) check_emst<3>(cloud, n, static_cast<std::uint32_t>(n), true);
    check_emst<3>(cloud, 800, 99, false);  // without the k-NN shortcut
  }
}

TEST(EuclideanMst, EqualsBruteForceMst2D) {
  for (const Cloud cloud : testing::all_clouds)
    for (const std::size_t n : {2u, 40u, 2000u}) check_emst<2>(cloud, n, static_cast<std::uint32_t>(n + 7), true);
}

TEST(EuclideanMst, NoEdgesForFewerThanTwoPoints) {
  const std::vector<Vec3> none;
  EXPECT_TRUE(euclidean_minimum_spanning_tree<3>(KdTree<3>(none), none).empty());
  const std::vector<Vec3> one = {Vec3(1.0, 2.0, 3.0)};
  EXPECT_TRUE(euclidean_minimum_spanning_tree<3>(KdTree<3>(one), one).empty());
}

// Hints that do not fit the points (another count) are not used: the tree
// is still exact.
TEST(EuclideanMst, HintsOfAnotherSizeAreIgnored) {
  const std::vector<Vec3> pts = make_cloud<3>(Cloud::clusters_and_outliers, 400, 12);
  const KdTree<3> tree(pts);
  NeighborLists lists;
  lists.k = 3;
  lists.indices.assign(3 * 10, 0);  // ten rows for 400 points
  const std::vector<double> radius2(10, 1e9);
  expect_same_edges(euclidean_minimum_spanning_tree<3>(tree, pts, EmstHints{&lists, radius2}),
                    brute_force_emst<3>(pts));
}

// Many exact copies of a few points (a scanner's "no return" written as
// 0 0 0 again and again): only the first of a run of copies asks the tree,
// and the tree is still exact.
TEST(EuclideanMst, ManyCopiesOfAFewPoints) {
  std::vector<Vec3> pts = make_cloud<3>(Cloud::uniform, 600, 21);
  for (std::size_t i = 0; i < pts.size(); i += 3) pts[i] = Vec3::Zero();
  for (std::size_t i = 1; i < pts.size(); i += 7) pts[i] = Vec3(0.5, 0.5, 0.5);
  const KdTree<3> tree(pts);
  expect_same_edges(euclidean_minimum_spanning_tree<3>(tree, pts, tree.all_knn(8)), brute_force_emst<3>(pts));
}

// The rounds run in parallel; the tree, and the order of its edges, do not
// depend on the thread count.
TEST(EuclideanMst, SameEdgesInTheSameOrderForAnyThreadCount) {
  const std::vector<Vec3> pts = make_cloud<3>(Cloud::clusters_and_outliers, 5000, 31);
  const KdTree<3> tree(pts);
  const KnnTable knn = tree.all_knn(6);
  const int threads = thread_count();
  set_thread_count(1);
  const std::vector<Edge> alone = euclidean_minimum_spanning_tree<3>(tree, pts, knn);
  set_thread_count(2);
  const std::vector<Edge> shared = euclidean_minimum_spanning_tree<3>(tree, pts, knn);
  set_thread_count(threads);
  EXPECT_EQ(alone, shared);
}

// Phase II's EMST is hinted by phase I's neighbourhoods, kept as indices
// with float radii: still exact, with noise, lone outliers and duplicates.
TEST(EuclideanMst, RiemannianGraphEmstEqualsBruteForce) {
  for (const std::uint32_t seed : {5u, 6u}) {
    PointCloud cloud = make_torus()->sample(2500, seed);
    std::mt19937 rng(seed);
    std::normal_distribution<double> noise(0.0, 0.01);
    for (Vec3& p : cloud.positions) p += Vec3(noise(rng), noise(rng), noise(rng));
    cloud.positions[7] = Vec3(3.0, 0.0, 0.0);  // lone outliers
    cloud.positions[8] = Vec3(0.0, 0.0, 0.9);
    cloud.positions[9] = cloud.positions[10];
    TangentPlaneOptions options;
    options.k = 10;
    const auto planes = estimate_tangent_planes<3>(cloud.positions, options);
    expect_same_edges(build_riemannian_graph<3>(planes).emst, brute_force_emst<3>(cloud.positions));
  }
}

TEST(EuclideanMst, GridWithManyEqualLengthsIsATree) {
  // All edges of a grid have the same length: only the tie-breaking order
  // keeps Borůvka from closing cycles.
  std::vector<Vec3> pts;
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 20; ++j) pts.emplace_back(i, j, 0.0);
  const KdTree<3> tree(pts);
  const KnnTable knn = tree.all_knn(5);
  const auto edges = euclidean_minimum_spanning_tree<3>(tree, pts, knn);
  ASSERT_EQ(edges.size(), pts.size() - 1);
  UnionFind sets(pts.size());
  for (const Edge& e : edges) {
    EXPECT_TRUE(sets.unite(e.u, e.v));
    EXPECT_DOUBLE_EQ(e.weight, 1.0);
  }
  expect_same_edges(edges, brute_force_emst<3>(pts));
}

}  // namespace
}  // namespace recon
