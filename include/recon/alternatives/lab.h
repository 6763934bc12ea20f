#pragma once
// The alternatives lab: every choice the course weighed for phases I and
// II, run on one cloud, timed, counted and checked against each other
// (`recon lab INPUT`).
//
// On the planes of phase I (PCA, the default k), it runs
//   - search: the k nearest neighbours of every point by the kd-tree
//     (kdtree.h), a uniform grid (uniform_grid.h) and brute force
//     (brute_force_search.h). They must find the same neighbour distances.
//   - queue:  Prim's algorithm over the Riemannian graph, costs
//     1 - |n_i . n_j|, on each priority queue: the indexed binary heap,
//     the Fibonacci heap, the pairing heap and the list heap. The queues
//     order ties alike, so they must grow the same tree.
//   - mst:    Prim (binary heap), Kruskal and Borůvka on that graph, and on
//     the complete Euclidean graph Prim's O(n^2) array version against the
//     Borůvka EMST with kd-tree queries (emst.h). All the trees of one
//     graph must weigh the same.
//   - graph:  phase II (the 1992 walk with its neighbour vote) along each
//     graph of orientation_graphs.h: its components, the normals it flips,
//     the share that agrees with the default run (the Riemannian graph),
//     and with the true side where the input's own normals give it. One
//     more run walks the Riemannian graph as the refined method does
//     (quadric fits, crease and facing-sheet rules, orientation.h), so that
//     what the graph decides and what the walk decides can be told apart.
//   - simplify (with LabOptions::simplify, `recon lab --simplify`): phase
//     VI's queue, "a priority queue with decrease-key again, now on a
//     mesh": the cloud is reconstructed (the default method) and its mesh
//     simplified to a tenth on the indexed binary heap (update_key, erase),
//     the pairing heap (the same), and a lazy queue (std::priority_queue,
//     a new entry per new key, stale ones skipped when they surface). Ties
//     are broken alike, so they must give the same mesh.
// A disagreement is not a row: run_lab throws LabDisagreementError.
// What would take too long is skipped, with the reason in the row
// (the complete graph, brute force and the list heap are quadratic).
// A queue's time is the wall-clock seconds of an uncounted run; its counts
// come from a second, instrumented run (counting every key comparison slows
// a queue down). The other runs count as they go (an addition per distance
// or find, next to the work it counts).

#include "recon/alternatives/orientation_graphs.h"
#include "recon/core/errors.h"
#include "recon/core/operation_counts.h"
#include "recon/phase1_planes/tangent_planes.h"
#include "recon/phase2_orientation/orientation.h"

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace recon {

/// Two alternatives that must agree did not.
class LabDisagreementError : public Error {
 public:
  using Error::Error;
};

enum class LabKind { search, queue, mst, graph, simplify };
/// "search", "queue", "mst", "graph", "simplify".
[[nodiscard]] std::string_view name_of(LabKind kind);

struct LabRun {
  std::string name;  ///< "kd-tree", "prim/fibonacci-heap", "kruskal", "mutual-knn", ... (unique)
  LabKind kind = LabKind::search;
  std::string graph;    ///< the graph it ran on (queue, mst, graph runs); empty for searches
  std::string skipped;  ///< why it did not run; empty when it ran
  double seconds = 0.0;
  OperationCounts counts;
  std::optional<double> tree_weight;  ///< the spanning forest's total weight (queue, mst, graph)
  // graph runs
  std::size_t edges = 0;
  std::size_t components = 0;
  std::size_t flips = 0;              ///< normals reversed from the PCA ones
  double agree_default = 0.0;         ///< share of normals on the default run's side
  std::optional<double> agree_truth;  ///< share on the true side, where it is known
  // simplify runs
  std::size_t triangles = 0;  ///< triangles left
};

struct LabOptions {
  TangentPlaneOptions planes{};  ///< phase I
  /// Outward normals of the input (a generated shape's), one per point, or
  /// empty: the graph runs then also report agreement with them.
  std::span<const Vec3> true_normals;
  std::size_t max_points_complete = 20'000;     ///< beyond: the complete graph is skipped (n^2 / 2 distances)
  std::size_t max_points_brute_force = 20'000;  ///< beyond: brute-force search is skipped (n^2 distances)
  std::size_t max_points_list_heap = 100'000;   ///< beyond: the list heap is skipped (a scan per pop)
  bool keep_graphs = false;                     ///< keep every graph's orientation (the report draws them)
  bool simplify = false;                        ///< also the simplify runs (a reconstruction first: off by default)
  /// Test hook: the run of this name has its result deliberately spoiled,
  /// so that the agreement checks must catch it. Empty in real use.
  std::string spoil;
};

struct LabGraph {
  OrientationGraph kind = OrientationGraph::riemannian;
  OrientedNormals<3> oriented;  ///< its graph, spanning forest and signs
};

struct LabResult {
  std::vector<LabRun> runs;
  /// Phase I, shared by every graph, queue and mst run, in the kd-tree's
  /// leaf order as reconstruct() works: plane i is that of input point
  /// order[i] (planes.point_tree.points()[i]). The per-point arrays of
  /// default_orientation and graphs are in this order too.
  TangentPlanes<3> planes;
  std::vector<std::uint32_t> order;
  OrientedNormals<3> default_orientation;  ///< the Riemannian graph's (the default run)
  std::vector<LabGraph> graphs;            ///< with keep_graphs: every graph that ran, in all_orientation_graphs order
  double seconds_planes = 0.0;
};

/// Every run of the lab (see above) on `points`, in the order listed there.
/// Cost: the sum of its runs: O(n^2) for the complete graph, brute force and the list heap up to their limits
/// (max_points_*), about O(n k log n) for the others; with simplify, a reconstruction and three simplifications.
/// Throws: InvalidInputError when true_normals are neither empty nor one per point, `spoil` names no run that ran,
/// or phase I (and with simplify, reconstruct()) finds the input unusable; ResourceLimitError from reconstruct()
/// with simplify; LabDisagreementError when two alternatives that must agree do not (the message names both and
/// their figures); what an interruption check throws.
/// Pre: none.
[[nodiscard]] LabResult run_lab(std::span<const Vec3> points, const LabOptions& options = {});

}  // namespace recon
