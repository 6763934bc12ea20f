#pragma once
// Kruskal's minimum spanning forest: take the edges cheapest first, and keep
// each one that joins two different trees of the forest grown so far; an
// edge whose ends are already in one tree would close a cycle. A union-find
// (union_find.h) holds the trees:
//   1. list the edges that may be taken (no self-loops, no infinite weight);
//   2. sort them;
//   3. for each in turn, unite its ends' sets; when they were two sets, the
//      edge joins the forest.
//
// Order and ties: edges are sorted by the strict total order lighter()
// (weight, smaller endpoint, larger endpoint), so the forest is unique: the
// very edges Borůvka (boruvka.h) finds. Prim (minimum_spanning_tree.h)
// breaks ties its own way: the same total weight, maybe other edges among
// equal weights. An edge of weight +infinity is never taken (as in Prim).
//
// Memory: 16 bytes per edge and 8 per vertex. Counts: `comparisons` are the
// sort's comparisons of two edges, `finds` and `unions` the union-find's
// (two finds per edge; a union per edge kept).
// Result: the forest's edges in the order taken (by lighter()), each with
// u < v; V - (number of trees) of them.

#include "recon/phase2_orientation/minimum_spanning_tree.h"
#include "recon/structures/graph.h"

#include <cstddef>
#include <vector>

namespace recon {

/// The minimum spanning forest of a list of edges over the vertices 0..vertex_count-1, in any order
/// and either direction; self-loops and repeated edges are allowed (a repeat
/// is never kept twice).
/// Cost: O(E log E) for the sort, then O(E alpha(V)) for the union-find.
/// Throws: InvalidInputError for an endpoint out of range or a NaN weight.
/// Pre: none.
[[nodiscard]] MinimumSpanningEdges kruskal_minimum_spanning_forest(std::size_t vertex_count, std::vector<Edge> edges);

/// The same from a graph with stored weights.
/// Cost: O(E log E).
/// Throws: InvalidInputError when the graph has no stored weights or one is NaN.
/// Pre: none.
[[nodiscard]] MinimumSpanningEdges kruskal_minimum_spanning_forest(const Graph& graph);

/// The same from a graph and `weight(v, e)`, the weight of the edge at CSR position e
/// of row v, as Prim takes it; asked once per edge, in its smaller end's row.
/// Cost: O(E log E).
/// Throws: InvalidInputError for a NaN weight; what `weight` throws.
/// Pre: none.
template <class Weight>
[[nodiscard]] MinimumSpanningEdges kruskal_minimum_spanning_forest(const Graph& graph, Weight&& weight) {
  return kruskal_minimum_spanning_forest(graph.vertex_count(), edge_list(graph, weight));
}

}  // namespace recon
