// The playground's window into the library: reconstruct_curve on the
// points the page sends, and every phase's result laid out as flat arrays of
// doubles that the page reads straight from WebAssembly memory (no
// serialisation; a few hundred points update in a few milliseconds).
//
// Protocol (all functions are C, called from playground.js):
//   recon_run(xy, n, k, rho, delta, cell, graph, tree) runs phases I-IV on n
//     points (xy: 2n doubles); rho, delta, cell <= 0 mean "estimate". graph
//     is the graph phase II walks (an index into all_orientation_graphs:
//     complete, emst, knn, mutual-knn, riemannian); tree the spanning-tree
//     algorithm run on it (an index into `trees` below), whose tree the
//     page draws and whose operation counts it shows. Returns 0, or 1 when
//     the library refused the input (recon_error() says why).
//     (Every minimum spanning tree of a graph weighs the same, and the
//     queues order ties alike: phase II's walk follows Prim's tree on the
//     binary heap whichever algorithm is chosen here, and the page compares
//     their work. The tree is timed as it counts: Prim's queues through
//     CountingQueue, so its time includes the counting.)
//   recon_layer(id) / recon_layer_size(id): layer `id`'s doubles, laid out
//     as described at `Layer` below, valid until the next recon_run.

#include "recon/alternatives/boruvka.h"
#include "recon/alternatives/counting_queue.h"
#include "recon/alternatives/kruskal.h"
#include "recon/core/errors.h"
#include "recon/core/timer.h"
#include "recon/curves/reconstruct_curve.h"
#include "recon/structures/fibonacci_heap.h"
#include "recon/structures/list_heap.h"
#include "recon/structures/pairing_heap.h"

#include <emscripten/emscripten.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <exception>
#include <string>
#include <utility>
#include <vector>

namespace {

using recon::Vec2;

// Layers (ids shared with playground.js):
constexpr std::size_t normals = 0;      // per point: nx, ny (oriented)
constexpr std::size_t kd_splits = 1;    // per inner kd-tree node: x0, y0, x1, y1 of its splitting segment, depth
constexpr std::size_t graph_edges = 2;  // per Riemannian graph edge: i, j (point indices)
constexpr std::size_t tree_edges = 3;   // per spanning tree edge of the chosen algorithm: its two ends (point indices)
constexpr std::size_t squares = 4;      // per visited square: x, y (lower left corner), f at its centre (mean of the
                                        // corners), defined (0/1: 0 when a corner is undefined)
constexpr std::size_t corners = 5;      // per evaluated corner: x, y, f, defined (0/1)
constexpr std::size_t vertices = 6;     // per curve vertex, curve after curve: x, y
constexpr std::size_t curves = 7;       // per curve: first vertex (counted in vertices), vertex count, closed (0/1)
constexpr std::size_t stats = 8;        // the figures below
constexpr std::size_t layer_count = 9;

// Entries of the stats layer.
enum Stat : std::size_t {
  k_used,
  rho_used,
  delta_used,
  cell_used,
  components,
  seconds_planes,
  seconds_orientation,
  seconds_distance,
  seconds_contour,
  seconds_total,
  undefined_squares,
  seam_squares,
  saddle_squares,
  // the chosen spanning-tree algorithm on the chosen graph (costs 1 - |n_i . n_j|)
  seconds_tree,
  tree_weight,
  pushes,
  pops,
  decrease_keys,
  comparisons,
  finds,
  unions,
  rounds,
  graph_edge_count,
  stat_count
};

// The spanning-tree algorithms the page offers (ids shared with playground.js).
enum Tree : int { prim_binary, prim_fibonacci, prim_pairing, prim_list, kruskal, boruvka, tree_count };

// What the chosen algorithm did: its edges, time and counts.
struct TreeRun {
  std::vector<recon::Edge> edges;
  double weight = 0.0, seconds = 0.0;
  recon::OperationCounts counts;
};

template <template <class> class Heap>
TreeRun prim_on(const recon::Graph& g) {
  TreeRun run;
  recon::Timer timer;
  const recon::SpanningForest forest = recon::prim_minimum_spanning_forest<recon::CountingQueue<Heap>>(g);
  run.seconds = timer.elapsed();
  run.counts = forest.counts;
  run.weight = forest.total_weight;
  for (std::uint32_t v = 0; v < forest.parent.size(); ++v)
    if (forest.parent[v] != recon::SpanningForest::no_parent) run.edges.push_back({forest.parent[v], v, 0.0});
  return run;
}

TreeRun edges_of(recon::MinimumSpanningEdges tree, double seconds) {
  return {std::move(tree.edges), tree.total_weight, seconds, tree.counts};
}

// The chosen algorithm on phase II's graph with its costs stored.
TreeRun run_tree(const recon::CurveReconstruction& r, int tree) {
  const recon::Graph g =
      recon::with_orientation_costs<2>(r.oriented.graph.graph, std::span<const Vec2>(r.planes.normals));
  recon::Timer timer;
  switch (tree) {
    case prim_fibonacci:
      return prim_on<recon::FibonacciHeap>(g);
    case prim_pairing:
      return prim_on<recon::PairingHeap>(g);
    case prim_list:
      return prim_on<recon::ListHeap>(g);
    case kruskal:
      return edges_of(recon::kruskal_minimum_spanning_forest(g), timer.elapsed());
    case boruvka:
      return edges_of(recon::boruvka_minimum_spanning_forest(g), timer.elapsed());
    default:
      return prim_on<recon::IndexedBinaryHeap>(g);
  }
}

std::array<std::vector<double>, layer_count> layers;
std::string error_message;

// Fills the layers, which recon_run has emptied.
void fill_layers(const recon::CurveReconstruction& r, const TreeRun& chosen, double seconds) {
  for (const Vec2& n : r.oriented.normals) layers[normals].insert(layers[normals].end(), {n.x(), n.y()});

  // A kd-tree node splits its box at the middle of the gap between its
  // children (left_max .. right_min) along its axis.
  const auto& tree = r.planes.point_tree;
  std::vector<int> depth(tree.nodes().size(), 0);
  for (std::size_t id = 0; id < tree.nodes().size(); ++id) {
    const auto& node = tree.nodes()[id];
    if (node.is_leaf()) continue;
    depth[node.left] = depth[node.right] = depth[id] + 1;
    const recon::Box<2>& box = tree.boxes()[id];
    const double at = 0.5 * (node.left_max + node.right_min);
    const double d = depth[id];
    if (node.axis == 0) {
      layers[kd_splits].insert(layers[kd_splits].end(), {at, box.min.y(), at, box.max.y(), d});
    } else {
      layers[kd_splits].insert(layers[kd_splits].end(), {box.min.x(), at, box.max.x(), at, d});
    }
  }

  const recon::Graph& graph = r.oriented.graph.graph;
  for (std::uint32_t v = 0; v < graph.vertex_count(); ++v)
    for (const std::uint32_t u : graph.neighbors(v))
      if (v < u) layers[graph_edges].insert(layers[graph_edges].end(), {double(v), double(u)});
  for (const recon::Edge& e : chosen.edges)
    layers[tree_edges].insert(layers[tree_edges].end(), {double(e.u), double(e.v)});

  const recon::MarchingSquaresResult& c = r.contour;
  auto corner_position = [&](std::int32_t i, std::int32_t j) {
    return Vec2(c.origin + c.cell * Vec2(static_cast<double>(i), static_cast<double>(j)));
  };
  for (const recon::SquareCorner& corner : c.corners) {
    const Vec2 p = corner_position(corner.index[0], corner.index[1]);
    layers[corners].insert(layers[corners].end(), {p.x(), p.y(), corner.value, corner.defined ? 1.0 : 0.0});
  }
  // Squares: their corners are among the kept ones (sorted by index).
  auto find_corner = [&](std::int32_t i, std::int32_t j) -> const recon::SquareCorner* {
    const std::array<std::int32_t, 2> key{i, j};
    auto at = std::lower_bound(
        c.corners.begin(), c.corners.end(), key,
        [](const recon::SquareCorner& a, const std::array<std::int32_t, 2>& b) { return a.index < b; });
    return at != c.corners.end() && at->index == key ? &*at : nullptr;
  };
  for (const auto& square : c.squares) {
    const Vec2 p = corner_position(square[0], square[1]);
    double sum = 0.0;
    bool defined = true;
    for (const auto& [di, dj] : {std::pair{0, 0}, std::pair{1, 0}, std::pair{1, 1}, std::pair{0, 1}}) {
      const recon::SquareCorner* corner = find_corner(square[0] + di, square[1] + dj);
      defined = defined && corner != nullptr && corner->defined;
      if (corner != nullptr) sum += corner->value;
    }
    layers[squares].insert(layers[squares].end(), {p.x(), p.y(), defined ? 0.25 * sum : 0.0, defined ? 1.0 : 0.0});
  }

  const recon::PolylineSet& set = c.curves;
  // Each curve's vertices contiguously, in curve order: the page draws
  // them one after the other.
  for (const recon::Polyline& line : set.polylines) {
    layers[curves].insert(layers[curves].end(),
                          {double(layers[vertices].size() / 2), double(line.vertices.size()), line.closed ? 1.0 : 0.0});
    for (const std::uint32_t v : line.vertices)
      layers[vertices].insert(layers[vertices].end(), {set.vertices[v].x(), set.vertices[v].y()});
  }

  std::vector<double>& s = layers[stats];
  s.assign(stat_count, 0.0);
  s[k_used] = r.planes.k;
  s[rho_used] = r.planes.rho;
  s[delta_used] = r.delta;
  s[cell_used] = c.cell;
  s[components] = static_cast<double>(r.oriented.component_count());
  s[seconds_planes] = r.planes.seconds_tree + r.planes.seconds_knn_pca + r.planes.seconds_spacing;
  s[seconds_orientation] = r.oriented.graph.seconds_emst + r.oriented.graph.seconds_graph + r.oriented.seconds_mst;
  s[seconds_distance] = r.seconds_distance_setup + c.seconds_field;
  s[seconds_contour] = c.seconds - c.seconds_field;
  s[seconds_total] = seconds;
  s[undefined_squares] = static_cast<double>(c.undefined_squares);
  s[seam_squares] = static_cast<double>(c.seam_squares);
  s[saddle_squares] = static_cast<double>(c.saddle_squares);
  s[seconds_tree] = chosen.seconds;
  s[tree_weight] = chosen.weight;
  s[pushes] = static_cast<double>(chosen.counts.pushes);
  s[pops] = static_cast<double>(chosen.counts.pops);
  s[decrease_keys] = static_cast<double>(chosen.counts.decrease_keys);
  s[comparisons] = static_cast<double>(chosen.counts.comparisons);
  s[finds] = static_cast<double>(chosen.counts.finds);
  s[unions] = static_cast<double>(chosen.counts.unions);
  s[rounds] = static_cast<double>(chosen.counts.rounds);
  s[graph_edge_count] = static_cast<double>(graph.edge_count());
}

}  // namespace

extern "C" {

EMSCRIPTEN_KEEPALIVE int recon_run(const double* xy, int n, int k, double rho, double delta, double cell, int graph,
                                   int tree) {
  error_message.clear();
  for (auto& layer : layers) layer.clear();
  try {
    recon::Timer timer;
    std::vector<Vec2> points;
    points.reserve(static_cast<std::size_t>(std::max(n, 0)));
    for (int i = 0; i < n; ++i) points.emplace_back(xy[2 * i], xy[2 * i + 1]);
    recon::CurveReconstructionOptions options;
    options.planes.k = k;
    options.planes.adapt_k = false;  // the slider's k is the k used
    if (rho > 0.0) options.planes.rho = rho;
    if (delta > 0.0) options.distance.delta = delta;
    if (cell > 0.0) options.cell = cell;
    options.keep_corners = true;
    if (graph < 0 || graph >= static_cast<int>(std::size(recon::all_orientation_graphs)) || tree < 0 ||
        tree >= tree_count)
      throw recon::InvalidInputError("playground: no graph " + std::to_string(graph) + " or tree " +
                                     std::to_string(tree));
    options.graph = recon::all_orientation_graphs[graph];
    const recon::CurveReconstruction r = recon::reconstruct_curve(points, options);
    const double seconds = timer.elapsed();
    fill_layers(r, run_tree(r, tree), seconds);
    return 0;
  } catch (const std::exception& e) {
    error_message = e.what();
    return 1;
  }
}

EMSCRIPTEN_KEEPALIVE const char* recon_error() { return error_message.c_str(); }

EMSCRIPTEN_KEEPALIVE const double* recon_layer(int id) {
  return id >= 0 && static_cast<std::size_t>(id) < layer_count ? layers[static_cast<std::size_t>(id)].data() : nullptr;
}

EMSCRIPTEN_KEEPALIVE int recon_layer_size(int id) {
  return id >= 0 && static_cast<std::size_t>(id) < layer_count
             ? static_cast<int>(layers[static_cast<std::size_t>(id)].size())
             : 0;
}

}  // extern "C"
