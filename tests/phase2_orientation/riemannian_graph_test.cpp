#include "recon/phase2_orientation/riemannian_graph.h"

#include "recon/core/errors.h"
#include "recon/core/shapes.h"
#include "recon/phase2_orientation/emst.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <span>
#include <string>

namespace recon {
namespace {

// Oracle: the same graph through the plain edge list and make_graph:
// symmetric pairs of phase I's neighbourhoods plus the EMST of the samples
// (computed without hints), less the pairs the header's gap rule removes
// (long, and leaving the surface).
bool oracle_gap(const TangentPlanes<3>& planes, std::uint32_t i, std::uint32_t j) {
  const Vec3 d = planes.origins[j] - planes.origins[i];
  if (d.norm() <= 1.5 * static_cast<double>(std::max(planes.local_gap[i], planes.local_gap[j]))) return false;
  return std::max(std::abs(d.normalized().dot(planes.normals[i])), std::abs(d.normalized().dot(planes.normals[j]))) >
         0.25;
}

void expect_oracle_graph(std::span<const Vec3> positions, const TangentPlanes<3>& planes,
                         const RiemannianGraph<3>& rg) {
  const KdTree<3> tree(positions);
  std::vector<Edge> edges;
  std::size_t gaps = 0;
  for (std::uint32_t i = 0; i < planes.origins.size(); ++i)
    for (const std::uint32_t j : planes.neighbors.row(i)) {
      if (j == i) continue;
      if (oracle_gap(planes, i, j)) {
        ++gaps;
        continue;
      }
      edges.push_back({i, j, 0.0});
    }
  std::printf("k-NN pairs left out as gaps: %zu of %zu\n", gaps, edges.size() + gaps);
  for (const Edge& e : euclidean_minimum_spanning_tree<3>(tree, positions)) edges.push_back({e.u, e.v, 0.0});
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
}

TEST(RiemannianGraph, EqualsTheSymmetricKnnGraphPlusEmst) {
  const PointCloud cloud = make_torus()->sample(3000, 41);
  TangentPlaneOptions options;
  options.k = 12;
  const auto planes = estimate_tangent_planes<3>(cloud.positions, options);
  const auto rg = build_riemannian_graph<3>(planes);
  ASSERT_EQ(rg.gap_emst_edges, 0u);
  ASSERT_EQ(rg.components.sizes.size(), 1u);
  expect_oracle_graph(cloud.positions, planes, rg);
  auto gap = [&](std::uint32_t i, std::uint32_t j) { return oracle_gap(planes, i, j); };

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

// Whether x_i is in x_j's neighbourhood is mostly told by distance (the
// neighbourhood holds every sample nearer than its farthest member); on a
// grid many samples lie at exactly that distance, and copies at distance 0,
// where only the list itself can tell. The graph must still be the oracle's.
TEST(RiemannianGraph, EqualsTheOracleWhereManySamplesTieAtTheNeighbourhoodRadius) {
  std::vector<Vec3> grid;
  for (int i = 0; i < 30; ++i)
    for (int j = 0; j < 30; ++j) grid.emplace_back(0.5 * i, 0.5 * j, 0.0);
  for (std::size_t c = 0; c < 40; ++c) {  // copies of 40 grid points
    const Vec3 copy = grid[(37 * c + 11) % 900];
    grid.push_back(copy);
  }
  for (const int k : {5, 9, 13, 21}) {
    TangentPlaneOptions options;
    options.k = k;
    const auto planes = estimate_tangent_planes<3>(grid, options);
    SCOPED_TRACE("k = " + std::to_string(k));
    expect_oracle_graph(grid, planes, build_riemannian_graph<3>(planes));
  }
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
