#include "recon/alternatives/boruvka.h"

#include "recon/core/errors.h"
#include "recon/structures/union_find.h"

#include <cstdint>
#include <utility>

namespace recon {

MinimumSpanningEdges boruvka_minimum_spanning_forest(std::size_t vertex_count, std::vector<Edge> edges) {
  constexpr std::size_t none = SIZE_MAX;
  MinimumSpanningEdges result;
  edges = spanning_forest_candidates(vertex_count, std::move(edges), "Borůvka");
  UnionFind trees(vertex_count);
  std::vector<std::uint32_t> tree_of(vertex_count);
  std::vector<std::size_t> pick(vertex_count, none);  // per tree, by its root: its cheapest edge out, in `edges`

  while (true) {
    // 1. Every vertex's tree.
    for (std::uint32_t v = 0; v < vertex_count; ++v) tree_of[v] = trees.find(v);
    // 2. Only the edges between two trees are left.
    std::erase_if(edges, [&](const Edge& e) { return tree_of[e.u] == tree_of[e.v]; });
    if (edges.empty()) break;
    ++result.counts.rounds;
    // 3. Each tree's cheapest edge out.
    auto offer = [&](std::uint32_t tree, std::size_t i) {
      if (pick[tree] == none || lighter(edges[i], edges[pick[tree]])) pick[tree] = i;
    };
    for (std::size_t i = 0; i < edges.size(); ++i) {
      offer(tree_of[edges[i].u], i);
      offer(tree_of[edges[i].v], i);
    }
    // 4. All picks join the forest (an edge picked by both its trees, once).
    for (std::uint32_t tree = 0; tree < vertex_count; ++tree) {
      if (pick[tree] == none) continue;
      const Edge& e = edges[std::exchange(pick[tree], none)];
      if (!trees.unite(e.u, e.v)) continue;
      result.edges.push_back(e);
      result.total_weight += e.weight;
    }
  }
  result.counts.finds = trees.finds();
  result.counts.unions = trees.unions();
  return result;
}

MinimumSpanningEdges boruvka_minimum_spanning_forest(const Graph& graph) {
  return boruvka_minimum_spanning_forest(graph, stored_weights(graph, "Borůvka"));
}

}  // namespace recon
