// What the tiles' tests (tiles_test.cpp, tile_statistics_test.cpp) share: a
// fresh scratch folder for a run's files, and the clouds their cases sample.

#pragma once

#include "recon/core/point_cloud.h"
#include "recon/core/shapes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>

#include <unistd.h>

namespace recon::tile_testing {

/// An empty folder `name` in GoogleTest's temporary folder (emptied first
/// if a run before left it), named for this process too: two test runs at
/// once (two checkouts on one machine) must not share it.
inline std::filesystem::path scratch_folder(const std::string& name) {
  const auto dir = std::filesystem::path(::testing::TempDir()) / (name + "-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

/// `points` samples of the named shape (seeded by `seed`), with noise of
/// `noise` sample spacings (seeded by `noise_seed`) when noise > 0.
inline PointCloud noisy_sample(const char* shape_name, std::size_t points, double noise, std::uint64_t seed,
                               std::uint64_t noise_seed) {
  const auto shape = make_shape(shape_name);
  PointCloud cloud = shape->sample(points, seed);
  const double spacing = std::sqrt(shape->area() / static_cast<double>(points));
  if (noise > 0.0) add_noise(cloud, noise * spacing / bounding_box<3>(cloud.positions).diagonal(), noise_seed);
  return cloud;
}

}  // namespace recon::tile_testing
