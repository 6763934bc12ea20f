#pragma once
// Spatial sorting for the benchmarks: the order of points along a Morton
// (Z-order) curve, so that points close in the array are close in space.
//
// The samples of recon::Shape come in random order, the worst case for any
// loop that reads or writes per-point data by index; scanners usually
// deliver something closer to a spatial order. Benchmarking both shows how
// much of a phase's time is memory order rather than arithmetic.

#include "recon/point_cloud.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

namespace recon::bench {

/// Interleaves the bits of three 21-bit lattice coordinates into one 63-bit
/// Morton code: bit b of axis a goes to bit 3 b + a.
inline std::uint64_t morton_code(std::uint32_t x, std::uint32_t y, std::uint32_t z) {
  std::uint64_t code = 0;
  for (int b = 0; b < 21; ++b) {
    code |= static_cast<std::uint64_t>((x >> b) & 1u) << (3 * b);
    code |= static_cast<std::uint64_t>((y >> b) & 1u) << (3 * b + 1);
    code |= static_cast<std::uint64_t>((z >> b) & 1u) << (3 * b + 2);
  }
  return code;
}

/// order[j] = index of the point that goes j-th along the Z-order curve of
/// the points' bounding box, quantized to 2^21 cells per axis (ties keep
/// their input order).
inline std::vector<std::uint32_t> morton_order(std::span<const Vec3> points) {
  const Box<3> box = bounding_box<3>(points);
  const Vec3 extent = box.extent().cwiseMax(1e-300);
  constexpr double cells = 2097151.0;  // 2^21 - 1
  auto cell = [&](const Vec3& p, int axis) {
    return static_cast<std::uint32_t>(std::lround((p[axis] - box.min[axis]) / extent[axis] * cells));
  };
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec3& p = points[i];
    keyed[i] = {morton_code(cell(p, 0), cell(p, 1), cell(p, 2)), static_cast<std::uint32_t>(i)};
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<std::uint32_t> order(keyed.size());
  for (std::size_t j = 0; j < keyed.size(); ++j) order[j] = keyed[j].second;
  return order;
}

/// values[order[0]], values[order[1]], ...
template <class T>
std::vector<T> permuted(const std::vector<T>& values, std::span<const std::uint32_t> order) {
  std::vector<T> out;
  out.reserve(order.size());
  for (const std::uint32_t i : order) out.push_back(values[i]);
  return out;
}

}  // namespace recon::bench
