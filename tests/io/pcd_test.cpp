// The PCD reader's DATA binary_compressed, colours and NaN rules. The LZF
// streams come from a small compressor written here (with real
// back-references, and a literals-only one), and one file from a second,
// independent implementation: Open3D's writer (the file is committed in the
// fuzz corpus; how it was made is said below).

#include "recon/io/point_io.h"

#include "io/io_test_helpers.h"
#include "recon/core/errors.h"

#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace recon::io {
namespace {

using namespace testing;  // io_test_helpers.h

// --------------------------------------------------------------------------
// A test-side LZF compressor

/// LZF's items (see liblzf): a literal run is a byte n - 1 (n = 1..32) and
/// n bytes; a back-reference of length L (3..264) at distance D (1..8192)
/// is a byte ((L - 2) << 5 | (D - 1) >> 8) when L - 2 < 7, else
/// (7 << 5 | (D - 1) >> 8) followed by L - 9, and then the byte (D - 1) & 255.
class LzfWriter {
 public:
  void literal(std::string_view bytes) {
    for (std::size_t at = 0; at < bytes.size(); at += 32) {
      const std::string_view run = bytes.substr(at, 32);
      out_ += static_cast<char>(run.size() - 1);
      out_ += run;
    }
  }
  void reference(std::size_t length, std::size_t distance) {
    const std::size_t l = length - 2;
    const std::size_t d = distance - 1;
    if (l < 7) {
      out_ += static_cast<char>((l << 5) | (d >> 8));
    } else {
      out_ += static_cast<char>((7 << 5) | (d >> 8));
      out_ += static_cast<char>(l - 7);
    }
    out_ += static_cast<char>(d & 255);
  }
  [[nodiscard]] const std::string& str() const { return out_; }

 private:
  std::string out_;
};

/// Greedy LZF: at each byte, the longest match among the last places its
/// first three bytes were seen (within 8192 bytes back), else a literal.
std::string lzf_compress(std::string_view data) {
  LzfWriter writer;
  std::unordered_map<std::uint32_t, std::size_t> last_seen;
  const auto key = [&](std::size_t i) {
    return static_cast<std::uint32_t>(static_cast<unsigned char>(data[i])) << 16 |
           static_cast<std::uint32_t>(static_cast<unsigned char>(data[i + 1])) << 8 |
           static_cast<unsigned char>(data[i + 2]);
  };
  std::size_t literal_start = 0;
  std::size_t i = 0;
  while (i + 3 <= data.size()) {
    const auto seen = last_seen.find(key(i));
    const std::size_t match = seen != last_seen.end() ? seen->second : i;
    std::size_t length = 0;
    if (match < i && i - match <= 8192) {
      while (i + length < data.size() && length < 264 && data[match + length] == data[i + length]) ++length;
    }
    last_seen[key(i)] = i;
    if (length < 3) {
      ++i;
      continue;
    }
    writer.literal(data.substr(literal_start, i - literal_start));
    writer.reference(length, i - match);
    i += length;
    literal_start = i;
  }
  writer.literal(data.substr(literal_start));
  return writer.str();
}

/// Only literal runs: a valid stream with no back-reference.
std::string lzf_literals(std::string_view data) {
  LzfWriter writer;
  writer.literal(data);
  return writer.str();
}

/// Whether a stream has a back-reference (walking its items).
bool has_back_reference(std::string_view stream) {
  for (std::size_t i = 0; i < stream.size();) {
    const auto control = static_cast<unsigned char>(stream[i]);
    if (control >= 32) return true;
    i += control + 2U;
  }
  return false;
}

// --------------------------------------------------------------------------
// PCD files written here

/// A field of a test file: its name, TYPE, SIZE and each point's value.
struct Column {
  explicit Column(std::string field, char field_type = 'F', std::size_t field_size = 4,
                  std::vector<double> field_values = {})
      : name(std::move(field)), type(field_type), size(field_size), values(std::move(field_values)) {}
  std::string name;
  char type;
  std::size_t size;
  std::vector<double> values;
  std::vector<std::uint32_t> bits;  ///< raw 32-bit values instead (packed colours); empty: use values
};

void put_value(Bytes& out, const Column& c, std::size_t i) {
  if (!c.bits.empty()) {
    out.put(c.bits[i]);
    return;
  }
  const double v = c.values[i];
  if (c.type == 'F') {
    if (c.size == 4)
      out.put(static_cast<float>(v));
    else
      out.put(v);
  } else if (c.type == 'U') {
    if (c.size == 1)
      out.put(static_cast<std::uint8_t>(v));
    else if (c.size == 2)
      out.put(static_cast<std::uint16_t>(v));
    else
      out.put(static_cast<std::uint32_t>(v));
  } else {
    out.put(static_cast<std::int32_t>(v));
  }
}

std::string pcd_header(const std::vector<Column>& columns, std::size_t width, std::size_t height,
                       std::string_view data) {
  std::string names, sizes, types;
  for (const Column& c : columns) {
    names += " " + c.name;
    sizes += " " + std::to_string(c.size);
    types += std::string(" ") + c.type;
  }
  return "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS" + names + "\nSIZE" + sizes + "\nTYPE" +
         types + "\nWIDTH " + std::to_string(width) + "\nHEIGHT " + std::to_string(height) +
         "\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " + std::to_string(width * height) + "\nDATA " + std::string(data) + "\n";
}

/// The uncompressed binary_compressed payload: every field's values in turn,
/// padding fields "_" left out (as PCL writes them).
std::string column_bytes(const std::vector<Column>& columns, std::size_t n) {
  Bytes out;
  for (const Column& c : columns) {
    if (c.name == "_") continue;
    for (std::size_t i = 0; i < n; ++i) put_value(out, c, i);
  }
  return out.str();
}

std::string compressed_pcd(const std::vector<Column>& columns, std::size_t width, std::size_t height,
                           bool literals_only = false) {
  const std::string raw = column_bytes(columns, width * height);
  const std::string stream = literals_only ? lzf_literals(raw) : lzf_compress(raw);
  Bytes out;
  out.text(pcd_header(columns, width, height, "binary_compressed"));
  out.put(static_cast<std::uint32_t>(stream.size())).put(static_cast<std::uint32_t>(raw.size()));
  return out.str() + stream;
}

std::string binary_pcd(const std::vector<Column>& columns, std::size_t width, std::size_t height) {
  Bytes out;
  out.text(pcd_header(columns, width, height, "binary"));
  for (std::size_t i = 0; i < width * height; ++i) {
    for (const Column& c : columns) put_value(out, c, i);
  }
  return out.str();
}

std::uint32_t packed(const Color& c) { return std::uint32_t{c[0]} << 16 | std::uint32_t{c[1]} << 8 | c[2]; }

/// A cloud with normals and colours, and the fields of a PCL
/// PointXYZRGBNormal-like file holding it (curvature and a padding field
/// beside the ones recon reads).
struct TestCloud {
  PointCloud cloud;
  std::vector<Column> columns;
};

TestCloud test_cloud(std::size_t n) {
  TestCloud t;
  const PointCloud random = testing::random_cloud(n, true, 11);
  for (const char* name : {"x", "y", "z", "rgb"}) t.columns.emplace_back(name);
  t.columns.emplace_back("_", 'U', 4);
  for (const char* name : {"normal_x", "normal_y", "normal_z", "curvature"}) t.columns.emplace_back(name);
  for (std::size_t i = 0; i < n; ++i) {
    // float32 values, so that they read back exactly; a repeating pattern for the compressor
    const Vec3 p(0.5 * static_cast<double>(i % 10), 0.25 * static_cast<double>(i / 10), static_cast<double>(i % 3));
    Vec3 normal;  // rounded to float, as the file holds it
    for (int k = 0; k < 3; ++k) normal[k] = static_cast<double>(static_cast<float>(random.normals[i][k]));
    const Color color = {static_cast<std::uint8_t>(i * 7), static_cast<std::uint8_t>(255 - i), 200};
    t.cloud.positions.push_back(p);
    t.cloud.normals.push_back(normal);
    t.cloud.colors.push_back(color);
    for (int k = 0; k < 3; ++k) t.columns[static_cast<std::size_t>(k)].values.push_back(p[k]);
    t.columns[3].bits.push_back(packed(color) | 0xFF000000U);  // PCL's alpha byte, which is not a colour
    t.columns[4].values.push_back(9);
    for (int k = 0; k < 3; ++k) t.columns[5 + static_cast<std::size_t>(k)].values.push_back(normal[k]);
    t.columns[8].values.push_back(0.125 * static_cast<double>(i));
  }
  return t;
}

void expect_same(const PointCloud& expected, const PointCloud& actual) {
  ASSERT_EQ(actual.size(), expected.size());
  ASSERT_EQ(actual.normals.size(), expected.normals.size());
  ASSERT_EQ(actual.colors.size(), expected.colors.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(actual.positions[i], expected.positions[i]) << "point " << i;
    if (expected.has_normals()) {
      EXPECT_EQ(actual.normals[i], expected.normals[i]) << "point " << i;
    }
    if (expected.has_colors()) {
      EXPECT_EQ(actual.colors[i], expected.colors[i]) << "point " << i;
    }
  }
}

// --------------------------------------------------------------------------
// DATA binary_compressed

TEST(PcdCompressed, ReadsTheSameCloudAsBinary) {
  TempFolder folder;
  const TestCloud t = test_cloud(300);
  const std::string compressed = compressed_pcd(t.columns, 300, 1);
  const std::string stream = compressed.substr(pcd_header(t.columns, 300, 1, "binary_compressed").size() + 8);
  ASSERT_TRUE(has_back_reference(stream));
  ASSERT_LT(stream.size(), column_bytes(t.columns, 300).size());  // it did compress (the normals are random)
  write_file(folder / "c.pcd", compressed);
  write_file(folder / "b.pcd", binary_pcd(t.columns, 300, 1));
  ReadNotes notes;
  expect_same(t.cloud, read_with_notes(folder / "c.pcd", notes));
  EXPECT_TRUE(notes.lines.empty());
  expect_same(t.cloud, read_points(folder / "b.pcd"));
}

TEST(PcdCompressed, LiteralsOnly) {
  TempFolder folder;
  const TestCloud t = test_cloud(50);
  write_file(folder / "l.pcd", compressed_pcd(t.columns, 50, 1, true));
  expect_same(t.cloud, read_points(folder / "l.pcd"));
}

TEST(PcdCompressed, LongAndOverlappingBackReferences) {
  // One x value repeated: the compressor writes references of up to 264
  // bytes at distance 4, each overlapping what it writes.
  TempFolder folder;
  std::vector<Column> columns = {Column("x"), Column("y", 'F', 8), Column("z", 'U', 2)};
  const std::size_t n = 1000;
  for (std::size_t i = 0; i < n; ++i) {
    columns[0].values.push_back(1.5);
    columns[1].values.push_back(static_cast<double>(i / 100));
    columns[2].values.push_back(static_cast<double>(i % 4));
  }
  const std::string raw = column_bytes(columns, n);
  EXPECT_LT(lzf_compress(raw).size(), raw.size() / 20);
  write_file(folder / "r.pcd", compressed_pcd(columns, n, 1));
  const PointCloud cloud = read_points(folder / "r.pcd");
  ASSERT_EQ(cloud.size(), n);
  for (std::size_t i = 0; i < n; ++i)
    ASSERT_EQ(cloud.positions[i], Vec3(1.5, static_cast<double>(i / 100), static_cast<double>(i % 4))) << i;
}

TEST(PcdCompressed, WrittenByOpen3D) {
  // fuzz/corpus/pcd_points/open3d_binary_compressed.pcd, written by Open3D
  // 0.16 (python3-open3d) with
  //   i = numpy.arange(40)
  //   points: (0.5 i, 0.25 (i mod 7) - 1, 3 - 0.125 i); normals (0, 0, 1);
  //   colours (6i mod 256, (255 - 5i) mod 256, 37i mod 256) / 255
  //   open3d.io.write_point_cloud(path, cloud, write_ascii=False, compressed=True)
  // Its fields: x y z normal_x normal_y normal_z rgb, all F 4.
  const std::filesystem::path path =
      std::filesystem::path(RECON_FUZZ_CORPUS_DIR) / "pcd_points" / "open3d_binary_compressed.pcd";
  ReadNotes notes;
  const PointCloud cloud = read_with_notes(path, notes);
  ASSERT_EQ(cloud.size(), 40U);
  ASSERT_EQ(cloud.normals.size(), 40U);
  ASSERT_EQ(cloud.colors.size(), 40U);
  EXPECT_TRUE(notes.lines.empty());
  for (std::size_t k = 0; k < 40; ++k) {
    const auto i = static_cast<double>(k);
    EXPECT_EQ(cloud.positions[k], Vec3(0.5 * i, 0.25 * static_cast<double>(k % 7) - 1.0, 3.0 - 0.125 * i)) << k;
    EXPECT_EQ(cloud.normals[k], Vec3(0, 0, 1)) << k;
    const Color expected = {static_cast<std::uint8_t>(k * 6 % 256), static_cast<std::uint8_t>((255 - 5 * k) % 256),
                            static_cast<std::uint8_t>(k * 37 % 256)};
    EXPECT_EQ(cloud.colors[k], expected) << k;
  }
}

TEST(PcdCompressed, BadData) {
  TempFolder folder;
  const std::vector<Column> columns = {Column("x", 'F', 4, {1, 2}), Column("y", 'F', 4, {3, 4}),
                                       Column("z", 'F', 4, {5, 6})};
  const std::vector<Column> million = {Column("x"), Column("y"), Column("z")};
  const std::string header = pcd_header(columns, 2, 1, "binary_compressed");
  const std::size_t data = header.size();
  const std::string raw = column_bytes(columns, 2);  // 24 bytes
  const auto sizes = [](std::size_t compressed, std::size_t uncompressed) {
    Bytes b;
    b.put(static_cast<std::uint32_t>(compressed)).put(static_cast<std::uint32_t>(uncompressed));
    return b.str();
  };
  const std::string literal = lzf_literals(raw);  // 25 bytes: one run
  struct Case {
    std::string name;
    std::string content;
    std::size_t byte;
    std::string what;
  };
  const std::vector<Case> cases = {
      {"no sizes", header + "abc", data, "the file ends before the two sizes"},
      {"wrong uncompressed size", header + sizes(25, 28) + literal, data + 4,
       "the uncompressed size 28 is not 2 points of 12 bytes"},
      {"compressed size beyond the file", header + sizes(26, 24) + literal, data,
       "the compressed size 26 goes beyond the end of the file (25 bytes after the sizes)"},
      {"more than LZF can expand to",
       pcd_header(million, 1'000'000, 1, "binary_compressed") + sizes(2, 12'000'000) + "ab",
       pcd_header(million, 1'000'000, 1, "binary_compressed").size() + 4,
       "2 compressed bytes cannot become the 12000000 bytes"},
      {"truncated literal", header + sizes(20, 24) + literal.substr(0, 20), data + 8,
       "bad LZF data: a literal run of 24 bytes is cut off by the end of the data"},
      // A literal 'a', then a reference of 3 bytes cut off before its distance byte, or 6 bytes back.
      {"truncated reference", header + sizes(3, 24) + std::string{'\0', 'a', '\x20'}, data + 8 + 2,
       "a back-reference is cut off"},
      {"reference before the start", header + sizes(4, 24) + std::string{'\0', 'a', '\x20', '\x05'}, data + 8 + 2,
       "a back-reference 6 bytes back reaches before the start of the decompressed data (at its byte 1)"},
      {"output overrun", header + sizes(27, 24) + literal + std::string{'\x20', '\0'}, data + 8 + 25,
       "a back-reference goes beyond the 24 bytes of decompressed data"},
      {"decompresses short", header + sizes(21, 24) + std::string(1, '\x13') + raw.substr(0, 20), data + 8 + 21,
       "the data decompresses to 20 bytes, not the 24 the header gives"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    write_file(folder / "bad.pcd", c.content);
    const std::string message = point_read_error(folder / "bad.pcd");
    EXPECT_CONTAINS(message, (folder / "bad.pcd").string() + ": byte " + std::to_string(c.byte) + ": ");
    EXPECT_CONTAINS(message, c.what);
  }
}

// --------------------------------------------------------------------------
// Colours

TEST(PcdColours, RgbAsPclWritesItInAsciiAndBinary) {
  TempFolder folder;
  const Color orange = {255, 128, 0};
  const std::uint32_t bits = packed(orange) | 0xFF000000U;  // alpha 255: as a float, a NaN
  const auto as_float = std::bit_cast<float>(packed(orange));
  // ascii: PCL writes a float rgb as the integer of its bits; older writers wrote the float.
  char float_text[64];
  std::snprintf(float_text, sizeof float_text, "%.9g", static_cast<double>(as_float));
  write_file(folder / "a.pcd", "FIELDS x y z rgb\nSIZE 4 4 4 4\nTYPE F F F F\nPOINTS 2\nDATA ascii\n1 2 3 " +
                                   std::to_string(bits) + "\n4 5 6 " + float_text + "\n");
  const PointCloud ascii = read_points(folder / "a.pcd");
  ASSERT_EQ(ascii.colors.size(), 2U);
  EXPECT_EQ(ascii.colors[0], orange);
  EXPECT_EQ(ascii.colors[1], orange);

  // rgba as an unsigned integer field; an 8-byte rgb is no packed colour and is skipped.
  write_file(folder / "u.pcd", "FIELDS x y z rgba\nSIZE 4 4 4 4\nTYPE F F F U\nPOINTS 1\nDATA ascii\n1 2 3 " +
                                   std::to_string(bits) + "\n");
  EXPECT_EQ(read_points(folder / "u.pcd").colors, std::vector<Color>{orange});
  write_file(folder / "d.pcd", "FIELDS x y z rgb\nSIZE 4 4 4 8\nTYPE F F F F\nPOINTS 1\nDATA ascii\n1 2 3 7\n");
  EXPECT_FALSE(read_points(folder / "d.pcd").has_colors());

  // binary: the bits as they are, NaN pattern or not.
  std::vector<Column> columns = {Column("x", 'F', 4, {1}), Column("y", 'F', 4, {2}), Column("z", 'F', 4, {3}),
                                 Column("rgb")};
  columns[3].bits = {bits};
  write_file(folder / "b.pcd", binary_pcd(columns, 1, 1));
  EXPECT_EQ(read_points(folder / "b.pcd").colors, std::vector<Color>{orange});
}

TEST(PcdColours, AColourThatIsNotANumberDropsTheColours) {
  TempFolder folder;
  ReadNotes notes;
  const PointCloud cloud = write_and_read(folder, "n.pcd",
                                          "FIELDS x y z rgb\nSIZE 4 4 4 4\nTYPE F F F F\nPOINTS 3\nDATA ascii\n"
                                          "1 2 3 255\n1 2 4 nan\n1 2 5 nan\n",
                                          notes);
  EXPECT_EQ(cloud.size(), 3U);
  EXPECT_FALSE(cloud.has_colors());
  ASSERT_EQ(notes.lines.size(), 1U);
  EXPECT_EQ(notes.lines[0], "colours dropped: 2 points have no colour (not a number), the first at line 7");
}

// --------------------------------------------------------------------------
// NaN as "no value"

/// A 4 x 3 organized cloud (a depth image): row 1 has no return at all,
/// and one more pixel (row 2, column 2) has only its z missing.
std::vector<Column> organized_columns() {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<Column> columns = {Column("x"), Column("y"), Column("z")};
  for (std::size_t row = 0; row < 3; ++row) {
    for (std::size_t column = 0; column < 4; ++column) {
      const bool hole = row == 1 || (row == 2 && column == 2);
      columns[0].values.push_back(row == 1 ? nan : static_cast<double>(column));
      columns[1].values.push_back(row == 1 ? nan : static_cast<double>(row));
      columns[2].values.push_back(hole ? nan : 1.0);
    }
  }
  return columns;
}

TEST(PcdNaN, OrganizedCloudsSkipPointsWithoutPosition) {
  TempFolder folder;
  const std::vector<Column> columns = organized_columns();
  std::string ascii = pcd_header(columns, 4, 3, "ascii");
  for (std::size_t i = 0; i < 12; ++i) {
    for (const Column& c : columns)
      ascii += (std::isnan(c.values[i]) ? std::string("nan") : std::to_string(c.values[i])) + " ";
    ascii += "\n";
  }
  const std::string binary = binary_pcd(columns, 4, 3);
  const std::size_t binary_data = pcd_header(columns, 4, 3, "binary").size();
  const std::pair<std::string, std::string> files[] = {
      {ascii, "line 15 (row 1, column 0)"},  // the header takes 10 lines: point 4 is on line 15
      {binary, "byte " + std::to_string(binary_data + 4 * 12) + " (row 1, column 0)"},
      {compressed_pcd(columns, 4, 3), "point 4 (row 1, column 0)"},
  };
  for (const auto& [content, first] : files) {
    ReadNotes notes;
    const PointCloud cloud = write_and_read(folder, "o.pcd", content, notes);
    ASSERT_EQ(cloud.size(), 7U);
    EXPECT_EQ(cloud.positions[4], Vec3(0, 2, 1));
    EXPECT_EQ(cloud.positions[6], Vec3(3, 2, 1));  // after the skipped (row 2, column 2)
    EXPECT_EQ(notes.skipped_points, 5U);
    ASSERT_EQ(notes.lines.size(), 1U);
    EXPECT_EQ(notes.lines[0],
              "skipped 5 points with no position (NaN x y z in an organized cloud); the first at " + first);
  }
}

TEST(PcdNaN, UnorganizedCloudsSkipOnlyAllNaNPoints) {
  // HEIGHT 1: all three NaN is PCL's "no measurement" and skipped (said in a
  // note); a NaN in only some coordinates is a corrupt point, refused unless
  // skip_invalid.
  TempFolder folder;
  const std::string header = "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 4\nHEIGHT 1\nPOINTS 4\nDATA ascii\n";
  write_file(folder / "u.pcd", header + "1 1 1\nnan nan nan\n2 2 2\n3 nan 3\n");
  EXPECT_EQ(point_read_error(folder / "u.pcd"),
            (folder / "u.pcd").string() +
                ": 1 point has a coordinate that is not finite or beyond +-1e+15; the first at line 11 (y = nan)");
  ReadNotes notes;
  const PointCloud cloud = read_with_notes(folder / "u.pcd", notes, true);
  ASSERT_EQ(cloud.size(), 2U);
  EXPECT_EQ(cloud.positions[1], Vec3(2, 2, 2));
  EXPECT_EQ(notes.skipped_points, 2U);
  ASSERT_EQ(notes.lines.size(), 2U);
  EXPECT_EQ(notes.lines[0], "skipped 1 point with no position (NaN x y z); the first at line 9");
  EXPECT_EQ(notes.lines[1],
            "skipped as invalid: 1 point has a coordinate that is not finite or beyond +-1e+15; the first at line 11 "
            "(y = nan)");
  // Infinity is refused in an organized cloud too.
  write_file(folder / "i.pcd",
             "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2\nHEIGHT 2\nPOINTS 4\nDATA ascii\n"
             "1 1 1\nnan nan nan\n2 inf 2\n3 3 3\n");
  EXPECT_CONTAINS(point_read_error(folder / "i.pcd"),
                  "1 point has a coordinate that is not finite or beyond +-1e+15; "
                  "the first at line 10 (y = inf)");
}

TEST(PcdNaN, NaNNormalsAreDroppedNotRefused) {
  // As PCL's sac_plane_test.pcd: valid points, some with NaN normal and curvature
  // where PCL could not estimate one.
  TempFolder folder;
  const std::string header =
      "FIELDS x y z normal_x normal_y normal_z curvature\nSIZE 4 4 4 4 4 4 4\nTYPE F F F F F F F\n"
      "COUNT 1 1 1 1 1 1 1\nWIDTH 4\nHEIGHT 1\nPOINTS 4\nDATA ascii\n";
  ReadNotes notes;
  const PointCloud cloud = write_and_read(folder, "s.pcd",
                                          header +
                                              "1 2 3 0 0 1 0.5\n4 5 6 nan nan nan nan\n7 8 9 1 0 0 nan\n"
                                              "1 1 1 nan nan nan nan\n",
                                          notes);
  ASSERT_EQ(cloud.size(), 4U);
  EXPECT_FALSE(cloud.has_normals());
  EXPECT_EQ(notes.skipped_points, 0U);
  ASSERT_EQ(notes.lines.size(), 1U);
  EXPECT_EQ(notes.lines[0],
            "normals dropped: 2 points have no normal (NaN), the first at line 10; recon estimates its own");

  // A NaN curvature alone changes nothing; an infinite normal is still corrupt.
  write_file(folder / "c.pcd", header + "1 2 3 0 0 1 nan\n4 5 6 0 1 0 nan\n7 8 9 1 0 0 nan\n1 1 1 0 0 1 inf\n");
  ReadNotes quiet;
  EXPECT_TRUE(read_with_notes(folder / "c.pcd", quiet).has_normals());
  EXPECT_TRUE(quiet.lines.empty());
  write_file(folder / "f.pcd", header + "1 2 3 0 0 1 0\n4 5 6 0 inf 0 0\n7 8 9 1 0 0 0\n1 1 1 0 0 1 0\n");
  EXPECT_CONTAINS(point_read_error(folder / "f.pcd"),
                  "1 point has a normal that is not finite (NaN or infinity); the first at line 10 (normal_y = inf)");
}

TEST(PcdReader, AFieldNamedTwiceIsRefused) {
  // FIELDS x y z x: taking the first x would drop the second silently.
  expect_read_errors(
      "e.pcd",
      {
          {"FIELDS x y z x\nSIZE 4 4 4 4\nTYPE F F F F\nPOINTS 1\nDATA ascii\n1 2 3 4\n",
           "e.pcd:1:", "FIELDS names 'x' twice (fields 0 and 3)"},
          {"VERSION 0.7\nFIELDS x y z normal_x normal_x normal_z\nSIZE 4 4 4 4 4 4\nTYPE F F F F F F\nPOINTS 1\n"
           "DATA ascii\n1 2 3 0 0 1\n",
           "e.pcd:2:", "FIELDS names 'normal_x' twice"},
      });
  // Padding "_" may repeat, as PCL writes it.
  TempFolder folder;
  const PointCloud cloud = write_and_read(folder, "ok.pcd",
                                          "FIELDS x _ y _ z\nSIZE 4 4 4 4 4\nTYPE F F F F F\nPOINTS 1\nDATA ascii\n"
                                          "1 9 2 9 3\n");
  ASSERT_EQ(cloud.size(), 1U);
  EXPECT_EQ(cloud.positions[0], Vec3(1, 2, 3));
}

}  // namespace
}  // namespace recon::io
