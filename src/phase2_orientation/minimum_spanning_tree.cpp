#include "recon/phase2_orientation/minimum_spanning_tree.h"

#include <cmath>
#include <limits>
#include <string>
#include <utility>

namespace recon {

SpanningForest prim_minimum_spanning_forest(const Graph& graph, std::span<const std::uint32_t> roots) {
  return prim_minimum_spanning_forest<IndexedBinaryHeap<double>>(graph, roots);
}

std::vector<Edge> spanning_forest_candidates(std::size_t vertex_count, std::vector<Edge> edges,
                                             std::string_view algorithm) {
  auto name = [](const Edge& e) { return "edge (" + std::to_string(e.u) + ", " + std::to_string(e.v) + ")"; };
  for (const Edge& e : edges) {
    if (e.u >= vertex_count || e.v >= vertex_count)
      throw InvalidInputError(std::string(algorithm) + ": " + name(e) + " names a vertex out of range (there are " +
                              std::to_string(vertex_count) + " vertices)");
    if (std::isnan(e.weight)) throw InvalidInputError(std::string(algorithm) + ": " + name(e) + " has a NaN weight");
  }
  std::erase_if(edges, [](const Edge& e) { return e.u == e.v || e.weight == std::numeric_limits<double>::infinity(); });
  for (Edge& e : edges)
    if (e.v < e.u) std::swap(e.u, e.v);
  return edges;
}

}  // namespace recon
