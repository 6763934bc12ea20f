#include "recon/minimum_spanning_tree.h"

#include "recon/errors.h"

namespace recon {

SpanningForest prim_minimum_spanning_forest(const Graph& graph, std::span<const std::uint32_t> roots) {
  if (graph.weights.size() != graph.targets.size())
    throw InvalidInputError("Prim: the graph has no stored weights; pass a weight function");
  return prim_minimum_spanning_forest(graph, roots,
                                      [&](std::uint32_t, std::uint64_t e) { return graph.weights[e]; });
}

}  // namespace recon
