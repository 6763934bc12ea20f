// The playground's window into the library: reconstruct_curve on the
// points the page sends, and every phase's result laid out as flat arrays of
// doubles that the page reads straight from WebAssembly memory (no
// serialisation; a few hundred points update in a few milliseconds).
//
// Protocol (all functions are C, called from playground.js):
//   recon_run(xy, n, k, rho, delta, cell) runs phases I-IV on n points
//     (xy: 2n doubles); rho, delta, cell <= 0 mean "estimate". Returns 0, or 1
//     when the library refused the input (recon_error() says why).
//   recon_layer(id) / recon_layer_size(id): layer `id`'s doubles, laid out
//     as described at `Layer` below, valid until the next recon_run.

#include "recon/errors.h"
#include "recon/reconstruct_curve.h"
#include "recon/timer.h"

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
constexpr std::size_t tree_edges = 3;   // per spanning tree edge: parent, child (point indices)
constexpr std::size_t squares = 4;      // per visited square: x, y (lower left corner), f at its centre (mean of the
                                        // corners), defined (0/1: 0 when a corner is undefined)
constexpr std::size_t corners = 5;      // per evaluated corner: x, y, f, defined (0/1)
constexpr std::size_t vertices = 6;     // per curve vertex, curve after curve: x, y
constexpr std::size_t curves = 7;       // per curve: first vertex (counted in vertices), vertex count, closed (0/1)
constexpr std::size_t stats = 8;        // the figures below
constexpr std::size_t layer_count = 9;

// Entries of the stats layer.
enum Stat : std::size_t {
  k_used, rho_used, delta_used, cell_used, components, seconds_planes, seconds_orientation, seconds_distance,
  seconds_contour, seconds_total, undefined_squares, seam_squares, saddle_squares, stat_count
};

std::array<std::vector<double>, layer_count> layers;
std::string error_message;

// Fills the layers, which recon_run has emptied.
void fill_layers(const recon::CurveReconstruction& r, double seconds) {
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
  const recon::SpanningForest& forest = r.oriented.tree;
  for (std::uint32_t v = 0; v < forest.parent.size(); ++v)
    if (forest.parent[v] != recon::SpanningForest::no_parent)
      layers[tree_edges].insert(layers[tree_edges].end(), {double(forest.parent[v]), double(v)});

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
    auto at = std::lower_bound(c.corners.begin(), c.corners.end(), key,
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
    layers[curves].insert(layers[curves].end(), {double(layers[vertices].size() / 2), double(line.vertices.size()),
                                                 line.closed ? 1.0 : 0.0});
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
}

}  // namespace

extern "C" {

EMSCRIPTEN_KEEPALIVE int recon_run(const double* xy, int n, int k, double rho, double delta, double cell) {
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
    const recon::CurveReconstruction r = recon::reconstruct_curve(points, options);
    fill_layers(r, timer.elapsed());
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
  return id >= 0 && static_cast<std::size_t>(id) < layer_count ? static_cast<int>(layers[static_cast<std::size_t>(id)].size())
                                                                : 0;
}

}  // extern "C"
