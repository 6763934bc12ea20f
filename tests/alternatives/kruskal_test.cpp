#include "recon/alternatives/kruskal.h"

#include "random_graphs.h"
#include "recon/core/errors.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>
#include <vector>

namespace recon {
namespace {

using testing::random_edges;

// Oracle: every subset of the edges. A spanning forest is a subset without
// a cycle, of the largest size such a subset has; the minimum one is the
// lightest of those. Cycles are found by relabelling, as by hand.
double brute_force_forest_weight(std::size_t n, const std::vector<Edge>& edges, std::size_t* forest_edges) {
  std::size_t best_size = 0;
  double best_weight = std::numeric_limits<double>::infinity();
  for (std::uint32_t subset = 0; subset < (1u << edges.size()); ++subset) {
    std::vector<std::size_t> label(n);
    for (std::size_t i = 0; i < n; ++i) label[i] = i;
    std::size_t size = 0;
    double weight = 0.0;
    bool cycle = false;
    for (std::size_t e = 0; e < edges.size() && !cycle; ++e) {
      if (!(subset & (1u << e))) continue;
      const std::size_t from = label[edges[e].v], to = label[edges[e].u];
      cycle = from == to;
      std::replace(label.begin(), label.end(), from, to);
      ++size;
      weight += edges[e].weight;
    }
    if (cycle) continue;
    if (size > best_size || (size == best_size && weight < best_weight)) {
      best_size = size;
      best_weight = weight;
    }
  }
  *forest_edges = best_size;
  return best_size == 0 ? 0.0 : best_weight;
}

TEST(Kruskal, EqualsBruteForceOnTinyGraphs) {
  for (std::uint32_t seed = 1; seed <= 300; ++seed) {
    std::mt19937 rng(seed);
    const std::uint32_t n = 1 + static_cast<std::uint32_t>(rng() % 6);
    std::vector<Edge> edges;
    const std::size_t m = rng() % 13;
    for (std::size_t e = 0; e < m; ++e)  // self-loops and repeats included
      edges.push_back({static_cast<std::uint32_t>(rng() % n), static_cast<std::uint32_t>(rng() % n),
                       static_cast<double>(rng() % 4)});
    std::size_t forest_edges = 0;
    const double expected = brute_force_forest_weight(n, edges, &forest_edges);
    const MinimumSpanningEdges got = kruskal_minimum_spanning_forest(n, edges);
    ASSERT_EQ(got.edges.size(), forest_edges) << "seed " << seed;
    ASSERT_EQ(got.total_weight, expected) << "seed " << seed;
  }
}

// A forest of the graph's edges, in the order taken, with the right count
// of edges; the three ways of calling agree.
TEST(Kruskal, IsASpanningForestOnRandomGraphs) {
  for (std::uint32_t seed = 1; seed <= 20; ++seed) {
    const auto [n, edges] = random_edges(seed);
    const Graph g = make_graph(n, edges);
    const MinimumSpanningEdges forest = kruskal_minimum_spanning_forest(n, edges);
    EXPECT_EQ(forest.edges.size(), n - connected_components(g).sizes.size());
    UnionFind sets(n);
    double total = 0.0;
    for (std::size_t e = 0; e < forest.edges.size(); ++e) {
      const Edge& edge = forest.edges[e];
      EXPECT_LT(edge.u, edge.v);
      EXPECT_TRUE(sets.unite(edge.u, edge.v)) << "a cycle";
      const auto nb = g.neighbors(edge.u);
      const auto at = std::find(nb.begin(), nb.end(), edge.v);
      ASSERT_TRUE(at != nb.end());
      EXPECT_EQ(g.neighbor_weights(edge.u)[static_cast<std::size_t>(at - nb.begin())], edge.weight)
          << "a repeated edge is taken at its lightest";
      if (e > 0) {
        EXPECT_TRUE(lighter(forest.edges[e - 1], edge));
      }
      total += edge.weight;
    }
    EXPECT_EQ(forest.total_weight, total);
    EXPECT_EQ(kruskal_minimum_spanning_forest(g).edges, forest.edges);
    EXPECT_EQ(kruskal_minimum_spanning_forest(g, [&](std::uint32_t, std::uint64_t e) { return g.weights[e]; }).edges,
              forest.edges);
    // Two finds per edge that may be taken (repeats too: self-loops not), a
    // union per edge kept.
    const auto loops =
        static_cast<std::size_t>(std::count_if(edges.begin(), edges.end(), [](const Edge& e) { return e.u == e.v; }));
    EXPECT_EQ(forest.counts.finds, 2 * (edges.size() - loops));
    EXPECT_EQ(forest.counts.unions, forest.edges.size());
    if (edges.size() - loops > 1) {
      EXPECT_GT(forest.counts.comparisons, 0u);
    }
  }
}

TEST(Kruskal, NeverTakesAnInfiniteEdge) {
  constexpr double infinite = std::numeric_limits<double>::infinity();
  const std::vector<Edge> edges = {{0, 1, 1.0}, {1, 2, infinite}, {2, 3, infinite}, {3, 4, 1.0}, {1, 4, 100.0}};
  const MinimumSpanningEdges forest = kruskal_minimum_spanning_forest(5, edges);
  EXPECT_EQ(forest.edges, (std::vector<Edge>{{0, 1, 1.0}, {3, 4, 1.0}, {1, 4, 100.0}}));
  EXPECT_EQ(forest.total_weight, 102.0);
}

TEST(Kruskal, TiesGoToTheSmallerEndpoints) {
  // A square of equal edges: the one left out is the last in the order.
  const std::vector<Edge> edges = {{3, 0, 1.0}, {2, 3, 1.0}, {1, 2, 1.0}, {0, 1, 1.0}};
  const MinimumSpanningEdges forest = kruskal_minimum_spanning_forest(4, edges);
  EXPECT_EQ(forest.edges, (std::vector<Edge>{{0, 1, 1.0}, {0, 3, 1.0}, {1, 2, 1.0}}));
}

TEST(Kruskal, EmptyAndEdgeless) {
  EXPECT_TRUE(kruskal_minimum_spanning_forest(0, {}).edges.empty());
  const MinimumSpanningEdges lone = kruskal_minimum_spanning_forest(3, {{1, 1, 5.0}});
  EXPECT_TRUE(lone.edges.empty());
  EXPECT_EQ(lone.total_weight, 0.0);
}

TEST(Kruskal, ThrowsOnBadInput) {
  testing::expect_bad_input_refused([](const auto&... input) { return kruskal_minimum_spanning_forest(input...); },
                                    {0, 2, 1.0});
}

}  // namespace
}  // namespace recon
