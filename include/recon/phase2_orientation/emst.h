#pragma once
// The exact Euclidean minimum spanning tree (EMST) of a point set, by
// Borůvka's algorithm with kd-tree queries.
//
// The textbook EMST is Prim's algorithm on the complete graph of the points:
// grow one tree from a point, always adding the shortest edge from the tree
// to a point outside it. O(n^2) time, O(n) memory, no spatial structure
// (complete_graph_mst.h; the tests' oracle). The version below gives the
// same tree in about O(n log n) per round:
//
// Borůvka works in rounds: every current component (a fragment of the final
// tree) finds its shortest edge to a point outside it, and all those edges
// join the tree at once; the number of components at least halves per round,
// so there are at most log2(n) rounds. The shortest outside edge of a
// component is the best, over its points, of each point's nearest point with
// another component label. Hints make most of those searches unnecessary:
// given, per point, its nearest neighbours in (distance, index) order and a
// radius within which the list is complete (every point closer is listed),
//   - the first listed point of another component IS the nearest outside
//     point;
//   - a point whose radius already exceeds its component's best edge is
//     skipped: nothing outside its list can be closer than that radius;
//   - only the rest query the kd-tree, bounded by the component's best so far,
//     skipping subtrees whose points all belong to the querying component.
// A k-NN table is such a hint (its radius is the k-th distance); phase II
// passes phase I's neighbourhoods.
// Edges are compared by (length, smaller endpoint, larger endpoint), a strict
// total order, so the tree is unique and equals what Prim or Kruskal on the
// complete graph give under the same order.

#include "recon/structures/graph.h"
#include "recon/structures/kdtree.h"

#include <span>
#include <vector>

namespace recon {

/// Optional hints (see above). lists->row(i): points nearest to point i, in
/// (squared distance, index) order as the kd-tree returns them;
/// certain_radius2[i]: every point at squared distance below it from point i
/// is in lists->row(i). Hints that break these promises can make the tree
/// wrong.
struct EmstHints {
  const NeighborLists* lists = nullptr;
  std::span<const double> certain_radius2;
};

/// The EMST of n points: its n - 1 edges (none for n <= 1), with weight = Euclidean length.
/// Cost: O(n^2) textbook (Prim on the complete graph); here about O(n log n) a round, at most log2 n
/// rounds, in parallel.
/// Throws: std::logic_error only when hints that break their promises make the components' choices
/// form a cycle; nothing else.
/// Pre: `tree` was built over `points` (or numbered by leaf order over its own copy of them).
template <int D>
[[nodiscard]] std::vector<Edge> euclidean_minimum_spanning_tree(const KdTree<D>& tree, std::span<const Vec<D>> points,
                                                                const EmstHints& hints = {});

/// The same, with hints from tree.all_knn(k) for some k.
/// Cost: as above, plus O(n k) to copy the table into hints.
/// Throws: as above.
/// Pre: as above, and `knn` is tree.all_knn(k) with k >= 1 over the same points.
template <int D>
[[nodiscard]] std::vector<Edge> euclidean_minimum_spanning_tree(const KdTree<D>& tree, std::span<const Vec<D>> points,
                                                                const KnnTable& knn);

}  // namespace recon
