// The Morton (Z-order) permutation of spatial_order.h.

#include "recon/structures/spatial_order.h"

#include "recon/core/parallel.h"
#include "recon/core/shapes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <vector>

namespace recon {
namespace {

std::vector<Vec3> uniform_points(std::size_t n, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Vec3> points(n);
  for (Vec3& p : points) p = Vec3(unit(rng), unit(rng), unit(rng));
  return points;
}

bool is_permutation_of_indices(const std::vector<std::uint32_t>& order, std::size_t n) {
  std::vector<std::uint32_t> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  std::vector<std::uint32_t> identity(n);
  std::iota(identity.begin(), identity.end(), 0u);
  return sorted == identity;
}

// The mean distance between points that follow each other in `order`.
double mean_step(std::span<const Vec3> points, const std::vector<std::uint32_t>& order) {
  double sum = 0.0;
  for (std::size_t j = 1; j < order.size(); ++j) sum += (points[order[j]] - points[order[j - 1]]).norm();
  return sum / static_cast<double>(order.size() - 1);
}

TEST(SpatialOrder, IsAPermutation) {
  for (const std::size_t n : {0u, 1u, 2u, 1000u}) {
    const std::vector<Vec3> points = uniform_points(n, static_cast<std::uint32_t>(n + 1));
    EXPECT_TRUE(is_permutation_of_indices(spatial_order(points), n)) << n << " points";
  }
  // A flat cloud (no extent along z) and a cloud of copies of one point.
  std::vector<Vec3> flat = uniform_points(500, 3);
  for (Vec3& p : flat) p.z() = 2.0;
  EXPECT_TRUE(is_permutation_of_indices(spatial_order(flat), flat.size()));
  const std::vector<Vec3> copies(40, Vec3(1.0, -2.0, 3.0));
  const std::vector<std::uint32_t> order = spatial_order(copies);
  std::vector<std::uint32_t> identity(copies.size());
  std::iota(identity.begin(), identity.end(), 0u);
  EXPECT_EQ(order, identity);  // one cell: input order
}

// Along the curve, each step is short: on a torus sample, the steps are a
// small fraction of those of a random order of the same points.
TEST(SpatialOrder, NeighboursInTheOrderAreNeighboursInSpace) {
  const std::vector<Vec3> points = make_torus()->sample(20000, 7).positions;
  const std::vector<std::uint32_t> order = spatial_order(points);
  std::vector<std::uint32_t> shuffled(points.size());
  std::iota(shuffled.begin(), shuffled.end(), 0u);
  std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937(8));
  EXPECT_LT(mean_step(points, order), 0.05 * mean_step(points, shuffled));
}

// The curve visits the eight octants of the bounding box one after the
// other, z slowest and x fastest, and within each octant its eight
// sub-octants likewise: points are ordered by their cell at every level.
TEST(SpatialOrder, VisitsTheOctantsInZOrder) {
  std::vector<Vec3> points = uniform_points(4000, 11);
  // Away from the planes that cut the cube in quarters (no quantisation
  // question), with two corners fixing the bounding box to the unit cube.
  std::erase_if(points, [](const Vec3& p) {
    for (int a = 0; a < 3; ++a)
      if (std::abs(4.0 * p[a] - std::round(4.0 * p[a])) < 1e-3) return true;
    return false;
  });
  points.emplace_back(0.0, 0.0, 0.0);
  points.emplace_back(1.0, 1.0, 1.0);
  auto morton_cell = [](const Vec3& p, int levels) {  // interleaved bits of the cell at that depth
    std::uint32_t code = 0;
    for (int level = 0; level < levels; ++level)
      for (int a = 2; a >= 0; --a) {
        const auto cell = static_cast<std::uint32_t>(std::min(p[a], 0.9999999) * (1 << levels));
        code = code << 1 | ((cell >> (levels - 1 - level)) & 1u);
      }
    return code;
  };
  const std::vector<std::uint32_t> order = spatial_order(points);
  for (const int levels : {1, 2})
    for (std::size_t j = 1; j < order.size(); ++j)
      ASSERT_LE(morton_cell(points[order[j - 1]], levels), morton_cell(points[order[j]], levels))
          << "level " << levels << ", position " << j;
  // The eight corners of a cube, given in reverse: x varies fastest.
  std::vector<Vec3> corners;
  for (int c = 7; c >= 0; --c) corners.emplace_back(c & 1, (c >> 1) & 1, (c >> 2) & 1);
  EXPECT_EQ(spatial_order(corners), (std::vector<std::uint32_t>{7, 6, 5, 4, 3, 2, 1, 0}));
}

// The keys are the order's: non-decreasing along it, and for the cube's
// corners the bits x, y, z of the corner (x the lowest).
TEST(SpatialOrder, KeysAreWhatTheOrderSorts) {
  const std::vector<Vec3> points = uniform_points(2000, 23);
  const std::vector<std::uint64_t> keys = spatial_keys(points);
  const std::vector<std::uint32_t> order = spatial_order(points);
  ASSERT_EQ(keys.size(), points.size());
  for (std::size_t j = 1; j < order.size(); ++j) ASSERT_LE(keys[order[j - 1]], keys[order[j]]) << "position " << j;
  std::vector<Vec3> corners;
  for (int c = 0; c < 8; ++c) corners.emplace_back(c & 1, (c >> 1) & 1, (c >> 2) & 1);
  const std::vector<std::uint64_t> corner_keys = spatial_keys(corners);
  for (std::size_t c = 1; c < 8; ++c) EXPECT_EQ(corner_keys[c] >> 60, c) << "corner " << c;
}

// Points in one cell (here exact copies) keep their input order.
TEST(SpatialOrder, CopiesKeepTheirInputOrder) {
  std::vector<Vec3> points = uniform_points(300, 13);
  for (std::size_t i = 0; i < points.size(); i += 4) points[i] = points[(i * 7) % 40];
  const std::vector<std::uint32_t> order = spatial_order(points);
  for (std::size_t j = 1; j < order.size(); ++j)
    if (points[order[j]] == points[order[j - 1]]) {
      EXPECT_LT(order[j - 1], order[j]) << "position " << j;
    }
}

TEST(SpatialOrder, SameOrderForAnyThreadCount) {
  const std::vector<Vec3> points = uniform_points(20000, 17);
  const int threads = thread_count();
  set_thread_count(1);
  const std::vector<std::uint32_t> alone = spatial_order(points);
  set_thread_count(2);
  const std::vector<std::uint32_t> shared = spatial_order(points);
  set_thread_count(threads);
  EXPECT_EQ(alone, shared);
}

TEST(SpatialOrder, PermutedReadsValuesInTheOrder) {
  const std::vector<int> values = {10, 11, 12, 13};
  const std::vector<std::uint32_t> order = {2, 0, 3, 1};
  EXPECT_EQ(permuted<int>(values, order), (std::vector<int>{12, 10, 13, 11}));
}

}  // namespace
}  // namespace recon
