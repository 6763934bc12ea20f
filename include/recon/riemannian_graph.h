#pragma once
// The Riemannian graph of phase II: which tangent planes are neighbours,
// and how costly it is to carry an orientation from one to the other.
//
// Vertices are the tangent-plane origins o_i. Edges are the union of
//   - the Euclidean minimum spanning tree of the o_i (it connects every
//     piece of surface, however sparse), and
//   - the symmetric k-NN graph of the o_i (it gives the orientation a choice
//     of paths, so it can go around sharp creases rather than across them).
// An edge costs 1 - |n_i . n_j|: near 0 between nearly parallel planes,
// where propagating the orientation is safe; near 1 between perpendicular
// ones, where it is a guess.
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

#include "recon/graph.h"
#include "recon/kdtree.h"
#include "recon/tangent_planes.h"

#include <vector>

namespace recon {

struct RiemannianGraphOptions {
  int k = 20;                ///< neighbours per origin (itself included) for the k-NN edges
  double gap_factor = 1.5;   ///< a gap is longer than this many local gaps (and leaves the surface)
  int min_component_points = 0;  ///< smaller pieces are joined back; 0 = 2 k
  KdTreeOptions tree{};      ///< kd-tree over the origins
};

template <int D>
struct RiemannianGraph {
  Graph graph;                    ///< kept edges, weight 1 - |n_i . n_j|
  std::vector<Edge> emst;         ///< every EMST edge of the origins, weight = length
  Components components;          ///< pieces of the data (over the kept edges)
  std::size_t gap_emst_edges = 0; ///< EMST edges found to be gaps (before small pieces rejoin)
  std::size_t rejoined = 0;       ///< small pieces joined back
  KdTree<D> origin_tree;          ///< over the origins; phase III queries it
  double seconds_knn = 0.0, seconds_emst = 0.0, seconds_graph = 0.0;
};

/// Precondition: planes comes from estimate_tangent_planes (normals unit).
/// Throws InvalidInputError when k exceeds the number of points.
template <int D>
[[nodiscard]] RiemannianGraph<D> build_riemannian_graph(const TangentPlanes<D>& planes,
                                                        const RiemannianGraphOptions& options = {});

}  // namespace recon
