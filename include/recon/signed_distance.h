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
// also defined when a sample lies within rho_i + delta + |f(p)| of p itself
// (a ball around p reaching as far as the foot point's ball would). Near a
// sharp corner, the projection onto one face's plane can overshoot the data
// while p is plainly next to it. Over a hole or beyond a boundary, points
// near the surface (|f| small, where a zero crossing could be drawn) are as
// far from the data as their foot points, so holes stay open.
//
// delta, when not given, is estimated from the PCA residuals: twice phase
// I's noise (the median RMS distance of a neighbourhood to its plane).

#include "recon/kdtree.h"
#include "recon/tangent_planes.h"

#include <cstdint>
#include <optional>
#include <span>

namespace recon {

struct SignedDistanceOptions {
  std::optional<double> delta;  ///< noise level; estimated when absent
};

template <int D>
class SignedDistance {
 public:
  /// The value at p, or std::nullopt where f is undefined.
  [[nodiscard]] std::optional<double> operator()(const Vec<D>& p) const { return evaluate(p).value; }

  /// The same, with the plane it came from (the origin nearest p).
  struct Evaluation {
    std::uint32_t plane = 0;
    std::optional<double> value;
  };
  static constexpr std::uint32_t no_hint = UINT32_MAX;
  /// `hint`: any plane, typically the previous point's when points come in
  /// spatial order; its origin's distance bounds the nearest-origin search
  /// from the start. The answer does not depend on it.
  [[nodiscard]] Evaluation evaluate(const Vec<D>& p, std::uint32_t hint = no_hint) const;

  [[nodiscard]] double delta() const { return delta_; }
  [[nodiscard]] bool delta_given() const { return delta_given_; }

 private:
  template <int E>
  friend SignedDistance<E> make_signed_distance(const TangentPlanes<E>&, std::span<const Vec<E>>, const KdTree<E>&,
                                                const SignedDistanceOptions&);
  const TangentPlanes<D>* planes_ = nullptr;
  std::span<const Vec<D>> normals_;
  const KdTree<D>* origin_tree_ = nullptr;
  double delta_ = 0.0;
  bool delta_given_ = false;
};

/// Builds f over the planes (origins, local rho, the tree of the samples),
/// their oriented unit normals (one per origin), and a kd-tree over the
/// origins (phase II builds one). All are referenced, not copied: they must
/// outlive the returned function. Throws InvalidInputError for a negative or
/// non-finite delta, or normals of the wrong count.
template <int D>
[[nodiscard]] SignedDistance<D> make_signed_distance(const TangentPlanes<D>& planes, std::span<const Vec<D>> normals,
                                                     const KdTree<D>& origin_tree,
                                                     const SignedDistanceOptions& options = {});

}  // namespace recon
