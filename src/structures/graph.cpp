#include "recon/structures/graph.h"

#include "recon/core/errors.h"

#include <algorithm>
#include <numeric>
#include <string>

namespace recon {

Graph make_graph(std::size_t vertex_count, std::span<const Edge> edges) {
  Graph g;
  g.offsets.assign(vertex_count + 1, 0);
  for (const Edge& e : edges) {
    if (e.u >= vertex_count || e.v >= vertex_count)
      throw InvalidInputError("graph edge (" + std::to_string(e.u) + ", " + std::to_string(e.v) +
                              ") names a vertex beyond " + std::to_string(vertex_count));
    if (e.u == e.v) continue;
    ++g.offsets[e.u + 1];
    ++g.offsets[e.v + 1];
  }
  std::partial_sum(g.offsets.begin(), g.offsets.end(), g.offsets.begin());
  std::vector<std::pair<std::uint32_t, double>> slots(g.offsets.back());
  std::vector<std::uint64_t> fill(g.offsets.begin(), g.offsets.end() - 1);
  for (const Edge& e : edges) {
    if (e.u == e.v) continue;
    slots[fill[e.u]++] = {e.v, e.weight};
    slots[fill[e.v]++] = {e.u, e.weight};
  }
  // Sort each row, merge repeated targets (keeping the lightest), compact.
  std::uint64_t write = 0;
  for (std::size_t v = 0; v < vertex_count; ++v) {
    const auto begin = slots.begin() + static_cast<std::ptrdiff_t>(g.offsets[v]);
    const auto end = slots.begin() + static_cast<std::ptrdiff_t>(g.offsets[v + 1]);
    std::sort(begin, end);  // by target, then weight: the first of a run is the lightest
    g.offsets[v] = write;
    for (auto it = begin; it != end; ++it)
      if (write == g.offsets[v] || slots[write - 1].first != it->first) slots[write++] = *it;
  }
  g.offsets[vertex_count] = write;
  g.targets.resize(write);
  g.weights.resize(write);
  for (std::uint64_t s = 0; s < write; ++s) {
    g.targets[s] = slots[s].first;
    g.weights[s] = slots[s].second;
  }
  return g;
}

Graph with_edges(const Graph& graph, std::span<const Edge> edges) {
  const std::size_t n = graph.vertex_count();
  const bool weighted = !graph.weights.empty();
  std::vector<Edge> all;
  all.reserve(graph.targets.size() / 2 + edges.size());
  for (std::uint32_t v = 0; v < n; ++v)
    for (std::uint64_t e = graph.offsets[v]; e < graph.offsets[v + 1]; ++e)
      if (v < graph.targets[e]) all.push_back({v, graph.targets[e], weighted ? graph.weights[e] : 0.0});
  all.insert(all.end(), edges.begin(), edges.end());
  Graph g = make_graph(n, all);
  if (!weighted) g.weights.clear();
  return g;
}

// Breadth-first search from each vertex not yet labelled, in index order.
Components connected_components(const Graph& graph) {
  const std::size_t n = graph.vertex_count();
  constexpr std::uint32_t unlabelled = UINT32_MAX;
  Components c;
  c.label.assign(n, unlabelled);
  std::vector<std::uint32_t> queue;
  queue.reserve(n);
  for (std::uint32_t start = 0; start < n; ++start) {
    if (c.label[start] != unlabelled) continue;
    const auto l = static_cast<std::uint32_t>(c.sizes.size());
    queue.clear();
    queue.push_back(start);
    c.label[start] = l;
    for (std::size_t head = 0; head < queue.size(); ++head)
      for (const std::uint32_t w : graph.neighbors(queue[head]))
        if (c.label[w] == unlabelled) {
          c.label[w] = l;
          queue.push_back(w);
        }
    c.sizes.push_back(static_cast<std::uint32_t>(queue.size()));
  }
  return c;
}

}  // namespace recon
