#include "recon/riemannian_graph.h"

#include "recon/emst.h"
#include "recon/errors.h"
#include "recon/timer.h"

#include <algorithm>
#include <cmath>
#include <numeric>
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

  // The graph is laid out directly in CSR form from the k-NN table (no
  // edge list to sort): row i holds i's own kept neighbours, then the points
  // that list i without i listing them (the symmetric closure), then EMST
  // edges that neither lists. i is in row j of the table exactly when
  // (d2, i) does not come after the row's last entry.
  const auto k = static_cast<std::size_t>(knn.k);
  auto listed_by = [&](std::uint32_t j, std::uint32_t i, double d2) {
    const Neighbor& last = knn.row(j).back();
    return d2 < last.distance2 || (d2 == last.distance2 && i <= last.index);
  };
  std::vector<std::uint8_t> kept(n * k, 0);
  std::vector<std::uint64_t> degree(n + 1, 0);
  const auto count = static_cast<std::int64_t>(n);
#pragma omp parallel for schedule(static)
  for (std::int64_t s = 0; s < count; ++s) {
    const auto i = static_cast<std::uint32_t>(s);
    const auto row = knn.row(i);
    for (std::size_t e = 0; e < k; ++e) {
      const Neighbor& nb = row[e];
      if (nb.index == i || is_gap(i, nb.index, std::sqrt(nb.distance2))) continue;
      kept[i * k + e] = 1;
      ++degree[i + 1];
    }
  }
  UnionFind pieces(n);
  std::vector<Edge> extra;  // rows beyond the table: symmetric closure, EMST, rejoined gaps
  for (std::uint32_t i = 0; i < n; ++i) {
    const auto row = knn.row(i);
    for (std::size_t e = 0; e < k; ++e) {
      if (!kept[i * k + e]) continue;
      pieces.unite(i, row[e].index);
      if (!listed_by(row[e].index, i, row[e].distance2)) extra.push_back({row[e].index, i, 0.0});
    }
  }
  std::vector<Edge> gaps;
  for (const Edge& e : result.emst) {
    if (is_gap(e.u, e.v, e.weight)) {
      ++result.gap_emst_edges;
      gaps.push_back(e);
      continue;
    }
    pieces.unite(e.u, e.v);
    const double d2 = (planes.origins[e.v] - planes.origins[e.u]).squaredNorm();  // as the tree computed it
    if (!listed_by(e.u, e.v, d2) && !listed_by(e.v, e.u, d2)) {
      extra.push_back({e.u, e.v, 0.0});
      extra.push_back({e.v, e.u, 0.0});
    }
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
      extra.push_back({e.u, e.v, 0.0});
      extra.push_back({e.v, e.u, 0.0});
    }
  }
  for (const Edge& e : extra) ++degree[e.u + 1];

  Graph& g = result.graph;
  g.offsets.resize(n + 1);
  std::partial_sum(degree.begin(), degree.end(), g.offsets.begin());
  g.targets.resize(g.offsets.back());
  g.weights.resize(g.offsets.back());
  std::vector<std::uint64_t> fill(g.offsets.begin(), g.offsets.end() - 1);
  for (std::uint32_t i = 0; i < n; ++i) {
    const auto row = knn.row(i);
    for (std::size_t e = 0; e < k; ++e)
      if (kept[i * k + e]) g.targets[fill[i]++] = row[e].index;
  }
  for (const Edge& e : extra) g.targets[fill[e.u]++] = e.v;
#pragma omp parallel for schedule(static)
  for (std::int64_t s = 0; s < count; ++s) {
    const auto i = static_cast<std::size_t>(s);
    const auto begin = g.targets.begin() + static_cast<std::ptrdiff_t>(g.offsets[i]);
    const auto end = g.targets.begin() + static_cast<std::ptrdiff_t>(g.offsets[i + 1]);
    std::sort(begin, end);
    for (std::uint64_t e = g.offsets[i]; e < g.offsets[i + 1]; ++e)
      g.weights[e] = cost(static_cast<std::uint32_t>(i), g.targets[e]);
  }
  result.components = connected_components(result.graph);
  result.seconds_graph = timer.lap();
  return result;
}

template RiemannianGraph<2> build_riemannian_graph<2>(const TangentPlanes<2>&, const RiemannianGraphOptions&);
template RiemannianGraph<3> build_riemannian_graph<3>(const TangentPlanes<3>&, const RiemannianGraphOptions&);

}  // namespace recon
