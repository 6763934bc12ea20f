#include "recon/structures/spatial_order.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace recon {
namespace {

// Spreads the 21 low bits of x so that bit b lands on bit 3 b.
std::uint64_t spread_bits(std::uint64_t x) {
  x &= 0x1fffff;
  x = (x | x << 32) & 0x1f00000000ffffULL;
  x = (x | x << 16) & 0x1f0000ff0000ffULL;
  x = (x | x << 8) & 0x100f00f00f00f00fULL;
  x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
  x = (x | x << 2) & 0x1249249249249249ULL;
  return x;
}

}  // namespace

std::vector<std::array<std::uint32_t, 3>> spatial_cells(std::span<const Vec3> points) {
  const Box<3> box = bounding_box<3>(points);
  constexpr double cells = 2097151.0;  // 2^21 - 1
  Vec3 scale = Vec3::Zero();
  for (int a = 0; a < 3; ++a)
    if (box.max[a] > box.min[a]) scale[a] = cells / (box.max[a] - box.min[a]);
  std::vector<std::array<std::uint32_t, 3>> out(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    for (int a = 0; a < 3; ++a)
      out[i][static_cast<std::size_t>(a)] =
          static_cast<std::uint32_t>(std::clamp((points[i][a] - box.min[a]) * scale[a], 0.0, cells));
  return out;
}

std::vector<std::uint64_t> spatial_keys(std::span<const Vec3> points) { return spatial_keys(spatial_cells(points)); }

std::vector<std::uint64_t> spatial_keys(std::span<const std::array<std::uint32_t, 3>> cells) {
  std::vector<std::uint64_t> keys(cells.size());
  for (std::size_t i = 0; i < cells.size(); ++i)
    keys[i] = spread_bits(cells[i][0]) | spread_bits(cells[i][1]) << 1 | spread_bits(cells[i][2]) << 2;
  return keys;
}

std::vector<std::uint32_t> spatial_order(std::span<const Vec3> points) {
  const std::vector<std::uint64_t> keys = spatial_keys(points);
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) keyed[i] = {keys[i], static_cast<std::uint32_t>(i)};
  std::sort(keyed.begin(), keyed.end());
  std::vector<std::uint32_t> order(keyed.size());
  for (std::size_t j = 0; j < keyed.size(); ++j) order[j] = keyed[j].second;
  return order;
}

}  // namespace recon
