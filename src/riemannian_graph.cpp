#include "recon/riemannian_graph.h"

#include "recon/emst.h"
#include "recon/errors.h"
#include "recon/timer.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace recon {

template <int D>
RiemannianGraph<D> build_riemannian_graph(const TangentPlanes<D>& planes, const RiemannianGraphOptions& options) {
  const std::size_t n = planes.origins.size();
  if (options.k < 1 || static_cast<std::size_t>(options.k) > n)
    throw InvalidInputError("k = " + std::to_string(options.k) + " for the Riemannian graph, but there are " +
                            std::to_string(n) + " points");
  RiemannianGraph<D> result;
  Timer timer;
  const std::span<const Vec<D>> origins(planes.origins);
  result.origin_tree = KdTree<D>(origins, options.tree);
  const KnnTable knn = result.origin_tree.all_knn(options.k);
  result.seconds_knn = timer.lap();
  result.emst = euclidean_minimum_spanning_tree<D>(result.origin_tree, origins, &knn);
  result.seconds_emst = timer.lap();

  auto is_gap = [&](std::uint32_t i, std::uint32_t j, double length) {
    if (!(length > options.gap_factor * std::max(planes.local_gap[i], planes.local_gap[j]))) return false;
    const Vec<D> direction = (planes.origins[j] - planes.origins[i]) / length;
    return std::max(std::abs(direction.dot(planes.normals[i])), std::abs(direction.dot(planes.normals[j]))) > 0.25;
  };
  auto cost = [&](std::uint32_t i, std::uint32_t j) {
    return 1.0 - std::abs(planes.normals[i].dot(planes.normals[j]));
  };

  std::vector<Edge> edges;
  edges.reserve(n * static_cast<std::size_t>(options.k) + result.emst.size());
  UnionFind pieces(n);
  // Both directions of the k-NN relation go in; make_graph merges the pairs
  // listed from both ends (the symmetric k-NN graph).
  for (std::uint32_t i = 0; i < n; ++i) {
    for (const Neighbor& nb : knn.row(i)) {
      if (nb.index == i || is_gap(i, nb.index, std::sqrt(nb.distance2))) continue;
      edges.push_back({i, nb.index, cost(i, nb.index)});
      pieces.unite(i, nb.index);
    }
  }
  std::vector<Edge> gaps;
  for (const Edge& e : result.emst) {
    if (is_gap(e.u, e.v, e.weight)) {
      ++result.gap_emst_edges;
      gaps.push_back(e);
      continue;
    }
    edges.push_back({e.u, e.v, cost(e.u, e.v)});
    pieces.unite(e.u, e.v);
  }
  // Join back pieces too small to be objects, shortest gap first. Pieces only
  // grow, so one pass leaves no small piece that still has a gap edge.
  const std::size_t min_points = options.min_component_points > 0
                                     ? static_cast<std::size_t>(options.min_component_points)
                                     : 2 * static_cast<std::size_t>(options.k);
  std::sort(gaps.begin(), gaps.end(), [](const Edge& a, const Edge& b) { return a.weight < b.weight; });
  for (const Edge& e : gaps) {
    if (pieces.set_size(e.u) >= min_points && pieces.set_size(e.v) >= min_points) continue;
    if (pieces.unite(e.u, e.v)) {
      ++result.rejoined;
      edges.push_back({e.u, e.v, cost(e.u, e.v)});
    }
  }
  result.graph = make_graph(n, edges);
  result.components = connected_components(result.graph);
  result.seconds_graph = timer.lap();
  return result;
}

template RiemannianGraph<2> build_riemannian_graph<2>(const TangentPlanes<2>&, const RiemannianGraphOptions&);
template RiemannianGraph<3> build_riemannian_graph<3>(const TangentPlanes<3>&, const RiemannianGraphOptions&);

}  // namespace recon
