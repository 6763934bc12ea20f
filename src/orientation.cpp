#include "recon/orientation.h"

#include "recon/timer.h"

#include <algorithm>
#include <utility>

namespace recon {

template <int D>
OrientedNormals<D> orient_normals(const TangentPlanes<D>& planes, const OrientationOptions& options) {
  return orient_normals<D>(planes, build_riemannian_graph<D>(planes, options.graph), options);
}

template <int D>
OrientedNormals<D> orient_normals(const TangentPlanes<D>& planes, RiemannianGraph<D> graph,
                                  const OrientationOptions& options) {
  OrientedNormals<D> result;
  result.graph = std::move(graph);
  Timer timer;
  const std::size_t n = planes.origins.size();

  // One root per component: its origin of largest last coordinate.
  const Components& components = result.graph.components;
  std::vector<std::uint32_t> roots(components.sizes.size(), UINT32_MAX);
  for (std::uint32_t i = 0; i < n; ++i) {
    std::uint32_t& r = roots[components.label[i]];
    if (r == UINT32_MAX || planes.origins[i][D - 1] > planes.origins[r][D - 1]) r = i;
  }
  const Graph& g = result.graph.graph;
  result.tree = prim_minimum_spanning_forest(g, roots, [&](std::uint32_t v, std::uint64_t e) {
    return orientation_cost<D>(planes.normals[v], planes.normals[g.targets[e]]);
  });

  result.normals = planes.normals;
  result.flipped.assign(n, 0);
  for (std::uint32_t v : result.tree.order) {
    const std::uint32_t p = result.tree.parent[v];
    const bool flip = p == SpanningForest::no_parent ? result.normals[v][D - 1] < 0.0
                                                     : result.normals[v].dot(result.normals[p]) < 0.0;
    if (flip) {
      result.normals[v] = -result.normals[v];
      result.flipped[v] = 1;
    }
  }

  // Clean-up vote: the tree decides each sign through one edge, and where
  // noise tilts a normal that one edge can be wrong. A normal that points
  // against most of its graph neighbours is turned round, from the signs of
  // the previous round (so the outcome does not depend on visiting order).
  std::vector<std::uint8_t> turn(n);
  const auto count = static_cast<std::int64_t>(n);
  for (int round = 0; round < options.vote_rounds; ++round) {
    std::size_t turned = 0;
#pragma omp parallel for schedule(dynamic, 4096) reduction(+ : turned)
    for (std::int64_t s = 0; s < count; ++s) {
      const auto v = static_cast<std::uint32_t>(s);
      double agreement = 0.0;
      for (const std::uint32_t u : g.neighbors(v)) agreement += result.normals[v].dot(result.normals[u]);
      turn[v] = agreement < 0.0 ? 1 : 0;
      turned += turn[v];
    }
    if (turned == 0) break;
    for (std::size_t v = 0; v < n; ++v)
      if (turn[v]) {
        result.normals[v] = -result.normals[v];
        result.flipped[v] ^= 1;
      }
    result.vote_flips += turned;
  }
  result.flip_count = static_cast<std::size_t>(std::count(result.flipped.begin(), result.flipped.end(), 1));
  result.seconds_mst = timer.lap();
  return result;
}

template OrientedNormals<2> orient_normals<2>(const TangentPlanes<2>&, const OrientationOptions&);
template OrientedNormals<3> orient_normals<3>(const TangentPlanes<3>&, const OrientationOptions&);
template OrientedNormals<2> orient_normals<2>(const TangentPlanes<2>&, RiemannianGraph<2>, const OrientationOptions&);
template OrientedNormals<3> orient_normals<3>(const TangentPlanes<3>&, RiemannianGraph<3>, const OrientationOptions&);

}  // namespace recon
