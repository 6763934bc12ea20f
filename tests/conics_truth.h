#pragma once
// The course's conics (make_conics, shapes.h), and the nested balls, as
// tests of orientation: the share of each piece whose normals agree with
// the true outward ones; and a ball in a bowl, which is nested in nothing.

#include "recon/core/shapes.h"

#include <cmath>
#include <memory>
#include <numbers>
#include <random>
#include <span>
#include <vector>

namespace recon::testing {

/// Per piece of `pieces`, the share of its samples whose normal in
/// `normals` points to the same side as the true one in `truth` (its
/// sample, positions and normals); a sample belongs to the piece nearest
/// it. Pre: one normal per sample, in the sample's order.
inline std::vector<double> right_per_piece(const PointCloud& truth, std::span<const Vec3> normals,
                                           const std::vector<std::unique_ptr<Shape>>& pieces) {
  std::vector<double> right(pieces.size()), total(pieces.size());
  for (std::size_t i = 0; i < truth.size(); ++i) {
    std::size_t nearest = 0;
    for (std::size_t p = 1; p < pieces.size(); ++p)
      if (pieces[p]->distance(truth.positions[i]) < pieces[nearest]->distance(truth.positions[i])) nearest = p;
    total[nearest] += 1.0;
    if (normals[i].dot(truth.normals[i]) > 0.0) right[nearest] += 1.0;
  }
  for (std::size_t p = 0; p < right.size(); ++p) right[p] = total[p] > 0.0 ? right[p] / total[p] : 0.0;
  return right;
}

/// The same per piece of make_conics_pieces().
inline std::vector<double> right_per_conic(const PointCloud& truth, std::span<const Vec3> normals) {
  return right_per_piece(truth, normals, make_conics_pieces());
}

/// The same per wall of make_nested_balls() (outer, cavity, inner ball;
/// walls = 3), or of make_hollow_ball() (the first two).
inline std::vector<double> right_per_ball(const PointCloud& truth, std::span<const Vec3> normals, std::size_t walls) {
  std::vector<std::unique_ptr<Shape>> spheres;
  for (const double r : {1.0, 0.7, 0.3}) spheres.push_back(make_sphere(r));
  spheres.resize(walls);
  return right_per_piece(truth, normals, spheres);
}

/// A bowl (the lower half of the unit sphere, open at the top: `bowl`
/// samples) with a ball of radius 0.2 near its bottom, at (0, 0, -0.7)
/// (`ball` samples after them); uniform by area (z uniform: Archimedes),
/// with normals away from each sphere's centre.
inline PointCloud ball_in_bowl(std::size_t bowl, std::size_t ball, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  PointCloud cloud;
  const auto add = [&](const Vec3& centre, double radius, double z_lo, double z_hi, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) {
      const double z = z_lo + (z_hi - z_lo) * u(rng), t = 2.0 * std::numbers::pi * u(rng);
      const Vec3 d(std::sqrt(1.0 - z * z) * std::cos(t), std::sqrt(1.0 - z * z) * std::sin(t), z);
      cloud.positions.push_back(centre + radius * d);
      cloud.normals.push_back(d);
    }
  };
  add(Vec3::Zero(), 1.0, -1.0, 0.0, bowl);
  add(Vec3(0.0, 0.0, -0.7), 0.2, -1.0, 1.0, ball);
  return cloud;
}

}  // namespace recon::testing
