#include "recon/signed_distance.h"

#include "recon/errors.h"

#include <cmath>
#include <limits>
#include <string>

namespace recon {

template <int D>
typename SignedDistance<D>::Evaluation SignedDistance<D>::evaluate(const Vec<D>& p, std::uint32_t hint) const {
  // The hint's own distance, a hair larger (any rounding apart from the
  // tree's), is at least the nearest one: the search may start bounded.
  const double bound2 = hint < planes_->origins.size() ? (planes_->origins[hint] - p).squaredNorm() * (1.0 + 1e-9)
                                                       : std::numeric_limits<double>::infinity();
  Neighbor plane;
  if (origin_tree_->knn(p, std::span<Neighbor>(&plane, 1), bound2) == 0)  // not expected; never a wrong plane
    origin_tree_->knn(p, std::span<Neighbor>(&plane, 1));
  const std::uint32_t i = plane.index;
  const Vec<D>& n = normals_[i];
  const double f = (p - planes_->origins[i]).dot(n);
  const Vec<D> foot = p - f * n;
  const auto rho = static_cast<double>(planes_->local_rho[i]);
  const double reach = rho + delta_;
  // "Is there a sample within r?" is a search bounded by r from the start,
  // which stops at the first sample found: far cheaper than finding the
  // nearest sample and comparing.
  // The plane's own sample, x_i, is the likeliest to be within reach: tried
  // first (the same test the search makes), it spares most searches.
  const Vec<D>* own = planes_->point_tree.numbered_by_leaf_order() ? &planes_->point_tree.points()[i] : nullptr;
  auto sample_within = [&](const Vec<D>& q, double r) {
    if (own != nullptr && (*own - q).squaredNorm() <= r * r) return true;
    return planes_->point_tree.any_within(q, r * r);
  };
  if (sample_within(foot, reach)) return {i, f};
  // Near a sharp corner the projection onto one face's plane can overshoot
  // the data while p is plainly close to it (see the header).
  if (sample_within(p, 0.5 * rho + reach + std::abs(f))) return {i, f};
  return {i, std::nullopt};
}

template <int D>
SignedDistance<D> make_signed_distance(const TangentPlanes<D>& planes, std::span<const Vec<D>> normals,
                                       const KdTree<D>& origin_tree, const SignedDistanceOptions& options) {
  if (normals.size() != planes.origins.size() || origin_tree.size() != planes.origins.size())
    throw InvalidInputError("signed distance: " + std::to_string(normals.size()) + " normals and a tree of " +
                            std::to_string(origin_tree.size()) + " origins for " +
                            std::to_string(planes.origins.size()) + " planes");
  SignedDistance<D> f;
  f.planes_ = &planes;
  f.normals_ = normals;
  f.origin_tree_ = &origin_tree;
  if (options.delta) {
    if (!(*options.delta >= 0.0 && std::isfinite(*options.delta)))
      throw InvalidInputError("delta must be a length of 0 or more");
    f.delta_ = *options.delta;
    f.delta_given_ = true;
  } else {
    f.delta_ = 2.0 * planes.noise;
  }
  return f;
}

template class SignedDistance<2>;
template class SignedDistance<3>;
template SignedDistance<2> make_signed_distance<2>(const TangentPlanes<2>&, std::span<const Vec<2>>,
                                                   const KdTree<2>&, const SignedDistanceOptions&);
template SignedDistance<3> make_signed_distance<3>(const TangentPlanes<3>&, std::span<const Vec<3>>,
                                                   const KdTree<3>&, const SignedDistanceOptions&);

}  // namespace recon
