#include "recon/alternatives/complete_graph_mst.h"

#include "recon/alternatives/kruskal.h"
#include "recon/core/errors.h"
#include "recon/phase2_orientation/emst.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <tuple>
#include <vector>

namespace recon {
namespace {

template <int D>
std::vector<Vec<D>> random_points(std::size_t n, std::uint32_t seed, bool clustered) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Vec<D>> pts(n);
  for (auto& p : pts) {
    for (int a = 0; a < D; ++a) p[a] = unit(rng);
    if (clustered) p = (p * 0.05).eval() + Vec<D>::Constant(static_cast<double>(rng() % 4));
  }
  for (std::size_t i = 3; i < n; i += 7) pts[i] = pts[i / 2];  // exact duplicates, some of them repeated
  return pts;
}

std::vector<Edge> sorted_by_ends(std::vector<Edge> edges) {
  std::sort(edges.begin(), edges.end(),
            [](const Edge& a, const Edge& b) { return std::tie(a.u, a.v) < std::tie(b.u, b.v); });
  return edges;
}

// Both compare edges by (squared length, smaller end, larger end): the same
// tree, edge for edge.
template <int D>
void expect_equals_emst(const std::vector<Vec<D>>& pts) {
  const std::size_t n = pts.size();
  const MinimumSpanningEdges prim = complete_graph_minimum_spanning_tree<D>(pts);
  const KdTree<D> tree(pts, {4});
  const std::vector<Edge> emst =
      euclidean_minimum_spanning_tree<D>(tree, pts, tree.all_knn(static_cast<int>(std::min<std::size_t>(6, n))));
  ASSERT_EQ(prim.edges.size(), n - 1);
  EXPECT_EQ(sorted_by_ends(prim.edges), sorted_by_ends(emst));
  double total = 0.0;
  for (const Edge& e : emst) total += e.weight;
  EXPECT_NEAR(prim.total_weight, total, 1e-12 * static_cast<double>(n));
  EXPECT_EQ(prim.counts.distance_evaluations, n * (n - 1) / 2);
}

TEST(CompleteGraphMst, EqualsEmst3D) {
  for (const std::size_t n : {2u, 3u, 60u, 700u}) {
    expect_equals_emst<3>(random_points<3>(n, static_cast<std::uint32_t>(n), false));
    expect_equals_emst<3>(random_points<3>(n, static_cast<std::uint32_t>(n + 1), true));
  }
}

TEST(CompleteGraphMst, EqualsEmst2D) {
  for (const std::size_t n : {2u, 45u, 900u}) {
    expect_equals_emst<2>(random_points<2>(n, static_cast<std::uint32_t>(n + 3), false));
    expect_equals_emst<2>(random_points<2>(n, static_cast<std::uint32_t>(n + 4), true));
  }
}

// A grid: every edge of the tree has the same length, and the tie-break
// alone picks which.
TEST(CompleteGraphMst, EqualsEmstOnAGrid) {
  std::vector<Vec2> pts;
  for (int i = 0; i < 15; ++i)
    for (int j = 0; j < 12; ++j) pts.emplace_back(static_cast<double>(i), static_cast<double>(j));
  expect_equals_emst<2>(pts);
  const MinimumSpanningEdges prim = complete_graph_minimum_spanning_tree<2>(pts);
  EXPECT_EQ(prim.total_weight, static_cast<double>(pts.size() - 1));
}

TEST(CompleteGraphMst, AllPointsEqual) {
  const std::vector<Vec3> pts(40, Vec3(0.5, -1.0, 2.0));
  expect_equals_emst<3>(pts);
  const MinimumSpanningEdges prim = complete_graph_minimum_spanning_tree<3>(pts);
  EXPECT_EQ(prim.total_weight, 0.0);
  for (std::uint32_t i = 1; i < pts.size(); ++i) EXPECT_EQ(prim.edges[i - 1], (Edge{0, i, 0.0}));
}

// A third algorithm: Kruskal on the complete graph, listed edge by edge.
TEST(CompleteGraphMst, EqualsKruskalOnTheListedCompleteGraph) {
  const std::vector<Vec3> pts = random_points<3>(120, 17, true);
  std::vector<Edge> all;
  for (std::uint32_t i = 0; i < pts.size(); ++i)
    for (std::uint32_t j = i + 1; j < pts.size(); ++j) all.push_back({i, j, (pts[i] - pts[j]).norm()});
  const MinimumSpanningEdges kruskal = kruskal_minimum_spanning_forest(pts.size(), all);
  const MinimumSpanningEdges prim = complete_graph_minimum_spanning_tree<3>(pts);
  ASSERT_EQ(prim.edges.size(), kruskal.edges.size());
  EXPECT_NEAR(prim.total_weight, kruskal.total_weight, 1e-12);
}

TEST(CompleteGraphMst, FewPoints) {
  EXPECT_TRUE(complete_graph_minimum_spanning_tree<3>(std::vector<Vec3>{}).edges.empty());
  const MinimumSpanningEdges one = complete_graph_minimum_spanning_tree<2>(std::vector<Vec2>{Vec2(1.0, 2.0)});
  EXPECT_TRUE(one.edges.empty());
  EXPECT_EQ(one.counts.distance_evaluations, 0u);
  const MinimumSpanningEdges two =
      complete_graph_minimum_spanning_tree<2>(std::vector<Vec2>{Vec2(4.0, 0.0), Vec2(0.0, 3.0)});
  EXPECT_EQ(two.edges, (std::vector<Edge>{{0, 1, 5.0}}));
  EXPECT_EQ(two.total_weight, 5.0);
}

TEST(CompleteGraphMst, ThrowsOnNonFiniteCoordinates) {
  const std::vector<Vec3> pts = {Vec3(0.0, 0.0, 0.0), Vec3(std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0)};
  EXPECT_THROW((void)complete_graph_minimum_spanning_tree<3>(pts), InvalidInputError);
}

}  // namespace
}  // namespace recon
