#include "recon/riemannian_graph.h"

#include "recon/emst.h"
#include "recon/shapes.h"

#include <gtest/gtest.h>

namespace recon {
namespace {

// Oracle: the same graph through the plain edge list and make_graph:
// symmetric k-NN pairs of the origins plus the EMST, less the pairs the
// header's gap rule removes (long, and leaving the surface).
TEST(RiemannianGraph, EqualsTheSymmetricKnnGraphPlusEmst) {
  const PointCloud cloud = make_torus()->sample(3000, 41);
  TangentPlaneOptions options;
  options.k = 12;
  const auto planes = estimate_tangent_planes<3>(cloud.positions, options);
  RiemannianGraphOptions graph_options;
  graph_options.k = 12;
  const auto rg = build_riemannian_graph<3>(planes, graph_options);
  ASSERT_EQ(rg.gap_emst_edges, 0u);
  ASSERT_EQ(rg.components.sizes.size(), 1u);

  const KdTree<3> tree(planes.origins);
  const KnnTable knn = tree.all_knn(12);
  std::vector<Edge> edges;
  auto cost = [&](std::uint32_t i, std::uint32_t j) {
    return 1.0 - std::abs(planes.normals[i].dot(planes.normals[j]));
  };
  auto gap = [&](std::uint32_t i, std::uint32_t j) {
    const Vec3 d = planes.origins[j] - planes.origins[i];
    if (d.norm() <= 1.5 * std::max(planes.local_gap[i], planes.local_gap[j])) return false;
    return std::max(std::abs(d.normalized().dot(planes.normals[i])), std::abs(d.normalized().dot(planes.normals[j]))) >
           0.25;
  };
  std::size_t gaps = 0;
  for (std::uint32_t i = 0; i < planes.origins.size(); ++i)
    for (const Neighbor& nb : knn.row(i)) {
      if (nb.index == i) continue;
      if (gap(i, nb.index)) {
        ++gaps;
        continue;
      }
      edges.push_back({i, nb.index, cost(i, nb.index)});
    }
  std::printf("k-NN pairs left out as gaps: %zu of %zu\n", gaps, edges.size() + gaps);
  for (const Edge& e : euclidean_minimum_spanning_tree<3>(tree, planes.origins, &knn))
    edges.push_back({e.u, e.v, cost(e.u, e.v)});
  const Graph expected = make_graph(planes.origins.size(), edges);

  EXPECT_EQ(rg.graph.offsets, expected.offsets);
  EXPECT_EQ(rg.graph.targets, expected.targets);
  ASSERT_EQ(rg.graph.weights.size(), expected.weights.size());
  for (std::size_t e = 0; e < expected.weights.size(); ++e) EXPECT_DOUBLE_EQ(rg.graph.weights[e], expected.weights[e]);
}

TEST(RiemannianGraph, SeparatesTwoObjectsButNotRandomGaps) {
  const auto two = make_sphere_and_torus(0.3);
  const auto planes = estimate_tangent_planes<3>(two->sample(20000, 42).positions);
  const auto rg = build_riemannian_graph<3>(planes);
  EXPECT_EQ(rg.components.sizes.size(), 2u);
  // A random sample of one sphere has gaps but is one object.
  const auto one = estimate_tangent_planes<3>(make_sphere()->sample(50000, 43).positions);
  EXPECT_EQ(build_riemannian_graph<3>(one).components.sizes.size(), 1u);
}

}  // namespace
}  // namespace recon
