// Delimited text (xyz, txt, csv, ...): separators, line ends, the
// byte-order mark, header lines, --columns (ReadPointsOptions::columns),
// columns told apart by their values, the notes that say what was chosen,
// and the errors. The basic xyz cases are in point_io_test.cpp.

#include "recon/io/curve_io.h"
#include "recon/io/point_io.h"
#include "recon/io/point_stream.h"

#include "io/io_test_helpers.h"
#include "recon/core/errors.h"
#include "test_data.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace recon::io {
namespace {

using namespace testing;  // io_test_helpers.h

/// A cloud read from text written to a fresh file, with the notes.
struct TextRead {
  PointCloud cloud;
  std::vector<std::string> notes;
};

TextRead read_text(const TempFolder& folder, const std::string& name, const std::string& content,
                   const std::vector<std::string>& columns = {}) {
  write_file(folder / name, content);
  ReadPointsOptions options;
  options.columns = columns;
  ReadNotes notes;
  TextRead result;
  result.cloud = read_points(folder / name, options, &notes);
  result.notes = notes.lines;
  return result;
}

/// The message of the error reading `content` as `name` throws (ParseError
/// unless E says otherwise).
template <typename E = ParseError>
std::string text_error(const TempFolder& folder, const std::string& name, const std::string& content,
                       const std::vector<std::string>& columns = {}) {
  write_file(folder / name, content);
  ReadPointsOptions options;
  options.columns = columns;
  return message_of<E>([&] { static_cast<void>(read_points(folder / name, options)); });
}

const std::vector<Vec3> corners = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};

void expect_corners(const PointCloud& cloud) {
  ASSERT_EQ(cloud.size(), 4U);
  for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(cloud.positions[i], corners[i]) << "point " << i;
}

// --------------------------------------------------------------------------
// The complaints of issue 17, one by one

TEST(PointIoTextColumns, CsvWithAHeaderLine) {
  TempFolder folder;
  const TextRead read = read_text(folder, "a.csv", "x,y,z\n0,0,0\n1,0,0\n0,1,0\n0,0,1\n");
  expect_corners(read.cloud);
  EXPECT_FALSE(read.cloud.has_normals());
  EXPECT_EQ(read.notes, std::vector<std::string>{"columns: x y z (from the header on line 1)"});
}

TEST(PointIoTextColumns, FourColumnsAreXyzAndAnIgnoredIntensity) {
  TempFolder folder;
  const TextRead read = read_text(folder, "a.xyz", "0 0 0 10\n1 0 0 20\n0 1 0 30.5\n0 0 1 -4\n");
  expect_corners(read.cloud);
  EXPECT_FALSE(read.cloud.has_normals());
  EXPECT_FALSE(read.cloud.has_colors());
  ASSERT_EQ(read.notes.size(), 1U);
  EXPECT_EQ(read.notes[0], "columns: x y z _ (no header; the 4th column, such as an intensity, is ignored)");
}

TEST(PointIoTextColumns, AByteOrderMarkIsSkipped) {
  TempFolder folder;
  expect_corners(read_text(folder, "a.xyz",
                           "\xEF\xBB\xBF"
                           "0 0 0\n1 0 0\n0 1 0\n0 0 1\n")
                     .cloud);
  const TextRead header = read_text(folder, "b.csv",
                                    "\xEF\xBB\xBF"
                                    "X,Y,Z\n0,0,0\n1,0,0\n0,1,0\n0,0,1\n");
  expect_corners(header.cloud);
  EXPECT_EQ(header.notes, std::vector<std::string>{"columns: x y z (from the header on line 1)"});
  // Line numbers are unchanged by it.
  EXPECT_CONTAINS(text_error(folder, "c.xyz",
                             "\xEF\xBB\xBF"
                             "0 0 0\n1 0 x\n"),
                  "c.xyz:2: expected a number for z");
}

TEST(PointIoTextColumns, SemicolonsSeparateAndCommasAreThenDecimalMarks) {
  TempFolder folder;
  expect_corners(read_text(folder, "a.csv", "x;y;z\n0;0;0\n1;0;0\n0;1;0\n0;0;1\n").cloud);
  const TextRead read = read_text(folder, "b.csv", "0,5;-1,25;3\n 2.5 ; 1e-3 ;-0,0\n");
  ASSERT_EQ(read.cloud.size(), 2U);
  EXPECT_EQ(read.cloud.positions[0], Vec3(0.5, -1.25, 3));
  EXPECT_EQ(read.cloud.positions[1], Vec3(2.5, 1e-3, -0.0));
  EXPECT_CONTAINS(text_error(folder, "c.csv", "1;2;3\n1;2;3,5,6\n"), "c.csv:2: expected a number for z, found '3,5,6'");
}

TEST(PointIoTextColumns, CarriageReturnsAloneEndLines) {
  TempFolder folder;
  const TextRead read = read_text(folder, "a.xyz", "# old Mac text\r0 0 0\r1 0 0\r\r0 1 0 # c\r0 0 1");
  expect_corners(read.cloud);
  EXPECT_CONTAINS(text_error(folder, "b.xyz", "0 0 0\r1 0 0\r1 2 abc\r"), "b.xyz:3: expected a number for z");
  // Mixed with "\r\n" and "\n", every one ends a line once.
  expect_corners(read_text(folder, "c.xyz", "0 0 0\r1 0 0\r\n0 1 0\n0 0 1\r").cloud);
}

TEST(PointIoTextColumns, ColoursAreNotReadAsNormals) {
  TempFolder folder;
  const TextRead read = read_text(folder, "a.xyz", "0 0 0 255 0 0\n1 0 0 0 255 0\n0 1 0 0 0 255\n0 0 1 10 20 30\n");
  expect_corners(read.cloud);
  EXPECT_FALSE(read.cloud.has_normals());
  ASSERT_TRUE(read.cloud.has_colors());
  EXPECT_EQ(read.cloud.colors[0], (Color{255, 0, 0}));
  EXPECT_EQ(read.cloud.colors[3], (Color{10, 20, 30}));
  EXPECT_EQ(read.notes,
            std::vector<std::string>{"columns: x y z r g b (no header; the last three are integers 0-255: colours)"});
}

// --------------------------------------------------------------------------
// Headers

TEST(PointIoTextColumns, CloudCompareHeaderWithCrLf) {
  TempFolder folder;
  const TextRead read =
      read_text(folder, "a.txt", "//X,Y,Z,R,G,B\r\n0,0,0,255,0,0\r\n1,0,0,0,255,0\r\n0,1,0,0,0,255\r\n0,0,1,1,2,3\r\n");
  expect_corners(read.cloud);
  ASSERT_TRUE(read.cloud.has_colors());
  EXPECT_EQ(read.cloud.colors[3], (Color{1, 2, 3}));
  EXPECT_EQ(read.notes,
            std::vector<std::string>{"columns: x y z r g b (from the header on line 1; colours: integers 0-255)"});
}

TEST(PointIoTextColumns, HeaderNamesInAnyCaseOrderAndSpelling) {
  TempFolder folder;
  const TextRead read = read_text(folder, "a.csv",
                                  "# exported\n\"Nx\";Intensity;Z;Y;X;normal_y;NZ;scalar_Time;Red;GREEN;blue\n"
                                  "0;7;3;2;1;1;0;5;0,5;0;1\n1;7;6;5;4;0;0;5;1;0,25;0\n");
  ASSERT_EQ(read.cloud.size(), 2U);
  EXPECT_EQ(read.cloud.positions[0], Vec3(1, 2, 3));
  EXPECT_EQ(read.cloud.positions[1], Vec3(4, 5, 6));
  ASSERT_TRUE(read.cloud.has_normals());
  EXPECT_EQ(read.cloud.normals[0], Vec3(0, 1, 0));
  EXPECT_EQ(read.cloud.normals[1], Vec3(1, 0, 0));
  ASSERT_TRUE(read.cloud.has_colors());
  EXPECT_EQ(read.cloud.colors[0], (Color{128, 0, 255}));  // 0.5 * 255 = 127.5, rounded away from zero
  EXPECT_EQ(read.cloud.colors[1], (Color{255, 64, 0}));
  EXPECT_EQ(read.notes, std::vector<std::string>{
                            "columns: nx _ z y x ny nz _ r g b (from the header on line 2; colours: fractions 0-1, "
                            "scaled to 0-255; ignored: Intensity, scalar_Time)"});
}

TEST(PointIoTextColumns, NormalsAndColoursNeedAllThreeNamed) {
  TempFolder folder;
  const TextRead read = read_text(folder, "a.txt", "x y z nx ny r g\n0 0 0 1 0 5 5\n1 0 0 1 0 5 5\n");
  EXPECT_FALSE(read.cloud.has_normals());
  EXPECT_FALSE(read.cloud.has_colors());
  ASSERT_EQ(read.notes.size(), 1U);
  EXPECT_CONTAINS(read.notes[0], "columns: x y z _ _ _ _ (from the header on line 1");
  EXPECT_CONTAINS(read.notes[0], "nx ny ignored: normals need all three");
  EXPECT_CONTAINS(read.notes[0], "r g ignored: colours need all three");
}

TEST(PointIoTextColumns, NamedNormalsMayHaveAnyLength) {
  TempFolder folder;
  const TextRead read = read_text(folder, "a.xyz", "x y z nx ny nz\n0 0 0 0 0 2\n1 0 0 0.1 0 0\n");
  ASSERT_TRUE(read.cloud.has_normals());
  EXPECT_EQ(read.cloud.normals[0], Vec3(0, 0, 2));
}

TEST(PointIoTextColumns, HeaderErrors) {
  TempFolder folder;
  std::string message = text_error(folder, "a.csv", "lat,lon,alt\n1,2,3\n");
  EXPECT_CONTAINS(message, "a.csv:1: the header line names no x, y and z column (it holds 'lat', 'lon', 'alt')");
  EXPECT_CONTAINS(message, "--columns");
  EXPECT_CONTAINS(text_error(folder, "b.csv", "x,y,z,X\n1,2,3,4\n"),
                  "b.csv:1: the header line names x twice (columns 1 and 4)");
  EXPECT_CONTAINS(text_error(folder, "c.csv", "x,y,z\n1,2,3\n1,2,3,4\n"),
                  "c.csv:3: the header on line 1 names 3 columns, but this line has 4");
  EXPECT_CONTAINS(text_error(folder, "d.csv", "x,y,z\n# nothing else\n"),
                  "d.csv: no points: the file holds only a header line, comments and blank lines");
  // A second line of names is data that is not numbers.
  EXPECT_CONTAINS(text_error(folder, "e.csv", "x,y,z\nX,Y,Z\n"), "e.csv:2: expected a number for x, found 'X'");
}

TEST(PointIoTextColumns, ColourValuesOutOfRangeAreErrorsWithTheLine) {
  TempFolder folder;
  const std::string header = "x y z red green blue\n";
  EXPECT_CONTAINS(text_error(folder, "a.xyz", header + "0 0 0 1 2 3\n0 0 0 1 2 300\n"),
                  "a.xyz:3: colour value out of range: 300 for b is neither an integer 0 to 255 nor a fraction 0 to 1");
  EXPECT_CONTAINS(text_error(folder, "b.xyz", header + "0 0 0 1 2 3\n0 0 0 -1 2 3\n"),
                  "b.xyz:3: colour value out of range: -1 for r");
  EXPECT_CONTAINS(text_error(folder, "c.xyz", header + "0 0 0 0.5 0 0\n0 0 0 1 1 1\n0 0 0 0 200 0\n"),
                  "c.xyz:4: colour value out of range: 200 for g is above 1, but line 2 has a fraction (0.5 for r)");
  EXPECT_CONTAINS(text_error(folder, "d.xyz", header + "0 0 0 127.5 0 0\n"),
                  "d.xyz:2: colour value out of range: 127.5 for r");
  EXPECT_CONTAINS(text_error(folder, "e.xyz", header + "0 0 0 nan 0 0\n"),
                  "e.xyz:2: colour value out of range: nan for r");
}

TEST(PointIoTextColumns, ZerosAndOnesAreFractions) {
  TempFolder folder;
  const TextRead read = read_text(folder, "a.xyz", "x y z r g b\n0 0 0 1 0 1\n1 1 1 0 0 0\n");
  ASSERT_TRUE(read.cloud.has_colors());
  EXPECT_EQ(read.cloud.colors[0], (Color{255, 0, 255}));
  EXPECT_CONTAINS(read.notes[0], "colours: only 0s and 1s, read as fractions 0-1 (1 is 255)");
}

// --------------------------------------------------------------------------
// --columns

TEST(PointIoTextColumns, ColumnsOptionNamesTheColumns) {
  TempFolder folder;
  const std::string text = "0 0 0 7 1 2 3\n1 0 0 7 4 5 6\n0 1 0 7 7 8 9\n0 0 1 7 1 2 3\n";
  const TextRead read = read_text(folder, "a.xyz", text, {"x", "y", "z", "_", "r", "g", "b"});
  expect_corners(read.cloud);
  ASSERT_TRUE(read.cloud.has_colors());
  EXPECT_EQ(read.cloud.colors[1], (Color{4, 5, 6}));
  EXPECT_EQ(read.notes, std::vector<std::string>{"columns: x y z _ r g b (from --columns; colours: integers 0-255)"});
  // Other orders and the long names.
  const TextRead other = read_text(folder, "b.xyz", "3 2 1 0 0 1\n", {"Z", "y", "x", "nx", "normal_y", "NZ"});
  EXPECT_EQ(other.cloud.positions[0], Vec3(1, 2, 3));
  EXPECT_EQ(other.cloud.normals[0], Vec3(0, 0, 1));
}

TEST(PointIoTextColumns, ColumnsOptionWinsOverAHeader) {
  TempFolder folder;
  const TextRead read = read_text(folder, "a.csv", "a,b,c,d\n1,2,3,4\n", {"_", "x", "y", "z"});
  ASSERT_EQ(read.cloud.size(), 1U);
  EXPECT_EQ(read.cloud.positions[0], Vec3(2, 3, 4));
  EXPECT_EQ(read.notes,
            std::vector<std::string>{"columns: _ x y z (from --columns; the header on line 1 is not used)"});
}

TEST(PointIoTextColumns, BadColumnsOptions) {
  TempFolder folder;
  const std::string text = "0 0 0 1 2 3\n";
  EXPECT_CONTAINS(text_error<InvalidInputError>(folder, "a.xyz", text, {"x", "y", "z", "q", "g", "b"}),
                  "--columns names an unknown column 'q' (known names: x, y, z, nx, ny, nz, r, g, b, and _");
  EXPECT_CONTAINS(text_error<InvalidInputError>(folder, "a.xyz", text, {"x", "y", "x", "r", "g", "b"}),
                  "--columns names x twice (columns 1 and 3)");
  EXPECT_CONTAINS(text_error<InvalidInputError>(folder, "a.xyz", text, {"x", "y", "_", "r", "g", "b"}),
                  "--columns must name x, y and z");
  EXPECT_CONTAINS(text_error<InvalidInputError>(folder, "a.xyz", text, {"x", "y", "z", "nx", "ny", "_"}),
                  "--columns names only some of nx, ny, nz");
  EXPECT_CONTAINS(text_error(folder, "a.xyz", text, {"x", "y", "z"}),
                  "a.xyz:1: --columns names 3 columns, but this line has 6");
  EXPECT_CONTAINS(text_error(folder, "a.xyz", "0 0 0\n0 0 0 1\n", {"x", "y", "z"}),
                  "a.xyz:2: --columns names 3 columns, but this line has 4");
}

// --------------------------------------------------------------------------
// Columns told apart by their values

TEST(PointIoTextColumns, UnitVectorsAreNormals) {
  TempFolder folder;
  // 0.577 three times has length 0.99937: within the 1 % allowed for rounding.
  const TextRead read = read_text(folder, "a.xyz", "0 0 0 0 0 -1\n1 0 0 0.577 0.577 0.577\n0 1 0 0.6 -0.8 0\n");
  ASSERT_TRUE(read.cloud.has_normals());
  EXPECT_FALSE(read.cloud.has_colors());
  EXPECT_EQ(read.cloud.normals[1], Vec3(0.577, 0.577, 0.577));
  EXPECT_EQ(read.notes,
            std::vector<std::string>{
                "columns: x y z nx ny nz (no header; the last three are unit vectors on every line: normals)"});
  // Positive axis vectors would fit colours 0-1 too; the note says so.
  const TextRead axes = read_text(folder, "b.xyz", "0 0 0 0 0 1\n1 0 0 1 0 0\n");
  ASSERT_TRUE(axes.cloud.has_normals());
  EXPECT_CONTAINS(axes.notes[0], "normals (colours would fit too: --columns reads them as r,g,b)");
}

TEST(PointIoTextColumns, FractionsThatAreNotUnitVectorsAreColours) {
  TempFolder folder;
  const TextRead read =
      read_text(folder, "a.xyz", "0 0 0 0.5 0.2 0.1\n1 0 0 1 1 1\n0 1 0 0 0 0\n0 0 1 0.25 0.5 0.75\n");
  expect_corners(read.cloud);
  ASSERT_TRUE(read.cloud.has_colors());
  EXPECT_FALSE(read.cloud.has_normals());
  EXPECT_EQ(read.cloud.colors[0], (Color{128, 51, 26}));
  EXPECT_EQ(read.cloud.colors[1], (Color{255, 255, 255}));
  EXPECT_EQ(read.notes,
            std::vector<std::string>{"columns: x y z r g b (no header; the last three are not unit vectors but "
                                     "fractions 0-1, scaled to 0-255: colours)"});
}

TEST(PointIoTextColumns, SevenColumnsAreAValueAndATriple) {
  TempFolder folder;
  // Leica's PTS order: x y z intensity r g b (intensities may be negative).
  const TextRead pts =
      read_text(folder, "a.txt", "0 0 0 -1021 255 0 0\n1 0 0 -3 0 255 0\n0 1 0 12 0 0 255\n0 0 1 0 9 9 9\n");
  expect_corners(pts.cloud);
  ASSERT_TRUE(pts.cloud.has_colors());
  EXPECT_EQ(pts.cloud.colors[0], (Color{255, 0, 0}));
  EXPECT_EQ(pts.notes, std::vector<std::string>{"columns: x y z _ r g b (no header; columns 5 to 7 are integers "
                                                "0-255: colours; column 4 is ignored)"});
  // x y z r g b and a scalar after them.
  const TextRead after = read_text(folder, "b.txt", "0 0 0 255 0 0 0.125\n1 0 0 0 255 0 7.5\n");
  ASSERT_TRUE(after.cloud.has_colors());
  EXPECT_EQ(after.cloud.colors[1], (Color{0, 255, 0}));
  EXPECT_CONTAINS(after.notes[0],
                  "columns: x y z r g b _ (no header; columns 4 to 6 are integers 0-255: colours; "
                  "column 7 is ignored)");
}

TEST(PointIoTextColumns, NineColumnsAreNormalsAndColoursInEitherOrder) {
  TempFolder folder;
  const TextRead read = read_text(folder, "a.xyz", "0 0 0 0 0 1 255 0 0\n1 0 0 -1 0 0 0 255 0\n");
  ASSERT_TRUE(read.cloud.has_normals());
  ASSERT_TRUE(read.cloud.has_colors());
  EXPECT_EQ(read.cloud.normals[1], Vec3(-1, 0, 0));
  EXPECT_EQ(read.cloud.colors[1], (Color{0, 255, 0}));
  const TextRead swapped = read_text(folder, "b.xyz", "0 0 0 255 0 0 0 0 1\n1 0 0 0 255 0 -1 0 0\n");
  EXPECT_EQ(swapped.cloud.normals[1], Vec3(-1, 0, 0));
  EXPECT_EQ(swapped.cloud.colors[1], (Color{0, 255, 0}));
  EXPECT_EQ(swapped.notes, std::vector<std::string>{
                               "columns: x y z r g b nx ny nz (no header; columns 4 to 6 are integers 0-255: colours; "
                               "7 to 9 are unit vectors on every line: normals)"});
}

TEST(PointIoTextColumns, DoubtfulColumnsAreRefusedNamingTheOption) {
  TempFolder folder;
  // Neither unit vectors nor colours.
  std::string message = text_error(folder, "a.xyz", "0 0 0 0.5 -0.2 0.1\n1 0 0 1 1 1\n");
  EXPECT_CONTAINS(message,
                  "a.xyz: the columns after x y z leave doubt: columns 4 to 6 are neither normals (line 1 has "
                  "a vector of length 0.5477) nor colours (line 1: -0.2 for column 5 is neither");
  EXPECT_CONTAINS(message, "--columns x,y,z,nx,ny,nz or --columns x,y,z,r,g,b");
  // Both placements of seven columns fit.
  message = text_error(folder, "b.xyz", "0 0 0 7 1 2 3\n1 0 0 7 4 5 6\n");
  EXPECT_CONTAINS(message, "columns 4 to 6 could be colours (integers 0-255), and columns 5 to 7 could be colours");
  EXPECT_CONTAINS(message, "--columns x,y,z,_,r,g,b or --columns x,y,z,r,g,b,_");
  // Nine columns of two unit triples.
  message = text_error(folder, "c.xyz", "0 0 0 0 0 1 0 1 0\n");
  EXPECT_CONTAINS(message,
                  "columns 4 to 6 could be normals (unit vectors on every line), and columns 7 to 9 could be normals");
  EXPECT_CONTAINS(message, "--columns x,y,z,nx,ny,nz,r,g,b");
  // Counts that cannot be read without names.
  for (const int count : {1, 5, 8, 10}) {
    std::string line = "0";
    for (int i = 1; i < count; ++i) line += " 1";
    message = text_error(folder, "d.xyz", line + "\n");
    EXPECT_CONTAINS(message,
                    "d.xyz:1: expected 3 numbers (x y z), 4 (and a value recon ignores), 6 (and normals or "
                    "colours), 7 (a value and normals or colours) or 9 (normals and colours) on a line, found " +
                        std::to_string(count));
    if (count > 3) {
      EXPECT_CONTAINS(message, "--columns x,y,z,_,_");
    }
  }
  EXPECT_CONTAINS(text_error(folder, "e.xyz", "0 1\n2 3\n"), "(two columns are 2D points");
}

TEST(PointIoTextColumns, TheWholeFileDecidesNotItsFirstLines) {
  TempFolder folder;
  // 5000 lines of colours 0-255, then one value that no colour has.
  std::string text;
  for (int i = 0; i < 5000; ++i) text += std::to_string(i) + " 0 0 " + std::to_string(i % 256) + " 10 20\n";
  EXPECT_CONTAINS(text_error(folder, "a.xyz", text + "1 2 3 0.5 -0.5 0\n"),
                  "columns 4 to 6 are neither normals (line 1 has a vector of length 22.36) nor colours (line 5001: "
                  "-0.5 for column 5");
  // 5000 lines of unit vectors, then one that is not.
  text.clear();
  for (int i = 0; i < 5000; ++i) text += std::to_string(i) + " 0 0 0 1 0\n";
  EXPECT_CONTAINS(text_error(folder, "b.xyz", text + "1 2 3 0 -2 0\n"), "(line 5001 has a vector of length 2)");
  // Colours 0-1 that a late 255 turns into a mix of scales.
  text.clear();
  for (int i = 0; i < 5000; ++i) text += std::to_string(i) + " 0 0 0.5 0.25 0\n";
  EXPECT_CONTAINS(text_error(folder, "c.xyz", text + "1 2 3 255 0 0\n"),
                  "nor colours (line 5001: 255 for column 4 is above 1, but line 1 has a fraction (0.5 for column 4))");
}

TEST(PointIoTextColumns, WrittenColoursReadBack) {
  // write_points writes "x y z [nx ny nz] r g b", r g b in 0-255, without a
  // header: the values tell the columns apart when the file is read back.
  TempFolder folder;
  PointCloud cloud = testing::random_cloud(300, true, 5);
  std::mt19937 random(5);
  std::uniform_int_distribution<int> byte(0, 255);
  for (std::size_t i = 0; i < cloud.size(); ++i)
    cloud.colors.push_back({static_cast<std::uint8_t>(byte(random)), static_cast<std::uint8_t>(byte(random)),
                            static_cast<std::uint8_t>(byte(random))});
  for (const bool normals : {true, false}) {
    if (!normals) cloud.normals.clear();
    write_points(folder / "c.xyz", cloud);
    const PointCloud back = read_points(folder / "c.xyz");
    EXPECT_EQ(back.positions, cloud.positions);
    EXPECT_EQ(back.normals, cloud.normals);
    EXPECT_EQ(back.colors, cloud.colors);
  }
}

// --------------------------------------------------------------------------
// Separators and their errors

TEST(PointIoTextColumns, TabsAndBlanksSeparate) {
  TempFolder folder;
  expect_corners(read_text(folder, "a.txt", "0\t0\t0\n1\t0\t0\n0 1\t0\n0\t\t0  1 # c\n").cloud);
  const TextRead header = read_text(folder, "b.txt", "x\ty\tz\tintensity\n0\t0\t0\t5\n");
  EXPECT_EQ(header.cloud.positions[0], Vec3(0, 0, 0));
}

TEST(PointIoTextColumns, OneSeparatorServesTheWholeFile) {
  TempFolder folder;
  EXPECT_CONTAINS(text_error(folder, "a.xyz", "1 2 3\n4,5,6\n"),
                  "a.xyz:2: mixed separators: '4,5,6' holds a comma, but line 1, the first of numbers, separates its "
                  "columns by blanks");
  EXPECT_CONTAINS(text_error(folder, "b.csv", "1,2,3\n4 5 6\n"), "b.csv:2: mixed separators: '4 5 6' holds a blank");
  EXPECT_CONTAINS(text_error(folder, "c.csv", "1,2 3\n"),
                  "c.csv:1: mixed separators: '2 3' holds a blank, but this line separates its columns by commas");
  EXPECT_CONTAINS(text_error(folder, "d.csv", "1;2;3\n4;5 6;7\n"), "d.csv:2: mixed separators: '5 6' holds a blank");
  // Blanks with decimal commas are refused, not read as six columns.
  EXPECT_CONTAINS(text_error(folder, "e.txt", "1,5 2,5 3,5\n"), "e.txt:1: mixed separators");
}

TEST(PointIoTextColumns, EmptyFieldsAreErrors) {
  TempFolder folder;
  EXPECT_CONTAINS(text_error(folder, "a.csv", "1,2,3\n1,,3\n"),
                  "a.csv:2: an empty field (two commas in a row, or a comma at the start or end of the line)");
  EXPECT_CONTAINS(text_error(folder, "b.csv", "1;2;3;\n"), "b.csv:1: an empty field (two semicolons in a row");
  // An empty field in a column recon ignores is no error.
  const TextRead read = read_text(folder, "c.csv", "x,y,z,label\n1,2,3,\n4,5,6,tree\n");
  EXPECT_EQ(read.cloud.size(), 2U);
}

// --------------------------------------------------------------------------
// Other readers of the same text: 2D points and plain .pts columns

TEST(PointIoTextColumns, TwoDimensionalTextWithAHeader) {
  TempFolder folder;
  const std::vector<Vec2> points = read_2d_text(folder, "c.csv", "X;Y\r0;0,5\r1;1,5\r");
  ASSERT_EQ(points.size(), 2U);
  EXPECT_EQ(points[1], Vec2(1.0, 1.5));
  write_file(folder / "d.csv", "a,b\n0,1\n");
  EXPECT_CONTAINS(message_of<ParseError>([&] { static_cast<void>(read_points_2d(folder / "d.csv")); }),
                  "d.csv:1: the header line of 2D points must name two columns, x y");
}

TEST(PointIoTextColumns, PtsColumnsMayHaveAHeader) {
  TempFolder folder;
  const TextRead read = read_text(folder, "a.pts", "\xEF\xBB\xBFx y z\r0 0 0\r1 0 0\r0 1 0\r0 0 1\r");
  expect_corners(read.cloud);
  // Hoppe's records after a byte-order mark, with "\r" line ends.
  expect_corners(read_text(folder, "b.pts", "\xEF\xBB\xBFp 0 0 0\rp 1 0 0\rd 1 1 1\rp 0 1 0\rp 0 0 1\r").cloud);
}

// --------------------------------------------------------------------------
// Binary data with '\r' bytes is not cut into short lines

TEST(PointIoTextColumns, ControlCharactersBeforeACarriageReturnAreNotText) {
  TempFolder folder;
  const std::string garbage = std::string("\x01\x02\x7f garbage\r") + std::string((std::size_t{1} << 20) + 1, 'a');
  EXPECT_CONTAINS(text_error(folder, "a.xyz", garbage), "a.xyz:1: line 1 is longer than 1048576 bytes");
  // UTF-8 text before it is text.
  expect_corners(read_text(folder, "b.xyz", "# H\xC3\xB6he\r0 0 0\r1 0 0\r0 1 0\r0 0 1").cloud);
}

// --------------------------------------------------------------------------
// Real files read as before: every value equal to what strtod makes of it

/// The numbers of each non-comment line of a text file, parsed with strtod.
std::vector<std::vector<double>> numbers_by_line(const std::filesystem::path& path, bool hoppe) {
  std::ifstream in(path);
  std::vector<std::vector<double>> rows;
  for (std::string line; std::getline(in, line);) {
    line = line.substr(0, line.find('#'));
    std::istringstream words(line);
    std::vector<double> row;
    std::string word;
    if (hoppe && !(words >> word && word == "p")) continue;
    while (words >> word) row.push_back(std::strtod(word.c_str(), nullptr));
    if (!row.empty()) rows.push_back(row);
  }
  return rows;
}

void expect_read_as_strtod(const std::filesystem::path& path, bool hoppe, bool normals) {
  RECON_REQUIRE_DATA(path);
  const PointCloud cloud = read_points(path);
  const auto rows = numbers_by_line(path, hoppe);
  ASSERT_EQ(cloud.size(), rows.size()) << path;
  ASSERT_EQ(cloud.has_normals(), normals) << path;
  EXPECT_FALSE(cloud.has_colors()) << path;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    ASSERT_EQ(cloud.positions[i], Vec3(rows[i][0], rows[i][1], rows[i][2])) << path << " point " << i;
    if (normals) {
      ASSERT_EQ(cloud.normals[i], Vec3(rows[i][3], rows[i][4], rows[i][5])) << path << " normal " << i;
    }
  }
}

TEST(PointIoTextColumns, RealFilesReadAsBefore) {
  using recon::testing::shared_data;
  expect_read_as_strtod(shared_data("cgal_kitten/kitten.xyz"), false, true);
  expect_read_as_strtod(shared_data("cgal_oni/oni.xyz"), false, true);
  expect_read_as_strtod(shared_data("powercrust_knot/knot.pts"), false, false);
  expect_read_as_strtod(shared_data("powercrust_hotdogs/hotdogs.pts"), false, false);
  expect_read_as_strtod(shared_data("hoppe_cactus/cactus.pts"), true, false);
  expect_read_as_strtod(shared_data("hoppe_distcap/distcap.pts"), true, false);
  expect_read_as_strtod(shared_data("hoppe_curve1/curve1.pts"), true, false);
}

TEST(TextColumns, ColumnsForAFormatWithNamedFieldsAreRefusedNotIgnored) {
  // --columns z,y,x on a PLY, LAS, PCD, OBJ or OFF file was ignored: the
  // points came back as x y z, with no word of it.
  TempFolder folder;
  write_points(folder / "c.ply", random_cloud(4, false, 1));
  write_file(folder / "c.pcd", "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nPOINTS 1\nDATA ascii\n1 2 3\n");
  write_file(folder / "c.obj", "v 1 2 3\n");
  write_file(folder / "c.off", "OFF\n1 0 0\n1 2 3\n");
  write_file(folder / "c.las", "LASF");  // refused before it is read
  write_file(folder / "hoppe.pts", "p 1 2 3\np 4 5 6\n");
  ReadPointsOptions options;
  options.columns = {"z", "y", "x"};
  for (const char* name : {"c.ply", "c.pcd", "c.obj", "c.off", "c.las"}) {
    const std::string message =
        message_of<InvalidInputError>([&] { static_cast<void>(read_points(folder / name, options)); });
    EXPECT_CONTAINS(message, (folder / name).string() + ": --columns applies to delimited text");
    PointChunkOptions chunks;
    chunks.read = options;
    EXPECT_THROW(static_cast<void>(read_points_in_chunks(folder / name, chunks, [](PointCloudView, std::size_t) {})),
                 InvalidInputError)
        << name;
  }
  const std::string message =
      message_of<InvalidInputError>([&] { static_cast<void>(read_points(folder / "hoppe.pts", options)); });
  EXPECT_CONTAINS(message, "hoppe.pts: --columns applies to plain columns, but this .pts file holds Hoppe's");
}

TEST(TextColumns, ColumnsApplyToPlainPtsColumns) {
  // A .pts file of plain columns is read as xyz text: --columns applies.
  TempFolder folder;
  write_file(folder / "plain.pts", "1 2 3\n4 5 6\n");
  ReadPointsOptions options;
  options.columns = {"z", "y", "x"};
  const PointCloud cloud = read_points(folder / "plain.pts", options);
  ASSERT_EQ(cloud.size(), 2U);
  EXPECT_EQ(cloud.positions[0], Vec3(3, 2, 1));
}

}  // namespace
}  // namespace recon::io
