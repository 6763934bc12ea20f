#pragma once
// Phase III: the signed distance function f built from the oriented
// tangent planes.
//
//   f(p) = (p - o_i) . n_i,  o_i the tangent-plane origin nearest to p,
//
// positive outside the surface (the side the normals point to), negative
// inside. f is only trusted near the data: the foot point
// z = p - f(p) n_i (p projected onto plane i) must lie within rho_i + delta of
// some sample, where rho_i is the local sampling density of plane i (phase
// I) and delta the noise level. Elsewhere f is UNDEFINED, and the surface is
// left open there: this is what keeps holes and open boundaries open rather
// than inventing surface across them. One addition to Hoppe's rule: p is
// also defined when a sample lies within rho_i / 2 + rho_i + delta + |f(p)|
// of p itself (a ball around p reaching a little further than the foot
// point's ball would). Near a sharp corner, the projection onto one face's
// plane can overshoot the data while p is plainly next to it. Over a hole or
// beyond a boundary, points near the surface (|f| small, where a zero
// crossing could be drawn) are as far from the data as their foot points, so
// holes wider than about 1.5 rho_i + delta stay open. The ball around p
// contains the foot point's ball, so in effect f(p) is undefined exactly
// where no sample lies within 1.5 rho_i + delta + |f(p)| of p; the foot
// point's test comes first only because it is cheaper and usually settles it.
//
// delta, when not given, is estimated from the PCA residuals: twice phase
// I's noise (the median RMS distance of a neighbourhood to its plane).
//
// Which plane (the refined method). The nearest origin is Hoppe's rule. Near
// a sharp edge it can pick the wrong face: just outside face A, next to the
// edge, a sample of face B can be as near as any of A's, and p lies inside
// B's plane, so f comes out negative outside the solid and the surface grows
// a fin along B's plane past the edge. (Planes through centroids hide this:
// they tilt across the edge and round it off.) With `candidates` > 1 the
// plane is chosen among that many nearest origins as the one p projects
// onto nearest to its own origin: the smallest d_i^2 + f_i^2 / 4, where d_i
// is the distance from p's foot on plane i to o_i and f_i the distance to
// the plane. On a smooth surface that is the plane whose origin lies right
// under p. Then, where a candidate across a crease (normals more than
// crease_angle_degrees apart) disagrees in sign, the edge decides: at a
// convex edge (each origin behind the other's plane) the solid is the
// intersection of the two half-spaces and f the larger value, at a concave
// edge their union and f the smaller.
//
// Cost: O(log n) expected per evaluation of f (a nearest-origin query and a bounded query for a sample;
// O(log n + c) with c candidates); the phase is as many evaluations as phase IV's walk asks for.

#include "recon/phase1_planes/tangent_planes.h"
#include "recon/structures/kdtree.h"

#include <cstdint>
#include <optional>
#include <span>

namespace recon {

struct SignedDistanceOptions {
  std::optional<double> delta;  ///< noise level; estimated when absent
  /// Planes considered (see above), 1 to 32; 1 is the nearest origin
  /// (Hoppe's). Absent: 1, and 8 in reconstruct()'s refined method.
  std::optional<int> candidates;
  /// Per plane, 1 where planes meeting it at a crease lie near
  /// (LocalQuadrics::near_crease): several candidates are weighed only where
  /// the nearest origin is such a plane, elsewhere the nearest decides.
  /// Empty: everywhere. Referenced, not copied.
  std::span<const std::uint8_t> near_crease;
};

template <int D>
class SignedDistance {
 public:
  /// The value at p, or std::nullopt where f is undefined.
  /// Cost: O(log n) expected (see the header).
  /// Throws: nothing.
  /// Pre: p finite; what make_signed_distance was given still lives.
  [[nodiscard]] std::optional<double> operator()(const Vec<D>& p) const { return evaluate(p).value; }

  /// The same, with the plane it came from (the origin nearest p).
  struct Evaluation {
    std::uint32_t plane = 0;
    std::optional<double> value;
    /// The plane was chosen across a crease (candidates > 1), by the
    /// normals' orientation: f with other signs of the normals is not just
    /// this value negated (reconstruct() evaluates such points again once
    /// the normals are oriented).
    bool by_orientation = false;
  };
  static constexpr std::uint32_t no_hint = UINT32_MAX;
  /// `hint`: any plane, typically the previous point's when points come in
  /// spatial order; its origin's distance bounds the nearest-origin search
  /// from the start (with one candidate). The answer does not depend on it.
  /// Cost: O(log n) expected, O(log n + c) with c candidates; a near hint saves most of the search.
  /// Throws: nothing.
  /// Pre: p finite; what make_signed_distance was given still lives.
  [[nodiscard]] Evaluation evaluate(const Vec<D>& p, std::uint32_t hint = no_hint) const;

  /// The plane f uses at p (see "Which plane" above).
  /// Cost: O(log n) expected, O(log n + c) with c candidates.
  /// Throws: nothing.
  /// Pre: as evaluate.
  [[nodiscard]] std::uint32_t plane_for(const Vec<D>& p, std::uint32_t hint = no_hint) const;

  [[nodiscard]] double delta() const { return delta_; }
  [[nodiscard]] bool delta_given() const { return delta_given_; }

 private:
  template <int E>
  friend SignedDistance<E> make_signed_distance(const TangentPlanes<E>&, std::span<const Vec<E>>, const KdTree<E>&,
                                                const SignedDistanceOptions&);
  const TangentPlanes<D>* planes_ = nullptr;
  std::span<const Vec<D>> normals_;
  struct Choice {
    std::uint32_t plane;
    bool by_orientation;
  };
  [[nodiscard]] Choice choose(const Vec<D>& p, std::uint32_t hint) const;
  static constexpr double crease_cosine = 0.90630778703664994;  // cos(crease_angle_degrees)
  const KdTree<D>* origin_tree_ = nullptr;
  int candidates_ = 1;
  std::span<const std::uint8_t> near_crease_;
  double delta_ = 0.0;
  bool delta_given_ = false;
};

/// Builds f over the planes (origins, local rho, the tree of the samples),
/// their oriented unit normals (one per origin), and a kd-tree over the
/// origins (phase II builds one). All are referenced, not copied. Without a
/// given delta, delta = 2 * planes.noise.
/// Cost: O(1).
/// Throws: InvalidInputError for a negative or non-finite delta, normals or a tree of origins of the
/// wrong count, candidates outside 1..32, or near_crease neither empty nor one per plane.
/// Pre: the planes, normals, origin tree and near_crease outlive the function; the tree's point i is
/// planes.origins[i]; unit normals.
template <int D>
[[nodiscard]] SignedDistance<D> make_signed_distance(const TangentPlanes<D>& planes, std::span<const Vec<D>> normals,
                                                     const KdTree<D>& origin_tree,
                                                     const SignedDistanceOptions& options = {});

}  // namespace recon
