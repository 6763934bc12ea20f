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
// The refined method also decides each component's side more robustly than
// by its highest point (sign_by_extremes). The highest point of a tall cone
// is its apex, whose plane stands nearly upright, and "make it point up"
// then picks a side at random; rims and creases on top do the same. So the
// samples within two neighbourhood radii of the top are searched for the
// normal nearest to vertical: where it is within 25 degrees of vertical,
// it points up, as in Hoppe's rule. Where no normal up there is (a tip, a
// crease), the same is asked of the other five axis directions (the
// extremes of a closed surface have outward normals along them), and the
// best-aligned direction decides. Which way the component's normals point
// there is a vote of the samples in that band, each weighted by its
// component along the direction and by exp(-depth / r) for its depth below
// the extreme (r its neighbourhood radius), not the word of the
// best-aligned sample alone: that one may be among the few the walk got
// wrong on noisy data, and in a plate thinner than two radii the band also
// holds the bottom sheet, rightly pointing the other way; the outermost
// layer and the majority decide. The whole component is turned round when
// the vote says inwards; the tree walk still decides every sign relative
// to the others. (Open surfaces, a terrain, a facade, have no inside: there the
// side facing up is kept, as before, wherever the top is well defined.)
//
// Nested pieces (the refined method). Each component's side is decided
// alone, at its extremes, as if it bounded a solid of its own. That is
// right for pieces side by side, but a piece inside another (the inner
// wall of a hollow ball) bounds a cavity, and its outward normals point
// into the cavity: away from the material, towards its own inside. Going
// inwards the sides alternate, material, cavity, material, so a piece
// enclosed by an odd number of others is turned round, one enclosed by an
// even number kept. The textbook test for "p is inside closed surface Q"
// is the winding number of Q around p (1 inside, 0 outside); for a cloud
// of oriented samples the generalized winding number (Barill et al. 2018)
// sums each sample's dipole, a_i (x_i - p) . n_i / (4 pi |x_i - p|^3)
// (2 pi |x_i - p|^2 in 2D), with a_i the area it stands for (here the
// k-NN estimate, pi r_i^2 / (k - 1) for neighbourhood radius r_i), and p
// is inside where |w| > 1/2 (|w|: Q's own sign may still be turned). An
// open piece bounds no cavity, but its winding number exceeds 1/2 inside a
// deep bowl: Q counts only when its samples close a surface
// (closes_a_surface: their area-weighted normals add up to nearly 0). Here
// after the extremes have decided: each piece's probe is its highest
// origin; Q is tested only when its bounding box holds P's (pieces side by
// side, the conics, are never tested); each sum runs serially in a fixed
// order, the pairs in parallel, so the outcome is the same for any thread
// count. Cost: O(sum over tested pairs of |Q|), nothing for a single piece
// or boxes that nest in no other, plus O(c^2) for c components' boxes.
//
// Facing sheets (the refined method). Where two sheets of surface lie
// closer than a neighbourhood (the two sides of a thin plate, two objects
// nearly touching), graph edges join them: their planes are parallel, the
// edge costs nothing, and Hoppe's walk makes the two normals agree, turning
// one sheet inside out. But facing sheets' outward normals point opposite
// ways, whether the gap between them is solid (a plate) or empty (two
// objects). With `sheet_misfit`, an edge between nearly parallel planes
// (within 25 degrees) that leaves both of them steeply (more than 30
// degrees from each plane, measured between the origins, which lie on the
// fitted surfaces) and whose planes lie apart by more than three times
// their fits' misfit (noise on one sheet tilts short edges, by less) joins
// two facing sheets, and the walk and the vote carry the orientation
// across it reversed. (With plane origins at the centroids of
// neighbourhoods spanning both sheets, such edges cannot be told: this
// needs local_quadrics.h's origins.)
//
// Sharp creases (the refined method). Across a crease sharper than a
// right angle (a cone's rim, a wedge) outward normals point more than 90
// degrees apart, and "agrees with its parent" is wrong for every tree edge
// that crosses it: one face comes out inside out. Geometry tells: across a
// crease the surface lies beyond both planes (convex) or beyond neither
// (concave), so outward normals satisfy (d . n_i)(d . n_j) < 0 for
// d = o_j - o_i. One edge can be fooled (a wavy surface sampled coarsely),
// so after the walk the faces are found as patches (pieces joined by
// nearly parallel, well-fitted planes) and every graph edge across a
// crease between two patches votes; a patch that at least 8 votes, four
// in five of them, say is inside out relative to its neighbours is turned
// round (orientation.cpp, turn_crease_patches).
//
// An addition to Hoppe's method: a few rounds of a local vote afterwards. A
// normal that points against the sum of its graph neighbours' normals is
// turned round. On clean data nothing changes; with noise about half the
// sample spacing, it corrects the few hundred in a hundred thousand that a
// single tree edge got wrong, which would otherwise become bubbles.
//
// Cost: O(n k log n) for n planes at k: the Riemannian graph, then Prim's O(E log V) on its E ~ n k
// edges; then O(n k) a vote round.

#include "recon/phase1_planes/tangent_planes.h"
#include "recon/phase2_orientation/minimum_spanning_tree.h"
#include "recon/phase2_orientation/riemannian_graph.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <span>
#include <vector>

namespace recon {

struct OrientationOptions {
  RiemannianGraphOptions graph{};  ///< k, gap factor
  int vote_rounds = 3;             ///< rounds of the neighbour vote after the tree walk (0: pure Hoppe)
  bool sign_by_extremes = false;   ///< decide each component's side at its best extreme (see above; refined)
  /// With sign_by_extremes: then turn the pieces nested in an odd number of
  /// others (see above). A tile (tiles.h) sees parts of pieces only, and
  /// leaves this to the reconciliation over all tiles.
  bool turn_nested = true;
  /// Per plane, the RMS misfit of its fit (LocalQuadrics::residual): when
  /// given, the orientation is carried reversed between facing sheets (see
  /// above; refined). Empty: never. Referenced, not copied.
  std::span<const float> sheet_misfit;
  /// Normals to carry the orientation with, on the same side as
  /// planes.normals (empty: planes.normals). The refined method walks with
  /// phase I's PCA normals: across a sharp edge the fitted planes of the two
  /// faces meet at right angles, where "agrees with its parent" is a coin
  /// toss, but the PCA planes of the neighbourhoods astride the edge turn
  /// from one face to the other in steps. The signs found are then given to
  /// planes.normals. Single precision: a direction is all it is asked for,
  /// and it is held beside everything else during phase II. Referenced, not
  /// copied. (3D only.)
  std::span<const Eigen::Vector3f> guide;
};

template <int D>
struct OrientedNormals {
  std::vector<Vec<D>> normals;  ///< unit, consistently oriented
  RiemannianGraph<D> graph;
  SpanningForest tree;                    ///< tree.roots[c] is the root of component c
  std::vector<std::uint8_t> flipped;      ///< 1 where the normal was reversed from the PCA one
  std::size_t flip_count = 0;             ///< normals reversed in the end
  std::size_t vote_flips = 0;             ///< of which changed by the vote
  std::size_t components_turned = 0;      ///< components turned round by sign_by_extremes
  std::size_t pieces_nested = 0;          ///< components inside another (sign_by_extremes; see above)
  std::size_t nested_turned = 0;          ///< of which turned round: inside an odd number of others
  std::size_t sheet_edges = 0;            ///< tree edges between facing sheets (walked reversed)
  std::size_t crease_patches_turned = 0;  ///< faces turned round across a sharp crease (see above)
  double seconds_mst = 0.0;

  [[nodiscard]] std::size_t component_count() const { return graph.components.sizes.size(); }
};

/// The area a sample stands for in a winding number (nested pieces, see above): its neighbourhood's radius r
/// spans k samples, itself included, so the k - 1 others cover pi r^2 (in 2D a segment, 2 r): the k-NN
/// estimate of the sampling density, exact on a sphere for any r (a cap's area is pi times its chord squared).
/// Cost: O(1).
/// Throws: nothing.
/// Pre: radius >= 0 (k below 2 is taken as 2).
template <int D>
[[nodiscard]] inline double sample_area(float radius, int k) {
  const double r = static_cast<double>(radius);
  return (D == 3 ? std::numbers::pi * r * r : 2.0 * r) / static_cast<double>(std::max(1, k - 1));
}

/// One sample's term of the generalized winding number at p (see above): a (x - p) . n over the full solid
/// angle times |x - p|^D (4 pi |x - p|^3; in 2D 2 pi |x - p|^2), given `area_normal` = a n; 0 where x = p.
/// Cost: O(D).
/// Throws: nothing.
/// Pre: finite arguments.
template <int D>
[[nodiscard]] inline double winding_term(const Vec<D>& x, const Vec<D>& area_normal, const Vec<D>& p) {
  const Vec<D> d = x - p;
  const double r2 = d.squaredNorm();
  if (r2 <= 0.0) return 0.0;
  const double full_angle = D == 3 ? 4.0 * std::numbers::pi * r2 * std::sqrt(r2) : 2.0 * std::numbers::pi * r2;
  return d.dot(area_normal) / full_angle;
}

/// Whether a winding number says inside: |w| > 1/2 (either side: the enclosing piece's own sign may still be
/// turned).
/// Cost: O(1).
/// Throws: nothing.
/// Pre: none.
[[nodiscard]] inline bool winding_inside(double w) { return std::abs(w) > 0.5; }

/// Whether a piece's samples close a surface, from the sum of their area-weighted normals (signs as
/// decided) and of their areas: over a closed surface the outward normals times area add up to zero (the
/// divergence theorem), over an open one to its opening (a hemisphere's, to half its area; a terrain's, to
/// about all of it). Only a closed piece bounds a cavity (see above): a ball in a bowl stays as it is.
/// Closed: |sum a n| at most a tenth of sum a.
/// Cost: O(D).
/// Throws: nothing.
/// Pre: none.
template <int D>
[[nodiscard]] inline bool closes_a_surface(const Vec<D>& area_normal_sum, double area_sum) {
  return area_normal_sum.norm() <= 0.1 * area_sum;
}

/// Phase II: the planes' normals, consistently oriented (one per plane, unit), with the Riemannian
/// graph and the spanning forest that carried the orientation.
/// Cost: O(n k log n) (see the header).
/// Throws: InvalidInputError when options.graph.k is negative or exceeds phase I's k, the planes'
/// neighbour lists were released, or options.guide is given but not one per plane; what an
/// interruption check throws.
/// Pre: planes comes from estimate_tangent_planes (normals unit); options.sheet_misfit empty or one per plane.
template <int D>
[[nodiscard]] OrientedNormals<D> orient_normals(const TangentPlanes<D>& planes, const OrientationOptions& options = {});

/// The same over a Riemannian graph already built from `planes` (with
/// options.graph ignored): lets the caller release planes.neighbors, the
/// graph's source, before the walk.
/// Cost: O(n k log n), less the graph's construction.
/// Throws: InvalidInputError when options.guide is given but not one per plane; what an interruption
/// check throws.
/// Pre: as above, and `graph` was built from these planes.
template <int D>
[[nodiscard]] OrientedNormals<D> orient_normals(const TangentPlanes<D>& planes, RiemannianGraph<D> graph,
                                                const OrientationOptions& options = {});

}  // namespace recon
