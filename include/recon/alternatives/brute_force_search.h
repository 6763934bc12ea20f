#pragma once
// Brute-force k nearest neighbours: the oracle every spatial search is
// checked against, and the baseline the alternatives lab measures them by.
//
// The textbook algorithm, for each query q:
//   1. compute the squared distance from q to every point;
//   2. keep the k smallest, ordered by (squared distance, index).
// No structure, no pruning: O(n) distances per query, O(n^2) for all points.
//
// Contract (the kd-tree's, kdtree.h, so that tables compare entry for entry)
// - Distances returned are SQUARED Euclidean distances, computed as
//   (p - q).squaredNorm(), the kd-tree's own expression: equal points give
//   bit-identical distances in both.
// - Indices are positions in the span given.
// - A query that is one of the points IS its own neighbour (distance 0).
// - Results are ordered by (squared distance, index): ties go to the smaller
//   index, so there is exactly one correct answer. Duplicates are fine.
// - Counting (counts != nullptr): adds to counts->distance_evaluations one
//   per squared distance computed: n for a query, so n * n for
//   brute_force_all_knn (each point's distance to itself included: every
//   query is a plain scan of all n points).
//
// D is not deduced from a std::vector: call brute_force_all_knn<3>(points, k).

#include "recon/core/operation_counts.h"
#include "recon/core/point_cloud.h"
#include "recon/structures/kdtree.h"

#include <span>
#include <vector>

namespace recon {

/// The k nearest of `points` to q, in (squared distance, index) order.
/// Cost: O(n log k): n distances and a partial sort.
/// Throws: InvalidInputError for k < 1, k > n, more than 2^32 - 2 points (indices are 32-bit), or coordinates
/// (of the points or of q) that are not finite or beyond +-max_coordinate.
/// Pre: none.
template <int D>
[[nodiscard]] std::vector<Neighbor> brute_force_knn(std::span<const Vec<D>> points, const Vec<D>& q, int k,
                                                    OperationCounts* counts = nullptr);

/// The k nearest neighbours of every point (itself included), as
/// KdTree::all_knn returns them: row i lists point i's k nearest. Queries
/// run in parallel; the table does not depend on the thread count.
/// Cost: O(n^2 log k): n^2 distances.
/// Throws: InvalidInputError for k < 1, k > n, more than 2^32 - 2 points, or coordinates that are not finite
/// or beyond +-max_coordinate.
/// Pre: none.
template <int D>
[[nodiscard]] KnnTable brute_force_all_knn(std::span<const Vec<D>> points, int k, OperationCounts* counts = nullptr);

}  // namespace recon
