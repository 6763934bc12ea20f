#include "recon/alternatives/boruvka.h"

#include "random_graphs.h"
#include "recon/alternatives/kruskal.h"
#include "recon/core/errors.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace recon {
namespace {

using testing::random_edges;

std::vector<Edge> sorted_by_order(std::vector<Edge> edges) {
  std::sort(edges.begin(), edges.end(), lighter);
  return edges;
}

// Under the strict order the forest is unique: Borůvka keeps Kruskal's very
// edges, on graphs full of ties, repeats, self-loops and components.
TEST(Boruvka, SameEdgesAsKruskalOnRandomGraphs) {
  for (std::uint32_t seed = 1; seed <= 40; ++seed) {
    const auto [n, edges] = random_edges(seed);
    const Graph g = make_graph(n, edges);
    const MinimumSpanningEdges expected = kruskal_minimum_spanning_forest(n, edges);
    const MinimumSpanningEdges forest = boruvka_minimum_spanning_forest(n, edges);
    EXPECT_EQ(sorted_by_order(forest.edges), expected.edges) << "seed " << seed;
    EXPECT_EQ(forest.total_weight, expected.total_weight);
    EXPECT_EQ(forest.edges.size(), n - connected_components(g).sizes.size());
    EXPECT_EQ(boruvka_minimum_spanning_forest(g).edges, forest.edges);
    EXPECT_EQ(boruvka_minimum_spanning_forest(g, [&](std::uint32_t, std::uint64_t e) { return g.weights[e]; }).edges,
              forest.edges);
    // The trees with a way out at least halve each round; a union per edge;
    // a find per vertex a round, and one more pass to see nothing is left.
    EXPECT_LE(static_cast<double>(forest.counts.rounds), std::ceil(std::log2(static_cast<double>(n))));
    EXPECT_EQ(forest.counts.unions, forest.edges.size());
    EXPECT_GE(forest.counts.finds, n * (forest.counts.rounds + 1));
  }
}

// Equal weights everywhere: only the order's tie-break keeps the picks of
// a round from closing a cycle (each vertex of a ring has two equal ways out).
TEST(Boruvka, RingOfEqualEdgesIsAPath) {
  std::vector<Edge> ring;
  const std::uint32_t n = 64;
  for (std::uint32_t i = 0; i < n; ++i) ring.push_back({i, (i + 1) % n, 1.0});
  const MinimumSpanningEdges forest = boruvka_minimum_spanning_forest(n, ring);
  ASSERT_EQ(forest.edges.size(), n - 1);
  EXPECT_EQ(sorted_by_order(forest.edges), kruskal_minimum_spanning_forest(n, ring).edges);
  EXPECT_EQ(forest.total_weight, n - 1.0);
}

TEST(Boruvka, NeverTakesAnInfiniteEdge) {
  constexpr double infinite = std::numeric_limits<double>::infinity();
  const std::vector<Edge> edges = {{0, 1, 1.0}, {1, 2, infinite}, {2, 3, infinite}, {3, 4, 1.0}, {1, 4, 100.0}};
  const MinimumSpanningEdges forest = boruvka_minimum_spanning_forest(5, edges);
  EXPECT_EQ(sorted_by_order(forest.edges), (std::vector<Edge>{{0, 1, 1.0}, {3, 4, 1.0}, {1, 4, 100.0}}));
  EXPECT_EQ(forest.total_weight, 102.0);
  EXPECT_EQ(forest.counts.rounds, 2u);  // {0,1} and {3,4} first, then the two pairs
}

TEST(Boruvka, EmptyAndEdgeless) {
  EXPECT_TRUE(boruvka_minimum_spanning_forest(0, {}).edges.empty());
  const MinimumSpanningEdges lone = boruvka_minimum_spanning_forest(3, {{2, 2, 1.0}});
  EXPECT_TRUE(lone.edges.empty());
  EXPECT_EQ(lone.counts.rounds, 0u);
}

TEST(Boruvka, ThrowsOnBadInput) {
  testing::expect_bad_input_refused([](const auto&... input) { return boruvka_minimum_spanning_forest(input...); },
                                    {3, 1, 1.0});
}

}  // namespace
}  // namespace recon
