// The LAS reader against files written from the specification (LAS 1.0 to
// 1.4, point data record formats 0 to 10) by las_test_file.h.

#include "recon/io/point_io.h"

#include "io/io_test_helpers.h"
#include "io/las_test_file.h"
#include "recon/core/errors.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace recon::io {
namespace {

using namespace testing;  // io_test_helpers.h, las_test_file.h

/// The smallest record of each format, as the specification gives it.
constexpr std::array<std::size_t, 11> spec_record_size = {20, 28, 26, 34, 57, 63, 30, 36, 38, 59, 67};

/// The formats each LAS 1.minor defines.
unsigned last_format(unsigned minor) { return minor <= 1 ? 1 : minor == 2 ? 3 : minor == 3 ? 5 : 10; }

std::vector<LasPoint> some_points(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 random(seed);
  std::uniform_int_distribution<std::int32_t> coordinate(std::numeric_limits<std::int32_t>::min(),
                                                         std::numeric_limits<std::int32_t>::max());
  std::uniform_int_distribution<int> channel(0, 65535);
  std::vector<LasPoint> points(n);
  for (LasPoint& p : points) {
    for (std::int32_t& c : p.xyz) c = coordinate(random);
    for (std::uint16_t& c : p.rgb) c = static_cast<std::uint16_t>(channel(random));
  }
  return points;
}

Vec3 expected_position(const LasFile& las, const LasPoint& p) {
  Vec3 v;
  for (int k = 0; k < 3; ++k)
    v[k] = static_cast<double>(p.xyz[static_cast<std::size_t>(k)]) * las.scale[static_cast<std::size_t>(k)] +
           las.offset[static_cast<std::size_t>(k)];
  return v;
}

TEST(LasReader, EveryFormatOfEveryVersion) {
  TempFolder folder;
  for (unsigned minor = 0; minor <= 4; ++minor) {
    for (unsigned format = 0; format <= last_format(minor); ++format) {
      SCOPED_TRACE("LAS 1." + std::to_string(minor) + ", format " + std::to_string(format));
      LasFile las;
      las.minor = minor;
      las.format = format;
      las.scale = {0.01, 0.001, 0.25};
      las.offset = {-100.0, 2000.5, 0.0};
      las.points = some_points(17, 10 * minor + format);
      for (LasPoint& p : las.points) {
        for (std::uint16_t& c : p.rgb) c = static_cast<std::uint16_t>(c & 0xFF00);  // 16-bit colours
      }
      ASSERT_EQ(las.record_length(), spec_record_size[format]);
      ReadNotes notes;
      const PointCloud cloud = write_and_read(folder, "f.las", las.bytes(), notes);
      ASSERT_EQ(cloud.size(), las.points.size());
      EXPECT_FALSE(cloud.has_normals());
      EXPECT_EQ(cloud.has_colors(), las.has_rgb());
      for (std::size_t i = 0; i < cloud.size(); ++i) {
        EXPECT_EQ(cloud.positions[i], expected_position(las, las.points[i])) << "point " << i;
        if (!las.has_rgb()) continue;
        const Rgb16& rgb = las.points[i].rgb;
        const Color high_bytes = {static_cast<std::uint8_t>(rgb[0] >> 8), static_cast<std::uint8_t>(rgb[1] >> 8),
                                  static_cast<std::uint8_t>(rgb[2] >> 8)};
        EXPECT_EQ(cloud.colors[i], high_bytes) << "point " << i;
      }
      EXPECT_EQ(notes.lines.size(), las.has_rgb() ? 1U : 0U);
      EXPECT_EQ(notes.skipped_points, 0U);
    }
  }
}

TEST(LasReader, ExtraBytesAndVariableLengthRecordsAreSkipped) {
  TempFolder folder;
  for (const unsigned format : {0U, 3U, 6U, 10U}) {
    LasFile las;
    las.minor = 4;
    las.format = format;
    las.extra_bytes = 13;
    las.vlr_bytes = 54 + 100;  // a VLR header and its payload: not read
    las.points = some_points(9, format);
    ReadNotes notes;
    const PointCloud cloud = write_and_read(folder, "x.las", las.bytes(), notes);
    ASSERT_EQ(cloud.size(), las.points.size());
    for (std::size_t i = 0; i < cloud.size(); ++i) EXPECT_EQ(cloud.positions[i], expected_position(las, las.points[i]));
  }
}

TEST(LasReader, LegacyAnd64BitCounts) {
  TempFolder folder;
  const auto read_count = [&](bool legacy, bool wide) {
    LasFile las;
    las.minor = 4;
    las.format = 6;
    las.points = some_points(5, 3);
    las.legacy_count = legacy;
    las.count_64 = wide;
    write_file(folder / "c.las", las.bytes());
    ReadNotes notes;
    return read_with_notes(folder / "c.las", notes).size();
  };
  EXPECT_EQ(read_count(false, true), 5U);  // formats 6-10: the legacy count is 0
  EXPECT_EQ(read_count(true, false), 5U);  // a writer that filled only the legacy count
  EXPECT_EQ(read_count(true, true), 5U);
  // Before 1.4 there is no 64-bit count: the bytes after a 1.3 header are points.
  LasFile old;
  old.minor = 3;
  old.format = 1;
  old.points = some_points(4, 4);
  write_file(folder / "old.las", old.bytes());
  ReadNotes notes;
  EXPECT_EQ(read_with_notes(folder / "old.las", notes).size(), 4U);
}

TEST(LasReader, GeoReferencedCoordinatesKeepTheMillimetre) {
  // A survey in a projected system: northings of 4.5e6 m, stored in
  // millimetres (scale 0.001). Every point must be exact to far below a
  // millimetre, over the whole int32 range.
  TempFolder folder;
  LasFile las;
  las.minor = 2;
  las.format = 1;
  las.scale = {0.001, 0.001, 0.001};
  las.offset = {4.5e6, 5.2e6, 150.0};
  las.points = some_points(2000, 99);
  las.points[0].xyz = {std::numeric_limits<std::int32_t>::max(), std::numeric_limits<std::int32_t>::min(), 1};
  ReadNotes notes;
  const PointCloud cloud = write_and_read(folder, "geo.las", las.bytes(), notes);
  ASSERT_EQ(cloud.size(), las.points.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    for (std::size_t k = 0; k < 3; ++k) {
      const long double exact =
          static_cast<long double>(las.offset[k]) + static_cast<long double>(las.points[i].xyz[k]) / 1000.0L;
      const double read = cloud.positions[i][static_cast<Eigen::Index>(k)];
      ASSERT_LT(std::fabs(static_cast<long double>(read) - exact), 1e-6L) << "point " << i << ", axis " << k;
      // The millimetre reads back exactly.
      ASSERT_EQ(std::llround((read - las.offset[k]) * 1000.0), las.points[i].xyz[k]) << "point " << i;
    }
  }
}

TEST(LasReader, ColoursOfEightBitsAreTakenAsTheyAre) {
  TempFolder folder;
  LasFile las;
  las.format = 2;
  las.points = some_points(20, 7);
  for (LasPoint& p : las.points) {
    for (std::uint16_t& c : p.rgb) c = static_cast<std::uint16_t>(c % 256);
  }
  las.points[3].rgb = {255, 0, 128};
  ReadNotes notes;
  const PointCloud cloud = write_and_read(folder, "c8.las", las.bytes(), notes);
  ASSERT_TRUE(cloud.has_colors());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Rgb16& rgb = las.points[i].rgb;
    EXPECT_EQ(cloud.colors[i], (Color{static_cast<std::uint8_t>(rgb[0]), static_cast<std::uint8_t>(rgb[1]),
                                      static_cast<std::uint8_t>(rgb[2])}));
  }
  expect_one_note(notes, {"all 0 to 255", "as they are"});
}

TEST(LasReader, ColoursOfSixteenBitsKeepTheirHighByte) {
  TempFolder folder;
  LasFile las;
  las.minor = 4;
  las.format = 7;
  las.points = some_points(3, 8);
  las.points[0].rgb = {65535, 256, 255};  // one value above 255 decides for the whole file
  las.points[1].rgb = {0, 32768, 511};
  las.points[2].rgb = {100, 200, 300};
  ReadNotes notes;
  const PointCloud cloud = write_and_read(folder, "c16.las", las.bytes(), notes);
  ASSERT_EQ(cloud.colors.size(), 3U);
  EXPECT_EQ(cloud.colors[0], (Color{255, 1, 0}));
  EXPECT_EQ(cloud.colors[1], (Color{0, 128, 1}));
  EXPECT_EQ(cloud.colors[2], (Color{0, 0, 1}));
  expect_one_note(notes, {"up to 65535", "high byte"});
}

TEST(LasReader, SkipInvalidLeavesOutPointsBeyondTheBound) {
  // A scale that sends some points beyond +-1e15: refused, or left out with skip_invalid
  // (their colours with them).
  TempFolder folder;
  LasFile las;
  las.format = 3;
  las.scale = {1e9, 1.0, 1.0};
  las.points = some_points(6, 1);
  for (std::size_t i = 0; i < las.points.size(); ++i) {
    las.points[i].xyz[0] = (i == 2 || i == 4) ? 2'000'000 : static_cast<std::int32_t>(i);
    las.points[i].rgb = {static_cast<std::uint16_t>(i), 0, 0};
  }
  write_file(folder / "s.las", las.bytes());
  const std::size_t third_record = 227 + 2 * 34;
  EXPECT_EQ(point_read_error(folder / "s.las"),
            (folder / "s.las").string() +
                ": 2 points have a coordinate that is not finite or beyond +-1e+15; the "
                "first at byte " +
                std::to_string(third_record) + " (x = 2e+15)");
  ReadNotes notes;
  const PointCloud cloud = read_with_notes(folder / "s.las", notes, true);
  ASSERT_EQ(cloud.size(), 4U);
  EXPECT_EQ(notes.skipped_points, 2U);
  const std::vector<std::uint8_t> kept_reds = {0, 1, 3, 5};
  for (std::size_t i = 0; i < cloud.size(); ++i) EXPECT_EQ(cloud.colors[i][0], kept_reds[i]);
  ASSERT_EQ(notes.lines.size(), 2U);  // the colours, and what was skipped
  EXPECT_EQ(notes.lines[1],
            "skipped as invalid: 2 points have a coordinate that is not finite or beyond +-1e+15; "
            "the first at byte " +
                std::to_string(third_record) + " (x = 2e+15)");
}

// --------------------------------------------------------------------------
// LAZ

TEST(LasReader, LazIsRefusedNamingToolsThatDecompressIt) {
  TempFolder folder;
  LasFile las;
  las.points = some_points(2, 2);
  write_file(folder / "scan.laz", las.bytes());
  for (const auto& options : {ReadPointsOptions{}, as_format(PointFormat::laz)}) {
    const std::string message =
        message_of<InvalidInputError>([&] { static_cast<void>(read_points(folder / "scan.laz", options)); });
    EXPECT_CONTAINS(message, (folder / "scan.laz").string() + ": LAZ (compressed LAS) is not read");
    EXPECT_CONTAINS(message, "laszip -i IN -o out.las");
    EXPECT_EQ(occurrences(message, "scan.laz"), 1U) << message;
    EXPECT_CONTAINS(message, "pdal translate");
    EXPECT_CONTAINS(message, "las2las");
  }
  EXPECT_EQ(point_format_from_path("a.LAZ"), PointFormat::laz);
  EXPECT_EQ(point_format_from_name("laz"), PointFormat::laz);

  // LAS content with laszip's compression bit (7, or 6 for the 1.4 formats), whatever its name.
  for (const std::uint8_t bit : {std::uint8_t{0x80}, std::uint8_t{0x40}}) {
    las.format_byte_bits = bit;
    write_file(folder / "named.las", las.bytes());
    const std::string message = point_read_error(folder / "named.las");
    EXPECT_CONTAINS(message, "named.las: byte 104: ");
    EXPECT_CONTAINS(message, "LAZ (compressed LAS) is not read");
    EXPECT_CONTAINS(message, "laszip -i ");
    EXPECT_EQ(occurrences(message, "named.las"), 1U) << message;
  }
}

TEST(LasReader, FormatByteWithTheHighBitsOverNoValidFormatIsNotCalledLaz) {
  // 255 has bits 7 and 6 set, but its low bits (63) are no point format:
  // the byte is bad, not compressed. 0x8B: bit 7 over 11, not a format either.
  TempFolder folder;
  LasFile las;
  las.points = some_points(2, 2);
  for (const std::uint8_t bits : {std::uint8_t{0xFF}, std::uint8_t{0x8B}}) {
    las.format_byte_bits = bits;
    write_file(folder / "odd.las", las.bytes());
    const std::string message = point_read_error(folder / "odd.las");
    EXPECT_CONTAINS(message, "odd.las: byte 104: point data record format " + std::to_string(bits) + " is not known");
    EXPECT_EQ(message.find("compressed"), std::string::npos) << message;
    EXPECT_EQ(occurrences(message, "odd.las"), 1U) << message;
  }
}

// --------------------------------------------------------------------------
// Bad files

struct BadLas {
  std::string name;
  std::string content;
  std::string where;  ///< ": byte N: " or ": "
  std::string what;
};

/// A file with one value of the header replaced.
template <typename T>
std::string patched(std::string content, std::size_t at, T value) {
  Bytes b;
  b.put(value);
  content.replace(at, sizeof(T), b.str());
  return content;
}

TEST(LasReader, BadFiles) {
  LasFile las;
  las.format = 1;
  las.points = some_points(3, 5);
  const std::string good = las.bytes();  // 227-byte header, records of 28 bytes
  LasFile las14;
  las14.minor = 4;
  las14.format = 6;
  las14.points = some_points(3, 6);
  const std::string good14 = las14.bytes();
  const double nan = std::numeric_limits<double>::quiet_NaN();

  const std::vector<BadLas> cases = {
      {"signature", "LASX" + good.substr(4), ": byte 0: ", "not a LAS file: it starts with 'LASX', not 'LASF'"},
      {"ply", "ply\nformat ascii 1.0\n", ": byte 0: ", "not a LAS file"},
      {"short header", good.substr(0, 200), ": byte 200: ", "the file ends inside the LAS header"},
      {"version 1.5", patched<std::uint8_t>(good, 25, 5), ": byte 24: ", "LAS version 1.5 is not known"},
      {"version 2.0", patched<std::uint8_t>(patched<std::uint8_t>(good, 24, 2), 25, 0),
       ": byte 24: ", "LAS version 2.0 is not known: recon reads LAS 1.0 to 1.4"},
      {"format 11", patched<std::uint8_t>(good, 104, 11),
       ": byte 104: ", "point data record format 11 is not known (LAS defines 0 to 10)"},
      {"record too short", patched<std::uint16_t>(good, 105, 27),
       ": byte 105: ", "point records of 27 bytes are shorter than the 28 bytes of point format 1"},
      {"header size", patched<std::uint16_t>(good, 94, 200),
       ": byte 94: ", "the header size 200 is smaller than the 227 bytes of a LAS 1.2 header"},
      {"1.4 header size", patched<std::uint16_t>(good14, 94, 235),
       ": byte 94: ", "smaller than the 375 bytes of a LAS 1.4 header"},
      {"offset inside header", patched<std::uint32_t>(good, 96, 100),
       ": byte 96: ", "the point data would start at byte 100, inside the 227-byte header"},
      {"offset beyond file", patched<std::uint32_t>(good, 96, 5000),
       ": byte 96: ", "beyond the end of the file (311 bytes)"},
      {"truncated", good.substr(0, good.size() - 5), ": byte " + std::to_string(227 + 2 * 28) + ": ",
       "the header promises 3 points of 28 bytes from byte 227, but the file holds only 2 whole points"},
      // A count far beyond the file: refused before anything is sized by it.
      {"huge count", patched<std::uint32_t>(good, 107, 4'000'000'000U), ": byte " + std::to_string(227 + 3 * 28) + ": ",
       "the header promises 4000000000 points"},
      {"huge 64-bit count", patched<std::uint64_t>(patched<std::uint32_t>(good14, 107, 0), 247, 1ULL << 60),
       ": byte " + std::to_string(375 + 3 * 30) + ": ", "the header promises 1152921504606846976 points"},
      {"counts differ", patched<std::uint32_t>(good14, 107, 2),
       ": byte 247: ", "the point count 3 differs from the legacy point count 2 at byte 107"},
      {"no points", patched<std::uint32_t>(good, 107, 0), ": ", "no points: the header declares 0 points"},
      {"zero scale", patched<double>(good, 139, 0.0),
       ": byte 139: ", "the y scale factor is 0: it must be a finite number other than 0"},
      {"nan scale", patched<double>(good, 147, nan), ": byte 147: ", "the z scale factor is nan"},
      {"nan offset", patched<double>(good, 155, nan), ": byte 155: ", "the x offset is not a finite number"},
  };
  TempFolder folder;
  for (const BadLas& c : cases) {
    SCOPED_TRACE(c.name);
    const std::filesystem::path path = folder / "bad.las";
    write_file(path, c.content);
    EXPECT_EQ(point_read_error(path).substr(0, path.string().size() + c.where.size()), path.string() + c.where);
    EXPECT_CONTAINS(point_read_error(path), c.what);
  }
}

}  // namespace
}  // namespace recon::io
