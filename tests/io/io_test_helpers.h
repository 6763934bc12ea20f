#pragma once
// Shared by the io tests: a fresh temporary folder per test, files from
// strings, binary content in either byte order, seeded random clouds and
// colours, exact comparisons of clouds and meshes, and checks on exception
// messages (one bad file, or a table of them).

#include "recon/core/errors.h"
#include "recon/core/point_cloud.h"
#include "recon/io/curve_io.h"
#include "recon/io/mesh_io.h"
#include "recon/io/point_io.h"
#include "recon/structures/mesh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <random>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <unistd.h>

/// Checks that `text` contains `part`, printing the whole text otherwise.
#define EXPECT_CONTAINS(text, part) \
  EXPECT_NE(std::string(text).find(part), std::string::npos) << "'" << (text) << "' lacks '" << (part) << "'"

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

/// Writes `content` to folder/name and reads it back as 2D points, once
/// holds_2d_points has taken it for 2D.
inline std::vector<Vec2> read_2d_text(const TempFolder& folder, std::string_view name, std::string_view content) {
  write_file(folder / name, content);
  EXPECT_TRUE(holds_2d_points(folder / name)) << name;
  return read_points_2d(folder / name);
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
  /// A binary PLY header in this byte order around `elements` (the element
  /// and property lines).
  Bytes& ply_header(std::string_view elements) {
    text(big_endian_ ? "ply\nformat binary_big_endian 1.0\n" : "ply\nformat binary_little_endian 1.0\n");
    text(elements);
    return text("end_header\n");
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

/// A seeded random mesh: the vertices of random_cloud() and triangles of
/// random corners (some degenerate: the readers and writers do not care).
inline Mesh random_mesh(std::size_t vertices, std::size_t triangles, std::uint64_t seed) {
  const PointCloud cloud = random_cloud(vertices, false, seed);
  Mesh mesh;
  mesh.vertices = cloud.positions;
  std::mt19937_64 random(seed);
  std::uniform_int_distribution<std::uint32_t> index(0, static_cast<std::uint32_t>(vertices - 1));
  for (std::size_t t = 0; t < triangles; ++t) mesh.triangles.push_back({index(random), index(random), index(random)});
  return mesh;
}

/// Seeded random colours, the first black and the last {255, 128, 1}.
inline std::vector<Color> random_colors(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 random(seed);
  std::uniform_int_distribution<int> byte(0, 255);
  std::vector<Color> colors(n);
  for (Color& c : colors)
    for (std::uint8_t& v : c) v = static_cast<std::uint8_t>(byte(random));
  colors.front() = {0, 0, 0};
  colors.back() = {255, 128, 1};
  return colors;
}

/// A strip of `vertices` random points (triangles v, v + 1, v + 2) with
/// random colours.
inline Mesh colored_mesh(std::size_t vertices, std::uint64_t seed) {
  Mesh mesh;
  mesh.vertices = random_cloud(vertices, false, seed).positions;
  for (std::uint32_t v = 0; v + 2 < vertices; ++v) mesh.triangles.push_back({v, v + 1, v + 2});
  mesh.colors = random_colors(vertices, seed);
  return mesh;
}

/// The same positions and normals, bit for bit.
inline void expect_same(const PointCloud& expected, const PointCloud& actual) {
  ASSERT_EQ(actual.size(), expected.size());
  ASSERT_EQ(actual.normals.size(), expected.normals.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    ASSERT_EQ(actual.positions[i], expected.positions[i]) << "point " << i;
    if (expected.has_normals()) {
      ASSERT_EQ(actual.normals[i], expected.normals[i]) << "normal " << i;
    }
  }
}

/// The same vertices, bit for bit, and the same triangles.
inline void expect_same(const Mesh& expected, const Mesh& actual) {
  ASSERT_EQ(actual.vertices.size(), expected.vertices.size());
  ASSERT_EQ(actual.triangles.size(), expected.triangles.size());
  for (std::size_t i = 0; i < expected.vertices.size(); ++i) ASSERT_EQ(actual.vertices[i], expected.vertices[i]) << i;
  for (std::size_t t = 0; t < expected.triangles.size(); ++t)
    ASSERT_EQ(actual.triangles[t], expected.triangles[t]) << t;
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

/// Checks that `f` throws an exception of type E whose message contains
/// every one of `parts`.
template <typename E, typename F>
void expect_message(F&& f, std::initializer_list<std::string_view> parts) {
  const std::string message = message_of<E>(std::forward<F>(f));
  for (const std::string_view part : parts) EXPECT_CONTAINS(message, part);
}

/// Checks what `format_from` (a format_from_path or format_from_name) makes
/// of each text of a table: the format it names.
template <typename Format, typename FormatFrom>
void expect_formats(FormatFrom&& format_from, std::initializer_list<std::pair<std::string_view, Format>> cases) {
  for (const auto& [text, format] : cases) EXPECT_EQ(format_from(std::string(text)), format) << text;
}

/// Checks that the reader said exactly one thing, and that it contains every
/// one of `parts`.
inline void expect_one_note(const ReadNotes& notes, std::initializer_list<std::string_view> parts) {
  ASSERT_EQ(notes.lines.size(), 1U);
  for (const std::string_view part : parts) EXPECT_CONTAINS(notes.lines[0], part);
}

/// Reads a point cloud, with what the reader said in `notes`.
inline PointCloud read_with_notes(const std::filesystem::path& path, ReadNotes& notes, bool skip_invalid = false) {
  ReadPointsOptions options;
  options.skip_invalid = skip_invalid;
  return read_points(path, options, &notes);
}

/// Writes `content` to folder/name and reads it back.
inline PointCloud write_and_read(const TempFolder& folder, std::string_view name, std::string_view content) {
  write_file(folder / name, content);
  return read_points(folder / name);
}

/// Writes `content` to folder/name and reads it back, with its notes.
inline PointCloud write_and_read(const TempFolder& folder, std::string_view name, std::string_view content,
                                 ReadNotes& notes) {
  write_file(folder / name, content);
  return read_with_notes(folder / name, notes);
}

/// How many times `part` occurs in `text` (not overlapping).
inline std::size_t occurrences(std::string_view text, std::string_view part) {
  std::size_t count = 0;
  for (std::size_t at = text.find(part); at != std::string_view::npos; at = text.find(part, at + part.size())) ++count;
  return count;
}

/// The message of the ParseError that reading `path` as a point cloud throws.
inline std::string point_read_error(const std::filesystem::path& path) {
  return message_of<ParseError>([&] { static_cast<void>(read_points(path)); });
}

/// The message of the ParseError that reading `path` as a mesh throws.
inline std::string mesh_read_error(const std::filesystem::path& path) {
  return message_of<ParseError>([&] { static_cast<void>(read_mesh(path)); });
}

/// One bad file of a table: its content, the place the message must name
/// ("e.xyz:2:", "t.pcd: byte 84:") and a phrase saying what was wrong.
struct BadContent {
  std::string content;
  std::string where;
  std::string what;
};

/// Writes each case as `name` in a fresh folder and checks the message of
/// the ParseError that reading it (as points, or as a mesh) throws.
inline void expect_read_errors(std::string_view name, const std::vector<BadContent>& cases, bool mesh = false) {
  TempFolder folder;
  const std::filesystem::path path = folder / name;
  for (const BadContent& c : cases) {
    write_file(path, c.content);
    const std::string message = mesh ? mesh_read_error(path) : point_read_error(path);
    EXPECT_CONTAINS(message, c.where);
    EXPECT_CONTAINS(message, c.what);
  }
}

}  // namespace recon::io::testing
