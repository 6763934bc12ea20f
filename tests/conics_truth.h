#pragma once
// The course's conics (make_conics, shapes.h) as a test of orientation:
// the share of each of its five pieces whose normals agree with the true
// outward ones.

#include "recon/core/shapes.h"

#include <span>
#include <vector>

namespace recon::testing {

/// Per piece of make_conics_pieces(), the share of its samples whose
/// normal in `normals` points to the same side as the true one in `truth`
/// (its sample, positions and normals); a sample belongs to the piece
/// nearest it. Pre: one normal per sample, in the sample's order.
inline std::vector<double> right_per_conic(const PointCloud& truth, std::span<const Vec3> normals) {
  const auto pieces = make_conics_pieces();
  std::vector<double> right(pieces.size()), total(pieces.size());
  for (std::size_t i = 0; i < truth.size(); ++i) {
    std::size_t nearest = 0;
    for (std::size_t p = 1; p < pieces.size(); ++p)
      if (pieces[p]->distance(truth.positions[i]) < pieces[nearest]->distance(truth.positions[i])) nearest = p;
    total[nearest] += 1.0;
    if (normals[i].dot(truth.normals[i]) > 0.0) right[nearest] += 1.0;
  }
  for (std::size_t p = 0; p < right.size(); ++p) right[p] /= total[p];
  return right;
}

}  // namespace recon::testing
