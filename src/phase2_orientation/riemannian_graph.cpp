#include "recon/phase2_orientation/riemannian_graph.h"

#include "recon/core/detail/parallel_for.h"
#include "recon/core/errors.h"
#include "recon/core/interruption.h"
#include "recon/core/parallel.h"  // AtomicRef
#include "recon/core/progress.h"
#include "recon/core/timer.h"
#include "recon/phase2_orientation/emst.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <numeric>
#include <string>

namespace recon {
namespace {

using detail::parallel_for;
using detail::parallel_for_dynamic;

// The k-NN edges to take from each of phase I's lists: the first k, all of
// them when options.k is 0.
template <int D>
std::size_t checked_k(const TangentPlanes<D>& planes, const RiemannianGraphOptions& options) {
  const int lists_k = planes.neighbors.k;
  if (options.k < 0 || options.k > lists_k || planes.neighbors.size() != planes.origins.size())
    throw InvalidInputError("k = " + std::to_string(options.k) + " for the Riemannian graph, but phase I kept " +
                            std::to_string(lists_k) + " neighbours per point");
  return static_cast<std::size_t>(options.k > 0 ? options.k : lists_k);
}

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

// The EMST of the samples, hinted by phase I's lists.
template <int D>
std::vector<Edge> emst_of_samples(const TangentPlanes<D>& planes, std::span<const Vec<D>> samples) {
  const std::vector<double> radius2 = certain_radii2(planes.radius);
  return euclidean_minimum_spanning_tree<D>(planes.point_tree, samples, EmstHints{&planes.neighbors, radius2});
}

// Phase I's lists and planes as this phase asks about them. (Raw pointers:
// the loops below run over every list entry.)
template <int D>
struct Neighbourhoods {
  const Vec<D>* origin;
  const Vec<D>* normal;
  const float* local_gap;
  const std::uint32_t* list;
  std::size_t stride;  // phase I's k
  std::size_t k;       // the entries of each list taken
  double gap_factor;
  const Vec<D>* sample;
  const float* radius;
  bool whole_lists;  // k == stride

  Neighbourhoods(const TangentPlanes<D>& planes, std::span<const Vec<D>> samples, std::size_t k_taken,
                 double gap_factor_)
      : origin(planes.origins.data()),
        normal(planes.normals.data()),
        local_gap(planes.local_gap.data()),
        list(planes.neighbors.indices.data()),
        stride(static_cast<std::size_t>(planes.neighbors.k)),
        k(k_taken),
        gap_factor(gap_factor_),
        sample(samples.data()),
        radius(planes.radius.data()),
        whole_lists(k == stride) {}

  [[nodiscard]] std::span<const std::uint32_t> row(std::uint32_t i) const { return {list + i * stride, k}; }

  // The gap test of the header, between origins.
  [[nodiscard]] bool is_gap(std::uint32_t i, std::uint32_t j) const {
    const Vec<D> d = origin[j] - origin[i];
    const double reach = gap_factor * static_cast<double>(std::max(local_gap[i], local_gap[j]));
    const double length2 = d.squaredNorm();
    if (!(length2 > reach * reach)) return false;
    // |unit(d) . n| > 0.25 at i or j, squared: no root and no division
    // (many list entries lie beyond the reach, and this runs for each).
    const double at_i = d.dot(normal[i]), at_j = d.dot(normal[j]);
    return std::max(at_i * at_i, at_j * at_j) > 0.0625 * length2;
  }

  // x_j in the first k of N(x_i), by reading the list.
  [[nodiscard]] bool in_list(std::uint32_t i, std::uint32_t j) const {
    const std::uint32_t* r = list + i * stride;
    for (std::size_t e = 0; e < k; ++e)
      if (r[e] == j) return true;
    return false;
  }

  // The same question answered by distance where it can be: N(x_i) holds
  // every sample nearer than its farthest member, and none farther, so only
  // a sample at (about) that distance needs the list read (radius is float:
  // the band around it covers its rounding).
  [[nodiscard]] bool listed(std::uint32_t i, std::uint32_t j) const {
    if (whole_lists) {
      const double d2 = (sample[j] - sample[i]).squaredNorm();
      const auto r = static_cast<double>(radius[i]);
      if (d2 < r * r * (1.0 - 1e-6)) return true;
      if (d2 > r * r * (1.0 + 1e-6)) return false;
    }
    return in_list(i, j);
  }
};

// The graph is laid out directly in CSR form (no edge list to sort). Row i
// holds, in this order: i's own kept neighbours (nearest first), the points
// that list i without i listing them (the symmetric closure, by index), and
// the EMST edges that neither lists. A first pass marks, per list entry,
// whether the edge is kept and whether it must also be written into the
// other row; the rows are then filled in parallel, and the closure part of
// each sorted, so the graph does not depend on the thread count.
struct RowPlan {
  std::size_t words;  // per list: 2 bits per entry (kept, reverse)
  std::vector<std::uint64_t> marks;
  std::vector<std::uint16_t> own;     // kept entries of row i (at most k <= 256)
  std::vector<std::uint32_t> degree;  // the other entries of row i

  [[nodiscard]] std::uint64_t bits(std::size_t i, std::size_t e) const {
    return marks[i * words + e / 32] >> (2 * (e % 32));
  }
};

// The first pass: which list entries are edges, and which must be written
// into the other row too (counted in that row's degree).
template <int D>
RowPlan mark_list_entries(const Neighbourhoods<D>& lists, std::size_t n) {
  const std::size_t k = lists.k;
  RowPlan plan{(k + 31) / 32, {}, {}, {}};
  plan.marks.assign(n * plan.words, 0);
  plan.own.assign(n, 0);
  plan.degree.assign(n, 0);
  parallel_for_dynamic(n, 4096, [&](std::size_t s) {
    // (Local copies, which the writes below cannot reach: the loop keeps
    // them in registers instead of reading them again after every write.)
    const Neighbourhoods<D> own_lists = lists;
    std::uint64_t* const marks = plan.marks.data() + s * plan.words;
    const auto i = static_cast<std::uint32_t>(s);
    const auto r = own_lists.row(i);
    for (std::size_t e = 0; e < k; ++e) {
      const std::uint32_t j = r[e];
      if (j == i || own_lists.is_gap(i, j)) continue;
      ++plan.own[i];
      std::uint64_t bits = 1;
      if (!own_lists.listed(j, i)) {
        bits |= 2;
        AtomicRef<std::uint32_t>(plan.degree[j]).fetch_add(1, std::memory_order_relaxed);
      }
      marks[e / 32] |= bits << (2 * (e % 32));
    }
  });
  return plan;
}

// The EMST edges that are gaps, and those that neither end lists (edges of
// their own), in the tree's order; the rest are in the lists already.
struct EmstEdgeKinds {
  std::vector<Edge> gaps;
  std::vector<Edge> extra;
};

template <int D>
EmstEdgeKinds sort_emst_edges(const Neighbourhoods<D>& lists, const std::vector<Edge>& emst) {
  enum : std::uint8_t { in_lists, extra_edge, gap_edge };
  std::vector<std::uint8_t> kind(emst.size());
  parallel_for(emst.size(), [&](std::size_t s) {
    const Edge& e = emst[s];
    kind[s] = lists.is_gap(e.u, e.v)                               ? gap_edge
              : !lists.listed(e.u, e.v) && !lists.listed(e.v, e.u) ? extra_edge
                                                                   : in_lists;
  });
  EmstEdgeKinds kinds;
  for (std::size_t s = 0; s < kind.size(); ++s) {
    if (kind[s] == gap_edge) kinds.gaps.push_back(emst[s]);
    if (kind[s] == extra_edge) kinds.extra.push_back(emst[s]);
  }
  return kinds;
}

// The rows' offsets, then each row's own kept entries and the closure
// entries it writes into other rows. plan.degree then counts the closure
// entries written into each row.
template <int D>
void fill_rows(const Neighbourhoods<D>& lists, RowPlan& plan, std::span<const Edge> extra, Graph& g) {
  const std::size_t n = plan.own.size();
  for (const Edge& e : extra) {
    ++plan.degree[e.u];
    ++plan.degree[e.v];
  }
  g.offsets.assign(n + 1, 0);
  for (std::size_t i = 0; i < n; ++i) g.offsets[i + 1] = g.offsets[i] + plan.own[i] + plan.degree[i];
  g.targets.resize(g.offsets.back());
  std::fill(plan.degree.begin(), plan.degree.end(), 0u);
  const std::size_t k = lists.k;
  ProgressCounter* const progress = progress_counter();
  parallel_for_dynamic(n, 4096, [&](std::size_t s) {
    if (progress != nullptr && (s & 4095) == 4095) progress->advance(4096);
    const std::uint64_t* const marks = plan.marks.data() + s * plan.words;  // (a local copy, as above)
    const auto i = static_cast<std::uint32_t>(s);
    const auto r = lists.row(i);
    std::uint64_t write = g.offsets[i];
    for (std::size_t e = 0; e < k; ++e) {
      const std::uint64_t bits = marks[e / 32] >> (2 * (e % 32));
      if (bits & 1) g.targets[write++] = r[e];
      if (bits & 2) {
        const std::uint32_t j = r[e];
        const std::uint32_t slot = AtomicRef<std::uint32_t>(plan.degree[j]).fetch_add(1, std::memory_order_relaxed);
        g.targets[g.offsets[j] + plan.own[j] + slot] = i;
      }
    }
  });
}

// The sets' members numbered as connected_components() numbers them: in
// order of each set's smallest member.
Components numbered_components(UnionFind& sets, std::vector<std::uint32_t>& scratch) {
  constexpr std::uint32_t none = UINT32_MAX;
  const std::size_t n = scratch.size();
  std::vector<std::uint32_t>& label_of_root = scratch;
  std::fill(label_of_root.begin(), label_of_root.end(), none);
  Components c;
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
  return c;
}

// The pieces of the data (the graph's connected components), without
// walking the graph: the kept EMST edges join nearly everything, and only
// the few kept k-NN edges between two of their pieces can join more (found
// in parallel). Numbered as connected_components() numbers them. When no
// EMST edge crosses a gap, the tree alone spans the graph: one piece.
template <int D>
Components pieces_of_the_data(const Neighbourhoods<D>& lists, const RowPlan& plan, std::span<const Edge> emst,
                              bool no_gaps) {
  const std::size_t n = plan.own.size();
  if (no_gaps && n > 0) {
    Components one;
    one.label.assign(n, 0);
    one.sizes.assign(1, static_cast<std::uint32_t>(n));
    return one;
  }
  UnionFind sets(n);
  for (const Edge& e : emst)
    if (!lists.is_gap(e.u, e.v)) sets.unite(e.u, e.v);
  std::vector<std::uint32_t> piece(n);
  parallel_for(n, [&](std::size_t s) { piece[s] = sets.root(static_cast<std::uint32_t>(s)); });
  std::vector<Edge> across;
  const auto count = static_cast<std::int64_t>(n);
  const std::size_t k = lists.k;
#pragma omp parallel
  {
    std::vector<Edge> mine;
#pragma omp for schedule(dynamic, 4096) nowait
    for (std::int64_t s = 0; s < count; ++s) {
      const auto i = static_cast<std::uint32_t>(s);
      const auto r = lists.row(i);
      for (std::size_t e = 0; e < k; ++e)
        if ((plan.bits(i, e) & 1u) && piece[i] != piece[r[e]]) mine.push_back({i, r[e], 0.0});
    }
#pragma omp critical(recon_riemannian_graph_across)
    across.insert(across.end(), mine.begin(), mine.end());
  }
  for (const Edge& e : across) sets.unite(e.u, e.v);  // order does not matter to the sets
  return numbered_components(sets, piece);
}

// The closure part of each row sorted by index, then the EMST edges of
// their own at the rows' ends.
void finish_rows(RowPlan& plan, std::span<const Edge> extra, Graph& g) {
  std::vector<std::uint32_t>& degree = plan.degree;
  parallel_for_dynamic(plan.own.size(), 4096, [&](std::size_t i) {
    const auto begin = g.targets.begin() + static_cast<std::ptrdiff_t>(g.offsets[i] + plan.own[i]);
    std::sort(begin, begin + static_cast<std::ptrdiff_t>(degree[i]));
  });
  for (const Edge& e : extra) {
    g.targets[g.offsets[e.u] + plan.own[e.u] + degree[e.u]++] = e.v;
    g.targets[g.offsets[e.v] + plan.own[e.v] + degree[e.v]++] = e.u;
  }
}

// Join back pieces too small to be objects, shortest gap first. Pieces only
// grow, so one pass leaves no small piece that still has a gap edge.
template <int D>
void rejoin_small_pieces(RiemannianGraph<D>& result, std::vector<Edge> gaps, std::size_t min_points) {
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
  if (joins.empty()) return;
  result.rejoined = joins.size();
  result.graph = with_edges(result.graph, joins);
  result.components = connected_components(result.graph);
}

}  // namespace

template <int D>
RiemannianGraph<D> build_riemannian_graph(const TangentPlanes<D>& planes, const RiemannianGraphOptions& options) {
  const std::size_t k = checked_k(planes, options);
  const std::size_t n = planes.origins.size();
  RiemannianGraph<D> result;
  Timer timer;
  // A tree numbered by leaf order holds the samples by index already.
  std::vector<Vec<D>> copy;
  if (!planes.point_tree.numbered_by_leaf_order()) copy = samples_of<D>(planes);
  const std::span<const Vec<D>> samples = copy.empty() ? planes.point_tree.points() : std::span<const Vec<D>>(copy);
  result.emst = emst_of_samples(planes, samples);
  result.seconds_emst = timer.lap();
  interruption_point();

  const Neighbourhoods<D> lists(planes, samples, k, options.gap_factor);
  RowPlan plan = mark_list_entries(lists, n);
  EmstEdgeKinds emst_kinds = sort_emst_edges(lists, result.emst);
  result.gap_emst_edges = emst_kinds.gaps.size();
  fill_rows(lists, plan, emst_kinds.extra, result.graph);
  result.components = pieces_of_the_data(lists, plan, result.emst, emst_kinds.gaps.empty());
  plan.marks = {};
  finish_rows(plan, emst_kinds.extra, result.graph);
  plan = {};
  if (!emst_kinds.gaps.empty()) {
    const std::size_t min_points = options.min_component_points > 0
                                       ? static_cast<std::size_t>(options.min_component_points)
                                       : 2 * static_cast<std::size_t>(planes.neighbors.k);
    rejoin_small_pieces(result, std::move(emst_kinds.gaps), min_points);
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
