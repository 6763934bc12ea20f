#include "recon/phase6_simplify/simplification.h"

#include "recon/structures/binary_heap.h"
#include "recon/core/detail/parallel_for.h"
#include "recon/phase6_simplify/detail/simplify_plain.h"
#include "recon/core/errors.h"
#include "recon/structures/pairing_heap.h"
#include "recon/core/parallel.h"
#include "recon/structures/spatial_order.h"
#include "recon/core/timer.h"
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

constexpr std::uint32_t none = UINT32_MAX;

// ---------------------------------------------------------------------------
// Quadrics: the sum of w (n . x + d)^2 over planes, as a symmetric 4x4 form
// (A = sum w n n^T, b = sum w d n, c = sum w d^2).

struct Quadric {
  double xx = 0, xy = 0, xz = 0, yy = 0, yz = 0, zz = 0, x = 0, y = 0, z = 0, c = 0;
  double weight = 0;  // the planes' total weight (an area): scales the tie-break term

  void add_plane(const Vec3& n, double d, double w) {
    xx += w * n.x() * n.x();
    xy += w * n.x() * n.y();
    xz += w * n.x() * n.z();
    yy += w * n.y() * n.y();
    yz += w * n.y() * n.z();
    zz += w * n.z() * n.z();
    x += w * d * n.x();
    y += w * d * n.y();
    z += w * d * n.z();
    c += w * d * d;
    weight += w;
  }
  Quadric& operator+=(const Quadric& q) {
    xx += q.xx, xy += q.xy, xz += q.xz, yy += q.yy, yz += q.yz, zz += q.zz;
    x += q.x, y += q.y, z += q.z, c += q.c, weight += q.weight;
    return *this;
  }
  // The sum of the weighted squared distances from p to the planes.
  [[nodiscard]] double at(const Vec3& p) const {
    const double px = p.x(), py = p.y(), pz = p.z();
    const double quadratic = xx * px * px + yy * py * py + zz * pz * pz +
                             2.0 * (xy * px * py + xz * px * pz + yz * py * pz);
    return std::max(0.0, quadratic + 2.0 * (x * px + y * py + z * pz) + c);
  }
};

// Ties of flat ground (a quadric error of 0) go to the shortest edge.
constexpr double tie_break = 1e-4;

// ---------------------------------------------------------------------------
// The three queues, one interface: push, update (either way), erase, pop
// the smallest (cost, vertex). Each counts its operations.

// An indexed heap with update_key and erase (binary or pairing): the same
// adapter for both.
template <class Heap>
class IndexedQueue {
 public:
  explicit IndexedQueue(std::size_t n) : heap_(n) {}
  [[nodiscard]] bool contains(std::uint32_t v) const { return heap_.contains(v); }
  void set(std::uint32_t v, double cost, OperationCounts& counts) {
    if (heap_.contains(v)) {
      ++counts.decrease_keys;
      heap_.update_key(v, cost);
    } else {
      ++counts.pushes;
      heap_.push(v, cost);
    }
  }
  void erase(std::uint32_t v) {
    if (heap_.contains(v)) heap_.erase(v);
  }
  [[nodiscard]] bool empty() { return heap_.empty(); }
  std::uint32_t pop(OperationCounts& counts) {
    ++counts.pops;
    return heap_.pop();
  }

 private:
  Heap heap_;
};
using HeapQueue = IndexedQueue<IndexedBinaryHeap<double>>;
using PairingQueue = IndexedQueue<PairingHeap<double>>;

// No update at all: a new key is a new entry, and the old ones are left in
// the queue, recognised as stale when they surface (their version is old).
class LazyQueue {
 public:
  explicit LazyQueue(std::size_t n) : version_(n, 0), queued_(n, 0) {}
  [[nodiscard]] bool contains(std::uint32_t v) const { return queued_[v] != 0; }
  void set(std::uint32_t v, double cost, OperationCounts& counts) {
    ++counts.pushes;
    queued_[v] = 1;
    entries_.push({cost, v, ++version_[v]});
  }
  void erase(std::uint32_t v) {
    queued_[v] = 0;
    ++version_[v];
  }
  [[nodiscard]] bool empty() {
    drop_stale();
    return entries_.empty();
  }
  std::uint32_t pop(OperationCounts& counts) {
    drop_stale();
    ++counts.pops;
    const std::uint32_t v = entries_.top().vertex;
    entries_.pop();
    queued_[v] = 0;
    ++version_[v];
    return v;
  }

 private:
  struct Entry {
    double cost;
    std::uint32_t vertex;
    std::uint32_t version;
    // std::priority_queue pops its largest: the larger entry is the later one.
    bool operator<(const Entry& o) const { return o.cost < cost || (!(cost < o.cost) && o.vertex < vertex); }
  };
  void drop_stale() {
    while (!entries_.empty() && entries_.top().version != version_[entries_.top().vertex]) {
      entries_.pop();
    }
  }
  std::priority_queue<Entry> entries_;
  std::vector<std::uint32_t> version_;
  std::vector<std::uint8_t> queued_;
};

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

Vec3 cross_of(const Vec3& a, const Vec3& b, const Vec3& c) { return (b - a).cross(c - a); }

// ---------------------------------------------------------------------------
// The collapses, on any of the queues.

enum Kind : std::uint8_t { free_vertex = 0, line_vertex = 1, fixed_vertex = 2 };
enum PlaneShape : std::uint8_t { flat = 0, crease = 1, corner = 2 };

// A second eigenvalue of the normals' moment over this: the planes around a
// vertex span two directions, a crease. Two planes at phase V's 25 degree
// crease angle, of equal areas, give 0.047; phase V's slivers along a
// crease a few thousandths.
constexpr double second_direction = 0.02;
// A third eigenvalue over this: a corner (three planes of equal areas give
// 1/3). At 0.1, one of the eight corners of phase V's box (unequal areas
// around it) moved along a crease at 100x fewer triangles; at 0.03 none did.
constexpr double third_direction = 0.03;
// A vertex whose fan is not flat is judged by the planes within this many
// of its mean edges: near a corner if their third eigenvalue is over
// third_direction_wide (phase V's part from 20,000 samples: 0.10 to 0.33
// for the candidates near its corners; a straight crease's ball has none).
constexpr double corner_reach = 3.0;
constexpr double third_direction_wide = 0.1;
// And a cluster of them is a corner when one of them has a ball whose third
// eigenvalue is over this. Three faces at right angles give 1/3, a
// hexagonal prism's corner 1/6; phase V's part, by its corners 0.29 to
// 0.33, and 0.12 where a ball of the coarse mesh on a hole's wall reached
// the rim (the wall's curvature makes its third direction).
constexpr double corner_strength = 0.15;
// A crease vertex lies within this fraction of the segment between its two
// crease neighbours from it: phase V's crease vertices lie on the line (a
// curved crease's sag is |e| / 8R of it). On phase V's box (60,000
// samples) 1,764 of its 2,029 crease candidates pass, 1,747 of them on the
// true edges.
constexpr double line_tolerance = 0.05;

// A triangle whose doubled area is below this fraction of the sum of its
// squared edges is a sliver (an equilateral one has 0.58; this is about a
// 2 degree smallest angle).
constexpr double sliver_ratio = 0.05;

// The loop comes two ways over the same rules. Fast (simplify): each
// vertex's cheapest move by cost is cached and recomputed only when the
// vertex's triangles or quadric change (a collapse u -> v touches only u's
// ring, v included), the start (quadrics, plane shapes, first costs) runs
// on all threads, and the queue is not touched when a key stays the same.
// Plain (detail::simplify_plain, the reference the tests hold the fast way
// to): every re-costing gathers the ring again, one thread, as the
// textbook loop reads. Both give the same mesh because the cache holds
// exactly what a re-costing would find: moves(w) and cost(w, .) read only
// w's triangles, w's quadric and what never changes (positions, plane
// shapes, kinds of the living vertices).
enum class Loop { fast, plain };

// A vertex's sorted ring as neighbours() last gathered it; size over the
// capacity: stale or too long to keep (one cache line a vertex).
struct RingMemo {
  static constexpr std::uint32_t stale = UINT32_MAX;
  std::uint32_t size = stale;
  std::array<std::uint32_t, 15> ring{};
};

// The mesh as the collapses change it, and what the start found per vertex
// and per triangle: what the lanes (below) share.
struct MeshState {
  std::vector<std::array<std::uint32_t, 3>> tris;
  std::vector<std::uint8_t> alive_tri;
  std::size_t triangles = 0;  // loaded (those with three distinct corners)
  std::vector<std::vector<std::uint32_t>> faces;
  std::vector<Quadric> q;
  std::vector<std::uint8_t> kind, kind0;
  std::vector<std::uint8_t> plane_shape;
  std::vector<Vec3> crease_direction;
  std::vector<std::array<std::uint32_t, 2>> boundary_edges;
  std::vector<std::uint32_t> best;
  std::vector<double> key;                              // u's key in the queue, when queued
  std::vector<std::pair<std::uint32_t, double>> cheap;  // u's cheapest move by cost (cheapest())
  std::vector<std::uint8_t> fresh;                      // whether cheap[u] still holds
  std::vector<RingMemo> rings;                          // fast loop only: a cache, not state
  bool on_all_threads = false;                          // rings read-only while true
  std::vector<std::vector<std::uint32_t>> kept;
  std::vector<std::uint8_t> inner;       // per vertex: a round's lane may queue it (mark_inner)
  std::vector<std::uint32_t> block_of;  // per vertex: its block in this round
  std::vector<std::uint32_t> local;     // per vertex: its place in its block's list
  std::vector<std::uint32_t> living;    // the vertices with triangles, in increasing order (the rounds')
  std::vector<double> cost;             // per vertex: its cheapest move's cost at the round's start
  std::vector<double> living_costs;      // scratch of round_limit: the living's costs (kept: no new pages a round)
};

template <class Queue, Loop loop = Loop::fast>
class Collapser {
 public:
  // The start, on the whole mesh: steps 0 to 4 and the first costs, into
  // `state`. It queues nothing: the lanes do.
  Collapser(const Mesh& mesh, const SimplifyOptions& options, MeshState& state)
      : p_(mesh.vertices),
        options_(options),
        s_(state),
        queue_(0),
        cos_turn_(std::cos(options.max_normal_turn_degrees * std::numbers::pi / 180.0)) {
    load_triangles(mesh);
    build_quadrics();
    find_features();
    add_boundary_planes();
    if (options_.max_error > 0.0) kept_.resize(tris_.size());
    best_.assign(p_.size(), none);
    key_.assign(p_.size(), 0.0);
    first_costs();
  }

  // A lane on the start's state: it queues the inner vertices of `block`
  // (its `members`, in increasing order), or every vertex (block = none).
  Collapser(const Collapser& start, std::span<const std::uint32_t> members, std::uint32_t block)
      : p_(start.p_),
        options_(start.options_),
        s_(start.s_),
        queue_(block == none ? start.p_.size() : members.size()),
        cos_turn_(start.cos_turn_),
        members_(members),
        block_(block) {}

  // Step 5, a lane's loop: queue the lane's vertices, then collapse the
  // cheapest allowed move until it has removed `may_remove` triangles, or
  // no move is left.
  void run(std::size_t may_remove) {
    for (std::uint32_t v = 0; v < p_.size(); ++v)
      if (mine(v)) requeue(v);
    collapse_cheapest(may_remove, std::numeric_limits<std::size_t>::max(), std::numeric_limits<double>::infinity());
  }

  // A block's loop in a round: queue the lane's vertices whose move costs
  // at most `limit` now (`cost`, from costs_now), then collapse the
  // cheapest allowed move while it costs at most `limit`, at most `most`
  // times. (A vertex over the limit may come under it when its ring
  // changes: it is queued then.)
  void run_below(double limit, std::size_t most, const std::vector<double>& cost) {
    for (const std::uint32_t v : members_)
      if (mine(v) && cost[v] <= limit) requeue(v);
    collapse_cheapest(std::numeric_limits<std::size_t>::max(), most, limit);
  }

  // Every living vertex's cheapest cost now (s_.living's), into `out`
  // (infinity for the others and the unmovable), on all threads, each
  // vertex alone; the fast loop keeps the moves it recomputes.
  void costs_now(std::vector<double>& out) {
    out.assign(p_.size(), std::numeric_limits<double>::infinity());
    const std::vector<std::uint32_t>& living = s_.living;
    const auto at = [&](std::size_t i) { return living[i]; };
    each_on_all_threads(living.size(), at, [&](std::uint32_t v, std::vector<std::uint32_t>& scratch) {
      if (!fresh_[v]) {
        keep_ring(v, scratch);
        const auto c = cheapest(v, scratch);
        out[v] = c.second;
        if (loop == Loop::plain) return;
        cheap_[v] = c;
        fresh_[v] = 1;
      }
      out[v] = cheap_[v].second;
    });
  }

  // body(v, scratch) for v = at(0), ..., at(count - 1), each vertex alone,
  // on all threads (blocks of 4096, a scratch each). Meanwhile neighbours()
  // keeps no ring, whatever vertex a rule asks about; keep_ring keeps the
  // ring of the vertex in hand (its thread is the only one to write it).
  template <class At, class Body>
  void each_on_all_threads(std::size_t count, At at, Body body) {
    on_all_threads_ = true;
    constexpr std::size_t block = 4096;
    detail::parallel_for_dynamic((count + block - 1) / block, 1, [&](std::size_t b) {
      std::vector<std::uint32_t> scratch;
      for (std::size_t i = b * block; i < std::min(count, (b + 1) * block); ++i)
        body(static_cast<std::uint32_t>(at(i)), scratch);
    });
    on_all_threads_ = false;
  }

  void collapse_cheapest(std::size_t may_remove, std::size_t most, double limit) {
    while (removed_ < may_remove && collapses_ < most && !queue_.empty()) {
      const std::uint32_t u = vertex_at(queue_.pop(counts_));
      if (key_[u] > limit) break;  // and every key after it
      const std::uint32_t v = best_[u];
      if (allowed(u, v)) {
        collapse(u, v);
        ++collapses_;
        continue;
      }
      ++refused_;
      retry(u);
    }
  }

  [[nodiscard]] Mesh result(const Mesh& mesh, Simplification& out) const {
    out.crease_vertices = static_cast<std::size_t>(std::count(kind0_.begin(), kind0_.end(), line_vertex));
    out.corner_vertices = static_cast<std::size_t>(std::count(kind0_.begin(), kind0_.end(), fixed_vertex));
    Mesh m;
    std::vector<std::uint32_t> index(p_.size(), none);
    for (std::size_t t = 0; t < tris_.size(); ++t)
      if (alive_tri_[t])
        for (const std::uint32_t v : tris_[t]) index[v] = 0;
    for (std::uint32_t v = 0; v < p_.size(); ++v) {
      if (index[v] == none) continue;
      index[v] = static_cast<std::uint32_t>(m.vertices.size());
      m.vertices.push_back(p_[v]);
      if (mesh.has_colors()) m.colors.push_back(mesh.colors[v]);
      if (mesh.has_normals()) m.normals.push_back(mesh.normals[v]);
    }
    for (std::size_t t = 0; t < tris_.size(); ++t)
      if (alive_tri_[t]) m.triangles.push_back({index[tris_[t][0]], index[tris_[t][1]], index[tris_[t][2]]});
    return m;
  }

 private:
  // Step 0: triangles and, per vertex, the triangles around it. A triangle
  // with a repeated vertex has no area and no plane: it is left out.
  // (Each thread fills the lists of its own run of vertices, every list in
  // the triangles' order, allocated once: the same lists on any threads.)
  void load_triangles(const Mesh& mesh) {
    tris_.reserve(mesh.triangles.size());
    for (const auto& t : mesh.triangles)
      if (t[0] != t[1] && t[1] != t[2] && t[0] != t[2]) tris_.push_back(t);
    faces_.resize(p_.size());
    const auto parts = static_cast<std::size_t>(std::max(1, thread_count()));
    detail::parallel_for(parts, [&](std::size_t part) {
      const std::size_t lo = part * p_.size() / parts, hi = (part + 1) * p_.size() / parts;
      std::vector<std::uint32_t> degree(hi - lo, 0);
      for (const auto& t : tris_)
        for (const std::uint32_t v : t)
          if (v >= lo && v < hi) ++degree[v - lo];
      for (std::size_t v = lo; v < hi; ++v) faces_[v].reserve(degree[v - lo]);
      for (std::uint32_t f = 0; f < tris_.size(); ++f)
        for (const std::uint32_t v : tris_[f])
          if (v >= lo && v < hi) faces_[v].push_back(f);
    });
    alive_tri_.assign(tris_.size(), 1);
    s_.triangles = tris_.size();
    if (loop == Loop::fast) rings_.assign(p_.size(), RingMemo{});
  }

  // Step 1: the area-weighted planes of the triangles around each vertex.
  // Each vertex sums its triangles' planes in the order of its triangle
  // list (the triangles' order), so the sums are the same on any threads.
  void build_quadrics() {
    struct Plane {
      Vec3 n;
      double d, w;  // w = 0: no area, no plane
    };
    std::vector<Plane> planes(tris_.size());
    detail::parallel_for(tris_.size(), [&](std::size_t t) {
      const auto& f = tris_[t];
      const Vec3 n2 = cross_of(p_[f[0]], p_[f[1]], p_[f[2]]);
      const double twice_area = n2.norm();
      if (!(twice_area > 0.0)) {
        planes[t] = {Vec3::Zero(), 0.0, 0.0};
        return;
      }
      const Vec3 n = n2 / twice_area;
      planes[t] = {n, -n.dot(p_[f[0]]), 0.5 * twice_area};
    });
    q_.assign(p_.size(), {});
    detail::parallel_for(p_.size(), [&](std::size_t v) {
      for (const std::uint32_t f : faces_[v])
        if (planes[f].w > 0.0) q_[v].add_plane(planes[f].n, planes[f].d, planes[f].w);
    });
  }

  // Step 2: what each vertex's planes say of it, by the eigenvalues of
  // their normals' second moment (area-weighted, so that the slivers phase V
  // leaves along a crease hardly count): one direction, flat ground; two, a
  // crease, along the third eigenvector; three, a corner. The fan only
  // nominates: the planes of a wider ball decide, one vertex per corner
  // (confirm_corners), and a crease vertex must lie on its crease line
  // (drop_off_line_creases).
  void shape_of_planes() {
    plane_shape_.assign(p_.size(), flat);
    crease_direction_.assign(p_.size(), Vec3::Zero());
    detail::parallel_for_dynamic(p_.size(), 4096, [&](std::size_t i) {  // each vertex alone: any threads
      const auto v = static_cast<std::uint32_t>(i);
      const Quadric& q = q_[v];
      if (!(q.weight > 0.0) || planar_fan(v)) return;
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(moment_of(q));
      const Vec3 lambda = solver.eigenvalues();  // ascending
      if (lambda[0] > third_direction) {
        plane_shape_[v] = corner;
      } else if (lambda[1] > second_direction) {
        plane_shape_[v] = crease;
        crease_direction_[v] = solver.eigenvectors().col(0);
      }
    });
    confirm_corners();
    drop_off_line_creases();
  }

  // A crease vertex lies between two neighbours on its crease (by
  // crease_edge), within line_tolerance of the segment joining them, as
  // the vertices phase V puts on a crease line do. One that does not is a
  // face vertex near a crease whose fan phase V tilted with a triangle
  // across the crease, or a fold: it is flat ground, and so moves out of
  // the crease line's way. One pass, judged on the classification before
  // it: passes until nothing changes would wear a crease away from any gap
  // in it, one end vertex at a time.
  void drop_off_line_creases() {
    std::vector<std::uint32_t> off;
    for (std::uint32_t v = 0; v < p_.size(); ++v)
      if (plane_shape_[v] == crease && !on_line(v)) off.push_back(v);
    for (const std::uint32_t v : off) plane_shape_[v] = flat;
  }

  // Whether v lies between two of its crease neighbours, on the segment
  // joining them (within line_tolerance of its length).
  [[nodiscard]] bool on_line(std::uint32_t v) {
    neighbours(v, ring_);
    std::erase_if(ring_, [&](std::uint32_t w) { return !crease_edge(v, w); });
    for (std::size_t i = 0; i < ring_.size(); ++i)
      for (std::size_t j = i + 1; j < ring_.size(); ++j) {
        const Vec3 a = p_[ring_[i]], ab = p_[ring_[j]] - a, av = p_[v] - a;
        if (!(ab.squaredNorm() > 0.0)) continue;
        const double t = av.dot(ab) / ab.squaredNorm();
        if (t > 0.0 && t < 1.0 && (av - t * ab).norm() <= line_tolerance * ab.norm()) return true;
      }
    return false;
  }

  // The planes' normals' second moment per unit weight (A / weight).
  [[nodiscard]] static Eigen::Matrix3d moment_of(const Quadric& q) {
    Eigen::Matrix3d a;
    a << q.xx, q.xy, q.xz, q.xy, q.yy, q.yz, q.xz, q.yz, q.zz;
    return a / q.weight;
  }

  // A fan can span three directions without a corner: where phase V left a
  // triangle across a crease (its normal is neither face's) or a fold, and
  // around a corner, several vertices near it do; and a corner vertex's fan
  // can be all but flat on one of its faces. So every vertex whose fan is
  // not flat is a candidate, and the planes of the triangles within
  // corner_reach of its mean edges decide (the faces' areas there outweigh
  // a few stray triangles): (1) three directions (third_direction_wide):
  // the candidate is near a corner; else it is a crease or flat ground by
  // those planes (demote_by_wide_planes). (2) Near-corner candidates in
  // each other's balls whose planes meet at the same point are one
  // cluster; a cluster whose strongest ball is weak (corner_strength) is
  // no corner (a curved crease's curvature gives its third direction).
  // (3) The member nearest where the cluster's planes meet (the corner
  // itself) is the corner; the others become crease vertices whose line
  // runs through it: they move along their crease into it, never off it.
  void confirm_corners() {
    std::vector<std::uint32_t> candidates;
    for (std::uint32_t v = 0; v < p_.size(); ++v)
      if (plane_shape_[v] != flat) candidates.push_back(v);
    std::vector<std::uint32_t> index(p_.size(), none);  // per vertex: its place in candidates
    for (std::uint32_t i = 0; i < candidates.size(); ++i) index[candidates[i]] = i;
    UnionFind clusters(candidates.size());
    std::vector<Quadric> wide(candidates.size());
    std::vector<std::uint8_t> confirmed(candidates.size(), 0);
    std::vector<Vec3> meet(candidates.size(), Vec3::Zero());
    std::vector<double> strength(candidates.size(), 0.0);  // the ball's third eigenvalue
    for (std::uint32_t i = 0; i < candidates.size(); ++i) {
      const std::uint32_t v = candidates[i];
      wide[i] = planes_in_ball(v, ball_);
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(moment_of(wide[i]));
      if (!(solver.eigenvalues()[0] > third_direction_wide)) {
        demote_by_wide_planes(v, solver);
        continue;
      }
      confirmed[i] = 1;
      meet[i] = meeting_point(wide[i]);
      strength[i] = solver.eigenvalues()[0];
      // A confirmed candidate in the ball whose planes meet at the same
      // point (within v's mean edge): the same corner.
      const double same = mean_edge(v);
      for (const std::uint32_t w : ball_) {
        const std::uint32_t j = index[w];
        if (j != none && j < i && confirmed[j] && (meet[j] - meet[i]).norm() <= same) clusters.unite(i, j);
      }
    }
    keep_one_per_cluster(candidates, confirmed, clusters, wide, strength);
  }

  // A candidate whose wider planes are not a corner: a crease or flat
  // ground, as those planes say.
  void demote_by_wide_planes(std::uint32_t v, const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>& wide) {
    if (wide.eigenvalues()[1] > second_direction) {
      plane_shape_[v] = crease;
      crease_direction_[v] = wide.eigenvectors().col(0);
    } else {
      plane_shape_[v] = flat;
    }
  }

  // Per cluster, the candidate nearest where its planes meet stays a
  // corner; the others become creases pointing at it.
  void keep_one_per_cluster(const std::vector<std::uint32_t>& candidates, const std::vector<std::uint8_t>& confirmed,
                            UnionFind& clusters, const std::vector<Quadric>& wide,
                            const std::vector<double>& strength) {
    const std::size_t n = candidates.size();
    std::vector<std::uint32_t> root(n, none);
    std::vector<Quadric> planes(n);  // per root: its cluster's planes
    for (std::uint32_t i = 0; i < n; ++i)
      if (confirmed[i]) {
        root[i] = clusters.find(i);
        planes[root[i]] += wide[i];
      }
    std::vector<double> strongest(n, 0.0);  // per root: its members' largest third eigenvalue
    for (std::uint32_t i = 0; i < n; ++i)
      if (root[i] != none) strongest[root[i]] = std::max(strongest[root[i]], strength[i]);
    for (std::uint32_t i = 0; i < n; ++i)
      if (root[i] != none && !(strongest[root[i]] > corner_strength)) {
        demote_by_wide_planes(candidates[i], Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(moment_of(wide[i])));
        root[i] = none;
      }
    std::vector<std::uint32_t> keeper(n, none);  // per root: the candidate kept
    for (std::uint32_t i = 0; i < n; ++i) {
      if (root[i] == none) continue;
      const Vec3 meet = meeting_point(planes[root[i]]);
      std::uint32_t& k = keeper[root[i]];
      if (k == none || (p_[candidates[i]] - meet).squaredNorm() < (p_[candidates[k]] - meet).squaredNorm()) k = i;
    }
    for (std::uint32_t i = 0; i < n; ++i) {
      if (root[i] == none) continue;
      if (keeper[root[i]] == i) {
        plane_shape_[candidates[i]] = corner;
        continue;
      }
      const Vec3 line = p_[candidates[i]] - p_[candidates[keeper[root[i]]]];
      plane_shape_[candidates[i]] = crease;
      crease_direction_[candidates[i]] = line.norm() > 0.0 ? Vec3(line.normalized()) : Vec3::UnitX();
    }
  }

  // The mean length of the edges around v.
  [[nodiscard]] double mean_edge(std::uint32_t v) {
    neighbours(v, ring_);
    double sum = 0.0;
    for (const std::uint32_t w : ring_) sum += (p_[w] - p_[v]).norm();
    return ring_.empty() ? 0.0 : sum / static_cast<double>(ring_.size());
  }

  // The point nearest all of q's planes (q spans three directions).
  [[nodiscard]] static Vec3 meeting_point(const Quadric& q) {
    Eigen::Matrix3d a;
    a << q.xx, q.xy, q.xz, q.xy, q.yy, q.yz, q.xz, q.yz, q.zz;
    return a.ldlt().solve(-Vec3(q.x, q.y, q.z));
  }

  // The planes of the triangles around the vertices within corner_reach
  // times v's mean edge of it (reached through the mesh); `inside` gets
  // those vertices.
  Quadric planes_in_ball(std::uint32_t v, std::vector<std::uint32_t>& inside) {
    const double reach = corner_reach * mean_edge(v);
    const double reach2 = reach * reach;
    inside.assign(1, v);
    seen_.resize(p_.size(), 0);
    seen_[v] = 1;
    Quadric q;
    for (std::size_t next = 0; next < inside.size(); ++next)
      for (const std::uint32_t f : faces_[inside[next]])
        for (const std::uint32_t w : tris_[f])
          if (!seen_[w] && (p_[w] - p_[v]).squaredNorm() <= reach2) {
            seen_[w] = 1;
            inside.push_back(w);
          }
    counted_.clear();
    counted_face_.resize(tris_.size(), 0);
    for (const std::uint32_t w : inside)
      for (const std::uint32_t f : faces_[w])
        if (!counted_face_[f]) {
          counted_face_[f] = 1;
          counted_.push_back(f);
        }
    for (const std::uint32_t f : counted_) {
      counted_face_[f] = 0;
      const Vec3 n2 = normal(f);
      const double twice_area = n2.norm();
      if (twice_area > 0.0) q.add_plane(n2 / twice_area, -n2.dot(p_[tris_[f][0]]) / twice_area, 0.5 * twice_area);
    }
    for (const std::uint32_t w : inside) seen_[w] = 0;
    return q;
  }

  // All the triangles around v face within 10 degrees of the first: flat
  // ground, no eigenvalues needed (most vertices).
  [[nodiscard]] bool planar_fan(std::uint32_t v) const {
    if (faces_[v].empty()) return true;
    const Vec3 first = normal(faces_[v][0]).normalized();
    for (const std::uint32_t f : faces_[v])
      if (normal(f).normalized().dot(first) < 0.985) return false;
    return true;
  }

  // Step 3: each vertex's kind. A crease vertex (by its planes) moves
  // along the crease: onto a neighbour also on a crease or a corner, the
  // edge between them along the crease at both ends (crease_edge). A vertex
  // on an open boundary (two boundary edges, flat planes) moves along the
  // boundary. Fixed: corners, boundary vertices on a crease, vertices on
  // more than two boundary edges or on a non-manifold edge.
  void find_features() {
    shape_of_planes();
    kind_.assign(p_.size(), free_vertex);
    std::vector<std::uint8_t> open(p_.size(), 0);
    each_on_all_threads(p_.size(), std::identity{}, [&](std::uint32_t a, std::vector<std::uint32_t>& ring) {
      keep_ring(a, ring);
      kind_[a] = kind_of(a, ring, open[a]);
    });
    for (std::uint32_t a = 0; a < p_.size(); ++a) {
      if (!open[a]) continue;
      neighbours(a, ring_);
      for (const std::uint32_t b : ring_)
        if (b > a && faces_on(a, b).second == 1) boundary_edges_.push_back({a, b});
    }
    kind0_ = kind_;
  }

  // Vertex a's kind by its plane shape and the edges around it; `open`
  // set when a lies on a boundary edge.
  [[nodiscard]] std::uint8_t kind_of(std::uint32_t a, std::vector<std::uint32_t>& ring, std::uint8_t& open) const {
    neighbours(a, ring);
    std::size_t boundary = 0;
    bool non_manifold = false;
    for (const std::uint32_t b : ring) {
      const std::size_t n = faces_on(a, b).second;
      boundary += n == 1 ? 1 : 0;
      non_manifold = non_manifold || n > 2;
    }
    open = boundary > 0 ? 1 : 0;
    const PlaneShape shape = static_cast<PlaneShape>(plane_shape_[a]);
    if (non_manifold || shape == corner || (boundary > 0 && (boundary != 2 || shape != flat))) return fixed_vertex;
    if (boundary == 2 || shape == crease) return line_vertex;
    return free_vertex;
  }

  // Whether u -> v runs along a crease: v on a crease or a corner, the edge
  // within 35 degrees of the crease direction at each crease end.
  [[nodiscard]] bool crease_edge(std::uint32_t u, std::uint32_t v) const {
    return plane_shape_[v] != flat && along_crease(u, v) && along_crease(v, u);
  }

  // Whether edge ab, seen from a, runs along a crease a lies on.
  [[nodiscard]] bool along_crease(std::uint32_t a, std::uint32_t b) const {
    if (plane_shape_[a] == corner) return true;
    if (plane_shape_[a] == flat) return false;
    const Vec3 e = p_[b] - p_[a];
    return std::abs(crease_direction_[a].dot(e)) > 0.82 * e.norm();
  }

  // Step 4: a plane through each boundary edge perpendicular to its
  // triangle, so that moving along a curved boundary costs its deviation.
  void add_boundary_planes() {
    for (const auto& [a, b] : boundary_edges_) {
      const std::uint32_t f = faces_on(a, b).first;
      const Vec3 along = p_[b] - p_[a];
      Vec3 m = along.cross(normal(f));
      if (!(m.norm() > 0.0)) continue;
      m.normalize();
      const double w = along.squaredNorm();
      q_[a].add_plane(m, -m.dot(p_[a]), w);
      q_[b].add_plane(m, -m.dot(p_[a]), w);
    }
  }

  // ---- small queries ----
  [[nodiscard]] bool has(std::uint32_t f, std::uint32_t v) const {
    return tris_[f][0] == v || tris_[f][1] == v || tris_[f][2] == v;
  }
  [[nodiscard]] bool traverses(std::uint32_t f, std::uint32_t a, std::uint32_t b) const {
    const auto& t = tris_[f];
    return (t[0] == a && t[1] == b) || (t[1] == a && t[2] == b) || (t[2] == a && t[0] == b);
  }
  [[nodiscard]] Vec3 normal(std::uint32_t f) const { return cross_of(p_[tris_[f][0]], p_[tris_[f][1]], p_[tris_[f][2]]); }
  [[nodiscard]] std::uint32_t third(std::uint32_t f, std::uint32_t a, std::uint32_t b) const {
    for (const std::uint32_t v : tris_[f])
      if (v != a && v != b) return v;
    return none;
  }
  // The first triangle on edge ab and how many there are.
  [[nodiscard]] std::pair<std::uint32_t, std::size_t> faces_on(std::uint32_t a, std::uint32_t b) const {
    std::pair<std::uint32_t, std::size_t> r{none, 0};
    for (const std::uint32_t f : faces_[a])
      if (has(f, b)) {
        if (r.second == 0) r.first = f;
        ++r.second;
      }
    return r;
  }
  // The vertices sharing a triangle with v, sorted, once each.
  // The fast loop keeps each ring it gathers (up to RingMemo's capacity)
  // until a collapse changes v's triangles (collapse() marks it stale).
  // On all threads (each_on_all_threads) it only reads what is kept:
  // whatever vertices a rule asks about, no two threads write.
  void neighbours(std::uint32_t v, std::vector<std::uint32_t>& out) const {
    if (rings_.empty()) return gather_ring(v, out);
    RingMemo& memo = rings_[v];
    if (memo.size <= memo.ring.size()) {
      out.assign(memo.ring.begin(), memo.ring.begin() + memo.size);
      return;
    }
    gather_ring(v, out);
    if (out.size() > memo.ring.size() || on_all_threads_) return;
    std::copy(out.begin(), out.end(), memo.ring.begin());
    memo.size = static_cast<std::uint32_t>(out.size());
  }

  // Gathers and keeps v's ring when it is stale (fast loop), on any
  // thread: the thread that handles v is the only one to write v's memo.
  void keep_ring(std::uint32_t v, std::vector<std::uint32_t>& scratch) const {
    if (rings_.empty()) return;
    RingMemo& memo = rings_[v];
    if (memo.size <= memo.ring.size()) return;
    gather_ring(v, scratch);
    if (scratch.size() > memo.ring.size()) return;
    std::copy(scratch.begin(), scratch.end(), memo.ring.begin());
    memo.size = static_cast<std::uint32_t>(scratch.size());
  }

  // (An insertion into a short sorted list: a ring has about six.)
  void gather_ring(std::uint32_t v, std::vector<std::uint32_t>& out) const {
    out.clear();
    for (const std::uint32_t f : faces_[v])
      for (const std::uint32_t w : tris_[f]) {
        if (w == v) continue;
        std::size_t i = out.size();
        while (i > 0 && out[i - 1] > w) --i;
        if (i > 0 && out[i - 1] == w) continue;
        out.push_back(w);
        for (std::size_t j = out.size() - 1; j > i; --j) out[j] = out[j - 1];
        out[i] = w;
      }
  }

  [[nodiscard]] double cost(std::uint32_t u, std::uint32_t v) const {
    return q_[u].at(p_[v]) + tie_break * q_[u].weight * (p_[v] - p_[u]).squaredNorm();
  }

  // The moves u may make by the feature rules: anywhere for a free vertex,
  // along its crease or boundary for a line vertex, none for a fixed one.
  void moves(std::uint32_t u, std::vector<std::uint32_t>& out) const {
    out.clear();
    if (kind_[u] == fixed_vertex) return;
    neighbours(u, out);
    if (kind_[u] == free_vertex) return;
    const bool on_boundary = plane_shape_[u] == flat;
    std::erase_if(out, [&](std::uint32_t v) {
      return on_boundary ? faces_on(u, v).second != 1 : !crease_edge(u, v);
    });
  }

  // ---- the queue ----
  // u's cheapest move by cost alone (validity is checked when it surfaces):
  // the neighbour and the cost, none and infinity when u may not move.
  [[nodiscard]] std::pair<std::uint32_t, double> cheapest(std::uint32_t u, std::vector<std::uint32_t>& scratch) const {
    moves(u, scratch);
    double best = std::numeric_limits<double>::infinity();
    std::uint32_t to = none;
    for (const std::uint32_t v : scratch) {
      const double c = cost(u, v);
      if (c < best) best = c, to = v;
    }
    return {to, best};
  }

  // Every vertex's first cheapest move, on all threads (each vertex alone).
  void first_costs() {
    cheap_.assign(p_.size(), {none, 0.0});
    fresh_.assign(p_.size(), 0);
    if constexpr (loop == Loop::plain) return;
    each_on_all_threads(p_.size(), std::identity{}, [&](std::uint32_t v, std::vector<std::uint32_t>& scratch) {
      keep_ring(v, scratch);
      cheap_[v] = cheapest(v, scratch);
      fresh_[v] = 1;
    });
  }

  // Queues u by its cheapest move, from the cache while u's triangles and
  // quadric are unchanged.
  void requeue(std::uint32_t u) {
    if (!fresh_[u]) {
      cheap_[u] = cheapest(u, moves_);
      fresh_[u] = loop == Loop::fast;
    }
    place(u, cheap_[u].first, cheap_[u].second);
  }

  // u's cheapest move that is allowed now: after the cheapest was refused.
  void retry(std::uint32_t u) {
    moves(u, moves_);
    ranked_.clear();
    for (const std::uint32_t v : moves_) ranked_.emplace_back(cost(u, v), v);
    std::sort(ranked_.begin(), ranked_.end());
    for (const auto& [c, v] : ranked_)
      if (allowed(u, v)) {
        best_[u] = v;
        key_[u] = c;
        queue_.set(id(u), c, counts_);
        return;
      }
  }

  // (A key the queue already holds is left alone: the queues order by
  // (cost, vertex), so the order is the same, and the heap is spared.)
  void place(std::uint32_t u, std::uint32_t to, double c) {
    if (to == none) {
      best_[u] = to;
      queue_.erase(id(u));
      return;
    }
    if (loop == Loop::fast && best_[u] == to && key_[u] == c && queue_.contains(id(u))) return;
    best_[u] = to;
    key_[u] = c;
    queue_.set(id(u), c, counts_);
  }

  // ---- validity ----
  [[nodiscard]] bool allowed(std::uint32_t u, std::uint32_t v) {
    return link_holds(u, v) && lines_stay(u, v) && no_fold(u, v) && within_bound(u, v);
  }

  // The vertices u and v share must be exactly the far corners of the
  // triangles on uv: else the collapse glues two sheets along an edge.
  bool link_holds(std::uint32_t u, std::uint32_t v) {
    neighbours(u, ring_);
    neighbours(v, ring2_);
    std::size_t shared = 0;
    for (std::size_t i = 0, j = 0; i < ring_.size() && j < ring2_.size();) {
      if (ring_[i] < ring2_[j]) {
        ++i;
      } else if (ring2_[j] < ring_[i]) {
        ++j;
      } else {
        ++shared, ++i, ++j;
      }
    }
    std::size_t far = 0;
    for (const std::uint32_t f : faces_[u])
      if (has(f, v)) ++far;
    return far > 0 && shared == far;
  }

  // A boundary loop of three (a triangular hole) would become an edge.
  bool lines_stay(std::uint32_t u, std::uint32_t v) {
    if (kind_[u] != line_vertex || plane_shape_[u] != flat || faces_on(u, v).second != 1) return true;
    neighbours(u, ring_);
    for (const std::uint32_t w : ring_)
      if (w != v && faces_on(u, w).second == 1 && faces_on(v, w).second == 1) return false;
    return true;
  }

  // No triangle turns by more than the limit or loses its area, and no two
  // triangles end on the same three vertices.
  bool no_fold(std::uint32_t u, std::uint32_t v) const {
    Vec3 fan = Vec3::Zero();
    for (const std::uint32_t f : faces_[u]) fan += normal(f);
    for (const std::uint32_t f : faces_[u]) {
      if (has(f, v)) continue;
      const Vec3 before = normal(f);
      std::array<Vec3, 3> c{};
      for (std::size_t i = 0; i < 3; ++i) c[i] = tris_[f][i] == u ? p_[v] : p_[tris_[f][i]];
      const Vec3 after = (c[1] - c[0]).cross(c[2] - c[0]);
      const double scale = (c[1] - c[0]).squaredNorm() + (c[2] - c[1]).squaredNorm() + (c[0] - c[2]).squaredNorm();
      if (!(after.norm() > 1e-10 * scale)) return false;
      // A sliver's normal (three vertices nearly in a row, as along phase
      // V's creases) says nothing: only a real triangle's turn is checked.
      const double scale_before = (p_[tris_[f][1]] - p_[tris_[f][0]]).squaredNorm() +
                                  (p_[tris_[f][2]] - p_[tris_[f][1]]).squaredNorm() +
                                  (p_[tris_[f][0]] - p_[tris_[f][2]]).squaredNorm();
      const bool sliver = before.norm() < sliver_ratio * scale_before;
      if (!sliver && before.dot(after) < cos_turn_ * before.norm() * after.norm()) return false;
      // A sliver may turn, but not fold over: it must still face the side
      // u's triangles face together.
      if (sliver && !(fan.dot(after) > 0.0)) return false;
      // Nor may a real triangle become a sliver: its normal would say
      // nothing more, and it could stand across the surface (a sharp edge
      // in the middle of a face).
      if (!sliver && after.norm() < sliver_ratio * scale) return false;
      if (duplicates(f, u, v)) return false;
    }
    return true;
  }

  // Whether triangle f, with u moved onto v, has the vertices of a triangle of v.
  [[nodiscard]] bool duplicates(std::uint32_t f, std::uint32_t u, std::uint32_t v) const {
    std::uint32_t a = none, b = none;
    for (const std::uint32_t w : tris_[f])
      if (w != u) (a == none ? a : b) = w;
    for (const std::uint32_t g : faces_[v])
      if (has(g, a) && has(g, b)) return true;
    return false;
  }

  // With a bound: the input vertices kept by u's triangles, and u itself,
  // each within max_error of one of the triangles around v after the move.
  bool within_bound(std::uint32_t u, std::uint32_t v) {
    if (kept_.empty()) return true;
    handed_.clear();
    handed_.push_back(u);
    for (const std::uint32_t f : faces_[u]) handed_.insert(handed_.end(), kept_[f].begin(), kept_[f].end());
    keepers_.clear();
    for (const std::uint32_t f : faces_[u])
      if (!has(f, v)) keepers_.push_back(f);
    nearest_.clear();
    for (const std::uint32_t x : handed_) {
      double best = std::numeric_limits<double>::infinity();
      std::uint32_t keeper = none;
      for (const std::uint32_t f : keepers_) {
        const auto& t = tris_[f];
        const auto at = [&](std::uint32_t w) -> const Vec3& { return w == u ? p_[v] : p_[w]; };
        const double d = point_triangle_distance(p_[x], at(t[0]), at(t[1]), at(t[2]));
        if (d < best) best = d, keeper = f;
      }
      if (!(best <= options_.max_error)) return false;
      nearest_.push_back({keeper, best});
    }
    return true;
  }

  // ---- the collapse ----
  // Only u's ring (v included) changes triangles or quadric: their cached
  // moves are stale; the rest of v's ring is re-queued from the cache.
  void collapse(std::uint32_t u, std::uint32_t v) {
    if (!kept_.empty()) hand_over(u);
    for (const std::uint32_t f : faces_[u])
      for (const std::uint32_t w : tris_[f]) {
        fresh_[w] = 0;
        if (!rings_.empty()) rings_[w].size = RingMemo::stale;
        prefetch_quadric(w);
      }
    for (const std::uint32_t f : faces_[u]) {
      if (has(f, v)) {
        remove_triangle(f, u);
      } else {
        for (std::uint32_t& w : tris_[f])
          if (w == u) w = v;
        faces_[v].push_back(f);
      }
    }
    faces_[u].clear();
    q_[v] += q_[u];
    kind_[u] = fixed_vertex;
    queue_.erase(id(u));
    requeue_around(v);
  }

  // v and its ring, each once or more (requeue is idempotent, and the
  // queues' order does not depend on the order of the updates).
  void requeue_around(std::uint32_t v) {
    if constexpr (loop == Loop::plain) {
      neighbours(v, around_);
      if (mine(v)) requeue(v);
      for (const std::uint32_t w : around_)
        if (mine(w)) requeue(w);
    } else {
      prefetch_stale_around(v);
      if (mine(v)) requeue(v);
      for (const std::uint32_t f : faces_[v])
        for (const std::uint32_t w : tris_[f])
          if (w != v && mine(w)) requeue(w);
    }
  }

  // Each vertex of u's triangles is about to be re-queued from its quadric
  // (cheapest()), which sits far from the last collapse's in memory: asking
  // for it now overlaps the misses with the rest of the collapse. A hint
  // only: no effect on any result.
  void prefetch_quadric(std::uint32_t w) const {
    const auto* bytes = reinterpret_cast<const char*>(&q_[w]);
    __builtin_prefetch(bytes);
    __builtin_prefetch(bytes + sizeof(Quadric) - 1);
  }

  // What re-queueing the stale vertices around v will read: their triangle
  // lists, those triangles, and their corners' positions (the moves'
  // costs). The queue's order jumps across the mesh, so these are mostly
  // cache misses; asked for in tight loops, one stage a pass, they
  // overlap instead of coming one after another inside cheapest(). A hint
  // only: no effect on any result.
  void prefetch_stale_around(std::uint32_t v) const {
    const auto for_stale = [&](auto&& visit) {
      for (const std::uint32_t f : faces_[v])
        for (const std::uint32_t w : tris_[f])
          if (mine(w) && !fresh_[w]) visit(w);  // (another block's lists may be changing)
    };
    for_stale([&](std::uint32_t w) { __builtin_prefetch(faces_[w].data()); });
    for_stale([&](std::uint32_t w) {
      for (const std::uint32_t g : faces_[w]) __builtin_prefetch(&tris_[g]);
    });
    for_stale([&](std::uint32_t w) {
      for (const std::uint32_t g : faces_[w])
        for (const std::uint32_t x : tris_[g]) __builtin_prefetch(&p_[x]);
    });
  }

  // within_bound just found each handed vertex's nearest keeper.
  void hand_over(std::uint32_t u) {  // before u's triangles change
    for (const std::uint32_t f : faces_[u]) kept_[f].clear();
    for (std::size_t i = 0; i < handed_.size(); ++i) {
      kept_[nearest_[i].first].push_back(handed_[i]);
      vertex_error_ = std::max(vertex_error_, nearest_[i].second);
    }
  }

  void remove_triangle(std::uint32_t f, std::uint32_t u) {
    alive_tri_[f] = 0;
    ++removed_;
    for (const std::uint32_t w : tris_[f]) {
      if (w == u) continue;
      auto& list = faces_[w];
      list.erase(std::find(list.begin(), list.end(), f));
    }
  }

 public:
  // The lane's tally.
  OperationCounts counts_;
  std::size_t collapses_ = 0, refused_ = 0;
  std::size_t removed_ = 0;  // triangles
  double vertex_error_ = 0.0;

 private:
  // Whether this lane queues v: every vertex, or its block's inner ones.
  [[nodiscard]] bool mine(std::uint32_t v) const {
    return block_ == none || (s_.block_of[v] == block_ && s_.inner[v]);
  }
  // v's name in the lane's queue, and back.
  [[nodiscard]] std::uint32_t id(std::uint32_t v) const { return block_ == none ? v : s_.local[v]; }
  [[nodiscard]] std::uint32_t vertex_at(std::uint32_t id) const { return block_ == none ? id : members_[id]; }

  const std::vector<Vec3>& p_;
  const SimplifyOptions& options_;
  MeshState& s_;
  Queue queue_;  // holds id(v)
  double cos_turn_;
  std::span<const std::uint32_t> members_;
  std::uint32_t block_ = none;
  // The shared state under the names the steps use.
  std::vector<std::array<std::uint32_t, 3>>& tris_ = s_.tris;
  std::vector<std::uint8_t>& alive_tri_ = s_.alive_tri;
  std::vector<std::vector<std::uint32_t>>& faces_ = s_.faces;
  std::vector<Quadric>& q_ = s_.q;
  std::vector<std::uint8_t>& kind_ = s_.kind;
  std::vector<std::uint8_t>& kind0_ = s_.kind0;
  std::vector<std::uint8_t>& plane_shape_ = s_.plane_shape;
  std::vector<Vec3>& crease_direction_ = s_.crease_direction;
  std::vector<std::array<std::uint32_t, 2>>& boundary_edges_ = s_.boundary_edges;
  std::vector<std::uint32_t>& best_ = s_.best;
  std::vector<double>& key_ = s_.key;
  std::vector<std::pair<std::uint32_t, double>>& cheap_ = s_.cheap;
  std::vector<std::uint8_t>& fresh_ = s_.fresh;
  std::vector<RingMemo>& rings_ = s_.rings;  // written through const members: a cache
  bool& on_all_threads_ = s_.on_all_threads;
  std::vector<std::vector<std::uint32_t>>& kept_ = s_.kept;
  // scratch
  std::vector<std::uint32_t> ring_, ring2_, moves_, around_, handed_, keepers_, ball_, counted_;
  std::vector<std::uint8_t> seen_, counted_face_;
  std::vector<std::pair<std::uint32_t, double>> nearest_;
  std::vector<std::pair<double, std::uint32_t>> ranked_;
};

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
constexpr double finish_share = 0.02;  // of the collapses asked for: the last queue's
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
    if (half == 0) std::sort(keyed.begin(), middle, before);
    else std::sort(middle, keyed.end(), before);
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
    case SimplifyQueue::pairing_heap: out = simplify_on<PairingQueue>(canonical, options, target); break;
    case SimplifyQueue::lazy: out = simplify_on<LazyQueue>(canonical, options, target); break;
    case SimplifyQueue::binary_heap: out = simplify_on<HeapQueue>(canonical, options, target); break;
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
