#include "recon/phase2_orientation/orientation.h"

#include "recon/core/detail/parallel_for.h"
#include "recon/core/errors.h"
#include "recon/core/timer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <span>
#include <tuple>
#include <utility>

namespace recon {
namespace {

constexpr double cos_25_degrees = 0.9063077870366499;   // "nearly parallel" planes
constexpr double cos_45_degrees = 0.7071067811865476;   // planes across a crease
constexpr double sin_30_degrees = 0.5;                  // a steep edge (facing sheets)
constexpr double sin_10_degrees = 0.17364817766693033;  // a steep edge across a wedge

// sign_by_extremes (see the header). The offer of one direction, per
// component: how well the best-aligned normal within two neighbourhood
// radii of the extreme is aligned with the direction, and whether the
// samples there point along it, by a vote (see offers_along).
struct Offer {
  double alignment = -1.0;
  bool outward = true;
  double vote = 0.0;  // sum of the samples' along x their weight
};

// The normals the walk is guided by (OrientationOptions::guide): the
// planes' own, or the single-precision ones given.
template <int D>
class Guide {
 public:
  Guide(std::span<const Vec<D>> own, std::span<const Eigen::Vector3f> given) : own_(own), given_(given) {}
  [[nodiscard]] Vec<D> operator[](std::size_t i) const {
    if constexpr (D == 3) {
      if (!given_.empty()) return given_[i].cast<double>();
    }
    return own_[i];
  }
  [[nodiscard]] std::size_t size() const { return given_.empty() ? own_.size() : given_.size(); }
  [[nodiscard]] bool is_own() const { return given_.empty(); }

 private:
  std::span<const Vec<D>> own_;
  std::span<const Eigen::Vector3f> given_;
};

// The normals the walk works with: the guide's, each turned where flipped
// says (not copied: result.normals is written once, at the end).
template <int D, typename Normals>
Vec<D> signed_normal(const Normals& guide, const std::vector<std::uint8_t>& flipped, std::size_t i) {
  return flipped[i] ? Vec<D>(-guide[i]) : Vec<D>(guide[i]);
}

// Which way the samples near the extreme point is a vote, not the word of
// the best-aligned one: that one may be among the few the walk got wrong
// (noise on a thin cone), and within two radii of a thin plate's top lie
// samples of its bottom sheet too, rightly pointing the other way. Each
// sample votes with its component along the direction, weighted by
// exp(-depth / r) for its depth below the extreme and its neighbourhood
// radius r: the outermost layer outweighs a sheet beneath it, and a
// majority outweighs a few. (A tie keeps the best-aligned sample's word.)
template <int D>
std::vector<Offer> offers_along(const TangentPlanes<D>& planes, const Guide<D>& guide, const OrientedNormals<D>& result,
                                int axis, double sign) {
  const std::vector<std::uint32_t>& label = result.graph.components.label;
  std::vector<double> top(result.graph.components.sizes.size(), -std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < label.size(); ++i)
    top[label[i]] = std::max(top[label[i]], sign * planes.origins[i][axis]);
  std::vector<Offer> offer(top.size());
  for (std::size_t i = 0; i < label.size(); ++i) {
    const auto radius = static_cast<double>(planes.radius[i]);
    if (sign * planes.origins[i][axis] < top[label[i]] - 2.0 * radius) continue;
    const double depth = top[label[i]] - sign * planes.origins[i][axis];
    const double along = sign * signed_normal<D>(guide, result.flipped, i)[axis];
    Offer& o = offer[label[i]];
    if (std::abs(along) > o.alignment) o = {std::abs(along), along > 0.0, o.vote};
    o.vote += along * (radius > 0.0 ? std::exp(-depth / radius) : 1.0);
  }
  for (Offer& o : offer)
    if (o.vote != 0.0) o.outward = o.vote > 0.0;
  return offer;
}

// The convexity rule (see the header): +1 where the edge (i, j) leaves
// both planes at more than the angle whose sine is `steep`, its ends apart
// from the planes by more than three times their fits' misfit (noise tilts
// short edges between neighbours on one sheet, by no more than that), and
// says their normals point the same way; -1 where it says opposite ways; 0
// where the edge is not that steep.
template <int D>
int convexity_sign(const TangentPlanes<D>& planes, std::span<const float> misfit, std::uint32_t i, std::uint32_t j,
                   double steep) {
  const Vec<D> d = planes.origins[j] - planes.origins[i];
  const double half = steep * steep * d.squaredNorm();
  const double at_i = d.dot(planes.normals[i]), at_j = d.dot(planes.normals[j]);
  const double apart = 3.0 * (static_cast<double>(misfit[i]) + static_cast<double>(misfit[j]));
  if (at_i * at_i <= half || at_j * at_j <= half || std::min(std::abs(at_i), std::abs(at_j)) <= apart) return 0;
  return at_i * at_j < 0.0 ? 1 : -1;
}

// Whether the edge (i, j) joins two facing sheets (see the header): the
// planes nearly parallel and the edge steep to both (more than 30 degrees).
template <int D>
bool joins_facing_sheets(const TangentPlanes<D>& planes, std::span<const float> misfit, std::uint32_t i,
                         std::uint32_t j) {
  return std::abs(planes.normals[i].dot(planes.normals[j])) >= cos_25_degrees &&
         convexity_sign<D>(planes, misfit, i, j, sin_30_degrees) != 0;
}

// Sharp creases (see the header), in three steps.
// 1. Patches: the pieces the graph falls into when only edges between
//    planes within 25 degrees of parallel are kept, between well-fitted
//    planes (misfit at most three times the median: the unresolved planes
//    on a crease would otherwise bridge its two faces in small steps).
// 2. Votes: every edge between two patches whose planes lie more than 45
//    degrees apart and which leaves both planes by more than 10 degrees
//    votes with the convexity rule: the signs found satisfy it, or not.
//    (A wedge's faces meet at its angle, and an edge across it leaves the
//    two by angles that add up to it: 30 degrees each would miss every
//    wedge sharper than 60.)
// 3. Turns: while some patch has at least 8 votes, four in five of them
//    against, the patch with the most net votes against it (the smaller on
//    a tie) is turned round; each turn satisfies more votes, so this ends.
//    One steep edge proves nothing (a wavy surface sampled coarsely has
//    some against); a whole crease line of them agreeing does.
struct PatchPair {
  std::uint32_t a = 0, b = 0;  // patch roots, a < b
  int votes = 0, against = 0;
};

struct Patches {
  std::vector<std::uint32_t> parent;  // union-find: root(v) is v's patch
  std::uint32_t root(std::uint32_t v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  }
};

// Whether any graph edge joins planes more than 45 degrees apart (most
// clouds of smooth surfaces have none, and skip the rest).
template <int D>
bool has_crease_edge(const TangentPlanes<D>& planes, const Graph& g) {
  const auto n = static_cast<std::int64_t>(planes.normals.size());
  int found = 0;
#pragma omp parallel for schedule(static) reduction(max : found)
  for (std::int64_t s = 0; s < n; ++s) {
    const auto v = static_cast<std::uint32_t>(s);
    for (const std::uint32_t u : g.neighbors(v))
      if (std::abs(planes.normals[v].dot(planes.normals[u])) < cos_45_degrees) found = 1;
  }
  return found != 0;
}

template <int D>
Patches find_patches(const TangentPlanes<D>& planes, const Graph& g, std::span<const float> misfit) {
  const auto n = static_cast<std::uint32_t>(planes.normals.size());
  Patches p;
  p.parent.resize(n);
  for (std::uint32_t v = 0; v < n; ++v) p.parent[v] = v;
  std::vector<float> sorted(misfit.begin(), misfit.end());
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(n / 2), sorted.end());
  const double poor = 3.0 * static_cast<double>(sorted[n / 2]);
  auto fitted = [&](std::uint32_t v) { return static_cast<double>(misfit[v]) <= poor; };
  for (std::uint32_t v = 0; v < n; ++v)
    for (const std::uint32_t u : g.neighbors(v)) {
      const double c = std::abs(planes.normals[v].dot(planes.normals[u]));
      if (u < v || c < cos_25_degrees || !fitted(v) || !fitted(u)) continue;
      const std::uint32_t a = p.root(v), b = p.root(u);
      if (a != b) p.parent[std::max(a, b)] = std::min(a, b);
    }
  return p;
}

template <int D>
std::vector<PatchPair> crease_votes(const TangentPlanes<D>& planes, const Graph& g, std::span<const float> misfit,
                                    Patches& patches, const std::vector<std::uint8_t>& flipped) {
  std::vector<PatchPair> pairs;
  for (std::uint32_t v = 0; v < flipped.size(); ++v)
    for (const std::uint32_t u : g.neighbors(v)) {
      if (u < v || std::abs(planes.normals[v].dot(planes.normals[u])) >= cos_45_degrees) continue;
      const std::uint32_t a = patches.root(v), b = patches.root(u);
      const int rule = a == b ? 0 : convexity_sign<D>(planes, misfit, v, u, sin_10_degrees);
      if (rule == 0) continue;
      const bool consistent = (rule < 0) == (flipped[v] != flipped[u]);
      pairs.push_back({std::min(a, b), std::max(a, b), 1, consistent ? 0 : 1});
    }
  std::sort(pairs.begin(), pairs.end(),
            [](const PatchPair& x, const PatchPair& y) { return std::pair(x.a, x.b) < std::pair(y.a, y.b); });
  std::vector<PatchPair> merged;
  for (const PatchPair& p : pairs) {
    if (!merged.empty() && merged.back().a == p.a && merged.back().b == p.b) {
      merged.back().votes += p.votes;
      merged.back().against += p.against;
    } else {
      merged.push_back(p);
    }
  }
  return merged;
}

// Step 3: which patches to turn (1 at a patch's root). Each round tallies
// every pair again; a few dozen turns at most are expected (one per face
// the walk got wrong), so the rounds stop at 64.
std::vector<std::uint8_t> patches_to_turn(const std::vector<PatchPair>& pairs, const std::vector<std::uint32_t>& size) {
  constexpr int min_votes = 8;
  constexpr std::size_t max_turns = 64;
  std::vector<std::uint8_t> turn(size.size(), 0);
  for (std::size_t step = 0; step < std::min(pairs.size(), max_turns); ++step) {
    std::map<std::uint32_t, std::array<int, 2>> tally;  // patch -> votes, against
    for (const PatchPair& p : pairs) {
      const int against = turn[p.a] != turn[p.b] ? p.votes - p.against : p.against;
      for (const std::uint32_t patch : {p.a, p.b}) {
        tally[patch][0] += p.votes;
        tally[patch][1] += against;
      }
    }
    auto worst = tally.end();
    int worst_net = 0;
    for (auto t = tally.begin(); t != tally.end(); ++t) {
      const auto [votes, against] = t->second;
      if (votes < min_votes || 5 * against < 4 * votes) continue;
      const int net = 2 * against - votes;
      if (net > worst_net || (worst != tally.end() && net == worst_net && size[t->first] < size[worst->first])) {
        worst = t;
        worst_net = net;
      }
    }
    if (worst == tally.end()) break;
    turn[worst->first] ^= 1;
  }
  return turn;
}

template <int D>
std::size_t turn_crease_patches(const TangentPlanes<D>& planes, const Graph& g, std::span<const float> misfit,
                                OrientedNormals<D>& result) {
  if (!has_crease_edge<D>(planes, g)) return 0;
  Patches patches = find_patches<D>(planes, g, misfit);
  const std::vector<PatchPair> pairs = crease_votes<D>(planes, g, misfit, patches, result.flipped);
  const auto n = static_cast<std::uint32_t>(planes.normals.size());
  std::vector<std::uint32_t> size(n, 0);
  for (std::uint32_t v = 0; v < n; ++v) ++size[patches.root(v)];
  const std::vector<std::uint8_t> turn = patches_to_turn(pairs, size);
  const auto turned = static_cast<std::size_t>(std::count(turn.begin(), turn.end(), 1));
  for (std::uint32_t v = 0; v < n && turned > 0; ++v)
    if (turn[patches.root(v)]) result.flipped[v] ^= 1;
  return turned;
}

template <int D>
std::size_t turn_components_outward(const TangentPlanes<D>& planes, const Guide<D>& guide, OrientedNormals<D>& result) {
  constexpr double well_aligned = cos_25_degrees;
  std::vector<Offer> best = offers_along<D>(planes, guide, result, D - 1, 1.0);  // up: Hoppe's direction
  std::vector<bool> decided(best.size());
  for (std::size_t c = 0; c < best.size(); ++c) decided[c] = best[c].alignment >= well_aligned;
  for (int axis = D - 1; axis >= 0; --axis)
    for (const double sign : {1.0, -1.0}) {
      if (axis == D - 1 && sign > 0.0) continue;
      const std::vector<Offer> offer = offers_along<D>(planes, guide, result, axis, sign);
      for (std::size_t c = 0; c < best.size(); ++c)
        if (!decided[c] && offer[c].alignment > best[c].alignment) best[c] = offer[c];
    }
  std::size_t turned = 0;
  for (const Offer& o : best) turned += o.outward ? 0u : 1u;
  if (turned == 0) return 0;
  const std::vector<std::uint32_t>& label = result.graph.components.label;
  for (std::size_t i = 0; i < label.size(); ++i)
    if (!best[label[i]].outward) result.flipped[i] ^= 1;
  return turned;
}

// Nested pieces (see the header), in three steps.
// 1. Boxes: each piece's bounding box (over its origins) and its probe, the
//    root of its spanning tree (its highest origin).
// 2. Winding numbers: for each pair of pieces (P, Q) where Q's box holds
//    P's and Q's samples close a surface (closes_a_surface), Q's winding
//    number at P's probe, summed over Q's samples with their signs as
//    decided (winding_number).
// 3. Turns: a piece inside an odd number of others is turned round.

// Sample i's area times its normal as decided (sample_area), for the sums
// below; zero for an isolated sample (no surface), which they leave out.
template <int D>
Vec<D> area_normal(const TangentPlanes<D>& planes, const std::vector<std::uint8_t>& flipped, std::uint32_t i) {
  if (!(planes.local_rho[i] > 0.0f)) return Vec<D>::Zero();
  return sample_area<D>(planes.radius[i], planes.k) * signed_normal<D>(planes.normals, flipped, i);
}

// Q's winding number at p (the header), from the oriented samples
// `members`, the sum in the members' order (the same for any thread count).
template <int D>
double winding_number(const TangentPlanes<D>& planes, const std::vector<std::uint8_t>& flipped,
                      std::span<const std::uint32_t> members, const Vec<D>& p) {
  double w = 0.0;
  for (const std::uint32_t i : members) w += winding_term<D>(planes.origins[i], area_normal<D>(planes, flipped, i), p);
  return w;
}

// Whether Q's oriented samples `members` close a surface (closes_a_surface).
template <int D>
bool closed_piece(const TangentPlanes<D>& planes, const std::vector<std::uint8_t>& flipped,
                  std::span<const std::uint32_t> members) {
  Vec<D> sum = Vec<D>::Zero();
  double area = 0.0;
  for (const std::uint32_t i : members) {
    const Vec<D> an = area_normal<D>(planes, flipped, i);
    sum += an;
    area += an.norm();
  }
  return closes_a_surface<D>(sum, area);
}

template <int D>
struct PieceBox {
  Vec<D> lo = Vec<D>::Constant(std::numeric_limits<double>::infinity());
  Vec<D> hi = Vec<D>::Constant(-std::numeric_limits<double>::infinity());
  [[nodiscard]] bool holds(const PieceBox& other) const {
    return (lo.array() <= other.lo.array()).all() && (other.hi.array() <= hi.array()).all();
  }
};

// Per piece, its members (sample indices, ascending) and its box.
template <int D>
struct PieceMembers {
  std::vector<std::uint32_t> first;  // piece c's members: [first[c], first[c + 1])
  std::vector<std::uint32_t> members;
  std::vector<PieceBox<D>> boxes;
};

template <int D>
PieceMembers<D> piece_members(const TangentPlanes<D>& planes, const Components& components) {
  const std::size_t pieces = components.sizes.size();
  PieceMembers<D> m;
  m.first.assign(pieces + 1, 0);
  for (std::size_t c = 0; c < pieces; ++c) m.first[c + 1] = m.first[c] + components.sizes[c];
  m.members.resize(components.label.size());
  m.boxes.resize(pieces);
  std::vector<std::uint32_t> next(m.first.begin(), m.first.end() - 1);
  for (std::uint32_t i = 0; i < components.label.size(); ++i) {
    const std::uint32_t c = components.label[i];
    m.members[next[c]++] = i;
    m.boxes[c].lo = m.boxes[c].lo.cwiseMin(planes.origins[i]);
    m.boxes[c].hi = m.boxes[c].hi.cwiseMax(planes.origins[i]);
  }
  return m;
}

// Step 2's pairs: (P, Q) with Q's box holding P's, P != Q.
template <int D>
std::vector<std::pair<std::uint32_t, std::uint32_t>> nesting_candidates(const std::vector<PieceBox<D>>& boxes) {
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  const auto pieces = static_cast<std::uint32_t>(boxes.size());
  for (std::uint32_t p = 0; p < pieces; ++p)
    for (std::uint32_t q = 0; q < pieces; ++q)
      if (p != q && boxes[q].holds(boxes[p])) pairs.emplace_back(p, q);
  return pairs;
}

// Returns the pieces inside at least one other, and those turned round.
template <int D>
std::pair<std::size_t, std::size_t> turn_nested_pieces(const TangentPlanes<D>& planes, OrientedNormals<D>& result) {
  const Components& components = result.graph.components;
  if (components.sizes.size() < 2) return {0, 0};
  const PieceMembers<D> m = piece_members<D>(planes, components);
  const auto pairs = nesting_candidates<D>(m.boxes);
  if (pairs.empty()) return {0, 0};
  const auto members_of = [&](std::uint32_t q) {
    return std::span<const std::uint32_t>(m.members.data() + m.first[q], components.sizes[q]);
  };
  std::vector<std::uint8_t> closed(components.sizes.size(), 0);  // (tested for the pieces that may enclose)
  for (const auto& [p, q] : pairs) closed[q] = 2;
  detail::parallel_for_dynamic(closed.size(), 1, [&](std::size_t q) {
    if (closed[q] == 2) closed[q] = closed_piece<D>(planes, result.flipped, members_of(static_cast<std::uint32_t>(q)));
  });
  std::vector<std::uint8_t> inside(pairs.size());
  detail::parallel_for_dynamic(pairs.size(), 1, [&](std::size_t e) {
    const auto [p, q] = pairs[e];
    if (closed[q] == 0) return;
    const double w = winding_number<D>(planes, result.flipped, members_of(q), planes.origins[result.tree.roots[p]]);
    inside[e] = winding_inside(w) ? 1 : 0;
  });
  std::vector<std::uint32_t> depth(components.sizes.size(), 0);
  for (std::size_t e = 0; e < pairs.size(); ++e) depth[pairs[e].first] += inside[e];
  std::size_t nested = 0, turned = 0;
  for (const std::uint32_t d : depth) {
    nested += d > 0 ? 1u : 0u;
    turned += d % 2 == 1 ? 1u : 0u;
  }
  for (std::size_t i = 0; i < components.label.size() && turned > 0; ++i)
    if (depth[components.label[i]] % 2 == 1) result.flipped[i] ^= 1;
  return {nested, turned};
}

}  // namespace

template <int D>
OrientedNormals<D> orient_normals(const TangentPlanes<D>& planes, const OrientationOptions& options) {
  return orient_normals<D>(planes, build_riemannian_graph<D>(planes, options.graph), options);
}

namespace {

// One root per component: its origin of largest last coordinate.
template <int D>
std::vector<std::uint32_t> highest_origins(const TangentPlanes<D>& planes, const Components& components) {
  std::vector<std::uint32_t> roots(components.sizes.size(), UINT32_MAX);
  for (std::uint32_t i = 0; i < planes.origins.size(); ++i) {
    std::uint32_t& r = roots[components.label[i]];
    if (r == UINT32_MAX || planes.origins[i][D - 1] > planes.origins[r][D - 1]) r = i;
  }
  return roots;
}

// The signs decided so far, as the walk and the vote read them: plane i's
// guide normal turned by result.flipped, and whether the edge (a, b) joins
// facing sheets (across which the normals must disagree).
template <int D>
struct Signs {
  const TangentPlanes<D>& planes;
  const Guide<D>& guide;
  const OrientedNormals<D>& result;
  std::span<const float> sheet_misfit;

  [[nodiscard]] Vec<D> normal(std::size_t i) const { return signed_normal<D>(guide, result.flipped, i); }
  [[nodiscard]] bool reversed(std::uint32_t a, std::uint32_t b) const {
    return !sheet_misfit.empty() && joins_facing_sheets<D>(planes, sheet_misfit, a, b);
  }
};

// Hoppe's walk: parents first, each root made to point up (+ last axis),
// each child flipped when it points against its parent (or, across facing
// sheets, along it).
template <int D>
void walk_the_tree(const Signs<D>& signs, OrientedNormals<D>& result) {
  for (std::uint32_t v : result.tree.order) {
    const std::uint32_t p = result.tree.parent[v];
    const bool across = p != SpanningForest::no_parent && signs.reversed(v, p);
    result.sheet_edges += across ? 1u : 0u;
    const bool flip = p == SpanningForest::no_parent ? signs.normal(v)[D - 1] < 0.0
                                                     : (signs.normal(v).dot(signs.normal(p)) < 0.0) != across;
    if (flip) result.flipped[v] = 1;
  }
}

// Clean-up vote: the tree decides each sign through one edge, and where
// noise tilts a normal that one edge can be wrong. A normal that points
// against most of its graph neighbours is turned round, from the signs of
// the previous round (so the outcome does not depend on visiting order).
template <int D>
void vote(const Signs<D>& signs, const Graph& g, int rounds, OrientedNormals<D>& result) {
  const std::size_t n = result.flipped.size();
  std::vector<std::uint8_t> turn(n);
  for (int round = 0; round < rounds; ++round) {
    const std::size_t turned = detail::parallel_count(n, 4096, [&](std::size_t i) {
      const auto v = static_cast<std::uint32_t>(i);
      const Vec<D> normal = signs.normal(v);
      double agreement = 0.0;
      for (const std::uint32_t u : g.neighbors(v))
        agreement += (signs.reversed(v, u) ? -1.0 : 1.0) * normal.dot(signs.normal(u));
      turn[v] = agreement < 0.0 ? 1 : 0;
      return turn[v];
    });
    if (turned == 0) break;
    for (std::size_t v = 0; v < n; ++v) result.flipped[v] ^= turn[v];
    result.vote_flips += turned;
  }
}

}  // namespace

template <int D>
OrientedNormals<D> orient_normals(const TangentPlanes<D>& planes, RiemannianGraph<D> graph,
                                  const OrientationOptions& options) {
  OrientedNormals<D> result;
  result.graph = std::move(graph);
  Timer timer;
  const std::size_t n = planes.origins.size();
  const Graph& g = result.graph.graph;
  std::span<const Eigen::Vector3f> given;
  if constexpr (D == 3) given = options.guide;
  const Guide<D> guide(planes.normals, given);
  if (guide.size() != n) throw InvalidInputError("orientation: the guide normals are not one per plane");

  // Prim's minimum spanning forest, from the highest origin of each component.
  result.tree = prim_minimum_spanning_forest(g, highest_origins(planes, result.graph.components),
                                             [&](std::uint32_t v, std::uint64_t e) {
                                               const double cost = orientation_cost<D>(guide[v], guide[g.targets[e]]);
                                               // (single-precision normals are unit to 1e-7 only)
                                               return guide.is_own() ? cost : std::max(0.0, cost);
                                             });
  result.flipped.assign(n, 0);
  const Signs<D> signs{planes, guide, result, options.sheet_misfit};
  walk_the_tree(signs, result);
  vote(signs, g, options.vote_rounds, result);
  if (!options.sheet_misfit.empty())
    result.crease_patches_turned = turn_crease_patches<D>(planes, g, options.sheet_misfit, result);
  if (options.sign_by_extremes) {
    result.components_turned = turn_components_outward<D>(planes, guide, result);
    if (options.turn_nested)
      std::tie(result.pieces_nested, result.nested_turned) = turn_nested_pieces<D>(planes, result);
  }

  // The signs found (with the guide, where there is one), on the planes' own normals.
  result.normals.resize(n);
  for (std::size_t i = 0; i < n; ++i) result.normals[i] = signed_normal<D>(planes.normals, result.flipped, i);
  result.flip_count = static_cast<std::size_t>(std::count(result.flipped.begin(), result.flipped.end(), 1));
  result.seconds_mst = timer.lap();
  return result;
}

template OrientedNormals<2> orient_normals<2>(const TangentPlanes<2>&, const OrientationOptions&);
template OrientedNormals<3> orient_normals<3>(const TangentPlanes<3>&, const OrientationOptions&);
template OrientedNormals<2> orient_normals<2>(const TangentPlanes<2>&, RiemannianGraph<2>, const OrientationOptions&);
template OrientedNormals<3> orient_normals<3>(const TangentPlanes<3>&, RiemannianGraph<3>, const OrientationOptions&);

}  // namespace recon
