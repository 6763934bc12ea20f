#include "recon/alternatives/lab.h"

#include "recon/alternatives/boruvka.h"
#include "recon/alternatives/brute_force_search.h"
#include "recon/alternatives/complete_graph_mst.h"
#include "recon/alternatives/counting_queue.h"
#include "recon/alternatives/kruskal.h"
#include "recon/alternatives/uniform_grid.h"
#include "recon/core/timer.h"
#include "recon/phase1_planes/local_quadrics.h"
#include "recon/phase2_orientation/emst.h"
#include "recon/phase6_simplify/simplification.h"
#include "recon/reconstruct.h"
#include "recon/structures/fibonacci_heap.h"
#include "recon/structures/indexed_heap.h"
#include "recon/structures/list_heap.h"
#include "recon/structures/pairing_heap.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <sstream>
#include <utility>

namespace recon {
namespace {

constexpr std::array<std::string_view, 5> kind_names = {"search", "queue", "mst", "graph", "simplify"};

std::string count_text(std::size_t n) { return std::to_string(n); }

LabRun make_run(std::string name, LabKind kind, std::string graph) {
  LabRun run;
  run.name = std::move(name);
  run.kind = kind;
  run.graph = std::move(graph);
  return run;
}

LabRun skipped_run(std::string name, LabKind kind, std::string graph, std::string reason) {
  LabRun run = make_run(std::move(name), kind, std::move(graph));
  run.skipped = std::move(reason);
  return run;
}

std::string too_many(std::size_t n, std::size_t limit, std::string_view what) {
  return count_text(n) + " points is more than " + count_text(limit) + " for " + std::string(what) +
         "; it would take too long";
}

// Two tree weights agree to rounding: sums of the same costs in another
// order differ by a few units in the last place per term.
bool same_weight(double a, double b) { return std::abs(a - b) <= 1e-9 * std::max(1.0, std::abs(a)); }

std::string weight_text(double w) {
  std::ostringstream out;
  out.precision(17);
  out << w;
  return out.str();
}

void check_weight(const LabRun& run, const LabRun& reference) {
  if (!run.tree_weight || !reference.tree_weight || same_weight(*run.tree_weight, *reference.tree_weight)) return;
  throw LabDisagreementError("lab: " + run.name + " and " + reference.name + " disagree on the " + run.graph +
                             " graph: trees of weight " + weight_text(*run.tree_weight) + " and " +
                             weight_text(*reference.tree_weight) + "; a minimum spanning forest has one weight");
}

// ---------------------------------------------------------------- searches

// The neighbour distances of `table` against the kd-tree's: entry by entry.
void check_search(const LabRun& run, const KnnTable& table, const KnnTable& reference) {
  for (std::size_t e = 0; e < reference.entries.size(); ++e)
    if (e >= table.entries.size() || table.entries[e].distance2 != reference.entries[e].distance2) {
      const std::size_t k = static_cast<std::size_t>(reference.k);
      throw LabDisagreementError("lab: the " + run.name + " search and the kd-tree disagree on point " +
                                 count_text(e / k) + "'s neighbour " + count_text(e % k) + " (squared distance " +
                                 (e < table.entries.size() ? weight_text(table.entries[e].distance2) : "missing") +
                                 " against " + weight_text(reference.entries[e].distance2) + ")");
    }
}

template <class Search>
LabRun search_run(std::string name, Search&& search, const KnnTable* reference, const LabOptions& options) {
  LabRun run = make_run(std::move(name), LabKind::search, "");
  Timer timer;
  KnnTable table = search(run.counts);
  run.seconds = timer.lap();
  if (options.spoil == run.name && !table.entries.empty()) table.entries.back().distance2 *= 1.5;
  if (reference) check_search(run, table, *reference);
  return run;
}

void run_searches(std::span<const Vec3> points, int k, const LabOptions& options, LabResult& result) {
  // The kd-tree first: it is the reference the others are held to.
  KnnTable reference;
  LabRun tree_run = search_run(
      "kd-tree",
      [&](OperationCounts& counts) {
        const KdTree<3> tree(points);
        reference = tree.all_knn(k, &counts);
        return reference;
      },
      nullptr, options);
  if (options.spoil == tree_run.name && !reference.entries.empty()) reference.entries.back().distance2 *= 1.5;
  result.runs.push_back(std::move(tree_run));
  result.runs.push_back(search_run(
      "grid", [&](OperationCounts& counts) { return UniformGrid<3>(points).all_knn(k, &counts); }, &reference,
      options));
  if (points.size() > options.max_points_brute_force) {
    result.runs.push_back(
        skipped_run("brute-force", LabKind::search, "",
                    too_many(points.size(), options.max_points_brute_force, "brute force (n^2 distances)")));
  } else {
    result.runs.push_back(search_run(
        "brute-force", [&](OperationCounts& counts) { return brute_force_all_knn<3>(points, k, &counts); }, &reference,
        options));
  }
}

// ------------------------------------------------------------------ queues

// Prim on the queue Heap over the graph's stored costs: timed plain (the
// tree grown is left in `forest`), counted in a second run.
template <template <class> class Heap>
requires IndexedMinHeap < Heap<double>,
double > LabRun queue_run(std::string name, const Graph& g, const LabOptions& options, SpanningForest& forest) {
  LabRun run = make_run("prim/" + std::move(name), LabKind::queue, "riemannian");
  Timer timer;
  forest = prim_minimum_spanning_forest<Heap<double>>(g);
  run.seconds = timer.lap();
  run.counts = prim_minimum_spanning_forest<CountingQueue<Heap>>(g).counts;
  if (options.spoil == run.name && !forest.order.empty())
    forest.parent[forest.order.back()] = SpanningForest::no_parent;
  run.tree_weight = forest.total_weight;
  return run;
}

// The queues order equal keys alike, so Prim must grow the same tree on each.
template <template <class> class Heap>
requires IndexedMinHeap < Heap<double>,
double > LabRun checked_queue_run(std::string name, const Graph& g, const LabOptions& options,
                                  const SpanningForest& binary_heap_tree) {
  SpanningForest forest;
  LabRun run = queue_run<Heap>(std::move(name), g, options, forest);
  if (forest.parent != binary_heap_tree.parent)
    throw LabDisagreementError("lab: " + run.name +
                               " and prim/binary-heap disagree: Prim grew different trees on "
                               "them, but the queues order equal keys alike, so the trees must be the same");
  return run;
}

void run_queues(const Graph& g, const LabOptions& options, LabResult& result) {
  SpanningForest binary_heap_tree;
  result.runs.push_back(queue_run<IndexedBinaryHeap>("binary-heap", g, options, binary_heap_tree));
  result.runs.push_back(checked_queue_run<FibonacciHeap>("fibonacci-heap", g, options, binary_heap_tree));
  result.runs.push_back(checked_queue_run<PairingHeap>("pairing-heap", g, options, binary_heap_tree));
  const std::size_t n = g.vertex_count();
  if (n > options.max_points_list_heap) {
    result.runs.push_back(skipped_run("prim/list-heap", LabKind::queue, "riemannian",
                                      too_many(n, options.max_points_list_heap, "the list heap (a scan per pop)")));
  } else {
    result.runs.push_back(checked_queue_run<ListHeap>("list-heap", g, options, binary_heap_tree));
  }
}

// ------------------------------------------------------------- MST on a graph

LabRun edges_run(std::string name, std::string graph, MinimumSpanningEdges tree, double seconds,
                 const LabOptions& options) {
  LabRun run = make_run(std::move(name), LabKind::mst, std::move(graph));
  run.seconds = seconds;
  run.counts = tree.counts;
  if (options.spoil == run.name && !tree.edges.empty()) tree.total_weight -= tree.edges.back().weight;
  run.tree_weight = tree.total_weight;
  return run;
}

void run_msts(const Graph& g, const LabOptions& options, LabResult& result) {
  const std::size_t first = result.runs.size();
  {
    LabRun prim = make_run("prim", LabKind::mst, "riemannian");
    Timer timer;
    const SpanningForest forest = prim_minimum_spanning_forest(g);
    prim.seconds = timer.lap();
    prim.tree_weight = forest.total_weight;
    if (options.spoil == prim.name) *prim.tree_weight *= 1.5;
    result.runs.push_back(std::move(prim));
  }
  Timer timer;
  MinimumSpanningEdges kruskal = kruskal_minimum_spanning_forest(g);
  result.runs.push_back(edges_run("kruskal", "riemannian", std::move(kruskal), timer.lap(), options));
  MinimumSpanningEdges boruvka = boruvka_minimum_spanning_forest(g);
  result.runs.push_back(edges_run("boruvka", "riemannian", std::move(boruvka), timer.lap(), options));
  for (std::size_t r = first + 1; r < result.runs.size(); ++r) check_weight(result.runs[r], result.runs[first]);
}

// The Euclidean MST two ways: Prim's array version on the complete graph,
// and Borůvka with kd-tree queries (phase II's).
void run_euclidean_msts(std::span<const Vec3> points, const LabOptions& options, LabResult& result) {
  const std::string graph = "complete-euclidean";
  Timer timer;
  const KdTree<3> tree(points);
  const std::vector<Edge> emst = euclidean_minimum_spanning_tree<3>(tree, points);
  MinimumSpanningEdges boruvka;
  boruvka.edges = emst;
  for (const Edge& e : emst) boruvka.total_weight += e.weight;
  result.runs.push_back(edges_run("boruvka-kdtree", graph, std::move(boruvka), timer.lap(), options));
  if (points.size() > options.max_points_complete) {
    result.runs.push_back(
        skipped_run("prim-array", LabKind::mst, graph,
                    too_many(points.size(), options.max_points_complete, "the complete graph (n^2 / 2 distances)")));
    return;
  }
  timer.lap();
  MinimumSpanningEdges dense = complete_graph_minimum_spanning_tree<3>(points);
  result.runs.push_back(edges_run("prim-array", graph, std::move(dense), timer.lap(), options));
  check_weight(result.runs.back(), result.runs[result.runs.size() - 2]);
}

// ------------------------------------------------------------------ graphs

double share_agreeing(std::span<const Vec3> a, std::span<const Vec3> b) {
  if (a.empty()) return 0.0;
  std::size_t agree = 0;
  for (std::size_t i = 0; i < a.size(); ++i) agree += a[i].dot(b[i]) > 0.0 ? 1u : 0u;
  return static_cast<double>(agree) / static_cast<double>(a.size());
}

// A graph run's figures, from the orientation it found.
void describe(const OrientedNormals<3>& oriented, std::span<const Vec3> truth, LabRun& run) {
  run.tree_weight = oriented.tree.total_weight;
  run.edges = oriented.graph.graph.edge_count();
  run.components = oriented.component_count();
  run.flips = oriented.flip_count;
  if (!truth.empty()) run.agree_truth = share_agreeing(oriented.normals, truth);
}

LabRun graph_run(OrientationGraph kind, const TangentPlanes<3>& planes, std::span<const Vec3> truth,
                 OrientedNormals<3>& oriented) {
  LabRun run = make_run(std::string(name_of(kind)), LabKind::graph, std::string(name_of(kind)));
  Timer timer;
  RiemannianGraph<3> graph = build_orientation_graph<3>(planes, kind, {}, &run.counts);
  oriented = orient_normals<3>(planes, std::move(graph), OrientationOptions{});  // the 1992 walk
  run.seconds = timer.lap();
  describe(oriented, truth, run);
  return run;
}

// The Riemannian graph walked as the refined method walks it (orientation.h:
// quadric fits, crease and facing-sheet rules, each piece's side at its
// best extreme): the same graph, another walk, to tell the two apart.
LabRun refined_walk_run(const TangentPlanes<3>& planes, std::span<const Vec3> truth, const LabResult& result) {
  LabRun run = make_run("riemannian/refined-walk", LabKind::graph, "riemannian");
  Timer timer;
  LocalQuadricOptions fits;
  fits.min_sheet_separation = 1.5 * planes.rho;  // as reconstruct() sets it, with its default cell rho
  LocalQuadrics quadrics = fit_local_quadrics(planes, fits);
  TangentPlanes<3> second_order = planes;
  adopt_second_order(second_order, quadrics);
  OrientationOptions walk;
  walk.sign_by_extremes = true;
  walk.sheet_misfit = quadrics.residual;
  walk.guide = quadrics.guide;
  const OrientedNormals<3> oriented = orient_normals<3>(second_order, walk);
  run.seconds = timer.lap();
  describe(oriented, truth, run);
  run.agree_default = share_agreeing(oriented.normals, result.default_orientation.normals);
  return run;
}

void run_graphs(const TangentPlanes<3>& planes, std::span<const Vec3> truth, const LabOptions& options,
                LabResult& result) {
  const std::size_t n = planes.origins.size();
  // The default run first: the others are compared with it.
  LabRun riemannian = graph_run(OrientationGraph::riemannian, planes, truth, result.default_orientation);
  riemannian.agree_default = 1.0;
  for (const OrientationGraph kind : all_orientation_graphs) {
    if (kind == OrientationGraph::riemannian) {
      result.runs.push_back(riemannian);
      if (options.keep_graphs) result.graphs.push_back({kind, result.default_orientation});
      continue;
    }
    if (kind == OrientationGraph::complete && n > options.max_points_complete) {
      result.runs.push_back(
          skipped_run(std::string(name_of(kind)), LabKind::graph, std::string(name_of(kind)),
                      too_many(n, options.max_points_complete, "the complete graph (n^2 / 2 distances)")));
      continue;
    }
    OrientedNormals<3> oriented;
    LabRun run = graph_run(kind, planes, truth, oriented);
    run.agree_default = share_agreeing(oriented.normals, result.default_orientation.normals);
    result.runs.push_back(std::move(run));
    if (options.keep_graphs) result.graphs.push_back({kind, std::move(oriented)});
  }
  result.runs.push_back(refined_walk_run(planes, truth, result));
}

// Phase VI on each of its queues, over the mesh of the cloud's default
// reconstruction; every queue's mesh must be the binary heap's.
void run_simplify_queues(std::span<const Vec3> points, const LabOptions& options, LabResult& result) {
  PointCloud cloud;
  cloud.positions.assign(points.begin(), points.end());
  ReconstructionOptions reconstruction;
  reconstruction.planes = options.planes;
  const Mesh mesh = reconstruct(std::move(cloud), reconstruction).mesh();
  SimplifyOptions simplify_options;
  simplify_options.ratio = 0.1;
  std::optional<Mesh> reference;
  for (const auto& [name, queue] :
       {std::pair{"binary-heap", SimplifyQueue::binary_heap}, std::pair{"pairing-heap", SimplifyQueue::pairing_heap},
        std::pair{"lazy-queue", SimplifyQueue::lazy}}) {
    LabRun run = make_run(std::string("simplify/") + name, LabKind::simplify, "mesh");
    simplify_options.queue = queue;
    Simplification s = simplify(mesh, simplify_options);
    if (options.spoil == run.name && !s.mesh.triangles.empty())
      std::swap(s.mesh.triangles[0][0], s.mesh.triangles[0][1]);
    run.seconds = s.seconds;
    run.counts = s.counts;
    run.triangles = s.mesh.triangles.size();
    if (!reference) {
      reference = std::move(s.mesh);
    } else if (s.mesh.triangles != reference->triangles || s.mesh.vertices != reference->vertices) {
      throw LabDisagreementError("lab: simplify on the " + std::string(name) + " gives " + count_text(run.triangles) +
                                 " triangles, not the binary heap's mesh of " +
                                 count_text(reference->triangles.size()) + " (or other ones)");
    }
    result.runs.push_back(std::move(run));
  }
}

// Reached only when no check threw: a spoiled run that nothing caught.
void check_spoil_caught(const LabResult& result, const LabOptions& options) {
  if (options.spoil.empty()) return;
  for (const LabRun& run : result.runs)
    if (run.name == options.spoil && run.skipped.empty())
      throw LabDisagreementError("lab: the run '" + options.spoil + "' was spoiled and no check caught it");
  throw InvalidInputError("lab: no run named '" + options.spoil + "' ran (the test hook spoils one)");
}

}  // namespace

std::string_view name_of(LabKind kind) { return kind_names[static_cast<std::size_t>(kind)]; }

LabResult run_lab(std::span<const Vec3> points, const LabOptions& options) {
  if (!options.true_normals.empty() && options.true_normals.size() != points.size())
    throw InvalidInputError("lab: " + count_text(options.true_normals.size()) + " true normals for " +
                            count_text(points.size()) + " points");
  LabResult result;
  Timer timer;
  // Phase I as reconstruct() runs it, in the kd-tree's leaf order (the
  // quadric fits of the refined walk need it).
  KdTree<3> tree(points, options.planes.tree);
  result.order = tree.renumber_by_leaf_order();
  result.planes = estimate_tangent_planes<3>(std::move(tree), options.planes);
  result.seconds_planes = timer.lap();
  std::vector<Vec3> truth;
  for (const std::uint32_t i : options.true_normals.empty() ? std::span<const std::uint32_t>{} : result.order)
    truth.push_back(options.true_normals[i]);
  run_searches(points, result.planes.k, options, result);
  run_graphs(result.planes, truth, options, result);
  const Graph g =
      with_orientation_costs<3>(result.default_orientation.graph.graph, std::span<const Vec3>(result.planes.normals));
  run_queues(g, options, result);
  run_msts(g, options, result);
  run_euclidean_msts(points, options, result);
  if (options.simplify) run_simplify_queues(points, options, result);
  check_spoil_caught(result, options);
  return result;
}

}  // namespace recon
