// recon_mst_bench: the alternatives of phase II's spanning tree, side by
// side on its real workload: the Riemannian graph of a Poisson sample of
// the torus, in spatial order, costs 1 - |n_i . n_j| stored once.
//
//   recon_mst_bench [--points N ...] [--reps R] [--max-list-heap N]
//
// For each N (default 100000 and 1000000) and each algorithm:
//   - Prim on the indexed binary heap (the default), the Fibonacci heap,
//     the pairing heap and the list heap (skipped beyond --max-list-heap,
//     default 100000: a scan of the whole queue per pop);
//   - Kruskal (sort, union-find) and Borůvka (rounds) on the same graph.
// Times are the fastest of R repetitions (default 3), the algorithms taking
// turns within each repetition, so that the machine's load falls on all
// alike. Counts come from one more, instrumented run (CountingQueue; the
// union-find's own counters). Every tree must weigh the same (checked:
// the program stops otherwise). Prints a markdown table.

#include "recon/alternatives/boruvka.h"
#include "recon/alternatives/counting_queue.h"
#include "recon/alternatives/kruskal.h"
#include "recon/core/shapes.h"
#include "recon/core/timer.h"
#include "recon/phase1_planes/tangent_planes.h"
#include "recon/phase2_orientation/minimum_spanning_tree.h"
#include "recon/phase2_orientation/riemannian_graph.h"
#include "recon/structures/fibonacci_heap.h"
#include "recon/structures/list_heap.h"
#include "recon/structures/pairing_heap.h"
#include "recon/structures/spatial_order.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace {

recon::Graph workload(std::size_t n) {
  const recon::PointCloud cloud = recon::make_torus()->sample(n, 1);
  const std::vector<recon::Vec3> points =
      recon::permuted<recon::Vec3>(cloud.positions, recon::spatial_order(cloud.positions));
  const auto planes = recon::estimate_tangent_planes<3>(points);
  return recon::with_orientation_costs<3>(recon::build_riemannian_graph<3>(planes).graph,
                                          std::span<const recon::Vec3>(planes.normals));
}

struct Contender {
  std::string name;
  std::function<double(const recon::Graph&)> run;                      // returns the tree's weight
  std::function<recon::OperationCounts(const recon::Graph&)> counted;  // one instrumented run
  bool quadratic = false;
  double best = std::numeric_limits<double>::infinity();
  double weight = 0.0;
  recon::OperationCounts counts;
};

Contender contender(std::string name, std::function<double(const recon::Graph&)> run,
                    std::function<recon::OperationCounts(const recon::Graph&)> counted, bool quadratic = false) {
  Contender c;
  c.name = std::move(name);
  c.run = std::move(run);
  c.counted = std::move(counted);
  c.quadratic = quadratic;
  return c;
}

template <template <class> class Heap>
Contender prim(std::string name, bool quadratic = false) {
  return contender(
      std::move(name),
      [](const recon::Graph& g) { return recon::prim_minimum_spanning_forest<Heap<double>>(g).total_weight; },
      [](const recon::Graph& g) { return recon::prim_minimum_spanning_forest<recon::CountingQueue<Heap>>(g).counts; },
      quadratic);
}

// The graph's edges in Kruskal's order, computed once per graph (the
// workloads differ in size, which tells them apart).
const std::vector<recon::Edge>& sorted_edges(const recon::Graph& g) {
  static std::size_t for_vertices = 0;
  static std::vector<recon::Edge> edges;
  if (for_vertices != g.vertex_count()) {
    edges = recon::edge_list(g, recon::stored_weights(g, "recon_mst_bench"));
    std::sort(edges.begin(), edges.end(), recon::lighter);
    for_vertices = g.vertex_count();
  }
  return edges;
}

std::vector<Contender> contenders() {
  std::vector<Contender> all;
  all.push_back(prim<recon::IndexedBinaryHeap>("prim/binary-heap"));
  all.push_back(prim<recon::FibonacciHeap>("prim/fibonacci-heap"));
  all.push_back(prim<recon::PairingHeap>("prim/pairing-heap"));
  all.push_back(prim<recon::ListHeap>("prim/list-heap", true));
  all.push_back(contender(
      "kruskal", [](const recon::Graph& g) { return recon::kruskal_minimum_spanning_forest(g).total_weight; },
      [](const recon::Graph& g) { return recon::kruskal_minimum_spanning_forest(g).counts; }));
  // Kruskal's cost is its sort: handed the edges already in order (as a
  // caller that has them sorted would), std::sort's pass over them is
  // nearly free and what remains is the union-find.
  all.push_back(contender(
      "kruskal/presorted",
      [](const recon::Graph& g) {
        return recon::kruskal_minimum_spanning_forest(g.vertex_count(), sorted_edges(g)).total_weight;
      },
      [](const recon::Graph& g) {
        return recon::kruskal_minimum_spanning_forest(g.vertex_count(), sorted_edges(g)).counts;
      }));
  all.push_back(contender(
      "boruvka", [](const recon::Graph& g) { return recon::boruvka_minimum_spanning_forest(g).total_weight; },
      [](const recon::Graph& g) { return recon::boruvka_minimum_spanning_forest(g).counts; }));
  return all;
}

std::string count(std::uint64_t v) { return v == 0 ? "" : std::to_string(v); }

void print_row(std::size_t n, const Contender& c, double base) {
  const recon::OperationCounts& k = c.counts;
  std::printf("| %zu | %s | %.1f | %.2f | %s | %s | %s | %s | %s | %s | %s |\n", n, c.name.c_str(), 1e3 * c.best,
              c.best / base, count(k.pushes).c_str(), count(k.pops).c_str(), count(k.decrease_keys).c_str(),
              count(k.comparisons).c_str(), count(k.finds).c_str(), count(k.unions).c_str(), count(k.rounds).c_str());
}

void bench(std::size_t n, int reps, std::size_t max_list_heap) {
  const recon::Graph g = workload(n);
  std::vector<Contender> all = contenders();
  std::erase_if(all, [&](const Contender& c) { return c.quadratic && n > max_list_heap; });
  for (int r = 0; r < reps; ++r)
    for (Contender& c : all) {
      recon::Timer timer;
      c.weight = c.run(g);
      c.best = std::min(c.best, timer.elapsed());
    }
  for (Contender& c : all) {
    c.counts = c.counted(g);
    if (std::abs(c.weight - all.front().weight) > 1e-9 * std::max(1.0, all.front().weight)) {
      std::fprintf(stderr, "recon_mst_bench: %s's tree weighs %.17g, prim/binary-heap's %.17g\n", c.name.c_str(),
                   c.weight, all.front().weight);
      std::exit(1);
    }
  }
  for (const Contender& c : all) print_row(n, c, all.front().best);
  if (n > max_list_heap)
    std::printf("| %zu | prim/list-heap | skipped: beyond --max-list-heap %zu | | | | | | | | |\n", n, max_list_heap);
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::size_t> sizes;
  int reps = 3;
  std::size_t max_list_heap = 100'000;
  for (int a = 1; a + 1 < argc; a += 2) {
    const std::string option = argv[a];
    const std::size_t value = std::strtoull(argv[a + 1], nullptr, 10);
    if (option == "--points")
      sizes.push_back(value);
    else if (option == "--reps")
      reps = std::max(1, static_cast<int>(value));
    else if (option == "--max-list-heap")
      max_list_heap = value;
    else {
      std::fprintf(stderr, "usage: recon_mst_bench [--points N ...] [--reps R] [--max-list-heap N]\n");
      return 2;
    }
  }
  if (sizes.empty()) sizes = {100'000, 1'000'000};
  std::printf(
      "| points | algorithm | ms (best of %d) | × binary heap | pushes | pops | decrease-keys | comparisons | finds | "
      "unions | rounds |\n",
      reps);
  std::printf("|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (const std::size_t n : sizes) bench(n, reps, max_list_heap);
  return 0;
}
