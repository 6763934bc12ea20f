// Step 3 of a tiled run (tiles.h): the tiles' orientations made to agree
// where their borders overlap, by a spanning forest over the tiles'
// pieces (union-find), one sign a piece; then, for the refined method, the
// objects nested in an odd number of others turned round.
#include "recon/core/errors.h"
#include "recon/core/timer.h"
#include "recon/phase2_orientation/orientation.h"
#include "recon/structures/union_find.h"
#include "recon/tiles/tiles.h"
#include "tiles/files.h"

#include <algorithm>
#include <limits>
#include <map>
#include <tuple>

namespace recon {

using tile_files::BorderRecord;
using tile_files::DipoleRecord;
using tile_files::Orientation;
using tile_files::PieceTop;

namespace {

struct Agreement {
  std::uint64_t agree = 0, disagree = 0;
};
using NodePair = std::pair<std::uint32_t, std::uint32_t>;

// Where a node's core samples lie (nested objects, below): their box and
// the highest origin (the probe); none for a piece of halo samples alone.
struct Extent {
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 hi = -lo;
  Vec3 probe = Vec3::Zero();
  bool any = false;
  void add(const Vec3& x) {
    if (!any || x.z() > probe.z()) probe = x;
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
    any = true;
  }
  void add(const Extent& other) {
    if (!other.any) return;
    add(other.probe);
    lo = lo.cwiseMin(other.lo);
    hi = hi.cwiseMax(other.hi);
  }
  [[nodiscard]] bool holds(const Extent& other) const {
    return any && other.any && (lo.array() <= other.lo.array()).all() && (other.hi.array() <= hi.array()).all();
  }
};

Vec3 vec(const float (&v)[3]) {
  return {static_cast<double>(v[0]), static_cast<double>(v[1]), static_cast<double>(v[2])};
}

struct SignGraph {
  std::vector<std::uint64_t> first_node;  // per tile, its first node
  std::vector<PieceTop> tops;             // per node
  std::vector<Extent> extents;            // per node
  std::map<NodePair, Agreement> edges;
  std::size_t shared = 0;
};

// Nodes, and the edges between the pieces that orient the same samples.
SignGraph sign_graph(const std::filesystem::path& dir, const TilePlan& plan) {
  SignGraph g;
  std::vector<BorderRecord> border;
  for (const TileInfo& info : plan.tiles) {
    Orientation o = tile_files::read_orientation(tile_files::of_tile(dir, info.id, "orient"));
    g.first_node.push_back(g.tops.size());
    if (o.tops.size() >= tile_files::none - g.tops.size())
      throw ResourceLimitError("the tiles hold more than 2^32 pieces between them; use larger tiles");
    for (BorderRecord& b : o.border) b.node += static_cast<std::uint32_t>(g.tops.size());
    g.tops.insert(g.tops.end(), o.tops.begin(), o.tops.end());
    g.extents.resize(g.tops.size());
    for (const DipoleRecord& d : o.dipoles) g.extents[g.first_node.back() + d.piece].add(vec(d.origin));
    border.insert(border.end(), o.border.begin(), o.border.end());
  }
  std::sort(border.begin(), border.end(), [](const BorderRecord& a, const BorderRecord& b) {
    return std::tie(a.index, a.node) < std::tie(b.index, b.node);
  });
  for (std::size_t s = 0; s < border.size();) {
    std::size_t e = s + 1;
    while (e < border.size() && border[e].index == border[s].index) ++e;
    for (std::size_t a = s; a < e; ++a)
      for (std::size_t b = a + 1; b < e; ++b) {
        const BorderRecord &x = border[a], &y = border[b];
        const float dot = x.normal[0] * y.normal[0] + x.normal[1] * y.normal[1] + x.normal[2] * y.normal[2];
        Agreement& edge = g.edges[{x.node, y.node}];
        (dot >= 0.0f ? edge.agree : edge.disagree) += 1;
        ++g.shared;
      }
    s = e;
  }
  return g;
}

// The maximum spanning forest by margin of agreement (Kruskal), walked
// breadth-first from each object's highest piece, which keeps its sign.
// Per node: its sign, and its object (the node it was walked from).
struct Signs {
  std::vector<std::int8_t> flip;
  std::vector<std::uint32_t> object;
};

Signs reconcile(const SignGraph& g, TileReconciliation& result) {
  const std::size_t n = g.tops.size();
  std::vector<std::pair<NodePair, Agreement>> edges(g.edges.begin(), g.edges.end());
  const auto margin = [](const Agreement& a) {
    return a.agree > a.disagree ? a.agree - a.disagree : a.disagree - a.agree;
  };
  std::stable_sort(edges.begin(), edges.end(),
                   [&](const auto& a, const auto& b) { return margin(a.second) > margin(b.second); });
  UnionFind sets(n);
  std::vector<std::vector<std::pair<std::uint32_t, std::int8_t>>> tree(n);
  for (const auto& [nodes, agreement] : edges) {
    if (!sets.unite(nodes.first, nodes.second)) continue;
    const std::int8_t relation = agreement.agree >= agreement.disagree ? 1 : -1;
    tree[nodes.first].emplace_back(nodes.second, relation);
    tree[nodes.second].emplace_back(nodes.first, relation);
  }
  std::vector<std::uint32_t> root(n, UINT32_MAX);  // per set: its highest node
  for (std::uint32_t v = 0; v < n; ++v) {
    std::uint32_t& best = root[sets.find(v)];
    const auto higher = [&](std::uint32_t a, std::uint32_t b) {
      return std::tie(g.tops[a].z, g.tops[b].index) > std::tie(g.tops[b].z, g.tops[a].index);
    };
    if (best == UINT32_MAX || higher(v, best)) best = v;
  }
  Signs s{std::vector<std::int8_t>(n, 0), std::vector<std::uint32_t>(n, UINT32_MAX)};
  for (std::uint32_t v = 0; v < n; ++v) {
    if (root[v] == UINT32_MAX) continue;
    if (g.tops[root[v]].index != UINT64_MAX) ++result.objects;  // (pieces of halos alone are no object)
    std::vector<std::uint32_t> queue{root[v]};
    s.flip[root[v]] = 1;
    for (std::size_t q = 0; q < queue.size(); ++q) {
      s.object[queue[q]] = root[v];
      for (const auto& [next, relation] : tree[queue[q]])
        if (s.flip[next] == 0) {
          s.flip[next] = static_cast<std::int8_t>(s.flip[queue[q]] * relation);
          queue.push_back(next);
        }
    }
  }
  return s;
}

// Nested objects (orientation.h, as phase II turns nested pieces in
// memory): each object's box and probe over its core samples; for each
// pair (P, Q) where Q's box holds P's, Q's winding number at P's probe,
// summed over Q's core samples in every tile (the orientation files read
// again, only when there is such a pair), and whether Q's samples close a
// surface (closes_a_surface); an object inside an odd number of closed
// others is turned round.
void turn_nested_objects(const std::filesystem::path& dir, const TilePlan& plan, const SignGraph& g, Signs& s,
                         TileReconciliation& result) {
  std::map<std::uint32_t, Extent> objects;  // by the node each was walked from
  for (std::uint32_t v = 0; v < g.extents.size(); ++v) objects[s.object[v]].add(g.extents[v]);
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;  // (P, Q), by object
  for (const auto& [p, inner] : objects)
    for (const auto& [q, outer] : objects)
      if (p != q && outer.holds(inner)) pairs.emplace_back(p, q);
  if (pairs.empty()) return;
  std::map<std::uint32_t, std::vector<std::size_t>> tested;  // per object Q, its pairs
  for (std::size_t e = 0; e < pairs.size(); ++e) tested[pairs[e].second].push_back(e);
  std::vector<double> w(pairs.size(), 0.0);
  std::map<std::uint32_t, std::pair<Vec3, double>> sums;  // per object Q: its area-weighted normals, its area
  for (std::size_t t = 0; t < plan.tiles.size(); ++t) {
    const tile_files::Orientation o =
        tile_files::read_orientation(tile_files::of_tile(dir, plan.tiles[t].id, "orient"));
    for (const DipoleRecord& d : o.dipoles) {
      const std::uint64_t node = g.first_node[t] + d.piece;
      const auto q = tested.find(s.object[node]);
      if (q == tested.end()) continue;
      const Vec3 x = vec(d.origin), an = static_cast<double>(s.flip[node]) * vec(d.area_normal);
      auto& [area_normal, area] = sums.try_emplace(q->first, Vec3::Zero(), 0.0).first->second;
      area_normal += an;
      area += an.norm();
      for (const std::size_t e : q->second) w[e] += winding_term<3>(x, an, objects[pairs[e].first].probe);
    }
  }
  const auto closed = [&](std::uint32_t q) {
    const auto sum = sums.find(q);
    return sum != sums.end() && closes_a_surface<3>(sum->second.first, sum->second.second);
  };
  std::map<std::uint32_t, std::uint32_t> depth;
  for (std::size_t e = 0; e < pairs.size(); ++e)
    depth[pairs[e].first] += closed(pairs[e].second) && winding_inside(w[e]) ? 1u : 0u;
  for (const auto& [object, d] : depth) {
    result.objects_nested += d > 0 ? 1u : 0u;
    result.nested_turned += d % 2 == 1 ? 1u : 0u;
  }
  for (std::uint32_t v = 0; v < s.flip.size(); ++v)
    if (const auto d = depth.find(s.object[v]); d != depth.end() && d->second % 2 == 1)
      s.flip[v] = static_cast<std::int8_t>(-s.flip[v]);
}

}  // namespace

TileReconciliation reconcile_tiles(const std::filesystem::path& work_dir) {
  Timer timer;
  const TilePlan plan = read_tile_plan(work_dir);
  const SignGraph g = sign_graph(work_dir, plan);
  TileReconciliation result;
  Signs signs = reconcile(g, result);
  const std::vector<std::int8_t>& flip = signs.flip;
  result.nodes = g.tops.size();
  result.edges = g.edges.size();
  result.shared_samples = g.shared;
  result.turned = static_cast<std::size_t>(std::count(flip.begin(), flip.end(), std::int8_t{-1}));
  for (const auto& [nodes, agreement] : g.edges)
    result.disagreeing += flip[nodes.first] == flip[nodes.second] ? agreement.disagree : agreement.agree;
  if (plan.method == Method::refined) turn_nested_objects(work_dir, plan, g, signs, result);
  tile_files::write_flips(work_dir, {g.first_node, flip, signs.object});
  result.seconds = timer.elapsed();
  return result;
}

}  // namespace recon
