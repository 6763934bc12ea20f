#pragma once
// Shared by the io tests: a fresh temporary folder per test, files from
// strings, binary content in either byte order, seeded random clouds, and
// checks on exception messages.

#include "recon/errors.h"
#include "recon/io/point_io.h"
#include "recon/point_cloud.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include <unistd.h>

namespace recon::io::testing {

/// A new, empty folder under the system's temporary folder, removed with
/// everything in it when the test ends.
class TempFolder {
 public:
  TempFolder() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::random_device entropy;
    const std::string name = std::string("recon_") + info->test_suite_name() + "_" + info->name() + "_" +
                             std::to_string(::getpid()) + "_" + std::to_string(entropy());
    path_ = std::filesystem::temp_directory_path() / name;
    std::filesystem::create_directories(path_);
  }
  TempFolder(const TempFolder&) = delete;
  TempFolder& operator=(const TempFolder&) = delete;
  ~TempFolder() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }

  [[nodiscard]] const std::filesystem::path& path() const { return path_; }
  [[nodiscard]] std::filesystem::path operator/(std::string_view name) const { return path_ / name; }

  /// Names of the entries in the folder, sorted.
  [[nodiscard]] std::vector<std::string> entries() const {
    std::vector<std::string> names;
    for (const auto& entry : std::filesystem::directory_iterator(path_))
      names.push_back(entry.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  }

 private:
  std::filesystem::path path_;
};

/// Read options naming the format (and the stream limit).
inline ReadPointsOptions as_format(PointFormat format, std::size_t max_stream_bytes = 0) {
  ReadPointsOptions options;
  options.format = format;
  options.max_stream_bytes = max_stream_bytes;
  return options;
}

inline void write_file(const std::filesystem::path& path, std::string_view content) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(content.data(), static_cast<std::streamsize>(content.size()));
  ASSERT_TRUE(out.good()) << "cannot write " << path;
}

inline std::string read_bytes(const std::filesystem::path& path) {
  std::string content(static_cast<std::size_t>(std::filesystem::file_size(path)), '\0');
  std::ifstream in(path, std::ios::binary);
  in.read(content.data(), static_cast<std::streamsize>(content.size()));
  return content;
}

/// Builds binary file content in a chosen byte order.
class Bytes {
 public:
  explicit Bytes(bool big_endian = false) : big_endian_(big_endian) {}
  Bytes& text(std::string_view s) {
    data_.append(s);
    return *this;
  }
  template <typename T>
  Bytes& put(T value) {
    char raw[sizeof(T)];
    std::memcpy(raw, &value, sizeof(T));
    if (big_endian_ != (std::endian::native == std::endian::big)) std::reverse(raw, raw + sizeof(T));
    data_.append(raw, sizeof(T));
    return *this;
  }
  [[nodiscard]] const std::string& str() const { return data_; }
  [[nodiscard]] std::size_t size() const { return data_.size(); }

 private:
  bool big_endian_;
  std::string data_;
};

/// Seeded random cloud with coordinates of very different magnitudes (to
/// exercise the number printing), all within +-max_coordinate so that they
/// read back, and unit normals when asked.
inline PointCloud random_cloud(std::size_t n, bool normals, std::uint64_t seed) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-30, 14);
  PointCloud cloud;
  for (std::size_t i = 0; i < n; ++i) {
    Vec3 p;
    for (int k = 0; k < 3; ++k) p[k] = unit(random) * std::pow(10.0, exponent(random));
    cloud.positions.push_back(p);
    if (normals) {
      Vec3 v(unit(random), unit(random), unit(random));
      cloud.normals.push_back(v.norm() > 1e-3 ? Vec3(v.normalized()) : Vec3::UnitZ());
    }
  }
  // A few values that are easy to get wrong.
  if (n >= 3) {
    cloud.positions[0] = Vec3(0.1, -0.0, 1e-300);
    cloud.positions[1] = Vec3(max_coordinate, -4.9406564584124654e-324, 123456789.0);
    cloud.positions[2] = Vec3(1.0 / 3.0, 2.0 / 3.0, -999999999999999.9);
  }
  return cloud;
}

/// The message of the exception of type E that `f` throws; a test failure
/// (and "") when it throws nothing or something else.
template <typename E, typename F>
std::string message_of(F&& f) {
  try {
    f();
  } catch (const E& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "threw another exception: " << e.what();
    return {};
  }
  ADD_FAILURE() << "threw nothing";
  return {};
}

/// Reads a point cloud, with what the reader said in `notes`.
inline PointCloud read_with_notes(const std::filesystem::path& path, ReadNotes& notes, bool skip_invalid = false) {
  ReadPointsOptions options;
  options.skip_invalid = skip_invalid;
  return read_points(path, options, &notes);
}

/// The message of the ParseError that reading `path` as a point cloud throws.
inline std::string point_read_error(const std::filesystem::path& path) {
  return message_of<ParseError>([&] { static_cast<void>(read_points(path)); });
}

}  // namespace recon::io::testing

/// Checks that `text` contains `part`, printing the whole text otherwise.
#define EXPECT_CONTAINS(text, part) \
  EXPECT_NE(std::string(text).find(part), std::string::npos) << "'" << (text) << "' lacks '" << (part) << "'"
