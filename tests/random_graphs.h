#pragma once
// Seeded random edge lists for the minimum spanning tree tests, made to be
// hard on them: few distinct weights (many ties), repeated edges with other
// weights, self-loops, and several components (edges only join vertices of
// one group, and sparse lists leave vertices alone). And the bad input
// every edge-list algorithm must refuse.

#include "recon/core/errors.h"
#include "recon/structures/graph.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <random>
#include <vector>

namespace recon::testing {

/// `forest(vertex_count, edges)` and `forest(graph)` must throw
/// InvalidInputError on an endpoint not below the vertex count (`outside`),
/// on a NaN weight, and on a graph without stored weights.
template <class Forest>
void expect_bad_input_refused(Forest&& forest, Edge outside) {
  EXPECT_THROW((void)forest(std::size_t{2}, std::vector<Edge>{outside}), InvalidInputError);
  EXPECT_THROW((void)forest(std::size_t{2}, std::vector<Edge>{{0, 1, std::numeric_limits<double>::quiet_NaN()}}),
               InvalidInputError);
  Graph unweighted = make_graph(2, std::vector<Edge>{{0, 1, 1.0}});
  unweighted.weights.clear();
  EXPECT_THROW((void)forest(unweighted), InvalidInputError);
}

struct RandomEdges {
  std::size_t vertex_count = 0;
  std::vector<Edge> edges;
};

/// Up to max_vertices vertices (at least 2); weights are small integers, so
/// every total is exact whatever the order of its sum.
inline RandomEdges random_edges(std::uint32_t seed, std::size_t max_vertices = 300) {
  std::mt19937 rng(seed);
  auto below = [&rng](std::size_t k) { return static_cast<std::uint32_t>(rng() % k); };
  RandomEdges g;
  g.vertex_count = 2 + below(max_vertices - 1);
  const std::uint32_t groups = 1 + below(4);
  const std::size_t m = below(4 * g.vertex_count);
  for (std::size_t e = 0; e < m; ++e) {
    const std::uint32_t u = below(g.vertex_count);
    std::uint32_t v = below(g.vertex_count);
    v = v - v % groups + u % groups;  // in u's group: the same remainder
    if (v >= g.vertex_count) v = u;   // a self-loop
    g.edges.push_back({u, v, static_cast<double>(below(20))});
  }
  return g;
}

}  // namespace recon::testing
