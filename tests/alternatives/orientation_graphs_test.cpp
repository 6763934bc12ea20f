#include "recon/alternatives/orientation_graphs.h"

#include "recon/core/errors.h"
#include "recon/core/shapes.h"
#include "recon/phase2_orientation/emst.h"
#include "recon/phase2_orientation/orientation.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <utility>

namespace recon {
namespace {

using Pairs = std::set<std::pair<std::uint32_t, std::uint32_t>>;

Pairs pairs_of(const Graph& g) {
  Pairs pairs;
  for (std::uint32_t v = 0; v < g.vertex_count(); ++v)
    for (const std::uint32_t u : g.neighbors(v)) pairs.insert({std::min(u, v), std::max(u, v)});
  return pairs;
}

// Oracle: the k nearest of every sample by brute force over the samples
// (itself included, ties to the smaller index, as the kd-tree orders them).
std::vector<std::vector<std::uint32_t>> brute_force_neighbourhoods(std::span<const Vec3> x, std::size_t k) {
  std::vector<std::vector<std::uint32_t>> rows(x.size());
  for (std::uint32_t i = 0; i < x.size(); ++i) {
    std::vector<std::pair<double, std::uint32_t>> all;
    for (std::uint32_t j = 0; j < x.size(); ++j) all.emplace_back((x[i] - x[j]).squaredNorm(), j);
    std::sort(all.begin(), all.end());
    for (std::size_t e = 0; e < k; ++e) rows[i].push_back(all[e].second);
  }
  return rows;
}

Pairs oracle_knn_pairs(std::span<const Vec3> x, std::size_t k, bool mutual) {
  const auto rows = brute_force_neighbourhoods(x, k);
  const auto lists = [&](std::uint32_t i, std::uint32_t j) {
    return std::find(rows[i].begin(), rows[i].end(), j) != rows[i].end();
  };
  Pairs pairs;
  for (std::uint32_t i = 0; i < x.size(); ++i)
    for (const std::uint32_t j : rows[i])
      if (j != i && (!mutual || lists(j, i))) pairs.insert({std::min(i, j), std::max(i, j)});
  return pairs;
}

struct Cloud {
  std::vector<Vec3> points;
  TangentPlanes<3> planes;
};

Cloud two_spheres(std::size_t n) {
  // Two unit spheres 0.5 apart: separate objects.
  Cloud c;
  c.points = make_sphere()->sample(n, 3).positions;
  const std::vector<Vec3> second = make_sphere()->sample(n, 4).positions;
  for (const Vec3& p : second) c.points.push_back(p + Vec3(2.5, 0.0, 0.0));
  c.planes = estimate_tangent_planes<3>(std::span<const Vec3>(c.points));
  return c;
}

TEST(OrientationGraphs, NamesRoundTrip) {
  for (const OrientationGraph g : all_orientation_graphs) EXPECT_EQ(orientation_graph_named(name_of(g)), g);
  EXPECT_FALSE(orientation_graph_named("star").has_value());
}

TEST(OrientationGraphs, KnnGraphsEqualTheirDefinitionsByBruteForce) {
  const Cloud c = two_spheres(400);
  const auto k = static_cast<std::size_t>(c.planes.k);
  for (const bool mutual : {false, true}) {
    const auto kind = mutual ? OrientationGraph::mutual_knn : OrientationGraph::knn;
    const RiemannianGraph<3> g = build_orientation_graph<3>(c.planes, kind);
    EXPECT_EQ(pairs_of(g.graph), oracle_knn_pairs(c.points, k, mutual)) << name_of(kind);
    EXPECT_EQ(g.components.sizes.size(), connected_components(g.graph).sizes.size());
  }
}

TEST(OrientationGraphs, EachGraphSitsInsideTheNextAsTheHeaderSays) {
  const Cloud c = two_spheres(500);
  const Pairs mutual = pairs_of(build_orientation_graph<3>(c.planes, OrientationGraph::mutual_knn).graph);
  const Pairs knn = pairs_of(build_orientation_graph<3>(c.planes, OrientationGraph::knn).graph);
  const RiemannianGraph<3> emst = build_orientation_graph<3>(c.planes, OrientationGraph::emst);
  const RiemannianGraph<3> riemannian = build_orientation_graph<3>(c.planes, OrientationGraph::riemannian);
  const Pairs all = pairs_of(riemannian.graph);
  EXPECT_TRUE(std::includes(knn.begin(), knn.end(), mutual.begin(), mutual.end()));
  EXPECT_LT(mutual.size(), knn.size());
  // The Riemannian graph: k-NN and EMST edges, less its gaps (the k-NN
  // graphs here are the textbook ones, uncut).
  Pairs knn_and_emst = knn;
  for (const Edge& e : riemannian.emst) knn_and_emst.insert({std::min(e.u, e.v), std::max(e.u, e.v)});
  EXPECT_TRUE(std::includes(knn_and_emst.begin(), knn_and_emst.end(), all.begin(), all.end()));
  const Pairs cut_emst = pairs_of(emst.graph);
  EXPECT_TRUE(std::includes(all.begin(), all.end(), cut_emst.begin(), cut_emst.end()));
  // The EMST of two objects has one edge across the gap, which the cut removes.
  EXPECT_EQ(cut_emst.size(), c.points.size() - 2);
  EXPECT_EQ(emst.components.sizes.size(), 2u);
  EXPECT_EQ(riemannian.components.sizes.size(), 2u);
}

TEST(OrientationGraphs, TheCompleteGraphsTreeIsTheUncutEmstAndJoinsSeparateObjects) {
  const Cloud c = two_spheres(300);
  OperationCounts counts;
  const RiemannianGraph<3> complete = build_orientation_graph<3>(c.planes, OrientationGraph::complete, {}, &counts);
  const std::size_t n = c.points.size();
  EXPECT_EQ(complete.graph.edge_count(), n - 1);
  EXPECT_EQ(complete.components.sizes.size(), 1u);
  EXPECT_GE(counts.distance_evaluations, n * (n - 1) / 2);
  double complete_weight = 0.0, emst_weight = 0.0;
  for (const Edge& e : complete.emst) complete_weight += e.weight;
  const KdTree<3> tree(c.points);
  for (const Edge& e : euclidean_minimum_spanning_tree<3>(tree, c.points)) emst_weight += e.weight;
  EXPECT_NEAR(complete_weight, emst_weight, 1e-9 * emst_weight);
  // Walked by phase II, the complete graph's tree carries one sphere's
  // orientation into the other, the cut EMST does not.
  const OrientedNormals<3> joined = orient_normals<3>(c.planes, complete, {});
  EXPECT_EQ(joined.component_count(), 1u);
}

TEST(OrientationGraphs, RefusesAKBeyondPhaseOnes) {
  const Cloud c = two_spheres(200);
  RiemannianGraphOptions options;
  options.k = c.planes.k + 1;
  EXPECT_THROW((void)build_orientation_graph<3>(c.planes, OrientationGraph::knn, options), InvalidInputError);
  options.k = -1;
  EXPECT_THROW((void)build_orientation_graph<3>(c.planes, OrientationGraph::mutual_knn, options), InvalidInputError);
}

}  // namespace
}  // namespace recon
