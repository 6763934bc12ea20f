#include "recon/minimum_spanning_tree.h"

#include "recon/binary_heap.h"

namespace recon {

SpanningForest prim_minimum_spanning_forest(const Graph& graph, std::span<const std::uint32_t> roots) {
  const std::size_t n = graph.vertex_count();
  SpanningForest forest;
  forest.parent.assign(n, SpanningForest::no_parent);
  forest.order.reserve(n);
  std::vector<bool> in_tree(n, false);
  IndexedBinaryHeap<double> heap(n);

  auto grow = [&](std::uint32_t root) {
    if (in_tree[root]) return;
    forest.roots.push_back(root);
    heap.push(root, 0.0);
    while (!heap.empty()) {
      const double w = heap.top_key();
      const std::uint32_t v = heap.pop();
      in_tree[v] = true;
      forest.order.push_back(v);
      if (forest.parent[v] != SpanningForest::no_parent) forest.total_weight += w;
      const auto targets = graph.neighbors(v);
      const auto weights = graph.neighbor_weights(v);
      for (std::size_t j = 0; j < targets.size(); ++j) {
        const std::uint32_t u = targets[j];
        if (!in_tree[u] && heap.push_or_decrease(u, weights[j])) forest.parent[u] = v;
      }
    }
  };
  for (std::uint32_t r : roots) grow(r);
  for (std::uint32_t v = 0; v < n; ++v) grow(v);
  return forest;
}

}  // namespace recon
