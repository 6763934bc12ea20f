#include "recon/alternatives/orientation_graphs.h"

#include "recon/alternatives/complete_graph_mst.h"
#include "recon/core/errors.h"
#include "recon/core/timer.h"

#include <algorithm>
#include <array>
#include <string>
#include <vector>

namespace recon {
namespace {

constexpr std::array<std::string_view, 5> names = {"complete", "emst", "knn", "mutual-knn", "riemannian"};

// The first k of each neighbourhood, itself excluded.
template <int D>
std::size_t neighbourhood_size(const TangentPlanes<D>& planes, const RiemannianGraphOptions& options) {
  if (options.k < 0 || options.k > planes.neighbors.k)
    throw InvalidInputError("orientation graph: k = " + std::to_string(options.k) + " is not within 0.." +
                            std::to_string(planes.neighbors.k) + " (phase I's k)");
  return static_cast<std::size_t>(options.k == 0 ? planes.neighbors.k : options.k);
}

template <int D>
bool lists(const TangentPlanes<D>& planes, std::size_t k, std::uint32_t i, std::uint32_t j) {
  const auto row = planes.neighbors.row(i).first(k);
  return std::find(row.begin(), row.end(), j) != row.end();
}

// k-NN edges: symmetric (either lists the other) or mutual (both do).
template <int D>
std::vector<Edge> knn_edges(const TangentPlanes<D>& planes, std::size_t k, bool mutual) {
  std::vector<Edge> edges;
  for (std::uint32_t i = 0; i < planes.neighbors.size(); ++i)
    for (const std::uint32_t j : planes.neighbors.row(i).first(k))
      if (j != i && (!mutual || lists(planes, k, j, i))) edges.push_back({std::min(i, j), std::max(i, j), 0.0});
  return edges;
}

// The EMST edges the Riemannian graph kept (the gaps cut).
template <int D>
std::vector<Edge> kept_emst_edges(const RiemannianGraph<D>& riemannian) {
  std::vector<Edge> edges;
  for (const Edge& e : riemannian.emst) {
    const auto row = riemannian.graph.neighbors(e.u);
    if (std::find(row.begin(), row.end(), e.v) != row.end()) edges.push_back(e);
  }
  return edges;
}

template <int D>
RiemannianGraph<D> from_edges(std::size_t n, const std::vector<Edge>& edges, std::vector<Edge> emst) {
  RiemannianGraph<D> result;
  result.graph = make_graph(n, edges);
  result.graph.weights.clear();  // costs come from the normals, as the Riemannian graph's do
  result.components = connected_components(result.graph);
  result.emst = std::move(emst);
  result.edge_count = result.graph.edge_count();
  return result;
}

}  // namespace

std::string_view name_of(OrientationGraph graph) { return names[static_cast<std::size_t>(graph)]; }

std::optional<OrientationGraph> orientation_graph_named(std::string_view name) {
  for (const OrientationGraph g : all_orientation_graphs)
    if (name_of(g) == name) return g;
  return std::nullopt;
}

template <int D>
RiemannianGraph<D> build_orientation_graph(const TangentPlanes<D>& planes, OrientationGraph kind,
                                           const RiemannianGraphOptions& options, OperationCounts* counts) {
  const std::size_t n = planes.origins.size();
  const std::size_t k = neighbourhood_size(planes, options);
  Timer timer;
  RiemannianGraph<D> result;
  switch (kind) {
    case OrientationGraph::riemannian:
      return build_riemannian_graph<D>(planes, options);
    case OrientationGraph::emst: {
      RiemannianGraph<D> riemannian = build_riemannian_graph<D>(planes, options);
      const std::vector<Edge> kept = kept_emst_edges(riemannian);
      result = from_edges<D>(n, kept, std::move(riemannian.emst));
      result.seconds_emst = riemannian.seconds_emst;
      break;
    }
    case OrientationGraph::complete: {
      const std::vector<Vec<D>> x = samples_of<D>(planes);
      MinimumSpanningEdges tree = complete_graph_minimum_spanning_tree<D>(x);
      if (counts) *counts += tree.counts;
      result = from_edges<D>(n, tree.edges, tree.edges);
      result.seconds_emst = timer.lap();
      break;
    }
    case OrientationGraph::knn:
    case OrientationGraph::mutual_knn:
      result = from_edges<D>(n, knn_edges(planes, k, kind == OrientationGraph::mutual_knn), {});
      break;
  }
  result.seconds_graph = timer.lap();
  return result;
}

template RiemannianGraph<2> build_orientation_graph<2>(const TangentPlanes<2>&, OrientationGraph,
                                                       const RiemannianGraphOptions&, OperationCounts*);
template RiemannianGraph<3> build_orientation_graph<3>(const TangentPlanes<3>&, OrientationGraph,
                                                       const RiemannianGraphOptions&, OperationCounts*);

}  // namespace recon
