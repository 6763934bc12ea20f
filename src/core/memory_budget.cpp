#include "recon/core/memory_budget.h"

#include "recon/core/errors.h"
#include "recon/core/resource_usage.h"

#include <algorithm>
#include <sstream>
#include <string>

namespace recon {
namespace {
// Measured peaks (docs/benchmarks.md), rounded up: a million points at k = 20
// peak at about 230 MB in phase I and 350 MB in phase II; a lattice walk
// holds under 250 bytes a visited cube, besides about 190 bytes a point
// still held from phases I and II.
constexpr double bytes_per_point_planes = 170.0, bytes_per_neighbour_planes = 4.0;
constexpr double bytes_per_point_graph = 210.0, bytes_per_neighbour_graph = 8.0;
constexpr double bytes_per_point_held = 190.0, bytes_per_cube = 250.0;
// The refined method: the fits' curvature (12 bytes), misfit (4), crease
// flags (1) and single-precision guide normals (12) during phase II, where
// a million points peak at 390 MB; 40 rounds that up.
constexpr double bytes_per_point_refined = 40.0;
// The 2D walk per visited square: the corner table's node, the queue, the
// vertices.
constexpr double bytes_per_square = 200.0;

std::string megabytes_or_gigabytes(double bytes) {
  std::ostringstream out;
  out.precision(3);
  if (bytes < 1e9) {
    out << bytes / 1e6 << " MB";
  } else {
    out << bytes / 1e9 << " GB";
  }
  return out.str();
}
}  // namespace

double estimated_bytes_planes_and_graph(std::size_t points, int k, bool second_order_fits) {
  const auto n = static_cast<double>(points);
  const double per_point = std::max(bytes_per_point_planes + bytes_per_neighbour_planes * k,
                                    bytes_per_point_graph + bytes_per_neighbour_graph * k);
  return n * (per_point + (second_order_fits ? bytes_per_point_refined : 0.0));
}

double estimated_bytes_lattice(std::size_t points, double cubes) {
  return static_cast<double>(points) * bytes_per_point_held + cubes * bytes_per_cube;
}

double estimated_bytes_reconstruction(std::size_t points, int k, bool second_order_fits) {
  return std::max(estimated_bytes_planes_and_graph(points, k, second_order_fits),
                  estimated_bytes_lattice(points, 3.0 * static_cast<double>(points)));
}

std::size_t max_cubes_within(std::size_t limit, std::size_t points) {
  return static_cast<std::size_t>(std::max(
      0.0, (static_cast<double>(limit) - static_cast<double>(points) * bytes_per_point_held) / bytes_per_cube));
}

std::size_t max_squares_within(std::size_t limit) {
  return static_cast<std::size_t>(static_cast<double>(limit) / bytes_per_square);
}

std::size_t memory_limit_or_default(std::size_t limit) { return limit > 0 ? limit : default_memory_limit(); }

void check_memory(double bytes, std::size_t limit, std::string_view what, std::string_view remedy) {
  if (bytes <= static_cast<double>(limit)) return;
  std::string message(what);
  message += " would need about " + megabytes_or_gigabytes(bytes) + ", more than the " +
             megabytes_or_gigabytes(static_cast<double>(limit)) +
             " allowed (--max-memory; default half the physical memory): ";
  message += remedy;
  message += ", or raise --max-memory";
  throw ResourceLimitError(message);
}

void check_memory_planes_and_graph(std::size_t points, int k, std::size_t limit, bool second_order_fits) {
  check_memory(estimated_bytes_planes_and_graph(points, k, second_order_fits), limit,
               "tangent planes and orientation of " + std::to_string(points) + " points at k = " + std::to_string(k),
               "lower --k or thin the cloud");
}

void check_statistics_sample(std::size_t drawn, std::size_t allowed, std::size_t cloud_points, int k,
                             std::size_t limit) {
  const auto needed = static_cast<std::size_t>(std::max(k, 0)) + 1;
  if (drawn >= needed || drawn >= cloud_points) return;
  throw ResourceLimitError(
      "the memory limit is too small for the cloud-wide statistics of a tiled run: the " +
      megabytes_or_gigabytes(static_cast<double>(limit)) + " allowed (--max-memory) hold a sample of " +
      std::to_string(allowed) + " of the " + std::to_string(cloud_points) +
      " points, drawn as whole patches of the cloud: " + std::to_string(drawn) + " drawn, and phase I needs at least " +
      std::to_string(needed) + " (k + 1 with k = " + std::to_string(k) + "); raise --max-memory");
}

}  // namespace recon
