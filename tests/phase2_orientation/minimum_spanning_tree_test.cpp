#include "recon/phase2_orientation/minimum_spanning_tree.h"

#include "random_graphs.h"
#include "recon/alternatives/kruskal.h"
#include "recon/core/errors.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>

namespace recon {
namespace {

using testing::random_edges;

// Oracle: Kruskal (kruskal.h, itself checked against every subset of tiny
// graphs in kruskal_test.cpp).
TEST(MinimumSpanningTree, PrimEqualsKruskalOnRandomGraphs) {
  for (std::uint32_t seed = 1; seed <= 20; ++seed) {
    const auto [n, edges] = random_edges(seed);  // many ties, repeated edges, self-loops, components
    const Graph g = make_graph(n, edges);
    const SpanningForest forest = prim_minimum_spanning_forest(g);
    const MinimumSpanningEdges kruskal = kruskal_minimum_spanning_forest(n, edges);
    EXPECT_EQ(forest.total_weight, kruskal.total_weight);  // small whole numbers: exact
    // A forest: one root per component, every vertex once in the order,
    // parents before children, each tree edge a graph edge.
    EXPECT_EQ(forest.roots.size(), n - kruskal.edges.size());
    EXPECT_EQ(forest.roots.size(), connected_components(g).sizes.size());
    ASSERT_EQ(forest.order.size(), n);
    std::vector<int> position(n, -1);
    for (std::size_t i = 0; i < n; ++i) position[forest.order[i]] = static_cast<int>(i);
    for (std::uint32_t v = 0; v < n; ++v) {
      ASSERT_GE(position[v], 0);
      const std::uint32_t p = forest.parent[v];
      if (p == SpanningForest::no_parent) continue;
      EXPECT_LT(position[p], position[v]);
      const auto nb = g.neighbors(v);
      EXPECT_TRUE(std::find(nb.begin(), nb.end(), p) != nb.end());
    }
    EXPECT_EQ(forest.counts, OperationCounts{});  // the default queue counts nothing
  }
}

// A queue with the binary heap's interface that counts what Prim asks of it
// (as counting_queue.h's CountingQueue does, with comparisons too).
class TallyingQueue {
 public:
  explicit TallyingQueue(std::size_t capacity) : heap_(capacity) {}
  [[nodiscard]] bool empty() const { return heap_.empty(); }
  [[nodiscard]] double top_key() const { return heap_.top_key(); }
  void push(std::uint32_t item, double key) {
    ++counts_.pushes;
    heap_.push(item, key);
  }
  std::uint32_t pop() {
    ++counts_.pops;
    return heap_.pop();
  }
  void decrease_key(std::uint32_t item, double key) {
    ++counts_.decrease_keys;
    heap_.decrease_key(item, key);
  }
  [[nodiscard]] const OperationCounts& counts() const { return counts_; }

 private:
  IndexedBinaryHeap<double> heap_;
  OperationCounts counts_;
};

// The queue is a template parameter: the default named, or another queue,
// grows the very same forest.
TEST(MinimumSpanningTree, OtherQueuesGrowTheSameForest) {
  for (std::uint32_t seed = 1; seed <= 10; ++seed) {
    const auto [n, edges] = random_edges(seed);
    const Graph g = make_graph(n, edges);
    const std::vector<std::uint32_t> roots = {static_cast<std::uint32_t>(n / 2)};
    auto weight = [&g](std::uint32_t, std::uint64_t e) { return g.weights[e]; };
    const SpanningForest expected = prim_minimum_spanning_forest(g, roots, weight);
    const SpanningForest named = prim_minimum_spanning_forest<IndexedBinaryHeap<double>>(g, roots, weight);
    const SpanningForest tallied = prim_minimum_spanning_forest<TallyingQueue>(g, roots, weight);
    for (const SpanningForest* forest : {&named, &tallied}) {
      EXPECT_EQ(forest->parent, expected.parent);
      EXPECT_EQ(forest->order, expected.order);
      EXPECT_EQ(forest->roots, expected.roots);
      EXPECT_EQ(forest->total_weight, expected.total_weight);
    }
    EXPECT_EQ(named.counts, OperationCounts{});
    // Every vertex enters the queue once and leaves it once.
    EXPECT_EQ(tallied.counts.pushes, n);
    EXPECT_EQ(tallied.counts.pops, n);
    EXPECT_LE(tallied.counts.decrease_keys, 2 * g.edge_count());
    // With the graph's stored weights.
    const SpanningForest stored = prim_minimum_spanning_forest<TallyingQueue>(g, roots);
    EXPECT_EQ(stored.parent, expected.parent);
    EXPECT_EQ(stored.counts, tallied.counts);
  }
  Graph unweighted = make_graph(2, std::vector<Edge>{{0, 1, 1.0}});
  unweighted.weights.clear();
  EXPECT_THROW((void)prim_minimum_spanning_forest<TallyingQueue>(unweighted), InvalidInputError);
}

TEST(MinimumSpanningTree, GrowsFromTheGivenRoots) {
  const std::vector<Edge> edges = {{0, 1, 1.0}, {1, 2, 1.0}, {3, 4, 2.0}};
  const Graph g = make_graph(5, edges);
  const std::vector<std::uint32_t> roots = {2, 4};
  const SpanningForest forest = prim_minimum_spanning_forest(g, roots);
  EXPECT_EQ(forest.roots, roots);
  EXPECT_EQ(forest.parent[2], SpanningForest::no_parent);
  EXPECT_EQ(forest.parent[1], 2u);
  EXPECT_EQ(forest.parent[0], 1u);
  EXPECT_EQ(forest.parent[3], 4u);
}

TEST(MinimumSpanningTree, NeverTakesAnInfiniteEdge) {
  // 0 - 1 cheap, 1 - 2 and 2 - 3 infinite, 3 - 4 cheap; 1 - 4 finite but
  // dear: it is the only way from {0, 1} to {3, 4}, and 2 is reached by none.
  constexpr double infinite = std::numeric_limits<double>::infinity();
  const std::vector<Edge> edges = {{0, 1, 1.0}, {1, 2, infinite}, {2, 3, infinite}, {3, 4, 1.0}, {1, 4, 100.0}};
  const Graph g = make_graph(5, edges);
  const SpanningForest forest = prim_minimum_spanning_forest(g);
  EXPECT_EQ(forest.roots, (std::vector<std::uint32_t>{0, 2}));
  EXPECT_EQ(forest.parent[2], SpanningForest::no_parent);
  EXPECT_EQ(forest.parent[4], 1u);
  EXPECT_EQ(forest.parent[3], 4u);
  EXPECT_DOUBLE_EQ(forest.total_weight, 102.0);
}

}  // namespace
}  // namespace recon
