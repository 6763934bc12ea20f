#pragma once
// The graphs phase II could walk, side by side: the alternatives the
// course weighed against the Riemannian graph (riemannian_graph.h).
//
// Phase II carries an orientation from plane to plane along a minimum
// spanning tree of some graph over the samples, with edge costs
// 1 - |n_i . n_j|. Which graph decides which planes may hand their
// orientation to which:
//   - complete:   every pair of samples. Its Euclidean minimum spanning tree
//                 (Prim's O(n^2) array version, complete_graph_mst.h) is
//                 what the course first walked; it is a tree, so it leaves
//                 no choice of path, and it always joins separate objects.
//   - emst:       the Euclidean minimum spanning tree, cut at the gaps the
//                 Riemannian graph cuts (riemannian_graph.h: long edges that
//                 leave the surface): separate objects stay apart, but there
//                 is still one path between any two planes.
//   - knn:        the symmetric k-NN graph: i and j are joined when either is
//                 among the other's k nearest. Paths to choose from, but a
//                 sparse or uneven sample can fall apart into pieces.
//   - mutual_knn: an edge only where each is among the other's k nearest:
//                 fewer edges across thin gaps, and more pieces where the
//                 sampling is uneven (a thin part breaks off).
//   - riemannian: the EMST and the symmetric k-NN graph together, the
//                 Riemannian graph of Hoppe's paper (today's default), less
//                 the gaps between separate objects (riemannian_graph.h).
//                 The two k-NN graphs above are the textbook ones: uncut.
// Each is returned as a RiemannianGraph (its `graph` the edges, its
// `components` their connected pieces) so that orient_normals walks it
// unchanged. The k-NN edges come from phase I's neighbourhoods (the first k
// of each, itself excluded), as the Riemannian graph's do.

#include "recon/core/operation_counts.h"
#include "recon/phase1_planes/tangent_planes.h"
#include "recon/phase2_orientation/riemannian_graph.h"

#include <optional>
#include <string_view>

namespace recon {

enum class OrientationGraph { complete, emst, knn, mutual_knn, riemannian };

inline constexpr OrientationGraph all_orientation_graphs[] = {OrientationGraph::complete, OrientationGraph::emst,
                                                              OrientationGraph::knn, OrientationGraph::mutual_knn,
                                                              OrientationGraph::riemannian};

/// "complete", "emst", "knn", "mutual-knn", "riemannian".
[[nodiscard]] std::string_view name_of(OrientationGraph graph);
/// The graph named so, or nothing.
/// Cost: O(1).
/// Throws: nothing.
/// Pre: none.
[[nodiscard]] std::optional<OrientationGraph> orientation_graph_named(std::string_view name);

/// The graph `kind` over planes' samples, its components computed.
/// options.k as for the Riemannian graph (0: phase I's k); `counts`, when
/// given, receives the distance evaluations of the complete graph.
/// Cost: complete O(n^2), n^2 / 2 distances (callers bound n: the lab skips it beyond a few thousand points);
/// knn O(n k log k); mutual_knn O(n k^2); emst and riemannian as build_riemannian_graph.
/// Throws: InvalidInputError when options.k is negative or exceeds phase I's k; what build_riemannian_graph
/// throws (emst, riemannian).
/// Pre: planes from estimate_tangent_planes.
template <int D>
[[nodiscard]] RiemannianGraph<D> build_orientation_graph(const TangentPlanes<D>& planes, OrientationGraph kind,
                                                         const RiemannianGraphOptions& options = {},
                                                         OperationCounts* counts = nullptr);

}  // namespace recon
