#include "recon/alternatives/kruskal.h"

#include "recon/core/errors.h"
#include "recon/structures/union_find.h"

#include <algorithm>
#include <utility>

namespace recon {

MinimumSpanningEdges kruskal_minimum_spanning_forest(std::size_t vertex_count, std::vector<Edge> edges) {
  MinimumSpanningEdges result;
  // 1. The edges that may be taken.
  edges = spanning_forest_candidates(vertex_count, std::move(edges), "Kruskal");
  // 2. Cheapest first.
  std::uint64_t& comparisons = result.counts.comparisons;
  std::sort(edges.begin(), edges.end(), [&comparisons](const Edge& a, const Edge& b) {
    ++comparisons;
    return lighter(a, b);
  });
  // 3. Keep each edge that joins two trees.
  UnionFind trees(vertex_count);
  for (const Edge& e : edges) {
    if (!trees.unite(e.u, e.v)) continue;  // both ends in one tree: a cycle
    result.edges.push_back(e);
    result.total_weight += e.weight;
  }
  result.counts.finds = trees.finds();
  result.counts.unions = trees.unions();
  return result;
}

MinimumSpanningEdges kruskal_minimum_spanning_forest(const Graph& graph) {
  return kruskal_minimum_spanning_forest(graph, stored_weights(graph, "Kruskal"));
}

}  // namespace recon
