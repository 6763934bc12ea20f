#pragma once
// Undirected weighted graphs in compressed sparse row (CSR) form, and their
// connected components. (The union-find that used to live here has a header
// of its own, union_find.h; it is included below so that code which found
// UnionFind here still compiles.)
//
// CSR: the neighbours of vertex v are targets[offsets[v] .. offsets[v+1]),
// with their edge weights at the same positions in `weights`, or no stored
// weights at all when the user computes them from the vertices (the
// Riemannian graph does: its costs come from the normals). Every edge
// {u, v} is stored twice, once in each row. make_graph sorts each row by
// target; other builders may choose another fixed order (the Riemannian
// graph lists a vertex's nearest neighbours first).
// Memory: 8 bytes per vertex + 4 bytes per directed edge (+ 8 with weights).

#include "recon/structures/detail/uninitialized_allocator.h"
#include "recon/structures/union_find.h"

#include <cstdint>
#include <span>
#include <vector>

namespace recon {

struct Edge {
  std::uint32_t u = 0, v = 0;
  double weight = 0.0;
  friend bool operator==(const Edge&, const Edge&) = default;
};

struct Graph {
  std::vector<std::uint64_t> offsets;  ///< vertex_count() + 1 entries
  /// Every entry is written by whoever builds the graph (resize() leaves
  /// new ones unwritten: detail/uninitialized_allocator.h).
  std::vector<std::uint32_t, detail::UninitializedAllocator<std::uint32_t>> targets;
  std::vector<double> weights;  ///< empty, or one per target

  [[nodiscard]] std::size_t vertex_count() const { return offsets.empty() ? 0 : offsets.size() - 1; }
  /// Undirected edges (each is stored twice).
  [[nodiscard]] std::size_t edge_count() const { return targets.size() / 2; }
  [[nodiscard]] std::span<const std::uint32_t> neighbors(std::uint32_t v) const {
    return {targets.data() + offsets[v], targets.data() + offsets[v + 1]};
  }
  [[nodiscard]] std::span<const double> neighbor_weights(std::uint32_t v) const {
    return {weights.data() + offsets[v], weights.data() + offsets[v + 1]};
  }
};

/// Builds the graph on `vertex_count` vertices (V) from a list of E edges. Self-loops
/// are dropped; an edge listed more than once is kept once, with the smallest
/// of its weights.
/// Cost: O(V + E) (counting into rows); here O(V + E log d), each row of at most d entries sorted.
/// Throws: InvalidInputError for an endpoint out of range.
/// Pre: no more than 2^32 - 1 vertices.
[[nodiscard]] Graph make_graph(std::size_t vertex_count, std::span<const Edge> edges);

/// `graph` with the undirected `edges` added (rows stay sorted; an edge
/// already present is not repeated, the lighter weight kept). Weights are
/// kept when the graph has them, taken from the new edges.
/// Cost: O(V + E log d), a make_graph over the old and the new edges.
/// Throws: InvalidInputError for an endpoint out of range.
/// Pre: none.
[[nodiscard]] Graph with_edges(const Graph& graph, std::span<const Edge> edges);

/// Every undirected edge once, as {u, v, weight(u, e)} with u < v and e its
/// position in row u; in row order. Self-loops are left out. `weight(v, e)`
/// is the weight of the edge at CSR position e of row v, as Prim takes it
/// (minimum_spanning_tree.h).
/// Cost: O(V + E) and E calls of `weight`.
/// Throws: what `weight` throws; nothing else.
/// Pre: none.
template <class Weight>
[[nodiscard]] std::vector<Edge> edge_list(const Graph& graph, Weight&& weight) {
  std::vector<Edge> edges;
  edges.reserve(graph.edge_count());
  const std::size_t n = graph.vertex_count();
  for (std::uint32_t u = 0; u < n; ++u)
    for (std::uint64_t e = graph.offsets[u]; e < graph.offsets[u + 1]; ++e)
      if (u < graph.targets[e]) edges.push_back({u, graph.targets[e], static_cast<double>(weight(u, e))});
  return edges;
}

/// Connected components: label per vertex, numbered 0.. in order of each
/// component's smallest vertex.
struct Components {
  std::vector<std::uint32_t> label;
  std::vector<std::uint32_t> sizes;  ///< vertices per component
};
/// The components of `graph`, by breadth-first search from each vertex not yet labelled, in index order.
/// Cost: O(V + E).
/// Throws: nothing.
/// Pre: none.
[[nodiscard]] Components connected_components(const Graph& graph);

}  // namespace recon
