// read_points_in_chunks against read_points, its oracle: for every format
// and variant, the chunks put end to end are read_points' cloud bit for bit
// (positions, normals, colours) with the same notes, for chunks of 1, 7 and
// 2^20 points; errors have read_points' messages, also where they come after
// chunks were handed out; and the resident memory of a streamed read stays
// far below the size of the file.

#include "recon/io/point_stream.h"

#include "io/io_test_helpers.h"
#include "io/las_test_file.h"
#include "recon/core/errors.h"
#include "recon/core/resource_usage.h"
#include "recon/io/point_io.h"

#include <gtest/gtest.h>

#include <sys/stat.h>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iostream>
#include <limits>
#include <optional>
#include <random>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace recon::io {
namespace {

using namespace testing;  // io_test_helpers.h, las_test_file.h

constexpr std::size_t chunk_sizes[] = {1, 7, std::size_t{1} << 20};

/// What a streamed read gave: the chunks put end to end.
struct Collected {
  PointCloud cloud;
  StreamedCloud result;
  ReadNotes notes;
  std::size_t chunks = 0;
};

/// Reads `path` in chunks of `chunk` points, checking each chunk's place and size.
Collected collect(const std::filesystem::path& path, ReadPointsOptions read, std::size_t chunk) {
  Collected out;
  PointChunkOptions options;
  options.chunk_points = chunk;
  options.read = std::move(read);
  out.result = read_points_in_chunks(
      path, options,
      [&](PointCloudView view, std::size_t first) {
        EXPECT_EQ(first, out.cloud.size());
        EXPECT_GT(view.size(), 0U);
        EXPECT_LE(view.size(), chunk);
        EXPECT_TRUE(view.normals.empty() || view.normals.size() == view.size());
        EXPECT_TRUE(view.colors.empty() || view.colors.size() == view.size());
        out.cloud.positions.insert(out.cloud.positions.end(), view.positions.begin(), view.positions.end());
        out.cloud.normals.insert(out.cloud.normals.end(), view.normals.begin(), view.normals.end());
        out.cloud.colors.insert(out.cloud.colors.end(), view.colors.begin(), view.colors.end());
        ++out.chunks;
      },
      &out.notes);
  return out;
}

template <class T>
bool same_bytes(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

/// Streams `path` with each chunk size and compares with read_points.
void expect_streams_as_read(const std::filesystem::path& path, const ReadPointsOptions& read, bool streamed) {
  ReadNotes expected_notes;
  const PointCloud expected = read_points(path, read, &expected_notes);
  for (const std::size_t chunk : chunk_sizes) {
    SCOPED_TRACE("chunks of " + std::to_string(chunk));
    const Collected got = collect(path, read, chunk);
    EXPECT_TRUE(same_bytes(got.cloud.positions, expected.positions));
    EXPECT_TRUE(same_bytes(got.cloud.normals, expected.normals));
    EXPECT_TRUE(same_bytes(got.cloud.colors, expected.colors));
    EXPECT_EQ(got.notes.lines, expected_notes.lines);
    EXPECT_EQ(got.notes.skipped_points, expected_notes.skipped_points);
    EXPECT_EQ(got.result.points, expected.size());
    EXPECT_EQ(got.result.has_normals, expected.has_normals());
    EXPECT_EQ(got.result.has_colors, expected.has_colors());
    EXPECT_EQ(got.result.streamed, streamed);
    EXPECT_EQ(got.chunks, (expected.size() + chunk - 1) / chunk);
  }
}

void expect_streams_as_read(const std::filesystem::path& path, bool streamed = true) {
  expect_streams_as_read(path, ReadPointsOptions{}, streamed);
}

struct NamedContent {
  std::string name;
  std::string content;
};

/// Writes each file in `folder` and streams it as read_points reads it.
void expect_each_streams_as_read(const TempFolder& folder, const std::vector<NamedContent>& files,
                                 bool streamed = true) {
  for (const NamedContent& f : files) {
    SCOPED_TRACE(f.name);
    write_file(folder / f.name, f.content);
    expect_streams_as_read(folder / f.name, ReadPointsOptions{}, streamed);
  }
}

/// A PLY file of `n` vertices x y z, nx ny nz and red green blue alpha, all
/// float but alpha (uchar), after a face element of two triangles; the
/// colours are fractions, but for the last vertex when `last_beyond_one`
/// (the whole file's colours are then 0-255).
std::string float_color_ply(std::size_t n, const std::string& encoding, bool last_beyond_one) {
  std::string header = "ply\nformat " + encoding +
                       " 1.0\ncomment faces first\nelement face 2\nproperty list uchar int vertex_indices\n"
                       "element vertex " +
                       std::to_string(n) + "\n";
  for (const char* name : {"x", "y", "z", "nx", "ny", "nz", "red", "green", "blue"})
    header += std::string("property float ") + name + "\n";
  header += "property uchar alpha\nend_header\n";
  const bool ascii = encoding == "ascii";
  Bytes body(encoding == "binary_big_endian");
  std::string text;
  for (int f = 0; f < 2; ++f) {
    body.put<std::uint8_t>(3).put<std::int32_t>(0).put<std::int32_t>(1).put<std::int32_t>(2);
    text += "3 0 1 2\n";
  }
  std::mt19937 random(17);
  std::uniform_real_distribution<float> unit(0.0F, 1.0F);
  for (std::size_t i = 0; i < n; ++i) {
    std::array<float, 9> v{};
    for (float& value : v) value = unit(random);
    if (last_beyond_one && i + 1 == n) v[6] = 200.0F;
    for (const float value : v) {
      body.put(value);
      text += std::to_string(value) + " ";
    }
    body.put<std::uint8_t>(255);
    text += "255\n";
  }
  return header + (ascii ? text : body.str());
}

TEST(PointStream, PlyOfEveryEncoding) {
  TempFolder folder;
  PointCloud cloud = random_cloud(300, true, 5);
  cloud.colors = random_colors(300, 6);
  write_points(folder / "b.ply", cloud);
  expect_streams_as_read(folder / "b.ply");
  WritePointsOptions ascii;
  ascii.ascii = true;
  write_points(folder / "a.ply", cloud, ascii);
  expect_streams_as_read(folder / "a.ply");
  for (const std::string encoding : {"ascii", "binary_little_endian", "binary_big_endian"}) {
    for (const bool beyond_one : {false, true}) {
      SCOPED_TRACE(encoding + (beyond_one ? ", colours 0-255" : ", colours 0-1"));
      write_file(folder / "f.ply", float_color_ply(100, encoding, beyond_one));
      expect_streams_as_read(folder / "f.ply");
    }
  }
}

TEST(PointStream, TextColumnsOfEveryKind) {
  TempFolder folder;
  PointCloud cloud = random_cloud(200, true, 7);
  write_points(folder / "n.xyz", cloud);  // 6 columns: normals, decided by the values
  cloud.colors = random_colors(200, 8);
  write_points(folder / "nc.xyz", cloud);  // 9 columns: normals and colours
  cloud.normals.clear();
  write_points(folder / "c.xyz", cloud);  // 6 columns: integer colours
  for (const char* name : {"n.xyz", "nc.xyz", "c.xyz"}) {
    SCOPED_TRACE(name);
    expect_streams_as_read(folder / name);
  }
  expect_each_streams_as_read(
      folder, {
                  {"three.txt", "1 2 3\n4 5 6\n7 8 9\n"},
                  {"four.asc", "1 2 3 100\n4 5 6 200\n# a comment\n\n7 8 9 300\n"},
                  // 0s and 1s until the last line, whose 2 makes the whole file integers 0-255 (else 1 is 255).
                  {"late.xyz", "1 2 3 0 1 1\n4 5 6 1 1 0\n7 8 9 0 0 2\n"},
                  {"fractions.xyz", "1 2 3 0.5 0.25 0\n4 5 6 0.5 0.5 0.5\n7 8 9 1 1 0.75\n"},
                  {"seven.xyz", "1 2 3 900 10 20 30\n4 5 6 800 40 50 60\n"},
                  {"seven_last.xyz", "1 2 3 1 0 0 9.5\n4 5 6 0 1 0 -3\n"},
                  {"header.csv", "X,Y,Z,Intensity,R,G,B\n1,2,3,9,10,20,30\n4,5,6,9,0,255,1\n"},
                  {"semicolons.csv", "//x;y;z;nx;ny;nz\r\n1,5;2;3;1;0;0\r\n4;5,25;6;0;0;-1\r\n"},
                  {"cr.xyz",
                   "\xEF\xBB\xBF"
                   "1 2 3\r4 5 6\r7 8 9\r"},
              });
  ReadPointsOptions columns;
  columns.columns = {"z", "_", "x", "y", "r", "g", "b"};
  write_file(folder / "option.txt", "x y z\n1 2 3 4 0.5 0.5 1\n5 6 7 8 0 0 0.25\n");
  expect_streams_as_read(folder / "option.txt", columns, true);
}

TEST(PointStream, LasWithAndWithoutColours) {
  TempFolder folder;
  std::mt19937 random(3);
  std::uniform_int_distribution<std::int32_t> coordinate(-2000000000, 2000000000);
  for (const unsigned format : {0U, 2U, 7U}) {
    for (const std::uint16_t largest : {std::uint16_t{255}, std::uint16_t{65535}}) {
      SCOPED_TRACE("format " + std::to_string(format) + ", colours up to " + std::to_string(largest));
      LasFile las;
      las.minor = format > 5 ? 4 : 2;
      las.format = format;
      las.scale = {0.001, 0.01, 0.25};
      las.offset = {4.5e6, -20.5, 0.0};
      las.extra_bytes = 5;
      las.points.resize(150);
      for (std::size_t i = 0; i < las.points.size(); ++i) {
        for (std::int32_t& c : las.points[i].xyz) c = coordinate(random);
        for (std::uint16_t& c : las.points[i].rgb) c = static_cast<std::uint16_t>((i * 37 + c) % 256);
      }
      las.points.back().rgb[1] = largest;  // the last point decides for the whole file
      write_file(folder / "p.las", las.bytes());
      expect_streams_as_read(folder / "p.las");
    }
  }
}

TEST(PointStream, OtherFormatsAreReadWholeAndHandedOutInChunks) {
  TempFolder folder;
  expect_each_streams_as_read(
      folder,
      {
          {"h.pts", "p 1 2 3\nn 0 0 1\np 4 5 6\np 7 8 9\n"},
          {"c.pts", "1 2 3\n4 5 6\n"},
          {"m.obj", "v 1 2 3 1 0 0\nv 4 5 6 0 1 0\nv 7 8 9 0 0 1\nvn 0 0 1\nvn 0 1 0\nvn 1 0 0\nf 1 2 3\n"},
          {"m.off", "OFF\n3 1 0\n1 2 3\n4 5 6\n7 8 9\n3 0 1 2\n"},
          {"p.pcd",
           "FIELDS x y z normal_x normal_y normal_z\nSIZE 4 4 4 4 4 4\nTYPE F F F F F F\nPOINTS 2\n"
           "DATA ascii\n1 2 3 0 0 1\n4 5 6 1 0 0\n"},
      },
      false);
}

TEST(PointStream, InvalidPointsAreSkippedAsReadPointsSkipsThem) {
  TempFolder folder;
  ReadPointsOptions skipping;
  skipping.skip_invalid = true;
  write_file(folder / "s.xyz", "0 0 0 1 0 0\n1 nan 1 0 1 0\n2 2 2 0 0 1\n1e300 0 0 1 0 0\n3 3 3 0 1 0\n");
  expect_streams_as_read(folder / "s.xyz", skipping, true);
  Bytes ply;
  ply.text(
      "ply\nformat binary_little_endian 1.0\nelement vertex 5\nproperty double x\nproperty double y\n"
      "property double z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n");
  for (int i = 0; i < 5; ++i) {
    ply.put(i == 1 ? std::numeric_limits<double>::infinity() : 1.0 * i).put(2.0).put(i == 3 ? 3e15 : 3.0);
    ply.put<std::uint8_t>(static_cast<std::uint8_t>(i)).put<std::uint8_t>(7).put<std::uint8_t>(9);
  }
  write_file(folder / "s.ply", ply.str());
  expect_streams_as_read(folder / "s.ply", skipping, true);
  // A part of invalid points only is not handed out: chunks of 1 skip it.
  write_file(folder / "none.xyz", "nan 0 0\ninf 1 1\n");
  const std::string expected =
      message_of<ParseError>([&] { static_cast<void>(read_points(folder / "none.xyz", skipping)); });
  EXPECT_CONTAINS(expected, "every point is invalid");
  EXPECT_EQ(message_of<ParseError>([&] { static_cast<void>(collect(folder / "none.xyz", skipping, 1)); }), expected);
}

TEST(PointStream, APipeIsReadWholeAndHandedOutInChunks) {
  TempFolder folder;
  const PointCloud cloud = random_cloud(50, true, 11);
  write_points(folder / "c.ply", cloud);
  const std::filesystem::path fifo = folder / "pipe.ply";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::thread writer([&] { write_file(fifo, read_bytes(folder / "c.ply")); });
  const Collected got = collect(fifo, ReadPointsOptions{}, 7);
  writer.join();
  EXPECT_FALSE(got.result.streamed);
  EXPECT_TRUE(same_bytes(got.cloud.positions, cloud.positions));
  EXPECT_TRUE(same_bytes(got.cloud.normals, cloud.normals));
}

TEST(PointStream, TakeReadsOtherFilesAsIfNothingWereSkipped) {
  // skip_invalid of the streamed file does not reach a file read by `take`.
  TempFolder folder;
  write_file(folder / "a.xyz", "1 2 3\nnan 0 0\n4 5 6\n");
  write_file(folder / "other.xyz", "1 2 3\ninf 0 0\n");
  PointChunkOptions options;
  options.chunk_points = 1;
  options.read.skip_invalid = true;
  std::size_t refused = 0;
  const StreamedCloud result = read_points_in_chunks(folder / "a.xyz", options, [&](PointCloudView, std::size_t) {
    if (!message_of<ParseError>([&] { static_cast<void>(read_points(folder / "other.xyz")); }).empty()) ++refused;
  });
  EXPECT_EQ(result.points, 2U);
  EXPECT_EQ(refused, 2U);
}

/// The ParseError of read_points on `path`, which reading it in chunks of
/// `chunk` must give too, after handing out at least `chunks_before` chunks.
void expect_same_error(const std::filesystem::path& path, std::size_t chunk, std::size_t chunks_before,
                       const std::string& phrase) {
  const std::string expected = point_read_error(path);
  EXPECT_CONTAINS(expected, phrase);
  std::size_t chunks = 0;
  PointChunkOptions options;
  options.chunk_points = chunk;
  const std::string got = message_of<ParseError>(
      [&] { static_cast<void>(read_points_in_chunks(path, options, [&](PointCloudView, std::size_t) { ++chunks; })); });
  EXPECT_EQ(got, expected);
  EXPECT_GE(chunks, chunks_before);
}

TEST(PointStream, ErrorsLateInTheFileAreReadPointsErrors) {
  TempFolder folder;
  std::string text;
  for (int i = 0; i < 500; ++i) text += std::to_string(i) + " 1 2\n";
  write_file(folder / "bad.xyz", text + "1 2 x\n");
  expect_same_error(folder / "bad.xyz", 7, 71, "bad.xyz:501:");
  write_file(folder / "count.xyz", text + "1 2 3 4\n");
  expect_same_error(folder / "count.xyz", 7, 71, "count.xyz:501:");
  write_file(folder / "nan.xyz", text + "1 nan 2\n" + text);
  expect_same_error(folder / "nan.xyz", 7, 142, "the first at line 501 (y = nan)");
  // Values that leave doubt are found by the first pass, before any chunk.
  write_file(folder / "doubt.xyz", "1 2 3 0.5 0.5 0.5\n4 5 6 7 8 900\n");
  expect_same_error(folder / "doubt.xyz", 1, 0, "leave doubt");

  PointCloud cloud = random_cloud(400, false, 9);
  WritePointsOptions ascii;
  ascii.ascii = true;
  write_points(folder / "a.ply", cloud, ascii);
  std::string content = read_bytes(folder / "a.ply");
  write_file(folder / "a.ply", content.substr(0, content.rfind(' ')));  // the last vertex without its z
  expect_same_error(folder / "a.ply", 7, 50, "the file ends inside vertex 399");
  write_file(folder / "extra.ply", content + "1 2 3\n");
  expect_same_error(folder / "extra.ply", 7, 50, "after the last element");
  write_points(folder / "b.ply", cloud);
  content = read_bytes(folder / "b.ply");
  write_file(folder / "b.ply", content.substr(0, content.size() - 30));
  expect_same_error(folder / "b.ply", 7, 0, "the file ends inside vertex 398");

  write_file(folder / "empty.ply", "");
  expect_same_error(folder / "empty.ply", 7, 0, "the file is empty");
  write_file(folder / "novertex.ply",
             "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\n"
             "property float z\nend_header\n");
  expect_same_error(folder / "novertex.ply", 7, 0, "no points");
}

TEST(PointStream, OtherErrors) {
  TempFolder folder;
  PointChunkOptions options;
  const auto ignore = [](PointCloudView, std::size_t) {};
  EXPECT_CONTAINS(
      message_of<IoError>([&] { static_cast<void>(read_points_in_chunks(folder / "missing.ply", options, ignore)); }),
      "missing.ply: cannot open");
  EXPECT_CONTAINS(message_of<InvalidInputError>(
                      [&] { static_cast<void>(read_points_in_chunks(folder / "a.laz", options, ignore)); }),
                  "LAZ");
  write_file(folder / "a.xyz", "1 2 3\n4 5 6\n");
  options.chunk_points = 0;
  EXPECT_CONTAINS(message_of<InvalidInputError>(
                      [&] { static_cast<void>(read_points_in_chunks(folder / "a.xyz", options, ignore)); }),
                  "chunk_points");
  // What `take` throws ends the reading.
  options.chunk_points = 1;
  std::size_t calls = 0;
  EXPECT_THROW(static_cast<void>(read_points_in_chunks(folder / "a.xyz", options,
                                                       [&](PointCloudView, std::size_t) {
                                                         ++calls;
                                                         throw std::runtime_error("stop");
                                                       })),
               std::runtime_error);
  EXPECT_EQ(calls, 1U);
}

// ---------------------------------------------------------------------------
// Memory

/// Peak growth of the resident memory during `read`, in bytes; nullopt when
/// /proc cannot say.
template <class F>
std::optional<std::size_t> peak_growth(F&& read) {
#if defined(__GLIBC__)
  // Free memory the heap still holds (earlier tests') would serve the read
  // without counting in the growth: give it back first.
  ::malloc_trim(0);
#endif
  if (!reset_peak_resident()) return std::nullopt;
  const auto before = resident_bytes();
  read();
  const auto peak = peak_resident_bytes();
  if (!before || !peak) return std::nullopt;
  return *peak > *before ? *peak - *before : 0;
}

/// A binary little-endian PLY file of `n` points of double x y z, written a block at a time.
void write_large_ply(const std::filesystem::path& path, std::size_t n) {
  std::ofstream out(path, std::ios::binary);
  const std::string header = "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(n) +
                             "\nproperty double x\nproperty double y\nproperty double z\nend_header\n";
  out << header;
  Bytes block;
  for (std::size_t i = 0; i < n; ++i) {
    const auto t = static_cast<double>(i);
    block.put(t).put(0.5 * t).put(std::sin(t));
    if (block.size() >= (std::size_t{1} << 20) || i + 1 == n) {
      out << block.str();
      block = Bytes();
    }
  }
  ASSERT_TRUE(out.good());
}

TEST(PointStreamMemory, StreamingAPlyFileHoldsFarLessThanTheFile) {
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
  GTEST_SKIP() << "the sanitizers' allocator and shadow memory change the resident memory measured";
#endif
  TempFolder folder;
  const std::filesystem::path path = folder / "large.ply";
  constexpr std::size_t n = 3'000'000;
  write_large_ply(path, n);
  const std::size_t file_size = std::filesystem::file_size(path);
  PointChunkOptions options;
  options.chunk_points = 65536;
  std::size_t points = 0;
  double sum = 0.0;
  const auto streamed = peak_growth([&] {
    static_cast<void>(read_points_in_chunks(path, options, [&](PointCloudView chunk, std::size_t) {
      points += chunk.size();
      for (const Vec3& p : chunk.positions) sum += p.z();
    }));
  });
  if (!streamed) GTEST_SKIP() << "/proc cannot say the peak resident memory here";
  EXPECT_EQ(points, n);
  EXPECT_TRUE(std::isfinite(sum));
  // The measure sees a whole read: read_points holds the mapped file and the cloud.
  const auto whole = peak_growth([&] { EXPECT_EQ(read_points(path).size(), n); });
  ASSERT_TRUE(whole);
  std::cout << "file " << file_size / 1024 << " KiB; peak resident growth: streamed " << *streamed / 1024
            << " KiB, read_points " << *whole / 1024 << " KiB\n";
  EXPECT_GT(*whole, file_size);
  EXPECT_LT(*streamed, file_size / 4);
}

TEST(PointStreamMemory, TextReadTwiceAndLasHoldFarLessThanTheFile) {
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
  GTEST_SKIP() << "the sanitizers' allocator and shadow memory change the resident memory measured";
#endif
  TempFolder folder;
  // Text of 6 columns: integer colours, decided by a first pass over the whole file.
  const std::filesystem::path text_path = folder / "large.xyz";
  {
    std::ofstream out(text_path, std::ios::binary);
    std::string block;
    for (std::size_t i = 0; i < 2'000'000; ++i) {
      block += std::to_string(i) + " " + std::to_string(i % 1000) + ".25 -17.5 " + std::to_string(i % 256) + " 7 200\n";
      if (block.size() > (std::size_t{1} << 20)) out << std::exchange(block, {});
    }
    out << block;
  }
  // LAS of format 2 (colours): a first walk over the colours, then the points.
  const std::filesystem::path las_path = folder / "large.las";
  {
    LasFile las;
    las.format = 2;
    las.points.resize(2'400'000);
    for (std::size_t i = 0; i < las.points.size(); ++i)
      las.points[i] = {{static_cast<std::int32_t>(i), -static_cast<std::int32_t>(i), 7}, {1, 2, 3}};
    write_file(las_path, las.bytes());
  }
  for (const auto& path : {text_path, las_path}) {
    const std::size_t file_size = std::filesystem::file_size(path);
    PointChunkOptions options;
    options.chunk_points = 65536;
    std::size_t points = 0;
    const auto streamed = peak_growth([&] {
      static_cast<void>(
          read_points_in_chunks(path, options, [&](PointCloudView chunk, std::size_t) { points += chunk.size(); }));
    });
    if (!streamed) GTEST_SKIP() << "/proc cannot say the peak resident memory here";
    std::cout << path.filename() << ": file " << file_size / 1024 << " KiB, " << points
              << " points; peak resident growth streamed " << *streamed / 1024 << " KiB\n";
    EXPECT_LT(*streamed, file_size / 4);
  }
}

}  // namespace
}  // namespace recon::io
