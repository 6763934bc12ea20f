#include "recon/phase6_simplify/simplification.h"
#include "phase6_simplify/collapser.h"
#include "phase6_simplify/queues.h"

#include "recon/core/detail/parallel_for.h"
#include "recon/core/errors.h"
#include "recon/core/parallel.h"
#include "recon/core/timer.h"
#include "recon/phase6_simplify/detail/simplify_plain.h"
#include "recon/structures/binary_heap.h"
#include "recon/structures/pairing_heap.h"
#include "recon/structures/spatial_order.h"
#include "recon/structures/union_find.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <numbers>
#include <numeric>
#include <queue>
#include <span>
#include <sstream>
#include <string>
#include <tuple>
#include <unordered_map>
#include <vector>

namespace recon {
namespace {

using namespace simplification_steps;

// ---------------------------------------------------------------------------
// The checked options: how many triangles to stop at.

std::size_t target_of(const Mesh& mesh, const SimplifyOptions& options) {
  const std::size_t n = mesh.triangles.size();
  const bool by_count = options.target_triangles > 0, by_ratio = options.ratio != 0.0;
  const bool bounded = options.max_error != 0.0;
  // isfinite first: an ordered comparison with a NaN raises the invalid
  // exception, which the sanitizer build traps.
  if (!std::isfinite(options.max_error) || options.max_error < 0.0)
    throw InvalidInputError("simplify: the error bound must be a finite distance >= 0, not " +
                            std::to_string(options.max_error));
  if (by_ratio && (!std::isfinite(options.ratio) || options.ratio <= 0.0 || options.ratio >= 1.0))
    throw InvalidInputError("simplify: the ratio must lie between 0 and 1 (exclusive), not " +
                            std::to_string(options.ratio));
  if (by_count && options.target_triangles > n)
    throw InvalidInputError("simplify: the target of " + std::to_string(options.target_triangles) +
                            " triangles exceeds the mesh's " + std::to_string(n));
  if (!by_count && !by_ratio && !bounded)
    throw InvalidInputError("simplify: give a triangle count, a ratio or an error bound");
  std::size_t target = 0;
  if (by_count) target = options.target_triangles;
  if (by_ratio) {
    const auto of_ratio = static_cast<std::size_t>(std::llround(options.ratio * static_cast<double>(n)));
    target = by_count ? std::min(target, of_ratio) : of_ratio;
  }
  return target;
}

void check_indices(const Mesh& mesh) {
  const std::size_t n = mesh.vertices.size();
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (const std::uint32_t v : mesh.triangles[t])
      if (v >= n)
        throw InvalidInputError("simplify: triangle " + std::to_string(t) + " uses vertex " + std::to_string(v) +
                                " of " + std::to_string(n));
}

// ---------------------------------------------------------------------------
// The collapses in rounds of blocks, then one queue. The queue's order is
// the output, so one queue runs on one thread, and over a large mesh it
// visits memory at random (cache misses were most of its time: 2.2 s for a
// million triangles). So first, rounds of blocks: the cells of a grid
// over the mesh holding about block_vertices vertices each (in the
// canonical order a cell's vertices are a few runs of consecutive ones,
// near in memory), each with its own queue over its inner vertices (those
// whose whole ring lies in the cell), on all threads. A collapse u -> v of
// an inner u changes only triangles and vertices of u's cell, so the blocks
// neither race nor see each other: the result is the same for any thread
// count and any order of the blocks.
//
// How far a block goes in a round: up to one cost for all, the round's
// limit, which at most a share of the living vertices' cheapest moves
// reach (round_fraction; and no more than the collapses still asked for).
// A collapse raises the costs around it, so fewer are made. So, as one
// queue over the whole mesh would, the blocks spend the collapses where
// they are cheapest, not the same share everywhere. Tried first: quotas by
// vertex count per block, which kept the Hausdorff-95 of million-triangle
// meshes but, in the tests' small meshes cut into 64-vertex blocks, left a
// dome's farthest input vertex 1.7 times as far from the result as one
// queue does (these rounds: 1.04 times); and half the vertices in every
// round, not only the first two, left a wavy rim 10 times as far off (these
// rounds: as far as one queue). Each block is also held to its share of the
// collapses still asked for (by its moves under the limit), so a round
// never passes the target. The grid shifts from round to round, so that
// each round's seams lie inside the next round's cells, and one queue over
// every vertex makes the last 2%.
//
// Of the living vertices, the most a round's limit lets move: half in the
// first two rounds (the mesh is fine, its costs close together: 8% faster
// than a quarter throughout; on the 1M-point clouds of docs/benchmarks.md
// the Hausdorff-95 stays within 1.5% of one queue's), then a quarter.
constexpr double round_fraction(std::size_t round) { return round < 2 ? 0.5 : 0.25; }
constexpr std::array<double, 4> round_shifts{0.0, 0.5, 0.25, 0.75};  // of a cell, on each axis
constexpr double finish_share = 0.02;                                // of the collapses asked for: the last queue's
constexpr std::size_t most_rounds = 24;

// The blocks of one round: the cells of a grid over the bounding box (an
// octree level's, in spatial_cells' coordinates), shifted by a
// fraction of a cell on each axis; each cell with living vertices is a
// block. Blocks are numbered by their first vertex; a block's vertices are
// listed in increasing order (s.local: each one's place in its list).
struct Partition {
  std::vector<std::uint32_t> start;    // per block: where its vertices begin in `members`
  std::vector<std::uint32_t> members;  // the living vertices, block by block
  [[nodiscard]] std::size_t count() const { return start.size() - 1; }
  [[nodiscard]] std::span<const std::uint32_t> block(std::size_t b) const {
    return std::span<const std::uint32_t>(members).subspan(start[b], start[b + 1] - start[b]);
  }
};

// The octree level whose cells hold about `per_block` vertices each, by
// counting the cells the vertices fill at each level (in Z-order a cell's
// vertices are consecutive: a new cell is where two neighbours' codes first
// differ).
unsigned level_for(const std::vector<std::array<std::uint32_t, 3>>& grid, std::size_t per_block) {
  const std::vector<std::uint64_t> codes = spatial_keys(grid);
  std::array<std::size_t, 22> splits{};  // splits[l]: consecutive vertices in different cells first at level l
  for (std::size_t i = 1; i < codes.size(); ++i) {
    const std::uint64_t x = codes[i] ^ codes[i - 1];
    if (x == 0) continue;
    const auto bits = static_cast<unsigned>(64 - std::countl_zero(x));  // the highest differing bit, 1-based
    ++splits[21 - (bits - 1) / 3];
  }
  // The first level whose cells hold fewer than per_block on average, or
  // the one before it, whichever is nearer by ratio.
  const auto n = static_cast<double>(grid.size());
  std::size_t cells = 1;
  double before = n;  // the average at the level before
  for (unsigned level = 1; level <= 20; ++level) {
    cells += splits[level];
    const double average = n / static_cast<double>(cells);
    if (average < static_cast<double>(per_block)) {
      const auto per = static_cast<double>(per_block);
      const bool coarser = level > 1 && before / per < per / average;
      return coarser ? level - 1 : level;
    }
    before = average;
  }
  return 20;
}

void partition(MeshState& s, const std::vector<std::array<std::uint32_t, 3>>& grid, unsigned level, double shift,
               Partition& out) {
  const unsigned side = 21 - level;
  const auto offset = static_cast<std::uint32_t>(shift * static_cast<double>(1u << side));
  const auto key_of = [&](std::size_t v) {
    std::uint64_t key = 0;
    for (const std::uint32_t q : grid[v]) key = key << 21 | ((q + offset) >> side);
    return key;
  };
  s.block_of.assign(s.faces.size(), none);
  s.local.assign(s.faces.size(), 0);
  std::unordered_map<std::uint64_t, std::uint32_t> id;
  std::vector<std::uint32_t> size;
  std::uint64_t last = ~std::uint64_t{0};
  std::uint32_t last_id = none;
  for (const std::uint32_t v : s.living) {
    const std::uint64_t key = key_of(v);
    if (key != last) {
      const auto [it, added] = id.emplace(key, static_cast<std::uint32_t>(size.size()));
      if (added) size.push_back(0);
      last = key, last_id = it->second;
    }
    s.block_of[v] = last_id;
    s.local[v] = size[last_id]++;
  }
  out.start.assign(size.size() + 1, 0);
  for (std::size_t b = 0; b < size.size(); ++b) out.start[b + 1] = out.start[b] + size[b];
  out.members.resize(out.start.back());
  for (const std::uint32_t v : s.living) out.members[out.start[s.block_of[v]] + s.local[v]] = v;
}

// The per-vertex mark of the blocks' lanes: v's move costs at most the
// round's limit (at the round's start: one whose cost falls under it in
// the round waits for the next), and v's ring lies in v's block.
void mark_inner(MeshState& s, double limit) {
  s.inner.assign(s.faces.size(), 0);
  detail::parallel_for_dynamic(s.living.size(), 4096, [&](std::size_t i) {
    const std::uint32_t v = s.living[i];
    bool inner = s.cost[v] <= limit;
    for (const std::uint32_t f : s.faces[v])
      for (const std::uint32_t w : s.tris[f]) inner = inner && s.block_of[w] == s.block_of[v];
    s.inner[v] = inner ? 1 : 0;
  });
}

// A round's limit: the `wanted`-th smallest cost of the living vertices'
// cheapest moves, `wanted` at most round_fraction(round) of them (infinity when
// fewer can move; -1 when none is wanted).
double round_limit(MeshState& s, std::size_t round, std::size_t wanted) {
  std::vector<double>& costs = s.living_costs;  // (the seams' too)
  costs.clear();
  for (const std::uint32_t v : s.living)
    if (s.cost[v] < std::numeric_limits<double>::infinity()) costs.push_back(s.cost[v]);
  wanted = std::min(wanted, static_cast<std::size_t>(round_fraction(round) * static_cast<double>(costs.size())));
  if (wanted == 0 || costs.empty()) return -1.0;
  if (wanted >= costs.size()) return std::numeric_limits<double>::infinity();
  std::nth_element(costs.begin(), costs.begin() + static_cast<std::ptrdiff_t>(wanted - 1), costs.end());
  return costs[wanted - 1];
}

// One lane's tally, added into `out` in the lanes' order.
struct LaneTally {
  std::size_t collapses = 0, refused = 0, removed = 0;
  OperationCounts counts;
  double vertex_error = 0.0;
};

template <class Lane>
LaneTally tally_of(const Lane& lane) {
  return {lane.collapses_, lane.refused_, lane.removed_, lane.counts_, lane.vertex_error_};
}

// One round: each block's lane, on all threads (one after another for the
// plain loop), its moves up to the round's limit, at most its share of
// `collapses` (by its moves under the limit). Adds each block's tally;
// returns the triangles removed.
template <class Queue, Loop loop>
std::size_t run_round(Collapser<Queue, loop>& start, MeshState& s, const Partition& blocks, std::size_t round,
                      std::size_t collapses, std::vector<LaneTally>& tallies) {
  std::vector<double>& cost = s.cost;
  start.costs_now(cost);
  const double limit = round_limit(s, round, collapses);
  mark_inner(s, limit);
  std::vector<std::size_t> under(blocks.count(), 0);  // per block: inner moves under the limit
  std::size_t all = 0;
  for (const std::uint32_t v : s.living)
    if (s.inner[v]) ++under[s.block_of[v]], ++all;  // (inner: under the limit too)
  if (all == 0) return 0;
  std::vector<LaneTally> lanes(blocks.count());
  const auto block = [&](std::size_t b) {
    const auto share = static_cast<std::size_t>(static_cast<double>(collapses) * static_cast<double>(under[b]) /
                                                static_cast<double>(all));
    if (share == 0) return;
    Collapser<Queue, loop> lane(start, blocks.block(b), static_cast<std::uint32_t>(b));
    lane.run_below(limit, share, cost);
    lanes[b] = tally_of(lane);
  };
  if constexpr (loop == Loop::plain) {
    for (std::size_t b = 0; b < blocks.count(); ++b) block(b);
  } else {
    detail::parallel_for_dynamic(blocks.count(), 1, block);
  }
  std::size_t removed = 0;
  for (const LaneTally& t : lanes) removed += t.removed;
  tallies.insert(tallies.end(), lanes.begin(), lanes.end());
  return removed;
}

// The rounds, until the last queue's share is left, or a round gains less
// than a hundredth of it. Returns the triangles left.
template <class Queue, Loop loop>
std::size_t run_rounds(Collapser<Queue, loop>& start, MeshState& s, const std::vector<Vec3>& points,
                       std::size_t block_vertices, std::size_t target, std::vector<LaneTally>& tallies) {
  const std::vector<std::array<std::uint32_t, 3>> grid = spatial_cells(points);
  const unsigned level = level_for(grid, block_vertices);
  std::size_t alive = s.triangles;
  const double asked = static_cast<double>(s.triangles - target);
  for (std::uint32_t v = 0; v < s.faces.size(); ++v)
    if (!s.faces[v].empty()) s.living.push_back(v);
  Partition blocks;
  // (A round never passes the target, so alive > target holds; checked
  // anyway, as alive - target must not wrap.)
  const auto more_asked = [&] { return alive > target && static_cast<double>(alive - target) > finish_share * asked; };
  for (std::size_t r = 0; r < most_rounds && more_asked(); ++r) {
    partition(s, grid, level, round_shifts[r % round_shifts.size()], blocks);
    // A collapse removes at most two triangles: half the excess never
    // passes the target.
    const std::size_t removed = run_round(start, s, blocks, r, (alive - target) / 2, tallies);
    alive -= removed;
    std::erase_if(s.living, [&](std::uint32_t v) { return s.faces[v].empty(); });
    if (static_cast<double>(removed) < 0.01 * finish_share * asked) break;
  }
  return alive;
}

template <class Queue, Loop loop = Loop::fast>
Simplification simplify_on(const Mesh& mesh, const SimplifyOptions& options, std::size_t target) {
  Simplification out;
  Timer timer;
  MeshState state;
  Collapser<Queue, loop> start(mesh, options, state);
  const std::size_t n = mesh.vertices.size();
  const std::size_t bv = options.block_vertices;
  std::vector<LaneTally> tallies;
  std::size_t alive = state.triangles;
  if (bv > 0 && n > bv && state.triangles > target)
    alive = run_rounds(start, state, mesh.vertices, bv, target, tallies);
  Collapser<Queue, loop> finish(start, {}, none);
  finish.run(alive > target ? alive - target : 0);
  tallies.push_back(tally_of(finish));
  for (const LaneTally& t : tallies) {
    out.collapses += t.collapses;
    out.refused += t.refused;
    out.counts += t.counts;
    out.vertex_error = std::max(out.vertex_error, t.vertex_error);
  }
  out.mesh = start.result(mesh, out);
  out.triangles_before = mesh.triangles.size();
  out.triangles_after = out.mesh.triangles.size();
  out.seconds = timer.elapsed();
  return out;
}

// The triangles renumbered, each starting at its smallest index (its
// orientation kept), in lexicographic order: bucketed by their first
// index (a counting sort, O(F + V)), then each short bucket sorted.
std::vector<std::array<std::uint32_t, 3>> triangles_in_order(const std::vector<std::array<std::uint32_t, 3>>& triangles,
                                                             const std::vector<std::uint32_t>& renumber) {
  std::vector<std::uint32_t> start(renumber.size() + 1, 0);
  std::vector<std::array<std::uint32_t, 3>> rotated(triangles.size());
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    std::array<std::uint32_t, 3> r{renumber[triangles[t][0]], renumber[triangles[t][1]], renumber[triangles[t][2]]};
    std::rotate(r.begin(), std::min_element(r.begin(), r.end()), r.end());
    rotated[t] = r;
    ++start[r[0] + 1];
  }
  std::partial_sum(start.begin(), start.end(), start.begin());
  std::vector<std::array<std::uint32_t, 3>> out(triangles.size());
  std::vector<std::uint32_t> next(start.begin(), start.end() - 1);
  for (const auto& r : rotated) out[next[r[0]]++] = r;
  for (std::size_t v = 0; v + 1 < start.size(); ++v)
    if (start[v + 1] - start[v] > 1) std::sort(out.begin() + start[v], out.begin() + start[v + 1]);
  return out;
}

// The mesh renumbered by its geometry alone: vertices along the Z-order
// curve of their bounding box (spatial_order.h), those in one cell of it
// by position (x, then y, then z; the old index only between coincident
// ones), each triangle starting at its smallest index (its orientation
// kept), triangles sorted. Why: the collapses break their ties by index,
// so without this the result would depend on how the vertices happen to be
// numbered (a tiled run's stitch numbers them otherwise than the run in
// memory, for the same triangles); and vertices near in space are near in
// memory, which the collapses, visiting the mesh in cost order, need (and
// a grid cell's vertices are a few runs of consecutive ones: a round's
// block).
// Cost O(V log V + F).
Mesh in_canonical_order(const Mesh& mesh) {
  const std::size_t n = mesh.vertices.size();
  // One sort, with the coordinates beside each index (no lookup through
  // it, no cache miss a comparison).
  const std::vector<std::uint64_t> codes = spatial_keys(mesh.vertices);
  struct Keyed {
    std::uint64_t code;
    double x, y, z;
    std::uint32_t index;
  };
  std::vector<Keyed> keyed(n);
  for (std::uint32_t i = 0; i < n; ++i)
    keyed[i] = {codes[i], mesh.vertices[i].x(), mesh.vertices[i].y(), mesh.vertices[i].z(), i};
  // (A total order, the index last: halves sorted on two threads and
  // merged give the one order.)
  const auto before = [](const Keyed& a, const Keyed& b) {
    return std::tie(a.code, a.x, a.y, a.z, a.index) < std::tie(b.code, b.x, b.y, b.z, b.index);
  };
  const auto middle = keyed.begin() + static_cast<std::ptrdiff_t>(n / 2);
  detail::parallel_for(2, [&](std::size_t half) {
    if (half == 0)
      std::sort(keyed.begin(), middle, before);
    else
      std::sort(middle, keyed.end(), before);
  });
  std::inplace_merge(keyed.begin(), middle, keyed.end(), before);
  Mesh out;
  std::vector<std::uint32_t> renumber(n);
  out.vertices.reserve(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t old = keyed[i].index;
    renumber[old] = i;
    out.vertices.push_back(mesh.vertices[old]);
    if (mesh.has_colors()) out.colors.push_back(mesh.colors[old]);
    if (mesh.has_normals()) out.normals.push_back(mesh.normals[old]);
  }
  out.triangles = triangles_in_order(mesh.triangles, renumber);
  return out;
}

}  // namespace

Simplification simplify(const Mesh& mesh, const SimplifyOptions& options) {
  const std::size_t target = target_of(mesh, options);
  check_indices(mesh);
  Timer timer;
  const Mesh canonical = in_canonical_order(mesh);
  const double seconds_order = timer.elapsed();

  Simplification out;
  switch (options.queue) {
    case SimplifyQueue::pairing_heap:
      out = simplify_on<PairingQueue>(canonical, options, target);
      break;
    case SimplifyQueue::lazy:
      out = simplify_on<LazyQueue>(canonical, options, target);
      break;
    case SimplifyQueue::binary_heap:
      out = simplify_on<HeapQueue>(canonical, options, target);
      break;
  }
  out.seconds += seconds_order;
  return out;
}

namespace detail {

Simplification simplify_plain(const Mesh& mesh, const SimplifyOptions& options) {
  const std::size_t target = target_of(mesh, options);
  check_indices(mesh);
  return simplify_on<HeapQueue, Loop::plain>(in_canonical_order(mesh), options, target);
}

}  // namespace detail
}  // namespace recon
