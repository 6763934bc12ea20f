#pragma once
// Prim's minimum spanning tree (forest) on a CSR graph, driven by our
// indexed binary heap with decrease-key.
//
// Prim grows one tree from a root: the heap holds every vertex adjacent to
// the tree, keyed by its cheapest edge into the tree; popping the smallest
// adds that vertex and edge, and its neighbours' keys are lowered. A vertex
// leaves the heap only after its parent did, so `order` lists the vertices
// parents-first: walking it is a traversal of the tree from the root with
// no recursion. Cost O(E log V).

#include "recon/binary_heap.h"
#include "recon/graph.h"

#include <cstdint>
#include <span>
#include <vector>

namespace recon {

struct SpanningForest {
  static constexpr std::uint32_t no_parent = UINT32_MAX;
  std::vector<std::uint32_t> parent;  ///< per vertex; no_parent for roots
  std::vector<std::uint32_t> order;   ///< every vertex, parents before children
  std::vector<std::uint32_t> roots;   ///< one per tree, in the order grown
  double total_weight = 0.0;
};

/// Minimum spanning forest. Trees are grown from `roots` first, in the given
/// order (a root already reached by an earlier tree is skipped); vertices left
/// unreached then start trees of their own, smallest index first.
/// Ties between equal weights go to the smaller vertex index, so the forest
/// is deterministic. `weight(v, e)` gives the weight of the edge at CSR
/// position e of row v (graph.targets[e] is its other end).
template <class Weight>
[[nodiscard]] SpanningForest prim_minimum_spanning_forest(const Graph& graph, std::span<const std::uint32_t> roots,
                                                          Weight&& weight) {
  const std::size_t n = graph.vertex_count();
  SpanningForest forest;
  forest.parent.assign(n, SpanningForest::no_parent);
  forest.order.reserve(n);
  std::vector<std::uint8_t> in_tree(n, 0);
  IndexedBinaryHeap<double> heap(n);

  auto grow = [&](std::uint32_t root) {
    if (in_tree[root]) return;
    forest.roots.push_back(root);
    heap.push(root, 0.0);
    while (!heap.empty()) {
      const double w = heap.top_key();
      const std::uint32_t v = heap.pop();
      in_tree[v] = 1;
      forest.order.push_back(v);
      if (forest.parent[v] != SpanningForest::no_parent) forest.total_weight += w;
      for (std::uint64_t e = graph.offsets[v]; e < graph.offsets[v + 1]; ++e) {
        const std::uint32_t u = graph.targets[e];
        if (!in_tree[u] && heap.push_or_decrease(u, weight(v, e))) forest.parent[u] = v;
      }
    }
  };
  for (std::uint32_t r : roots) grow(r);
  for (std::uint32_t v = 0; v < n; ++v) grow(v);
  return forest;
}

/// The same with the graph's stored weights. Throws InvalidInputError when
/// the graph has none.
[[nodiscard]] SpanningForest prim_minimum_spanning_forest(const Graph& graph,
                                                          std::span<const std::uint32_t> roots = {});

}  // namespace recon
