#include "recon/orientation.h"

#include "recon/timer.h"

#include <algorithm>

namespace recon {

template <int D>
OrientedNormals<D> orient_normals(const TangentPlanes<D>& planes, const OrientationOptions& options) {
  OrientedNormals<D> result;
  result.graph = build_riemannian_graph<D>(planes, options.graph);
  Timer timer;
  const std::size_t n = planes.origins.size();

  // One root per component: its origin of largest last coordinate.
  const Components& components = result.graph.components;
  std::vector<std::uint32_t> roots(components.sizes.size(), UINT32_MAX);
  for (std::uint32_t i = 0; i < n; ++i) {
    std::uint32_t& r = roots[components.label[i]];
    if (r == UINT32_MAX || planes.origins[i][D - 1] > planes.origins[r][D - 1]) r = i;
  }
  result.tree = prim_minimum_spanning_forest(result.graph.graph, roots);

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
  const Graph& g = result.graph.graph;
  for (int round = 0; round < options.vote_rounds; ++round) {
    std::vector<std::uint32_t> turn;
    for (std::uint32_t v = 0; v < n; ++v) {
      double agreement = 0.0;
      for (std::uint32_t u : g.neighbors(v)) agreement += result.normals[v].dot(result.normals[u]);
      if (agreement < 0.0) turn.push_back(v);
    }
    if (turn.empty()) break;
    for (std::uint32_t v : turn) {
      result.normals[v] = -result.normals[v];
      result.flipped[v] ^= 1;
    }
    result.vote_flips += turn.size();
  }
  result.flip_count = static_cast<std::size_t>(std::count(result.flipped.begin(), result.flipped.end(), 1));
  result.seconds_mst = timer.lap();
  return result;
}

template OrientedNormals<2> orient_normals<2>(const TangentPlanes<2>&, const OrientationOptions&);
template OrientedNormals<3> orient_normals<3>(const TangentPlanes<3>&, const OrientationOptions&);

}  // namespace recon
