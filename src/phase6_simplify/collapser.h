#pragma once
// Phase VI's edge collapses (simplification.h), on any of the queues
// (queues.h): the quadrics, the features each vertex keeps (steps 0 to 4)
// and the loop of collapses (step 5), in class Collapser. Its long member
// functions are defined in three parts, included at the end:
// collapser_features.h (steps 0 to 4: triangles, quadrics, plane shapes,
// creases and corners, boundary planes), collapser_moves.h (the rings, the
// moves and their costs, the queue) and collapser_collapse.h (the
// validity of a move, the collapse, the loops). Private to phase6_simplify/.

#include "recon/core/detail/parallel_for.h"
#include "recon/core/parallel.h"
#include "recon/phase6_simplify/simplification.h"
#include "recon/structures/union_find.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <numbers>
#include <span>
#include <vector>

namespace recon::simplification_steps {

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
    const double quadratic =
        xx * px * px + yy * py * py + zz * pz * pz + 2.0 * (xy * px * py + xz * px * pz + yz * py * pz);
    return std::max(0.0, quadratic + 2.0 * (x * px + y * py + z * pz) + c);
  }
};

// Ties of flat ground (a quadric error of 0) go to the shortest edge.
constexpr double tie_break = 1e-4;

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
  std::vector<std::uint8_t> inner;      // per vertex: a round's lane may queue it (mark_inner)
  std::vector<std::uint32_t> block_of;  // per vertex: its block in this round
  std::vector<std::uint32_t> local;     // per vertex: its place in its block's list
  std::vector<std::uint32_t> living;    // the vertices with triangles, in increasing order (the rounds')
  std::vector<double> cost;             // per vertex: its cheapest move's cost at the round's start
  std::vector<double> living_costs;     // scratch of round_limit: the living's costs (kept: no new pages a round)
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
  void run(std::size_t may_remove);

  // A block's loop in a round: queue the lane's vertices whose move costs
  // at most `limit` now (`cost`, from costs_now), then collapse the
  // cheapest allowed move while it costs at most `limit`, at most `most`
  // times. (A vertex over the limit may come under it when its ring
  // changes: it is queued then.)
  void run_below(double limit, std::size_t most, const std::vector<double>& cost);

  // Every living vertex's cheapest cost now (s_.living's), into `out`
  // (infinity for the others and the unmovable), on all threads, each
  // vertex alone; the fast loop keeps the moves it recomputes.
  void costs_now(std::vector<double>& out);

  // body(v, scratch) for v = at(0), ..., at(count - 1), each vertex alone,
  // on all threads (blocks of 4096, a scratch each). Meanwhile neighbours()
  // keeps no ring, whatever vertex a rule asks about; keep_ring keeps the
  // ring of the vertex in hand (its thread is the only one to write it).
  template <class At, class Body>
  void each_on_all_threads(std::size_t count, At at, Body body);

  void collapse_cheapest(std::size_t may_remove, std::size_t most, double limit);

  [[nodiscard]] Mesh result(const Mesh& mesh, Simplification& out) const;

 private:
  // Step 0: triangles and, per vertex, the triangles around it. A triangle
  // with a repeated vertex has no area and no plane: it is left out.
  // (Each thread fills the lists of its own run of vertices, every list in
  // the triangles' order, allocated once: the same lists on any threads.)
  void load_triangles(const Mesh& mesh);

  // Step 1: the area-weighted planes of the triangles around each vertex.
  // Each vertex sums its triangles' planes in the order of its triangle
  // list (the triangles' order), so the sums are the same on any threads.
  void build_quadrics();

  // Step 2: what each vertex's planes say of it, by the eigenvalues of
  // their normals' second moment (area-weighted, so that the slivers phase V
  // leaves along a crease hardly count): one direction, flat ground; two, a
  // crease, along the third eigenvector; three, a corner. The fan only
  // nominates: the planes of a wider ball decide, one vertex per corner
  // (confirm_corners), and a crease vertex must lie on its crease line
  // (drop_off_line_creases).
  void shape_of_planes();

  // A crease vertex lies between two neighbours on its crease (by
  // crease_edge), within line_tolerance of the segment joining them, as
  // the vertices phase V puts on a crease line do. One that does not is a
  // face vertex near a crease whose fan phase V tilted with a triangle
  // across the crease, or a fold: it is flat ground, and so moves out of
  // the crease line's way. One pass, judged on the classification before
  // it: passes until nothing changes would wear a crease away from any gap
  // in it, one end vertex at a time.
  void drop_off_line_creases();

  // Whether v lies between two of its crease neighbours, on the segment
  // joining them (within line_tolerance of its length).
  [[nodiscard]] bool on_line(std::uint32_t v);

  // The planes' normals' second moment per unit weight (A / weight).
  [[nodiscard]] static Eigen::Matrix3d moment_of(const Quadric& q);

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
  void confirm_corners();

  // A candidate whose wider planes are not a corner: a crease or flat
  // ground, as those planes say.
  void demote_by_wide_planes(std::uint32_t v, const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>& wide);

  // Per cluster, the candidate nearest where its planes meet stays a
  // corner; the others become creases pointing at it.
  void keep_one_per_cluster(const std::vector<std::uint32_t>& candidates, const std::vector<std::uint8_t>& confirmed,
                            UnionFind& clusters, const std::vector<Quadric>& wide, const std::vector<double>& strength);

  // The mean length of the edges around v.
  [[nodiscard]] double mean_edge(std::uint32_t v);

  // The point nearest all of q's planes (q spans three directions).
  [[nodiscard]] static Vec3 meeting_point(const Quadric& q);

  // The planes of the triangles around the vertices within corner_reach
  // times v's mean edge of it (reached through the mesh); `inside` gets
  // those vertices.
  Quadric planes_in_ball(std::uint32_t v, std::vector<std::uint32_t>& inside);

  // All the triangles around v face within 10 degrees of the first: flat
  // ground, no eigenvalues needed (most vertices).
  [[nodiscard]] bool planar_fan(std::uint32_t v) const;

  // Step 3: each vertex's kind. A crease vertex (by its planes) moves
  // along the crease: onto a neighbour also on a crease or a corner, the
  // edge between them along the crease at both ends (crease_edge). A vertex
  // on an open boundary (two boundary edges, flat planes) moves along the
  // boundary. Fixed: corners, boundary vertices on a crease, vertices on
  // more than two boundary edges or on a non-manifold edge.
  void find_features();

  // Vertex a's kind by its plane shape and the edges around it; `open`
  // set when a lies on a boundary edge.
  [[nodiscard]] std::uint8_t kind_of(std::uint32_t a, std::vector<std::uint32_t>& ring, std::uint8_t& open) const;

  // Whether u -> v runs along a crease: v on a crease or a corner, the edge
  // within 35 degrees of the crease direction at each crease end.
  [[nodiscard]] bool crease_edge(std::uint32_t u, std::uint32_t v) const {
    return plane_shape_[v] != flat && along_crease(u, v) && along_crease(v, u);
  }

  // Whether edge ab, seen from a, runs along a crease a lies on.
  [[nodiscard]] bool along_crease(std::uint32_t a, std::uint32_t b) const;

  // Step 4: a plane through each boundary edge perpendicular to its
  // triangle, so that moving along a curved boundary costs its deviation.
  void add_boundary_planes();

  // ---- small queries ----
  [[nodiscard]] bool has(std::uint32_t f, std::uint32_t v) const {
    return tris_[f][0] == v || tris_[f][1] == v || tris_[f][2] == v;
  }
  [[nodiscard]] bool traverses(std::uint32_t f, std::uint32_t a, std::uint32_t b) const {
    const auto& t = tris_[f];
    return (t[0] == a && t[1] == b) || (t[1] == a && t[2] == b) || (t[2] == a && t[0] == b);
  }
  [[nodiscard]] Vec3 normal(std::uint32_t f) const {
    return cross_of(p_[tris_[f][0]], p_[tris_[f][1]], p_[tris_[f][2]]);
  }
  [[nodiscard]] std::uint32_t third(std::uint32_t f, std::uint32_t a, std::uint32_t b) const;
  // The first triangle on edge ab and how many there are.
  [[nodiscard]] std::pair<std::uint32_t, std::size_t> faces_on(std::uint32_t a, std::uint32_t b) const;
  // The vertices sharing a triangle with v, sorted, once each.
  // The fast loop keeps each ring it gathers (up to RingMemo's capacity)
  // until a collapse changes v's triangles (collapse() marks it stale).
  // On all threads (each_on_all_threads) it only reads what is kept:
  // whatever vertices a rule asks about, no two threads write.
  void neighbours(std::uint32_t v, std::vector<std::uint32_t>& out) const;

  // Gathers and keeps v's ring when it is stale (fast loop), on any
  // thread: the thread that handles v is the only one to write v's memo.
  void keep_ring(std::uint32_t v, std::vector<std::uint32_t>& scratch) const;

  // (An insertion into a short sorted list: a ring has about six.)
  void gather_ring(std::uint32_t v, std::vector<std::uint32_t>& out) const;

  [[nodiscard]] double cost(std::uint32_t u, std::uint32_t v) const {
    return q_[u].at(p_[v]) + tie_break * q_[u].weight * (p_[v] - p_[u]).squaredNorm();
  }

  // The moves u may make by the feature rules: anywhere for a free vertex,
  // along its crease or boundary for a line vertex, none for a fixed one.
  void moves(std::uint32_t u, std::vector<std::uint32_t>& out) const;

  // ---- the queue ----
  // u's cheapest move by cost alone (validity is checked when it surfaces):
  // the neighbour and the cost, none and infinity when u may not move.
  [[nodiscard]] std::pair<std::uint32_t, double> cheapest(std::uint32_t u, std::vector<std::uint32_t>& scratch) const;

  // Every vertex's first cheapest move, on all threads (each vertex alone).
  void first_costs();

  // Queues u by its cheapest move, from the cache while u's triangles and
  // quadric are unchanged.
  void requeue(std::uint32_t u);

  // u's cheapest move that is allowed now: after the cheapest was refused.
  void retry(std::uint32_t u);

  // (A key the queue already holds is left alone: the queues order by
  // (cost, vertex), so the order is the same, and the heap is spared.)
  void place(std::uint32_t u, std::uint32_t to, double c);

  // ---- validity ----
  [[nodiscard]] bool allowed(std::uint32_t u, std::uint32_t v) {
    return link_holds(u, v) && lines_stay(u, v) && no_fold(u, v) && within_bound(u, v);
  }

  // The vertices u and v share must be exactly the far corners of the
  // triangles on uv: else the collapse glues two sheets along an edge.
  bool link_holds(std::uint32_t u, std::uint32_t v);

  // A boundary loop of three (a triangular hole) would become an edge.
  bool lines_stay(std::uint32_t u, std::uint32_t v);

  // No triangle turns by more than the limit or loses its area, and no two
  // triangles end on the same three vertices.
  bool no_fold(std::uint32_t u, std::uint32_t v) const;

  // Whether triangle f, with u moved onto v, has the vertices of a triangle of v.
  [[nodiscard]] bool duplicates(std::uint32_t f, std::uint32_t u, std::uint32_t v) const;

  // With a bound: the input vertices kept by u's triangles, and u itself,
  // each within max_error of one of the triangles around v after the move.
  bool within_bound(std::uint32_t u, std::uint32_t v);

  // ---- the collapse ----
  // Only u's ring (v included) changes triangles or quadric: their cached
  // moves are stale; the rest of v's ring is re-queued from the cache.
  void collapse(std::uint32_t u, std::uint32_t v);

  // v and its ring, each once or more (requeue is idempotent, and the
  // queues' order does not depend on the order of the updates).
  void requeue_around(std::uint32_t v);

  // Each vertex of u's triangles is about to be re-queued from its quadric
  // (cheapest()), which sits far from the last collapse's in memory: asking
  // for it now overlaps the misses with the rest of the collapse. A hint
  // only: no effect on any result.
  void prefetch_quadric(std::uint32_t w) const;

  // What re-queueing the stale vertices around v will read: their triangle
  // lists, those triangles, and their corners' positions (the moves'
  // costs). The queue's order jumps across the mesh, so these are mostly
  // cache misses; asked for in tight loops, one stage a pass, they
  // overlap instead of coming one after another inside cheapest(). A hint
  // only: no effect on any result.
  void prefetch_stale_around(std::uint32_t v) const;

  // within_bound just found each handed vertex's nearest keeper.
  void hand_over(std::uint32_t u);

  void remove_triangle(std::uint32_t f, std::uint32_t u);

 public:
  // The lane's tally.
  OperationCounts counts_;
  std::size_t collapses_ = 0, refused_ = 0;
  std::size_t removed_ = 0;  // triangles
  double vertex_error_ = 0.0;

 private:
  // Whether this lane queues v: every vertex, or its block's inner ones.
  [[nodiscard]] bool mine(std::uint32_t v) const { return block_ == none || (s_.block_of[v] == block_ && s_.inner[v]); }
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

}  // namespace recon::simplification_steps

#include "phase6_simplify/collapser_collapse.h"
#include "phase6_simplify/collapser_features.h"
#include "phase6_simplify/collapser_moves.h"
