#pragma once
// Prim's minimum spanning tree of the complete Euclidean graph of a point
// set, in its O(n^2) textbook form: no heap, no neighbour search.
//
// Every pair of points is an edge, so each point's neighbours are all the
// others and a heap would be no help. An array holds instead, for each
// point outside the tree, its cheapest edge into the tree so far:
//   1. the tree starts as point 0;
//   2. every point outside the tree lowers its entry to its edge to the
//      point that joined last, when that edge is cheaper;
//   3. the outside point with the cheapest entry joins, with that edge (both
//      steps are one pass over the array);
//   4. repeat from 2 until every point is in.
// n - 1 passes of O(n) each, O(n) memory. The textbook alternative to the EMST of emst.h (Borůvka with
// kd-tree queries, about O(n log n) a round): the same tree, edge for edge,
// as both compare edges by lighter() on (squared length, smaller endpoint,
// larger endpoint), a strict total order under which the tree is unique;
// exact duplicates of a point are joined by edges of length 0, ordered by
// their endpoints like any others.
//
// Result: n - 1 edges (none for n <= 1) in the order their points joined,
// each with u < v and weight = Euclidean length; counts.distance_evaluations
// = n(n-1)/2 (squared distances computed), other counters 0.

#include "recon/core/point_cloud.h"
#include "recon/phase2_orientation/minimum_spanning_tree.h"

#include <span>

namespace recon {

/// The Euclidean minimum spanning tree of `points` (n by D; D = 2 and 3 are compiled).
/// Cost: O(n^2): exactly n(n-1)/2 distances.
/// Throws: InvalidInputError for a coordinate that is not finite or beyond +-max_coordinate
/// (check_coordinates, kdtree.h), or for 2^32 - 1 points or more.
/// Pre: none.
template <int D>
[[nodiscard]] MinimumSpanningEdges complete_graph_minimum_spanning_tree(std::span<const Vec<D>> points);

}  // namespace recon
