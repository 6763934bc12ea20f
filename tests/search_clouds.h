#pragma once
// Point sets for the neighbour-search tests (brute force, uniform grid,
// kd-tree), each reproducible from its seed, and a table comparison that
// names the first entry that differs.

#include "recon/core/shapes.h"
#include "recon/structures/kdtree.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

namespace recon::testing {

enum class Cloud {
  uniform,                // in the unit cube (square)
  surface,                // a torus sample in 3D; a wavy closed curve in 2D
  clusters_and_outliers,  // five tight clusters, and one point in 50 thousands of units away
  integer_lattice,        // integer coordinates 0..4: many copies, exact ties everywhere
};

inline std::string name_of(Cloud cloud) {
  switch (cloud) {
    case Cloud::uniform:
      return "uniform";
    case Cloud::surface:
      return "surface";
    case Cloud::clusters_and_outliers:
      return "clusters and outliers";
    case Cloud::integer_lattice:
      return "integer lattice";
  }
  return "?";
}

inline constexpr Cloud all_clouds[] = {Cloud::uniform, Cloud::surface, Cloud::clusters_and_outliers,
                                       Cloud::integer_lattice};

template <int D>
std::vector<Vec<D>> make_cloud(Cloud cloud, std::size_t n, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> gauss(0.0, 0.01);
  if constexpr (D == 3)
    if (cloud == Cloud::surface) return make_torus()->sample(n, seed).positions;
  std::vector<Vec<D>> centres(5);
  for (auto& c : centres)
    for (int a = 0; a < D; ++a) c[a] = unit(rng);
  std::vector<Vec<D>> points(n);
  for (std::size_t i = 0; i < n; ++i) {
    Vec<D>& p = points[i];
    switch (cloud) {
      case Cloud::uniform:
        for (int a = 0; a < D; ++a) p[a] = unit(rng);
        break;
      case Cloud::surface: {  // 2D: r = 1 + 0.3 sin 3t
        const double t = 2.0 * std::numbers::pi * unit(rng);
        const double r = 1.0 + 0.3 * std::sin(3.0 * t);
        p.setZero();
        p[0] = r * std::cos(t);
        p[1] = r * std::sin(t);
        break;
      }
      case Cloud::clusters_and_outliers:
        if (i % 50 == 49) {
          for (int a = 0; a < D; ++a) p[a] = (unit(rng) - 0.5) * 1e4;
        } else {
          p = centres[i % centres.size()];
          for (int a = 0; a < D; ++a) p[a] += gauss(rng);
        }
        break;
      case Cloud::integer_lattice:
        for (int a = 0; a < D; ++a) p[a] = std::floor(unit(rng) * 5.0);
        break;
    }
  }
  return points;
}

/// Two answers to one query, equal entry for entry: indices and squared
/// distances exactly.
inline ::testing::AssertionResult same_neighbors(const std::vector<Neighbor>& got, const std::vector<Neighbor>& want) {
  if (got.size() != want.size())
    return ::testing::AssertionFailure() << got.size() << " neighbours, not " << want.size();
  for (std::size_t j = 0; j < got.size(); ++j) {
    if (got[j] == want[j]) continue;
    return ::testing::AssertionFailure() << "neighbour " << j << ": index " << got[j].index << " at "
                                         << got[j].distance2 << ", expected index " << want[j].index << " at "
                                         << want[j].distance2;
  }
  return ::testing::AssertionSuccess();
}

/// Tables equal entry for entry: indices and squared distances exactly.
inline ::testing::AssertionResult same_table(const KnnTable& got, const KnnTable& want) {
  if (got.k != want.k) return ::testing::AssertionFailure() << "k " << got.k << " != " << want.k;
  if (got.entries.size() != want.entries.size())
    return ::testing::AssertionFailure() << got.entries.size() << " entries, not " << want.entries.size();
  for (std::size_t e = 0; e < got.entries.size(); ++e) {
    if (got.entries[e] == want.entries[e]) continue;
    const auto k = static_cast<std::size_t>(got.k);
    return ::testing::AssertionFailure() << "row " << e / k << ", neighbour " << e % k << ": index "
                                         << got.entries[e].index << " at " << got.entries[e].distance2
                                         << ", expected index " << want.entries[e].index << " at "
                                         << want.entries[e].distance2;
  }
  return ::testing::AssertionSuccess();
}

}  // namespace recon::testing
