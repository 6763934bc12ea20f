#include "recon/phase3_distance/signed_distance.h"

#include "recon/core/errors.h"

#include <array>
#include <cmath>
#include <limits>
#include <string>

namespace recon {

namespace {
constexpr int max_candidates = 32;
}

template <int D>
typename SignedDistance<D>::Choice SignedDistance<D>::choose(const Vec<D>& p, std::uint32_t hint) const {
  // The hint's own distance, a hair larger (any rounding apart from the
  // tree's), is at least the nearest one: the search may start bounded.
  const double bound2 = hint < planes_->origins.size() ? (planes_->origins[hint] - p).squaredNorm() * (1.0 + 1e-9)
                                                       : std::numeric_limits<double>::infinity();
  Neighbor nearest;
  if (origin_tree_->knn(p, std::span<Neighbor>(&nearest, 1), bound2) == 0)  // not expected; never a wrong plane
    origin_tree_->knn(p, std::span<Neighbor>(&nearest, 1));
  if (candidates_ == 1 || (!near_crease_.empty() && !near_crease_[nearest.index])) return {nearest.index, false};
  std::array<Neighbor, max_candidates> found;
  const std::size_t count =
      origin_tree_->knn(p, std::span<Neighbor>(found.data(), static_cast<std::size_t>(candidates_)));
  auto value = [&](std::uint32_t i) { return (p - planes_->origins[i]).dot(normals_[i]); };
  // The plane p projects onto nearest its origin: the least d^2 + f^2 / 4,
  // where d^2 = |p - o|^2 - f^2.
  Choice choice{found[0].index, false};
  double best_score = std::numeric_limits<double>::infinity();
  for (std::size_t c = 0; c < count; ++c) {
    const double f = value(found[c].index);
    const double score = found[c].distance2 - 0.75 * f * f;
    if (score < best_score) {
      best_score = score;
      choice.plane = found[c].index;
    }
  }
  // A candidate across a crease that disagrees in sign: the solid is the
  // intersection of the two half-spaces at a convex edge (f = the larger
  // value), their union at a concave one (the smaller).
  double f_best = value(choice.plane);
  for (std::size_t c = 0; c < count; ++c) {
    const std::uint32_t j = found[c].index;
    const Vec<D>&n_b = normals_[choice.plane], &n_j = normals_[j];
    if (std::abs(n_b.dot(n_j)) >= crease_cosine) continue;
    choice.by_orientation = true;
    const double f_j = value(j);
    if ((f_j < 0.0) == (f_best < 0.0)) continue;
    const Vec<D> between = planes_->origins[j] - planes_->origins[choice.plane];
    const double j_side = n_b.dot(between), b_side = -n_j.dot(between);
    if ((j_side < 0.0 && b_side < 0.0 && f_j > f_best) || (j_side > 0.0 && b_side > 0.0 && f_j < f_best)) {
      choice.plane = j;
      f_best = f_j;
    }
  }
  return choice;
}

template <int D>
std::uint32_t SignedDistance<D>::plane_for(const Vec<D>& p, std::uint32_t hint) const {
  return choose(p, hint).plane;
}

template <int D>
typename SignedDistance<D>::Evaluation SignedDistance<D>::evaluate(const Vec<D>& p, std::uint32_t hint) const {
  const Choice choice = choose(p, hint);
  const std::uint32_t i = choice.plane;
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
  if (sample_within(foot, reach)) return {i, f, choice.by_orientation};
  // Near a sharp corner the projection onto one face's plane can overshoot
  // the data while p is plainly close to it (see the header).
  if (sample_within(p, 0.5 * rho + reach + std::abs(f))) return {i, f, choice.by_orientation};
  return {i, std::nullopt, choice.by_orientation};
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
  const int candidates = options.candidates.value_or(1);
  if (candidates < 1 || candidates > max_candidates)
    throw InvalidInputError("signed distance: " + std::to_string(candidates) + " candidate planes; 1 to " +
                            std::to_string(max_candidates) + " are allowed");
  f.candidates_ = candidates;
  if (!options.near_crease.empty() && options.near_crease.size() != planes.origins.size())
    throw InvalidInputError("signed distance: crease flags for " + std::to_string(options.near_crease.size()) +
                            " planes, not " + std::to_string(planes.origins.size()));
  f.near_crease_ = options.near_crease;
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
template SignedDistance<2> make_signed_distance<2>(const TangentPlanes<2>&, std::span<const Vec<2>>, const KdTree<2>&,
                                                   const SignedDistanceOptions&);
template SignedDistance<3> make_signed_distance<3>(const TangentPlanes<3>&, std::span<const Vec<3>>, const KdTree<3>&,
                                                   const SignedDistanceOptions&);

}  // namespace recon
