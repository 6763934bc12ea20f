#pragma once
// The course's conics (make_conics, shapes.h), and the nested balls, as
// tests of orientation: the share of each piece whose normals agree with
// the true outward ones.

#include "recon/core/shapes.h"

#include <memory>
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

}  // namespace recon::testing
