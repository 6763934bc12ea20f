// Graphs in CSR form (graph.h): building from edge lists, adding edges,
// listing them back, connected components.

#include "recon/structures/graph.h"

#include "random_graphs.h"
#include "recon/core/errors.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <utility>
#include <vector>

namespace recon {
namespace {

using testing::random_edges;

// Oracle: the edge list as a map {min end, max end} -> lightest weight,
// self-loops left out.
std::map<std::pair<std::uint32_t, std::uint32_t>, double> edge_map(const std::vector<Edge>& edges) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, double> map;
  for (const Edge& e : edges) {
    if (e.u == e.v) continue;
    const auto key = std::minmax(e.u, e.v);
    const auto [it, added] = map.try_emplace(key, e.weight);
    if (!added) it->second = std::min(it->second, e.weight);
  }
  return map;
}

// Every row sorted by target, every edge stored in both rows with one
// weight, and the graph's edges exactly those of `expected`.
void expect_graph_of(const Graph& g, std::size_t n, const std::vector<Edge>& expected) {
  ASSERT_EQ(g.vertex_count(), n);
  ASSERT_EQ(g.offsets.size(), n + 1);
  ASSERT_EQ(g.weights.size(), g.targets.size());
  const auto map = edge_map(expected);
  EXPECT_EQ(g.edge_count(), map.size());
  for (std::uint32_t v = 0; v < n; ++v) {
    const auto row = g.neighbors(v);
    EXPECT_TRUE(std::is_sorted(row.begin(), row.end())) << "row " << v;
    EXPECT_TRUE(std::adjacent_find(row.begin(), row.end()) == row.end()) << "a repeated target in row " << v;
    for (std::size_t e = 0; e < row.size(); ++e) {
      const auto it = map.find(std::minmax(v, row[e]));
      ASSERT_TRUE(it != map.end()) << v << " - " << row[e] << " is no edge";
      EXPECT_EQ(g.neighbor_weights(v)[e], it->second);
    }
  }
}

TEST(Graph, MergesRepeatedEdgesKeepingTheLightest) {
  const std::vector<Edge> edges = {{0, 1, 3.0}, {1, 0, 2.0}, {1, 1, 0.5}, {1, 2, 1.0}};
  const Graph g = make_graph(3, edges);
  EXPECT_EQ(g.edge_count(), 2u);
  ASSERT_EQ(g.neighbors(1).size(), 2u);
  EXPECT_EQ(g.neighbors(1)[0], 0u);
  EXPECT_EQ(g.neighbor_weights(1)[0], 2.0);
  EXPECT_EQ(g.neighbor_weights(0)[0], 2.0);
}

TEST(Graph, MakeGraphHoldsExactlyTheEdgesOnRandomGraphs) {
  for (std::uint32_t seed = 1; seed <= 20; ++seed) {
    const auto [n, edges] = random_edges(seed);  // repeats, self-loops, isolated vertices
    expect_graph_of(make_graph(n, edges), n, edges);
  }
}

TEST(Graph, WithEdgesAddsToTheGraph) {
  for (std::uint32_t seed = 1; seed <= 10; ++seed) {
    const auto [n, edges] = random_edges(seed);
    const std::size_t half = edges.size() / 2;
    const std::vector<Edge> first(edges.begin(), edges.begin() + static_cast<std::ptrdiff_t>(half));
    const std::vector<Edge> second(edges.begin() + static_cast<std::ptrdiff_t>(half), edges.end());
    const Graph g = with_edges(make_graph(n, first), second);
    expect_graph_of(g, n, edges);
  }
  // Without stored weights, the result has none either.
  Graph unweighted = make_graph(3, std::vector<Edge>{{0, 1, 1.0}});
  unweighted.weights.clear();
  const Graph more = with_edges(unweighted, std::vector<Edge>{{1, 2, 5.0}, {0, 1, 0.5}});
  EXPECT_TRUE(more.weights.empty());
  EXPECT_EQ(more.edge_count(), 2u);
  EXPECT_EQ(std::vector<std::uint32_t>(more.neighbors(1).begin(), more.neighbors(1).end()),
            (std::vector<std::uint32_t>{0, 2}));
}

TEST(Graph, EdgeListListsEveryEdgeOnceInRowOrder) {
  const auto [n, edges] = random_edges(4);
  const Graph g = make_graph(n, edges);
  const std::vector<Edge> listed = edge_list(g, [&g](std::uint32_t, std::uint64_t e) { return g.weights[e]; });
  ASSERT_EQ(listed.size(), g.edge_count());
  for (std::size_t e = 0; e < listed.size(); ++e) {
    EXPECT_LT(listed[e].u, listed[e].v);
    if (e > 0) {
      EXPECT_TRUE(std::pair(listed[e - 1].u, listed[e - 1].v) < std::pair(listed[e].u, listed[e].v));
    }
  }
  expect_graph_of(make_graph(n, listed), n, edges);  // the same graph again
}

TEST(Graph, RefusesAnEndpointOutOfRange) {
  EXPECT_THROW((void)make_graph(3, std::vector<Edge>{{0, 3, 1.0}}), InvalidInputError);
  const Graph g = make_graph(3, std::vector<Edge>{{0, 1, 1.0}});
  EXPECT_THROW((void)with_edges(g, std::vector<Edge>{{4, 1, 1.0}}), InvalidInputError);
}

// Oracle: union-find over the same edges.
TEST(Graph, ConnectedComponentsMatchUnionFind) {
  for (std::uint32_t seed = 1; seed <= 20; ++seed) {
    const auto [n, edges] = random_edges(seed);
    const Components c = connected_components(make_graph(n, edges));
    UnionFind sets(n);
    for (const Edge& e : edges) sets.unite(e.u, e.v);
    ASSERT_EQ(c.label.size(), n);
    std::vector<std::uint32_t> sizes;
    for (std::uint32_t v = 0; v < n; ++v) {
      // Numbered in order of each component's smallest vertex: a vertex
      // opens the next label exactly when it is the first of its set.
      bool first = true;
      for (std::uint32_t u = 0; u < v && first; ++u) first = sets.find(u) != sets.find(v);
      if (first) {
        EXPECT_EQ(c.label[v], sizes.size()) << "vertex " << v;
        sizes.push_back(0);
      }
      ++sizes[c.label[v]];
      for (std::uint32_t u = 0; u < v; ++u) EXPECT_EQ(c.label[u] == c.label[v], sets.find(u) == sets.find(v));
    }
    EXPECT_EQ(c.sizes, sizes);
  }
}

TEST(Graph, Empty) {
  const Graph g = make_graph(0, std::vector<Edge>{});
  EXPECT_EQ(g.vertex_count(), 0u);
  EXPECT_EQ(g.edge_count(), 0u);
  EXPECT_TRUE(connected_components(g).sizes.empty());
  EXPECT_EQ(Graph{}.vertex_count(), 0u);
}

}  // namespace
}  // namespace recon
