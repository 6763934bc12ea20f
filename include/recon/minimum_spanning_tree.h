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
/// is deterministic.
[[nodiscard]] SpanningForest prim_minimum_spanning_forest(const Graph& graph,
                                                          std::span<const std::uint32_t> roots = {});

}  // namespace recon
