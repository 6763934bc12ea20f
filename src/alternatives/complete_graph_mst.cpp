#include "recon/alternatives/complete_graph_mst.h"

#include "recon/core/errors.h"
#include "recon/structures/kdtree.h"  // check_coordinates

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace recon {

template <int D>
MinimumSpanningEdges complete_graph_minimum_spanning_tree(std::span<const Vec<D>> points) {
  check_coordinates<D>(points);
  if (points.size() >= UINT32_MAX)
    throw InvalidInputError("complete-graph MST: " + std::to_string(points.size()) +
                            " points is more than the 2^32 - 2 supported");
  const auto n = static_cast<std::uint32_t>(points.size());
  MinimumSpanningEdges result;
  if (n < 2) return result;
  result.edges.reserve(n - 1);
  // Per point outside the tree, its cheapest edge into the tree so far,
  // weighted by squared length while the tree grows (none yet: +infinity).
  constexpr std::uint32_t none = UINT32_MAX;
  std::vector<Edge> best(n, Edge{none, none, std::numeric_limits<double>::infinity()});
  std::vector<bool> in_tree(n, false);
  // 1. The tree starts as point 0.
  std::uint32_t last = 0;
  in_tree[last] = true;
  for (std::uint32_t step = 1; step < n; ++step) {
    std::uint32_t next = none;
    for (std::uint32_t i = 0; i < n; ++i) {
      if (in_tree[i]) continue;
      // 2. Lower i's entry by its edge to the point that joined last.
      const Edge to_last{std::min(i, last), std::max(i, last), (points[i] - points[last]).squaredNorm()};
      ++result.counts.distance_evaluations;
      if (lighter(to_last, best[i])) best[i] = to_last;
      // 3. The cheapest entry so far.
      if (next == none || lighter(best[i], best[next])) next = i;
    }
    const Edge& joining = best[next];
    result.edges.push_back({joining.u, joining.v, std::sqrt(joining.weight)});
    result.total_weight += result.edges.back().weight;
    in_tree[next] = true;
    last = next;
  }
  return result;
}

template MinimumSpanningEdges complete_graph_minimum_spanning_tree<2>(std::span<const Vec<2>>);
template MinimumSpanningEdges complete_graph_minimum_spanning_tree<3>(std::span<const Vec<3>>);

}  // namespace recon
