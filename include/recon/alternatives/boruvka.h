#pragma once
// Borůvka's minimum spanning forest on a graph. It works in rounds: every
// tree of the forest so far (at first, each vertex alone) picks the
// cheapest edge leaving it, and all the picked edges join the forest at
// once; rounds go on until no tree has an edge leaving it. A union-find
// (union_find.h) holds the trees. One round:
//   1. name every vertex's tree (a find per vertex);
//   2. drop the edges inside one tree: they can never leave it again. None
//      left: done;
//   3. each tree's cheapest edge out, in one pass over the edges left (an
//      edge is offered to the trees at both its ends);
//   4. unite along each tree's pick; two trees that picked each other
//      picked the same edge, which joins the forest once.
// Why no cycle forms although many edges join at once: edges are compared
// by the strict total order lighter() (weight, smaller endpoint, larger
// endpoint). In a cycle of picks T1 -> T2 -> ... -> Tk -> T1, the pick that
// leads into a tree leaves that tree too, so the tree's own pick is no
// heavier; going round, all the picks are one edge, and one edge joins only
// two trees: k = 2. (Compared by weight alone, a cycle of equal edges could
// be picked whole.)
//
// Order and ties: under that order the forest is unique: the very edges
// Kruskal (kruskal.h) keeps. An edge of weight +infinity is never taken.
// Rounds: every tree with an edge out merges with at least one other, so
// their number at least halves each round: at most log2(V) rounds of
// O(V + E). Memory: 16 bytes per edge, 20 per vertex. Counts: `rounds`
// (the rounds that joined trees), `finds` and `unions` (the union-find's).
// Result: the forest's edges, round by round and within a round by the
// picking tree's root; each with u < v.
//
// The same algorithm on the complete Euclidean graph of a point set, where
// the edges are too many to list and a tree's cheapest edge out comes from
// kd-tree queries instead, is phase II's EMST: emst.h, src/phase2_orientation/emst.cpp.

#include "recon/phase2_orientation/minimum_spanning_tree.h"
#include "recon/structures/graph.h"

#include <cstddef>
#include <vector>

namespace recon {

/// The minimum spanning forest of a list of edges over the vertices 0..vertex_count-1, in any order
/// and either direction; self-loops and repeated edges are allowed.
/// Cost: O((V + E) log V).
/// Throws: InvalidInputError for an endpoint out of range or a NaN weight.
/// Pre: none.
[[nodiscard]] MinimumSpanningEdges boruvka_minimum_spanning_forest(std::size_t vertex_count, std::vector<Edge> edges);

/// The same from a graph with stored weights.
/// Cost: O((V + E) log V).
/// Throws: InvalidInputError when the graph has no stored weights or one is NaN.
/// Pre: none.
[[nodiscard]] MinimumSpanningEdges boruvka_minimum_spanning_forest(const Graph& graph);

/// The same from a graph and `weight(v, e)`, the weight of the edge at CSR position e
/// of row v, as Prim takes it; asked once per edge, in its smaller end's row.
/// Cost: O((V + E) log V).
/// Throws: InvalidInputError for a NaN weight; what `weight` throws.
/// Pre: none.
template <class Weight>
[[nodiscard]] MinimumSpanningEdges boruvka_minimum_spanning_forest(const Graph& graph, Weight&& weight) {
  return boruvka_minimum_spanning_forest(graph.vertex_count(), edge_list(graph, weight));
}

}  // namespace recon
