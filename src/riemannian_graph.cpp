#include "recon/riemannian_graph.h"

#include "recon/emst.h"
#include "recon/errors.h"
#include "recon/interruption.h"
#include "recon/parallel.h"  // AtomicRef
#include "recon/timer.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <numeric>
#include <string>

namespace recon {
namespace {

// How far phase I's lists reach for certain: every sample closer to x_i
// than the farthest listed one is listed (the float radius is shaded down
// so that rounding cannot overstate it).
std::vector<double> certain_radii2(std::span<const float> radius) {
  std::vector<double> radius2(radius.size());
  for (std::size_t i = 0; i < radius.size(); ++i) {
    const double r = static_cast<double>(radius[i]) * (1.0 - 1e-6);
    radius2[i] = r * r;
  }
  return radius2;
}

}  // namespace

template <int D>
RiemannianGraph<D> build_riemannian_graph(const TangentPlanes<D>& planes, const RiemannianGraphOptions& options) {
  const std::size_t n = planes.origins.size();
  const int lists_k = planes.neighbors.k;
  if (options.k < 0 || options.k > lists_k || planes.neighbors.size() != n)
    throw InvalidInputError("k = " + std::to_string(options.k) + " for the Riemannian graph, but phase I kept " +
                            std::to_string(lists_k) + " neighbours per point");
  const auto k = static_cast<std::size_t>(options.k > 0 ? options.k : lists_k);
  RiemannianGraph<D> result;
  Timer timer;
  // A tree numbered by leaf order holds the samples by index already.
  std::vector<Vec<D>> copy;
  if (!planes.point_tree.numbered_by_leaf_order()) copy = samples_of<D>(planes);
  const std::span<const Vec<D>> samples = copy.empty() ? planes.point_tree.points() : std::span<const Vec<D>>(copy);
  {
    const std::vector<double> radius2 = certain_radii2(planes.radius);
    result.emst = euclidean_minimum_spanning_tree<D>(planes.point_tree, samples, EmstHints{&planes.neighbors, radius2});
  }
  result.seconds_emst = timer.lap();
  interruption_point();

  // (Raw pointers: the loops below run over every list entry.)
  const Vec<D>* const origin = planes.origins.data();
  const Vec<D>* const normal = planes.normals.data();
  const float* const local_gap = planes.local_gap.data();
  const std::uint32_t* const list = planes.neighbors.indices.data();
  const auto stride = static_cast<std::size_t>(lists_k);
  const double gap_factor = options.gap_factor;
  auto is_gap = [=](std::uint32_t i, std::uint32_t j) {
    const Vec<D> d = origin[j] - origin[i];
    const double reach = gap_factor * static_cast<double>(std::max(local_gap[i], local_gap[j]));
    const double length2 = d.squaredNorm();
    if (!(length2 > reach * reach)) return false;
    // |unit(d) . n| > 0.25 at i or j, squared: no root and no division
    // (many list entries lie beyond the reach, and this runs for each).
    const double at_i = d.dot(normal[i]), at_j = d.dot(normal[j]);
    return std::max(at_i * at_i, at_j * at_j) > 0.0625 * length2;
  };
  auto row = [=](std::uint32_t i) { return std::span<const std::uint32_t>(list + i * stride, k); };
  auto lists = [=](std::uint32_t i, std::uint32_t j) {  // x_j in the first k of N(x_i)
    const std::uint32_t* r = list + i * stride;
    for (std::size_t e = 0; e < k; ++e)
      if (r[e] == j) return true;
    return false;
  };
  // The same question answered by distance where it can be: N(x_i) holds
  // every sample nearer than its farthest member, and none farther, so only
  // a sample at (about) that distance needs the list read (radius is float:
  // the band around it covers its rounding).
  const Vec<D>* const sample = samples.data();
  const float* const radius = planes.radius.data();
  const bool whole_lists = k == static_cast<std::size_t>(lists_k);
  auto listed = [=](std::uint32_t i, std::uint32_t j) {  // x_j in the first k of N(x_i)
    if (whole_lists) {
      const double d2 = (sample[j] - sample[i]).squaredNorm();
      const auto r = static_cast<double>(radius[i]);
      if (d2 < r * r * (1.0 - 1e-6)) return true;
      if (d2 > r * r * (1.0 + 1e-6)) return false;
    }
    return lists(i, j);
  };

  // The graph is laid out directly in CSR form (no edge list to sort). Row
  // i holds, in this order: i's own kept neighbours (nearest first), the
  // points that list i without i listing them (the symmetric closure, by
  // index), and the EMST edges that neither lists. A first pass marks, per
  // list entry, whether the edge is kept and whether it must also be
  // written into the other row; the rows are then filled in parallel, and
  // the closure part of each sorted, so the graph does not depend on the
  // thread count.
  const std::size_t words = (k + 31) / 32;  // 2 bits per entry: kept, reverse
  std::vector<std::uint64_t> marks(n * words, 0);
  std::vector<std::uint16_t> own(n, 0);      // kept entries of row i (at most k <= 256)
  std::vector<std::uint32_t> degree(n, 0);   // the other entries of row i
  const auto count = static_cast<std::int64_t>(n);
#pragma omp parallel for schedule(dynamic, 4096)
  for (std::int64_t s = 0; s < count; ++s) {
    const auto i = static_cast<std::uint32_t>(s);
    const auto r = row(i);
    for (std::size_t e = 0; e < k; ++e) {
      const std::uint32_t j = r[e];
      if (j == i || is_gap(i, j)) continue;
      ++own[i];
      std::uint64_t bits = 1;
      if (!listed(j, i)) {
        bits |= 2;
        AtomicRef<std::uint32_t>(degree[j]).fetch_add(1, std::memory_order_relaxed);
      }
      marks[i * words + e / 32] |= bits << (2 * (e % 32));
    }
  }
  // Each EMST edge is a gap, or in the lists already, or an edge of its own
  // (told apart in parallel, collected in the tree's order).
  enum : std::uint8_t { in_lists, extra_edge, gap_edge };
  std::vector<std::uint8_t> kind(result.emst.size());
  const auto emst_count = static_cast<std::int64_t>(result.emst.size());
#pragma omp parallel for schedule(static)
  for (std::int64_t s = 0; s < emst_count; ++s) {
    const Edge& e = result.emst[static_cast<std::size_t>(s)];
    kind[static_cast<std::size_t>(s)] = is_gap(e.u, e.v)                               ? gap_edge
                                        : !listed(e.u, e.v) && !listed(e.v, e.u) ? extra_edge
                                                                                 : in_lists;
  }
  std::vector<Edge> extra;  // EMST edges that neither end lists
  std::vector<Edge> gaps;
  for (std::size_t s = 0; s < kind.size(); ++s) {
    if (kind[s] == gap_edge) gaps.push_back(result.emst[s]);
    if (kind[s] == extra_edge) extra.push_back(result.emst[s]);
  }
  result.gap_emst_edges = gaps.size();
  kind = {};
  for (const Edge& e : extra) {
    ++degree[e.u];
    ++degree[e.v];
  }

  Graph& g = result.graph;
  g.offsets.assign(n + 1, 0);
  for (std::size_t i = 0; i < n; ++i) g.offsets[i + 1] = g.offsets[i] + own[i] + degree[i];
  g.targets.resize(g.offsets.back());
  // degree[i] now counts the closure entries written into row i.
  std::fill(degree.begin(), degree.end(), 0u);
#pragma omp parallel for schedule(dynamic, 4096)
  for (std::int64_t s = 0; s < count; ++s) {
    const auto i = static_cast<std::uint32_t>(s);
    const auto r = row(i);
    std::uint64_t write = g.offsets[i];
    for (std::size_t e = 0; e < k; ++e) {
      const std::uint64_t bits = marks[i * words + e / 32] >> (2 * (e % 32));
      if (bits & 1) g.targets[write++] = r[e];
      if (bits & 2) {
        const std::uint32_t j = r[e];
        const std::uint32_t slot = AtomicRef<std::uint32_t>(degree[j]).fetch_add(1, std::memory_order_relaxed);
        g.targets[g.offsets[j] + own[j] + slot] = i;
      }
    }
  }
  // The pieces of the data (the graph's connected components), without
  // walking the graph: the kept EMST edges join nearly everything, and only
  // the few kept k-NN edges between two of their pieces can join more (found
  // in parallel). Numbered as connected_components() numbers them. When no
  // EMST edge crosses a gap, the tree alone spans the graph: one piece.
  if (gaps.empty() && n > 0) {
    result.components.label.assign(n, 0);
    result.components.sizes.assign(1, static_cast<std::uint32_t>(n));
  } else {
    UnionFind sets(n);
    for (const Edge& e : result.emst)
      if (!is_gap(e.u, e.v)) sets.unite(e.u, e.v);
    std::vector<std::uint32_t> piece(n);
#pragma omp parallel for schedule(static)
    for (std::int64_t s = 0; s < count; ++s) piece[static_cast<std::size_t>(s)] = sets.root(static_cast<std::uint32_t>(s));
    std::vector<Edge> across;
#pragma omp parallel
    {
      std::vector<Edge> mine;
#pragma omp for schedule(dynamic, 4096) nowait
      for (std::int64_t s = 0; s < count; ++s) {
        const auto i = static_cast<std::uint32_t>(s);
        const auto r = row(i);
        for (std::size_t e = 0; e < k; ++e)
          if (((marks[i * words + e / 32] >> (2 * (e % 32))) & 1u) && piece[i] != piece[r[e]])
            mine.push_back({i, r[e], 0.0});
      }
#pragma omp critical(recon_riemannian_graph_across)
      across.insert(across.end(), mine.begin(), mine.end());
    }
    for (const Edge& e : across) sets.unite(e.u, e.v);  // order does not matter to the sets
    constexpr std::uint32_t none = UINT32_MAX;
    std::vector<std::uint32_t>& label_of_root = piece;  // reused
    std::fill(label_of_root.begin(), label_of_root.end(), none);
    Components& c = result.components;
    c.label.resize(n);
    for (std::uint32_t v = 0; v < n; ++v) {
      std::uint32_t& l = label_of_root[sets.find(v)];
      if (l == none) {
        l = static_cast<std::uint32_t>(c.sizes.size());
        c.sizes.push_back(0);
      }
      c.label[v] = l;
      ++c.sizes[l];
    }
  }
  marks = {};
#pragma omp parallel for schedule(dynamic, 4096)
  for (std::int64_t s = 0; s < count; ++s) {
    const auto i = static_cast<std::size_t>(s);
    const auto begin = g.targets.begin() + static_cast<std::ptrdiff_t>(g.offsets[i] + own[i]);
    std::sort(begin, begin + static_cast<std::ptrdiff_t>(degree[i]));
  }
  for (const Edge& e : extra) {
    g.targets[g.offsets[e.u] + own[e.u] + degree[e.u]++] = e.v;
    g.targets[g.offsets[e.v] + own[e.v] + degree[e.v]++] = e.u;
  }
  own = {};
  degree = {};

  // Join back pieces too small to be objects, shortest gap first. Pieces only
  // grow, so one pass leaves no small piece that still has a gap edge.
  if (!gaps.empty()) {
    const std::size_t min_points = options.min_component_points > 0
                                       ? static_cast<std::size_t>(options.min_component_points)
                                       : 2 * static_cast<std::size_t>(lists_k);
    const std::vector<std::uint32_t>& piece = result.components.label;
    UnionFind pieces(result.components.sizes.size());
    std::vector<std::uint32_t> size = result.components.sizes;
    std::sort(gaps.begin(), gaps.end(), [](const Edge& a, const Edge& b) { return a.weight < b.weight; });
    std::vector<Edge> joins;
    for (const Edge& e : gaps) {
      const std::uint32_t a = pieces.find(piece[e.u]), b = pieces.find(piece[e.v]);
      if (a == b || (size[a] >= min_points && size[b] >= min_points)) continue;
      pieces.unite(a, b);
      size[pieces.find(a)] = size[a] + size[b];
      joins.push_back(e);
    }
    if (!joins.empty()) {
      result.rejoined = joins.size();
      g = with_edges(g, joins);
      result.components = connected_components(g);
    }
  }
  result.edge_count = result.graph.edge_count();
  result.seconds_graph = timer.lap();
  return result;
}

template <int D>
Graph with_orientation_costs(Graph graph, std::span<const Vec<D>> normals) {
  graph.weights.resize(graph.targets.size());
  for (std::uint32_t v = 0; v < graph.vertex_count(); ++v)
    for (std::uint64_t e = graph.offsets[v]; e < graph.offsets[v + 1]; ++e)
      graph.weights[e] = std::max(0.0, orientation_cost<D>(normals[v], normals[graph.targets[e]]));
  return graph;
}

template Graph with_orientation_costs<2>(Graph, std::span<const Vec<2>>);
template Graph with_orientation_costs<3>(Graph, std::span<const Vec<3>>);
template RiemannianGraph<2> build_riemannian_graph<2>(const TangentPlanes<2>&, const RiemannianGraphOptions&);
template RiemannianGraph<3> build_riemannian_graph<3>(const TangentPlanes<3>&, const RiemannianGraphOptions&);

}  // namespace recon
