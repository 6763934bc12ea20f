#include "recon/riemannian_graph.h"

#include "recon/emst.h"
#include "recon/errors.h"
#include "recon/shapes.h"

#include <gtest/gtest.h>

#include <algorithm>

namespace recon {
namespace {

// Oracle: the same graph through the plain edge list and make_graph:
// symmetric pairs of phase I's neighbourhoods plus the EMST of the samples
// (computed without hints), less the pairs the header's gap rule removes
// (long, and leaving the surface).
TEST(RiemannianGraph, EqualsTheSymmetricKnnGraphPlusEmst) {
  const PointCloud cloud = make_torus()->sample(3000, 41);
  TangentPlaneOptions options;
  options.k = 12;
  const auto planes = estimate_tangent_planes<3>(cloud.positions, options);
  const auto rg = build_riemannian_graph<3>(planes);
  ASSERT_EQ(rg.gap_emst_edges, 0u);
  ASSERT_EQ(rg.components.sizes.size(), 1u);

  const KdTree<3> tree(cloud.positions);
  std::vector<Edge> edges;
  auto gap = [&](std::uint32_t i, std::uint32_t j) {
    const Vec3 d = planes.origins[j] - planes.origins[i];
    if (d.norm() <= 1.5 * static_cast<double>(std::max(planes.local_gap[i], planes.local_gap[j]))) return false;
    return std::max(std::abs(d.normalized().dot(planes.normals[i])), std::abs(d.normalized().dot(planes.normals[j]))) >
           0.25;
  };
  std::size_t gaps = 0;
  for (std::uint32_t i = 0; i < planes.origins.size(); ++i)
    for (const std::uint32_t j : planes.neighbors.row(i)) {
      if (j == i) continue;
      if (gap(i, j)) {
        ++gaps;
        continue;
      }
      edges.push_back({i, j, 0.0});
    }
  std::printf("k-NN pairs left out as gaps: %zu of %zu\n", gaps, edges.size() + gaps);
  for (const Edge& e : euclidean_minimum_spanning_tree<3>(tree, cloud.positions)) edges.push_back({e.u, e.v, 0.0});
  const Graph expected = make_graph(planes.origins.size(), edges);

  EXPECT_EQ(rg.graph.offsets, expected.offsets);
  Graph sorted = rg.graph;  // same neighbours, in whatever order the rows keep them
  for (std::size_t v = 0; v < sorted.vertex_count(); ++v)
    std::sort(sorted.targets.begin() + static_cast<std::ptrdiff_t>(sorted.offsets[v]),
              sorted.targets.begin() + static_cast<std::ptrdiff_t>(sorted.offsets[v + 1]));
  EXPECT_EQ(sorted.targets, expected.targets);
  EXPECT_TRUE(rg.graph.weights.empty());  // costs come from the normals
  // The pieces, found from the EMST and the k-NN marks, are the graph's components.
  const Components walked = connected_components(rg.graph);
  EXPECT_EQ(rg.components.label, walked.label);
  EXPECT_EQ(rg.components.sizes, walked.sizes);

  // A smaller k takes the first k of each neighbourhood.
  RiemannianGraphOptions smaller;
  smaller.k = 6;
  const auto rg6 = build_riemannian_graph<3>(planes, smaller);
  EXPECT_LT(rg6.graph.edge_count(), rg.graph.edge_count());
  for (std::uint32_t i = 0; i < planes.origins.size(); ++i)
    for (const std::uint32_t j : planes.neighbors.row(i).first(6)) {
      if (j == i || gap(i, j)) continue;
      const auto row = rg6.graph.neighbors(i);
      EXPECT_NE(std::find(row.begin(), row.end(), j), row.end()) << i << " " << j;
    }
  smaller.k = 13;
  EXPECT_THROW((void)build_riemannian_graph<3>(planes, smaller), InvalidInputError);
}

TEST(RiemannianGraph, SeparatesTwoObjectsButNotRandomGaps) {
  const auto two = make_sphere_and_torus(0.3);
  const auto planes = estimate_tangent_planes<3>(two->sample(20000, 42).positions);
  const auto rg = build_riemannian_graph<3>(planes);
  EXPECT_EQ(rg.components.sizes.size(), 2u);
  EXPECT_EQ(rg.components.label, connected_components(rg.graph).label);
  // A random sample of one sphere has gaps but is one object.
  const auto one = estimate_tangent_planes<3>(make_sphere()->sample(50000, 43).positions);
  const auto rg_one = build_riemannian_graph<3>(one);
  EXPECT_EQ(rg_one.components.sizes.size(), 1u);
  std::printf("sphere: %zu EMST edges are gaps\n", rg_one.gap_emst_edges);
  EXPECT_EQ(rg_one.components.label, connected_components(rg_one.graph).label);
  // A box: at its creases some EMST edges count as gaps, and k-NN edges
  // across the crease join the faces again (the case the pieces are found
  // for without walking the graph).
  const auto box = estimate_tangent_planes<3>(make_box()->sample(20000, 44).positions);
  const auto rg_box = build_riemannian_graph<3>(box);
  std::printf("box: %zu EMST edges are gaps, %zu pieces rejoined\n", rg_box.gap_emst_edges, rg_box.rejoined);
  EXPECT_EQ(rg_box.components.sizes.size(), 1u);
  EXPECT_EQ(rg_box.components.label, connected_components(rg_box.graph).label);
}

}  // namespace
}  // namespace recon
