#pragma once
// The exact Euclidean minimum spanning tree (EMST) of a point set, by
// Borůvka's algorithm with kd-tree queries.
//
// Borůvka works in rounds: every current component (a fragment of the final
// tree) finds its shortest edge to a point outside it, and all those edges
// join the tree at once; the number of components at least halves per round,
// so there are at most log2(n) rounds. The shortest outside edge of a
// component is the best, over its points, of each point's nearest point with
// another component label:
//   - when the point's k-nearest-neighbour list (if given) holds a point of
//     another component, the first such entry IS that nearest outside point;
//   - otherwise every outside point is farther than the list's last entry, so
//     the point is skipped when that already exceeds the component's best;
//   - only the rest query the kd-tree, skipping subtrees whose points all
//     belong to the querying component.
// Edges are compared by (length, smaller endpoint, larger endpoint), a strict
// total order, so the tree is unique and equals what Prim or Kruskal on the
// complete graph give under the same order. Cost about O(n log n) per round.

#include "recon/graph.h"
#include "recon/kdtree.h"

#include <span>
#include <vector>

namespace recon {

/// Returns the n - 1 edges (n - 1 for n >= 1 points; none for n <= 1), with
/// weight = Euclidean length. `tree` must have been built over `points`;
/// `knn`, when given, must be tree.all_knn(k) for some k.
template <int D>
[[nodiscard]] std::vector<Edge> euclidean_minimum_spanning_tree(const KdTree<D>& tree,
                                                                std::span<const Vec<D>> points,
                                                                const KnnTable* knn = nullptr);

}  // namespace recon
