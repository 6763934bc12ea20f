#pragma once
// Spatial order: a permutation of points along a Morton (Z-order) curve, so
// that points close in the array are close in space.
//
// Every phase reads per-point arrays by neighbour index. When neighbours are
// far apart in memory, each read is a cache miss, and the phases slow down
// several times over (docs/benchmarks.md). reconstruct() and the command line
// get the same effect from phase I's kd-tree (KdTree::renumber_by_leaf_order:
// its leaf order is a spatial order, and its copy of the points is the only
// one). This Morton order is for callers of the phases who want their own
// arrays sorted first, and for the benchmarks.

#include "recon/core/point_cloud.h"

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace recon {

/// order[j] = index of the point that comes j-th along the Z-order curve of
/// the points' bounding box, quantized to 2^21 cells per axis (points in one
/// cell keep their input order).
/// Cost: O(n log n), one sort of 64-bit keys.
/// Throws: nothing.
/// Pre: fewer than 2^32 points, finite coordinates.
[[nodiscard]] std::vector<std::uint32_t> spatial_order(std::span<const Vec3> points);

/// Each point's place on that curve: its 63-bit Z-order code (the key
/// spatial_order sorts by).
/// Cost: O(n).
/// Throws: nothing.
/// Pre: finite coordinates.
[[nodiscard]] std::vector<std::uint64_t> spatial_keys(std::span<const Vec3> points);

/// Each point's cell on that grid: its coordinates quantized to 0 ..
/// 2^21 - 1 across the bounding box, per axis (what spatial_keys
/// interleaves).
/// Cost: O(n).
/// Throws: nothing.
/// Pre: finite coordinates.
[[nodiscard]] std::vector<std::array<std::uint32_t, 3>> spatial_cells(std::span<const Vec3> points);

/// The Z-order codes of cells spatial_cells gave (spatial_keys of the
/// points they came from).
/// Cost: O(n).
/// Throws: nothing.
/// Pre: none (bits above the 21st of each coordinate are ignored).
[[nodiscard]] std::vector<std::uint64_t> spatial_keys(std::span<const std::array<std::uint32_t, 3>> cells);

/// values[order[0]], values[order[1]], ...
/// Cost: O(m) for m = order.size().
/// Throws: nothing.
/// Pre: every order[j] < values.size().
template <class T>
[[nodiscard]] std::vector<T> permuted(std::span<const T> values, std::span<const std::uint32_t> order) {
  std::vector<T> out;
  out.reserve(order.size());
  for (const std::uint32_t i : order) out.push_back(values[i]);
  return out;
}

}  // namespace recon
