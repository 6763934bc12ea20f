#include "recon/minimum_spanning_tree.h"

#include "recon/complete_graph_mst.h"
#include "recon/emst.h"
#include "recon/errors.h"
#include "recon/kruskal.h"
#include "recon/riemannian_graph.h"
#include "recon/shapes.h"
#include "random_graphs.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>

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

TEST(Graph, MergesRepeatedEdgesKeepingTheLightest) {
  const std::vector<Edge> edges = {{0, 1, 3.0}, {1, 0, 2.0}, {1, 1, 0.5}, {1, 2, 1.0}};
  const Graph g = make_graph(3, edges);
  EXPECT_EQ(g.edge_count(), 2u);
  ASSERT_EQ(g.neighbors(1).size(), 2u);
  EXPECT_EQ(g.neighbors(1)[0], 0u);
  EXPECT_EQ(g.neighbor_weights(1)[0], 2.0);
  EXPECT_EQ(g.neighbor_weights(0)[0], 2.0);
}

// Oracle for the EMST: Prim on the complete graph, O(n^2), with the same
// (length, smaller end, larger end) edge order (complete_graph_mst.h).
template <int D>
std::vector<Edge> brute_force_emst(const std::vector<Vec<D>>& pts) {
  return complete_graph_minimum_spanning_tree<D>(pts).edges;
}

// The same edge set (endpoints and lengths), whatever the order.
void expect_same_edges(std::vector<Edge> got, std::vector<Edge> expected) {
  ASSERT_EQ(got.size(), expected.size());
  auto by_ends = [](const Edge& a, const Edge& b) { return std::tie(a.u, a.v) < std::tie(b.u, b.v); };
  std::sort(got.begin(), got.end(), by_ends);
  std::sort(expected.begin(), expected.end(), by_ends);
  for (std::size_t e = 0; e < got.size(); ++e) {
    ASSERT_EQ(got[e].u, expected[e].u) << "edge " << e;
    ASSERT_EQ(got[e].v, expected[e].v) << "edge " << e;
    ASSERT_DOUBLE_EQ(got[e].weight, expected[e].weight) << "edge " << e;
  }
}

template <int D>
void check_emst(std::size_t n, std::uint32_t seed, bool clustered, bool with_knn) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Vec<D>> pts(n);
  for (auto& p : pts) {
    for (int a = 0; a < D; ++a) p[a] = unit(rng);
    if (clustered) p = (p * 0.05).eval() + Vec<D>::Constant(static_cast<double>(rng() % 4));
  }
  if (n > 10) pts[n - 1] = pts[n / 2];  // an exact duplicate
  const KdTree<D> tree(pts, {4});
  const KnnTable knn = tree.all_knn(static_cast<int>(std::min<std::size_t>(6, n)));
  const auto got =
      with_knn ? euclidean_minimum_spanning_tree<D>(tree, pts, knn) : euclidean_minimum_spanning_tree<D>(tree, pts);
  ASSERT_EQ(got.size(), n - 1);
  expect_same_edges(got, brute_force_emst<D>(pts));
}

TEST(EuclideanMst, EqualsBruteForceMst3D) {
  for (std::size_t n : {2u, 3u, 50u, 500u, 3000u}) {
    check_emst<3>(n, static_cast<std::uint32_t>(n), false, true);
    check_emst<3>(n, static_cast<std::uint32_t>(n + 1), true, true);
  }
  check_emst<3>(800, 99, true, false);  // without the k-NN shortcut
}

TEST(EuclideanMst, EqualsBruteForceMst2D) {
  for (std::size_t n : {2u, 40u, 2000u}) check_emst<2>(n, static_cast<std::uint32_t>(n + 7), false, true);
}

// Phase II's EMST is hinted by phase I's neighbourhoods, kept as indices
// with float radii: still exact, with noise, lone outliers and duplicates.
TEST(EuclideanMst, RiemannianGraphEmstEqualsBruteForce) {
  for (const std::uint32_t seed : {5u, 6u}) {
    PointCloud cloud = make_torus()->sample(2500, seed);
    std::mt19937 rng(seed);
    std::normal_distribution<double> noise(0.0, 0.01);
    for (Vec3& p : cloud.positions) p += Vec3(noise(rng), noise(rng), noise(rng));
    cloud.positions[7] = Vec3(3.0, 0.0, 0.0);  // lone outliers
    cloud.positions[8] = Vec3(0.0, 0.0, 0.9);
    cloud.positions[9] = cloud.positions[10];
    TangentPlaneOptions options;
    options.k = 10;
    const auto planes = estimate_tangent_planes<3>(cloud.positions, options);
    expect_same_edges(build_riemannian_graph<3>(planes).emst, brute_force_emst<3>(cloud.positions));
  }
}

TEST(EuclideanMst, GridWithManyEqualLengthsIsATree) {
  // All edges of a grid have the same length: only the tie-breaking order
  // keeps Borůvka from closing cycles.
  std::vector<Vec3> pts;
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 20; ++j) pts.emplace_back(i, j, 0.0);
  const KdTree<3> tree(pts);
  const KnnTable knn = tree.all_knn(5);
  const auto edges = euclidean_minimum_spanning_tree<3>(tree, pts, knn);
  ASSERT_EQ(edges.size(), pts.size() - 1);
  UnionFind sets(pts.size());
  for (const Edge& e : edges) {
    EXPECT_TRUE(sets.unite(e.u, e.v));
    EXPECT_DOUBLE_EQ(e.weight, 1.0);
  }
}

}  // namespace
}  // namespace recon
