#pragma once
// Phase II: consistent orientation of the tangent planes.
//
// PCA gives each plane a normal line but no direction. Neighbouring planes
// on a smooth surface should point the same way, so the orientation is
// propagated along the Riemannian graph, preferring edges between nearly
// parallel planes: the propagation follows the graph's minimum spanning tree
// (Prim's algorithm on our indexed binary heap), starting in each component
// from the origin of largest z (last coordinate), whose normal is made to
// point to +z: on a closed surface that point's outward normal does. Walking
// the tree parents-first (Prim's own visiting order, no recursion), a child
// whose normal points against its parent's (n_child . n_parent < 0) is
// flipped.
//
// An addition to Hoppe's method: a few rounds of a local vote afterwards. A
// normal that points against the sum of its graph neighbours' normals is
// turned round. On clean data nothing changes; with noise about half the
// sample spacing, it corrects the few hundred in a hundred thousand that a
// single tree edge got wrong, which would otherwise become bubbles.

#include "recon/minimum_spanning_tree.h"
#include "recon/riemannian_graph.h"
#include "recon/tangent_planes.h"

#include <cstdint>
#include <vector>

namespace recon {

struct OrientationOptions {
  RiemannianGraphOptions graph{};  ///< k, gap factor
  int vote_rounds = 3;             ///< rounds of the neighbour vote after the tree walk (0: pure Hoppe)
};

template <int D>
struct OrientedNormals {
  std::vector<Vec<D>> normals;        ///< unit, consistently oriented
  RiemannianGraph<D> graph;
  SpanningForest tree;                ///< tree.roots[c] is the root of component c
  std::vector<std::uint8_t> flipped;  ///< 1 where the normal was reversed from the PCA one
  std::size_t flip_count = 0;         ///< normals reversed in the end
  std::size_t vote_flips = 0;         ///< of which changed by the vote
  double seconds_mst = 0.0;

  [[nodiscard]] std::size_t component_count() const { return graph.components.sizes.size(); }
};

template <int D>
[[nodiscard]] OrientedNormals<D> orient_normals(const TangentPlanes<D>& planes, const OrientationOptions& options = {});

/// The same over a Riemannian graph already built from `planes` (with
/// options.graph ignored): lets the caller release planes.neighbors, the
/// graph's source, before the walk.
template <int D>
[[nodiscard]] OrientedNormals<D> orient_normals(const TangentPlanes<D>& planes, RiemannianGraph<D> graph,
                                                const OrientationOptions& options = {});

}  // namespace recon
