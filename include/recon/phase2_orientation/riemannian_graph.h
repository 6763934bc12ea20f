#pragma once
// The Riemannian graph of phase II: which tangent planes are neighbours,
// and how costly it is to carry an orientation from one to the other.
//
// Vertices are the tangent planes. Edges are the union of
//   - the Euclidean minimum spanning tree (it connects every piece of
//     surface, however sparse), and
//   - the symmetric k-NN graph (it gives the orientation a choice of paths,
//     so it can go around sharp creases rather than across them): i and j
//     are joined when x_j is in the k-neighbourhood N(x_i) that plane i was
//     fitted to, or x_i in N(x_j).
// Hoppe's paper builds both over the origins o_i. Here both are built over
// the samples x_i, whose neighbourhoods phase I has already found: an origin
// is the centroid of its sample's neighbourhood, a fraction of a spacing
// away, so the two graphs differ only in near-ties, and reusing phase I's
// lists saves a second k-NN search over all the points (docs/benchmarks.md).
// CGAL's Hoppe orientation makes the same choice. The gap test below
// measures edges between origins.
//
// The textbook construction lists the edges and sorts them into a graph:
// every EMST edge and every pair (i, j) with x_j in N(x_i), as one edge
// list, then make_graph (graph.h), which drops the repeats. The version here
// lays the rows out directly from phase I's lists, in parallel, in this
// order per row: i's own kept neighbours (nearest first), the points that
// list i without i listing them (by index), and the EMST edges that neither
// lists; the same edges, in a fixed order that does not depend on the
// thread count. It also finds the pieces of the data from the EMST and the
// few k-NN edges between its pieces, without walking the graph.
// An edge costs 1 - |n_i . n_j| (orientation_cost): near 0 between nearly
// parallel planes, where propagating the orientation is safe; near 1
// between perpendicular ones, where it is a guess. Costs are computed from
// the normals when needed, not stored (8 bytes an edge saved).
//
// Separate objects. Orientation must not be carried across the gap between
// two objects: where two surfaces face each other, their normals are nearly
// parallel, the edge looks cheap, and the second object would come out
// inside-out. An edge is a gap when it is
//   - longer than the sampling allows: length > gap_factor * max(gap_i, gap_j)
//     (gap from phase I, the widest local spacing between samples), and
//   - leaves the surface: it makes more than about 15 degrees with one of its
//     two tangent planes (|unit(o_j - o_i) . n| > 0.25 at i or at j).
// The second test matters for random (Poisson) samples, whose holes between
// samples reach twice the typical gap but lie along the surface; between
// two objects, the gap is crossed along the normals. Pieces smaller than
// min_component_points that such cuts would isolate (a few samples near a
// crease, an outlier) are joined back through their shortest EMST edge; the
// connected components of what remains are the separate objects, and each is
// oriented alone.
//
// Cost: the EMST's (emst.h), then O(n k) for the rows, in parallel; the textbook edge list through
// make_graph takes O(n k log k) for them.

#include "recon/phase1_planes/tangent_planes.h"
#include "recon/structures/graph.h"
#include "recon/structures/kdtree.h"

#include <cmath>
#include <span>
#include <vector>

namespace recon {

/// The cost of carrying an orientation across an edge: 1 - |n_i . n_j|, in [0, 1] up to rounding.
/// Cost: O(D).
/// Throws: nothing.
/// Pre: unit normals.
template <int D>
[[nodiscard]] inline double orientation_cost(const Vec<D>& n_i, const Vec<D>& n_j) {
  return 1.0 - std::abs(n_i.dot(n_j));
}

/// `graph` with the cost of each edge stored in its weights, computed from
/// `normals` (one per vertex) and clamped at 0 (rounding can take
/// 1 - |n_i . n_j| a hair below it), for the algorithms that read stored
/// weights: Kruskal, Borůvka, the lab's queues, the benchmarks. Phase II
/// computes the costs as it goes instead.
/// Cost: O(V + E).
/// Throws: nothing.
/// Pre: one unit normal per vertex.
template <int D>
[[nodiscard]] Graph with_orientation_costs(Graph graph, std::span<const Vec<D>> normals);

struct RiemannianGraphOptions {
  int k = 0;                     ///< k-NN edges from the first k of each neighbourhood (itself included); 0: all
  double gap_factor = 1.5;       ///< a gap is longer than this many local gaps (and leaves the surface)
  int min_component_points = 0;  ///< smaller pieces are joined back; 0 = 2 k (phase I's k)
};

template <int D>
struct RiemannianGraph {
  Graph graph;                     ///< kept edges (no stored weights: see orientation_cost)
  std::vector<Edge> emst;          ///< every EMST edge of the samples, weight = length
  Components components;           ///< pieces of the data (over the kept edges)
  std::size_t gap_emst_edges = 0;  ///< EMST edges found to be gaps (before small pieces rejoin)
  std::size_t rejoined = 0;        ///< small pieces joined back
  std::size_t edge_count = 0;      ///< graph.edge_count(), kept when the graph itself is released
  double seconds_emst = 0.0, seconds_graph = 0.0;
};

/// The Riemannian graph over phase I's n planes: the kept EMST and k-NN edges, the EMST itself, and the
/// separate pieces of the data (see the header).
/// Cost: see the header.
/// Throws: InvalidInputError when options.k is negative or exceeds phase I's k, or the planes' neighbour
/// lists were released; what an interruption check throws.
/// Pre: planes comes from estimate_tangent_planes (normals unit).
template <int D>
[[nodiscard]] RiemannianGraph<D> build_riemannian_graph(const TangentPlanes<D>& planes,
                                                        const RiemannianGraphOptions& options = {});

}  // namespace recon
