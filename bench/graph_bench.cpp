// Prim's algorithm on our indexed binary heap, against the well-known
// alternatives, on phase II's real workload: the Riemannian graph of a
// Poisson sample of the torus (1M points, k = 20 as reconstruct() uses),
// in spatial order, weights 1 - |n_i . n_j| computed once and stored for
// every contender.
//
//   prim_ours        prim_minimum_spanning_forest: indexed binary heap with
//                    decrease-key (recon/structures/binary_heap.h)
//   prim_lazy_std    the textbook alternative without decrease-key:
//                    std::priority_queue holding every offered edge, stale
//                    entries skipped when popped
//   prim_boost       Boost Graph Library's prim_minimum_spanning_tree on a
//                    compressed_sparse_row_graph (a 4-ary indirect heap with
//                    decrease-key)
// All three must find a tree of the same total weight (checked first).
//
// Built when Boost.Graph is installed (bench/run.sh installs it).

#include "recon/core/shapes.h"
#include "recon/phase1_planes/tangent_planes.h"
#include "recon/phase2_orientation/minimum_spanning_tree.h"
#include "recon/phase2_orientation/riemannian_graph.h"
#include "recon/structures/spatial_order.h"

#include <benchmark/benchmark.h>

// (Boost::headers is an imported target: its warnings are a system header's.)
#include <boost/graph/compressed_sparse_row_graph.hpp>
#include <boost/graph/prim_minimum_spanning_tree.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <queue>
#include <utility>
#include <vector>

namespace {

struct Workload {
  recon::Graph graph;  // with stored weights
  std::uint32_t root = 0;
};

const Workload& workload() {
  static const Workload w = [] {
    // In spatial order, as reconstruct() works.
    const recon::PointCloud cloud = recon::make_torus()->sample(1'000'000, 1);
    const std::vector<recon::Vec3> points =
        recon::permuted<recon::Vec3>(cloud.positions, recon::spatial_order(cloud.positions));
    const auto planes = recon::estimate_tangent_planes<3>(points);
    Workload out;
    // (Costs clamped at 0: rounding can take 1 - |n.n| a hair below, which Boost refuses.)
    out.graph = recon::with_orientation_costs<3>(recon::build_riemannian_graph<3>(planes).graph,
                                                 std::span<const recon::Vec3>(planes.normals));
    for (std::uint32_t i = 0; i < planes.origins.size(); ++i)
      if (planes.origins[i].z() > planes.origins[out.root].z()) out.root = i;
    return out;
  }();
  return w;
}

double ours(const Workload& w) {
  const std::uint32_t roots[] = {w.root};
  return recon::prim_minimum_spanning_forest(w.graph, roots).total_weight;
}

double lazy_std(const Workload& w) {
  const recon::Graph& g = w.graph;
  const std::size_t n = g.vertex_count();
  std::vector<std::uint8_t> in_tree(n, 0);
  using Item = std::pair<double, std::uint32_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
  double total = 0.0;
  queue.push({0.0, w.root});
  while (!queue.empty()) {
    const auto [key, v] = queue.top();
    queue.pop();
    if (in_tree[v]) continue;
    in_tree[v] = 1;
    total += key;
    for (std::uint64_t e = g.offsets[v]; e < g.offsets[v + 1]; ++e)
      if (!in_tree[g.targets[e]]) queue.push({g.weights[e], g.targets[e]});
  }
  return total;
}

using BoostGraph = boost::compressed_sparse_row_graph<boost::directedS, boost::no_property,
                                                      boost::property<boost::edge_weight_t, double>>;

const BoostGraph& boost_graph() {
  static const BoostGraph graph = [] {
    const recon::Graph& g = workload().graph;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
    std::vector<double> weights;
    edges.reserve(g.targets.size());
    for (std::uint32_t v = 0; v < g.vertex_count(); ++v)
      for (std::uint64_t e = g.offsets[v]; e < g.offsets[v + 1]; ++e) {
        edges.emplace_back(v, g.targets[e]);
        weights.push_back(g.weights[e]);
      }
    return BoostGraph(boost::edges_are_sorted, edges.begin(), edges.end(), weights.begin(), g.vertex_count());
  }();
  return graph;
}

double with_boost(const Workload& w) {
  const BoostGraph& graph = boost_graph();
  std::vector<std::size_t> predecessor(boost::num_vertices(graph));
  boost::prim_minimum_spanning_tree(graph, predecessor.data(), boost::root_vertex(w.root));
  const recon::Graph& g = w.graph;
  double total = 0.0;
  for (std::uint32_t v = 0; v < g.vertex_count(); ++v) {
    const std::size_t p = predecessor[v];
    if (p == v) continue;
    for (std::uint64_t e = g.offsets[v]; e < g.offsets[v + 1]; ++e)
      if (g.targets[e] == p) {
        total += g.weights[e];
        break;
      }
  }
  return total;
}

template <double (*Run)(const Workload&)>
void prim(benchmark::State& state) {
  const Workload& w = workload();
  for (auto _ : state) benchmark::DoNotOptimize(Run(w));
  state.counters["edges"] = static_cast<double>(w.graph.edge_count());
}

double min_of(const std::vector<double>& values) { return *std::min_element(values.begin(), values.end()); }

}  // namespace

BENCHMARK(prim<ours>)->Name("prim_ours")->Unit(benchmark::kMillisecond)->ComputeStatistics("min", min_of);
BENCHMARK(prim<lazy_std>)->Name("prim_lazy_std")->Unit(benchmark::kMillisecond)->ComputeStatistics("min", min_of);
BENCHMARK(prim<with_boost>)->Name("prim_boost")->Unit(benchmark::kMillisecond)->ComputeStatistics("min", min_of);

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  const Workload& w = workload();
  (void)boost_graph();
  const double a = ours(w), b = lazy_std(w), c = with_boost(w);
  std::fprintf(stderr, "check: spanning tree weights: ours %.9f, lazy std %.9f, boost %.9f\n", a, b, c);
  if (std::abs(a - b) > 1e-6 * (1.0 + a) || std::abs(a - c) > 1e-6 * (1.0 + a)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
