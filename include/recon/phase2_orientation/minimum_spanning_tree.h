#pragma once
// Prim's minimum spanning tree (forest) on a CSR graph, driven by an indexed
// priority queue with decrease-key: by default our binary heap.
//
// Prim grows one tree from a root: the heap holds every vertex adjacent to
// the tree, keyed by its cheapest edge into the tree; popping the smallest
// adds that vertex and edge, and its neighbours' keys are lowered. A vertex
// leaves the heap only after its parent did, so `order` lists the vertices
// parents-first: walking it is a traversal of the tree from the root with
// no recursion.
//
// As in the textbook, each vertex also has its key in an array of its own:
// +infinity until an edge reaches it, -infinity once it is in the tree. One
// comparison against that array decides an edge (is it a cheaper way into
// the tree for a vertex outside it?), where asking "in the tree?" and then
// "cheaper than its key in the heap?" took two hard-to-predict branches per
// edge: on phase II's graph of a million points (21 edge ends a vertex, one
// in four of them lowering a key) Prim took 9 % less time.
//
// The queue is a template parameter, so that the alternatives lab can run
// this very loop on another heap, or on one that counts its work. A queue
// is any DecreaseKeyQueue<double> (indexed_heap.h): Queue(capacity), empty(),
// top_key(), pop(), push(item, key), decrease_key(item, key); every
// IndexedMinHeap is one. When
// it also has a `counts()` member returning OperationCounts (as
// counting_queue.h's CountingQueue does), the forest's `counts` is a copy of
// them after the run; with any other queue, the default one included,
// nothing is counted and the forest's counts stay 0.
//
// The other minimum spanning trees of the course, each a pair of its own:
//   kruskal.h            sort the edges, keep those that join two sets
//   boruvka.h            rounds: every component takes its cheapest way out
//   complete_graph_mst.h Prim with an array instead of a heap, on the
//                        complete Euclidean graph of a point set, O(n^2)
//   emst.h               Borůvka on the same complete graph, with kd-tree
//                        queries: the one phase II uses
// They return MinimumSpanningEdges (below).

#include "recon/core/errors.h"
#include "recon/core/interruption.h"
#include "recon/core/operation_counts.h"
#include "recon/core/progress.h"
#include "recon/structures/binary_heap.h"
#include "recon/structures/graph.h"
#include "recon/structures/indexed_heap.h"

#include <concepts>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace recon {

struct SpanningForest {
  static constexpr std::uint32_t no_parent = UINT32_MAX;
  std::vector<std::uint32_t> parent;  ///< per vertex; no_parent for roots
  std::vector<std::uint32_t> order;   ///< every vertex, parents before children
  std::vector<std::uint32_t> roots;   ///< one per tree, in the order grown
  double total_weight = 0.0;
  OperationCounts counts;  ///< the queue's, when it counts (see above); else all 0
};

/// A minimum spanning forest as a list of edges: what Kruskal, Borůvka and
/// complete-graph Prim return.
struct MinimumSpanningEdges {
  std::vector<Edge> edges;    ///< u < v, weight as given; in the order each algorithm takes them
  double total_weight = 0.0;  ///< the sum of the edges' weights
  OperationCounts counts;     ///< which counters apply is said by each algorithm's header
};

/// The strict total order in which Kruskal and Borůvka take edges (and
/// complete-graph Prim and the EMST compare them): by weight, then smaller
/// endpoint, then larger endpoint. Under it no two edges tie, so the minimum
/// spanning forest is unique.
/// Cost: O(1).
/// Throws: nothing.
/// Pre: u < v in both edges; no NaN weight.
[[nodiscard]] inline bool lighter(const Edge& a, const Edge& b) {
  if (a.weight != b.weight) return a.weight < b.weight;
  if (a.u != b.u) return a.u < b.u;
  return a.v < b.v;
}

/// The edges of a list that a spanning forest may take, where Kruskal and
/// Borůvka start: each turned to have u < v; self-loops and edges of weight
/// +infinity left out (as Prim never takes them).
/// Cost: O(E).
/// Throws: InvalidInputError, its message starting with `algorithm`, for an endpoint not below
/// vertex_count or a NaN weight (NaN has no place in the order).
/// Pre: none.
[[nodiscard]] std::vector<Edge> spanning_forest_candidates(std::size_t vertex_count, std::vector<Edge> edges,
                                                           std::string_view algorithm);

/// A queue that reports its work (counting_queue.h's CountingQueue does).
template <class Queue>
concept counts_operations = requires(const Queue& queue) {
  { queue.counts() } -> std::convertible_to<OperationCounts>;
};

/// Minimum spanning forest. Trees are grown from `roots` first, in the given
/// order (a root already reached by an earlier tree is skipped); vertices left
/// unreached then start trees of their own, smallest index first.
/// Ties between equal weights go to the smaller vertex index, so the forest
/// is deterministic. `weight(v, e)` gives the weight of the edge at CSR
/// position e of row v (graph.targets[e] is its other end); an edge of
/// infinite weight is never taken.
/// `Queue`: see the header comment; prim_minimum_spanning_forest<MyQueue>(
/// graph, roots, weight) runs on MyQueue.
/// Cost: O(E log V) with a binary heap (O(E + V log V) with a Fibonacci heap), E calls of `weight`.
/// Throws: what `weight`, the queue or an interruption check (every 65536 vertices) throws; nothing else.
/// Pre: no weight is NaN; every root < V.
template <DecreaseKeyQueue<double> Queue = IndexedBinaryHeap<double>, class Weight>
[[nodiscard]] SpanningForest prim_minimum_spanning_forest(const Graph& graph, std::span<const std::uint32_t> roots,
                                                          Weight&& weight) {
  const std::size_t n = graph.vertex_count();
  SpanningForest forest;
  forest.parent.assign(n, SpanningForest::no_parent);
  forest.order.reserve(n);
  constexpr double unreached = std::numeric_limits<double>::infinity();
  constexpr double in_tree = -std::numeric_limits<double>::infinity();
  std::vector<double> key(n, unreached);
  Queue heap(n);

  // (Raw pointers: the inner loop runs once per edge end, 21 million times
  // at a million points, and the compiler cannot keep vectors' data in
  // registers across the heap's calls.)
  const std::uint64_t* const offsets = graph.offsets.data();
  const std::uint32_t* const targets = graph.targets.data();
  double* const key_of = key.data();
  std::uint32_t* const parent = forest.parent.data();

  auto grow = [&](std::uint32_t root) {
    if (key_of[root] == in_tree) return;
    forest.roots.push_back(root);
    heap.push(root, 0.0);
    while (!heap.empty()) {
      const double w = heap.top_key();
      const std::uint32_t v = heap.pop();
      key_of[v] = in_tree;
      forest.order.push_back(v);
      if ((forest.order.size() & 0xffff) == 0) {  // a caller may stop a long run here, or follow it
        interruption_point();
        if (ProgressCounter* progress = progress_counter()) progress->advance(0x10000);
      }
      if (parent[v] != SpanningForest::no_parent) forest.total_weight += w;
      for (std::uint64_t e = offsets[v]; e < offsets[v + 1]; ++e) {
        const std::uint32_t u = targets[e];
        const double c = weight(v, e);
        if (!(c < key_of[u])) continue;  // u is in the tree, or has a key no larger
        if (key_of[u] == unreached) {
          heap.push(u, c);
        } else {
          heap.decrease_key(u, c);
        }
        key_of[u] = c;
        parent[u] = v;
      }
    }
  };
  for (std::uint32_t r : roots) grow(r);
  for (std::uint32_t v = 0; v < n; ++v) grow(v);
  if constexpr (counts_operations<Queue>) forest.counts = heap.counts();
  return forest;
}

/// The same with the graph's stored weights.
/// Cost: O(E log V).
/// Throws: InvalidInputError when the graph has no stored weights; what an interruption check throws.
/// Pre: no weight is NaN; every root < V.
[[nodiscard]] SpanningForest prim_minimum_spanning_forest(const Graph& graph,
                                                          std::span<const std::uint32_t> roots = {});

/// The graph's stored weights as a weight function (weight(v, e) =
/// graph.weights[e]), for the algorithms' stored-weight forms.
/// Cost: O(1).
/// Throws: InvalidInputError, its message starting with `algorithm`, when the graph has none.
/// Pre: `graph` outlives the function returned.
[[nodiscard]] inline auto stored_weights(const Graph& graph, std::string_view algorithm) {
  if (graph.weights.size() != graph.targets.size())
    throw InvalidInputError(std::string(algorithm) + ": the graph has no stored weights; pass a weight function");
  return [&graph](std::uint32_t, std::uint64_t e) { return graph.weights[e]; };
}

/// The same on another queue: prim_minimum_spanning_forest<MyQueue>(graph).
/// Cost, throws and preconditions as the stored-weight form above, with MyQueue's costs.
template <DecreaseKeyQueue<double> Queue>
[[nodiscard]] SpanningForest prim_minimum_spanning_forest(const Graph& graph,
                                                          std::span<const std::uint32_t> roots = {}) {
  return prim_minimum_spanning_forest<Queue>(graph, roots, stored_weights(graph, "Prim"));
}

}  // namespace recon
