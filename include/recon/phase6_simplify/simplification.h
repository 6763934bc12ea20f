#pragma once
// Phase VI, optional: simplification. Phase V leaves about one triangle per
// sample, most of them on flat or gently curved ground; this removes most
// of them while keeping what phase V drew: creases, corners, open
// boundaries, and separate objects apart.
//
// The textbook algorithm (Garland & Heckbert 1997, quadric error metrics):
//   1. Give every vertex the quadric Q_v = sum of the squared distances to
//      the planes of the triangles around it (area-weighted).
//   2. For every edge, the cost of collapsing it: the quadric error of the
//      merged vertex at its best place; queue the edges by cost.
//   3. Repeatedly collapse the cheapest edge, add the two quadrics, and
//      re-cost the edges around the merged vertex, until the target.
//
// What changes here, and why:
//   - Half-edge collapse: a vertex u moves onto a neighbour v, which keeps
//     its position. Every vertex left is a vertex of phase V's mesh, exactly
//     on its surface; a crease vertex stays exactly on its crease; colours
//     carry over unchanged. The cost of u -> v is Q_u(v), plus a small
//     multiple of |uv|^2 (times u's area) that breaks the ties of flat
//     ground (all zero) towards short edges, i.e. rounder triangles.
//   - The queue holds vertices, not edges: a vertex's key is the cost of its
//     cheapest allowed move. A collapse changes the keys of the vertices
//     around it up or down, hence the indexed heap's update_key and erase.
//   - Features, found on the input by the planes around each vertex: the
//     eigenvalues of their normals' second moment (area-weighted, so that
//     the slivers phase V leaves along a crease hardly count) say whether
//     they span one direction (flat ground), two (a crease, running along
//     the third eigenvector) or three (a corner). A fan says too much on
//     phase V's meshes: a triangle left across a crease tilts the fans next
//     to it, and several vertices near a corner span three directions. So
//     a vertex's fan only nominates it; the planes in a ball of a few edges
//     around it decide: three directions make it a corner candidate, and
//     candidates whose planes meet at one point are one corner, kept at the
//     candidate nearest that point (the others move along their line into
//     it); two directions make it a crease, along their direction, if it
//     also lies between two neighbours on its crease. A flat vertex moves
//     freely; a crease vertex only onto a neighbour on a crease or corner
//     along the crease direction; a vertex on an open boundary only along
//     it; a corner, a crease meeting a boundary, a non-manifold vertex
//     never. Phase V's own labels are not used, so that meshes from
//     elsewhere (hoppe92's) are treated alike.
//     Boundary edges add a constraint plane (through the edge,
//     perpendicular to its triangle) to their ends' quadrics, so that a
//     curved boundary costs what it deviates.
//   - Only valid meshes: a collapse is refused when it breaks the link
//     condition (the neighbours u and v share must be exactly the far
//     corners of the triangles on uv: otherwise an edge turns non-manifold,
//     or a handle or a separate part pinches), when it would make two
//     triangles on the same three vertices (a tetrahedron folding flat),
//     when a moved triangle's normal turns by more than max_normal_turn,
//     or it becomes a sliver (a sliver's normal says nothing, and one
//     standing across a face is a sharp edge in its middle).
//   - The error bound: every vertex of the input is kept by one triangle
//     (first its own vertex's, then the triangle it is handed to when its
//     triangle changes: the nearest of those around v after the move); a
//     collapse that leaves one farther than max_error from the triangle
//     keeping it is refused. Guaranteed: every input vertex lies within
//     max_error of the simplified mesh. Not guaranteed (measured in
//     docs/benchmarks.md): the distance from the simplified mesh's interior
//     points back to the input.
//
//   - Caches: each vertex's cheapest move by cost and its ring are kept
//     until a collapse changes its triangles or quadric (only the ring of
//     the vertex that moves), and a key the queue holds is not set again.
//     detail/simplify_plain.h is the loop without them; the tests hold the
//     two to the same mesh.
//   - Rounds of blocks, for speed: one queue must run on one thread (its
//     order is the output), and over a large mesh it jumps across memory
//     at every pop. So a mesh of more than block_vertices vertices is
//     first cut into blocks, the cells of a grid holding about that many
//     vertices each, with a queue each over the vertices whose whole ring
//     lies in the cell, on all threads: a collapse there touches its own
//     block only, so the blocks cannot race or see each other. In a round
//     every block makes its moves up to one cost, the round's limit (the
//     cost half the moves reach in the first two rounds, a quarter
//     after), so the collapses go where they
//     are cheapest, as with one queue; the grid shifts between rounds so
//     that the seams move. One queue over the whole mesh makes the last
//     2%, cheapest first. The textbook loop is that last queue alone
//     (block_vertices = 0, or a small mesh).
//
// Determinism: each queue runs on one thread, in its order; the blocks of
// a round in any order on any threads (they share nothing they write); the
// start (quadrics, plane shapes, first costs) on all, each vertex alone,
// its sums in its triangles' order. Ties in a queue are broken by vertex
// index, after the vertices are renumbered by their positions. So the
// output is the same for any thread count, and for any numbering of the
// same triangles (a tiled run's stitched mesh simplifies to the in-memory
// run's).
//
// Cost: textbook O(F log F) for F triangles. Here the same, times the
// vertex degree for the re-costing and checks; with max_error, also the
// input vertices handed on per collapse (a few per triangle). Memory: a
// quadric (11 doubles), a triangle list, a ring (64 bytes) and a heap slot
// per vertex; each round of blocks adds O(V) for its grid, marks and
// limit. Measured (docs/benchmarks.md, bench/simplify_speed.sh): 973,520
// triangles to a tenth in 0.85-1.01 s (median 0.94) on this machine's 2
// threads, 1.5-1.6 s on one, the numbering included; one queue over the
// whole mesh took 2.3-2.4 s beside it, mostly cache misses in its random
// order; meshoptimizer takes 0.54 s.

#include "recon/core/operation_counts.h"
#include "recon/structures/mesh.h"

#include <cstddef>

namespace recon {

/// Which priority queue orders the collapses (the lab compares them; they
/// give the same mesh).
enum class SimplifyQueue {
  binary_heap,   ///< IndexedBinaryHeap with update_key / erase (the default)
  pairing_heap,  ///< PairingHeap with update_key / erase
  lazy,          ///< std::priority_queue of (cost, vertex, version): stale entries skipped when popped
};

struct SimplifyOptions {
  std::size_t target_triangles = 0;       ///< stop at this many triangles or fewer (0: no count target)
  double ratio = 0.0;                     ///< or at this fraction of the input's (0 < ratio < 1; 0: none)
  double max_error = 0.0;                 ///< distance every input vertex stays within (input units; 0: no bound)
  double max_normal_turn_degrees = 60.0;  ///< a collapse may turn a triangle's normal by at most this
  SimplifyQueue queue = SimplifyQueue::binary_heap;
  /// The blocks' size, in vertices (see "Rounds of blocks" above; 0: none,
  /// one queue over the whole mesh). A mesh of at most this many vertices
  /// has one queue either way. The result depends on it, never on the
  /// thread count.
  std::size_t block_vertices = std::size_t{1} << 14;
};

struct Simplification {
  Mesh mesh;  ///< the simplified mesh: a subset of the input's vertices (ordered by position: x, y, z), colours and
              ///< normals carried
  std::size_t triangles_before = 0;
  std::size_t triangles_after = 0;
  std::size_t collapses = 0;
  std::size_t refused = 0;          ///< moves refused at the top of the queue (topology, flips, the bound)
  std::size_t crease_vertices = 0;  ///< input vertices that move only along a crease or boundary
  std::size_t corner_vertices = 0;  ///< input vertices that never move
  /// The largest distance from an input vertex to the triangle keeping it
  /// (an upper bound of its distance to the simplified mesh); tracked only
  /// with max_error, else 0.
  double vertex_error = 0.0;
  /// The queue's pushes, pops (the lazy queue's stale entries not included) and
  /// key updates, up or down (in decrease_keys); comparisons are not counted.
  OperationCounts counts;
  double seconds = 0.0;
};

/// Simplifies `mesh` until it has at most the target's triangles (the
/// smaller of target_triangles and ratio's, when both are given) or no move
/// is allowed (within max_error, when given).
/// Cost: O(F log F) for F triangles; here times the vertex degree, and the vertices handed on (see above).
/// Throws: InvalidInputError when no target and no bound is given, when target_triangles exceeds the
/// mesh's triangles, when ratio is not in (0, 1), when max_error is negative or not finite, or when a
/// triangle's index is out of range.
/// Pre: finite vertices; an edge-manifold, consistently oriented mesh (phase IV and V's meshes are); on
/// others, the non-manifold edges are features.
[[nodiscard]] Simplification simplify(const Mesh& mesh, const SimplifyOptions& options);

}  // namespace recon
