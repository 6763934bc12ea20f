// read_points / write_points: format choice, the text formats (xyz, pts,
// obj, off), PCD, errors common to all formats, and the real data sets.
// PLY has its own file, ply_test.cpp; the round trips of every format are in
// round_trip_test.cpp.

#include "recon/io/point_io.h"

#include "io/io_test_helpers.h"
#include "recon/core/errors.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

namespace recon::io {
namespace {

using namespace testing;  // io_test_helpers.h

// --------------------------------------------------------------------------
// Format names and extensions

TEST(PointIoFormat, FromName) {
  expect_formats<PointFormat>(point_format_from_name, {{"ply", PointFormat::ply},
                                                       {"XYZ", PointFormat::xyz},
                                                       {"pts", PointFormat::pts},
                                                       {"obj", PointFormat::obj},
                                                       {"off", PointFormat::off},
                                                       {"pcd", PointFormat::pcd},
                                                       {"LAS", PointFormat::las}});
  expect_message<InvalidInputError>([] { static_cast<void>(point_format_from_name("e57")); },
                                    {"'e57'", "ply, xyz, pts, obj, off, pcd, las"});
}

TEST(PointIoFormat, FromExtension) {
  expect_formats<PointFormat>(point_format_from_path, {{"a/b.ply", PointFormat::ply},
                                                       {"b.PLY", PointFormat::ply},
                                                       {"b.xyz", PointFormat::xyz},
                                                       {"b.txt", PointFormat::xyz},
                                                       {"b.asc", PointFormat::xyz},
                                                       {"b.pwn", PointFormat::xyz},
                                                       {"b.pts", PointFormat::pts},
                                                       {"b.obj", PointFormat::obj},
                                                       {"b.Off", PointFormat::off},
                                                       {"b.pcd", PointFormat::pcd},
                                                       {"b.CSV", PointFormat::xyz},
                                                       {"b.las", PointFormat::las}});
}

TEST(PointIoFormat, UnknownExtensionNamesTheFormatsAndTheOption) {
  expect_message<InvalidInputError>([] { static_cast<void>(read_points("scan.e57")); },
                                    {"scan.e57", ".las", ".ply", ".pcd", "--format"});
  EXPECT_CONTAINS(message_of<InvalidInputError>([] { static_cast<void>(point_format_from_path("noext")); }),
                  "no extension");
}

TEST(PointIoFormat, NamedFormatOverridesTheExtension) {
  TempFolder folder;
  write_file(folder / "points.dat", "1 2 3\n4 5 6\n");
  const PointCloud cloud = read_points(folder / "points.dat", as_format(PointFormat::xyz));
  EXPECT_EQ(cloud.size(), 2U);
}

// --------------------------------------------------------------------------
// Errors shared by every format

TEST(PointIoErrors, MissingFileAndFolder) {
  TempFolder folder;
  const std::string missing = message_of<IoError>([&] { static_cast<void>(read_points(folder / "none.xyz")); });
  EXPECT_CONTAINS(missing, "none.xyz: cannot open: ");
  std::filesystem::create_directory(folder / "dir.ply");
  const std::string directory = message_of<IoError>([&] { static_cast<void>(read_points(folder / "dir.ply")); });
  EXPECT_CONTAINS(directory, "dir.ply: cannot open: ");
}

TEST(PointIoErrors, EmptyFile) {
  TempFolder folder;
  for (const char* name : {"e.ply", "e.xyz", "e.pts", "e.obj", "e.off", "e.pcd"}) {
    write_file(folder / name, "");
    const std::string message = point_read_error(folder / name);
    EXPECT_CONTAINS(message, name);
    EXPECT_CONTAINS(message, "empty");
  }
}

TEST(PointIoErrors, NoPoints) {
  TempFolder folder;
  const std::pair<const char*, const char*> files[] = {
      {"c.xyz", "# only a comment\n\n"},
      {"c.pts", "# only a comment\n"},
      {"h.pts", "d 0 0 0\ns 0 0 0\n"},
      {"c.obj", "# nothing\nvt 0 0\n"},
      {"c.off", "OFF\n0 0 0\n"},
      {"c.ply",
       "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\nend_header\n"},
      {"c.pcd", "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 0\nPOINTS 0\nDATA ascii\n"},
  };
  for (const auto& [name, content] : files) {
    write_file(folder / name, content);
    const std::string message = point_read_error(folder / name);
    EXPECT_CONTAINS(message, name);
    EXPECT_CONTAINS(message, "no points");
  }
}

// --------------------------------------------------------------------------
// xyz

TEST(PointIoXyz, ReadsPositionsCommentsAndBlankLines) {
  TempFolder folder;
  const PointCloud cloud =
      write_and_read(folder, "a.xyz", "# header comment\n\n1 2 3\n  4.5\t-5e-3  6  # trailing comment\r\n+7 8 9");
  ASSERT_EQ(cloud.size(), 3U);
  EXPECT_FALSE(cloud.has_normals());
  EXPECT_EQ(cloud.positions[1], Vec3(4.5, -5e-3, 6));
  EXPECT_EQ(cloud.positions[2], Vec3(7, 8, 9));
}

TEST(PointIoXyz, SixColumnsAreNormals) {
  TempFolder folder;
  const PointCloud cloud = write_and_read(folder, "a.pwn", "0 0 0 0 0 1\n1 0 0 1 0 0\n");
  ASSERT_EQ(cloud.size(), 2U);
  ASSERT_TRUE(cloud.has_normals());
  EXPECT_EQ(cloud.normals[1], Vec3(1, 0, 0));
}

TEST(PointIoXyz, CommasSeparateToo) {
  TempFolder folder;
  const PointCloud cloud = write_and_read(folder, "a.txt", "1,2,3\n4 , 5 ,6\n");
  ASSERT_EQ(cloud.size(), 2U);
  EXPECT_EQ(cloud.positions[1], Vec3(4, 5, 6));
}

TEST(PointIoXyz, Errors) {
  expect_read_errors("e.xyz", {
                                  {"1 2 3\n4 5 6 7 8 9\n", "e.xyz:2:", "every line must have the same count"},
                                  {"1 2 3 4 5\n", "e.xyz:1:", "found 5"},
                                  {"1 2 3\n\n1 2 x\n", "e.xyz:3:", "expected a number for z, found 'x'"},
                                  {"# c\n1 2 1e999\n", "e.xyz:2:", "too large for a double"},
                                  {"1,,2,3\n", "e.xyz:1:", "comma"},
                                  {"1 2 3,\n", "e.xyz:1:", "comma"},
                                  {"1 2 3\n1 2 3e\n", "e.xyz:2:", "'3e'"},
                              });
}

TEST(PointIoXyz, TinyValuesBecomeZeroInsteadOfFailing) {
  TempFolder folder;
  const PointCloud cloud = write_and_read(folder, "t.xyz", "1e-400 -1e-400 5e-324\n");
  EXPECT_EQ(cloud.positions[0].x(), 0.0);
  EXPECT_EQ(cloud.positions[0].y(), 0.0);
  EXPECT_GT(cloud.positions[0].z(), 0.0);
}

// --------------------------------------------------------------------------
// pts

TEST(PointIoPts, HoppeRecordsWithOtherLetters) {
  TempFolder folder;
  const PointCloud cloud = write_and_read(folder, "h.pts",
                                          "# Created by a scanner\n"
                                          "d 0 0 0\n"
                                          "s 0 0 0\n"
                                          "g 1 0 0\n"
                                          "p 0.5 0.25 1\n"
                                          "n 0 0 1\n"
                                          "p 1 2 3 # comment\n"
                                          "\n"
                                          "p -1 -2 -3\n");
  ASSERT_EQ(cloud.size(), 3U);
  EXPECT_FALSE(cloud.has_normals());
  EXPECT_EQ(cloud.positions[0], Vec3(0.5, 0.25, 1));
  EXPECT_EQ(cloud.positions[2], Vec3(-1, -2, -3));
}

TEST(PointIoPts, PlainColumns) {
  TempFolder folder;
  const PointCloud cloud = write_and_read(folder, "c.pts", " 0 0 0 \n-0.5 6.8 2.1 \n");
  ASSERT_EQ(cloud.size(), 2U);
  EXPECT_EQ(cloud.positions[1], Vec3(-0.5, 6.8, 2.1));
}

TEST(PointIoPts, Errors) {
  expect_read_errors("e.pts", {
                                  {"p 1 2 3\np 1 2\n", "e.pts:2:", "found 2"},
                                  {"# c\np 1 2 3\n4 5 6\n", "e.pts:3:", "line 2"},
                                  {"p 1 2 3\npoint 5 6 7\n", "e.pts:2:", "'point'"},
                              });
}

// --------------------------------------------------------------------------
// obj

TEST(PointIoObj, VerticesAndMatchingNormals) {
  TempFolder folder;
  const PointCloud cloud = write_and_read(folder, "a.obj",
                                          "# exported\nmtllib a.mtl\no thing\n"
                                          "v 0 0 0\nv 1 0 0 1.0\nv 0 1 0 0.5 0.5 0.5\n"
                                          "vt 0 0\nvn 0 0 1\nvn 0 0 1\nvn 0 0 -1\n"
                                          "f 1/1/1 2/1/2 3/1/3\n");
  ASSERT_EQ(cloud.size(), 3U);
  EXPECT_EQ(cloud.positions[1], Vec3(1, 0, 0));  // w ignored
  EXPECT_EQ(cloud.positions[2], Vec3(0, 1, 0));  // colour ignored
  ASSERT_TRUE(cloud.has_normals());
  EXPECT_EQ(cloud.normals[2], Vec3(0, 0, -1));
}

TEST(PointIoObj, NormalsOfAnotherCountAreDropped) {
  // Dropped normals are not checked either: a NaN among them does not matter.
  TempFolder folder;
  const PointCloud cloud =
      write_and_read(folder, "a.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nvn nan 0 0\nf 1//1 2//1 3//1\n");
  EXPECT_EQ(cloud.size(), 3U);
  EXPECT_FALSE(cloud.has_normals());
}

TEST(PointIoObj, Errors) {
  expect_read_errors("e.obj", {
                                  {"v 1 2 3\n# c\nv 1 2\n", "e.obj:3:", "3 numbers"},
                                  {"v 1 2 3\nvn a 0 1\n", "e.obj:2:", "'a'"},
                              });
}

// --------------------------------------------------------------------------
// off

TEST(PointIoOff, CountsOnTheNextLineAndComments) {
  TempFolder folder;
  const PointCloud cloud =
      write_and_read(folder, "a.off", "OFF\n# a comment\n3 1 0\n0 0 0\n1 0 0 # corner\n\n0 1 0\n3 0 1 2\n");
  ASSERT_EQ(cloud.size(), 3U);
  EXPECT_FALSE(cloud.has_normals());
  EXPECT_EQ(cloud.positions[1], Vec3(1, 0, 0));
}

TEST(PointIoOff, CountsOnTheHeaderLine) {
  TempFolder folder;
  const PointCloud cloud = write_and_read(folder, "a.off", "OFF 2 0 0\n1 2 3\n4 5 6\n");
  ASSERT_EQ(cloud.size(), 2U);
  EXPECT_EQ(cloud.positions[1], Vec3(4, 5, 6));
}

TEST(PointIoOff, NoffHasNormalsAndColoursAreIgnored) {
  TempFolder folder;
  PointCloud cloud = write_and_read(folder, "a.off", "NOFF\n2 0 0\n1 2 3 0 0 1\n4 5 6 1 0 0\n");
  ASSERT_TRUE(cloud.has_normals());
  EXPECT_EQ(cloud.normals[1], Vec3(1, 0, 0));

  write_file(folder / "c.off", "COFF\n2 0 0\n1 2 3 255 0 0 255\n4 5 6 0 255 0 255\n");
  cloud = read_points(folder / "c.off");
  EXPECT_FALSE(cloud.has_normals());
  EXPECT_EQ(cloud.positions[1], Vec3(4, 5, 6));
}

TEST(PointIoOff, Errors) {
  expect_read_errors("e.off", {
                                  {"OFF\n3 0 0\n0 0 0\n1 0 0\n", "e.off:4:", "promises 3"},
                                  {"OFF\n2 0 0\n0 0 0\n1 0\n", "e.off:4:", "needs 3 numbers"},
                                  {"NOFF\n1 0 0\n0 0 0\n", "e.off:3:", "needs 6 numbers"},
                                  {"OFF\n1 0 0\n0 x 0\n", "e.off:3:", "'x'"},
                                  {"# c\nPLY\n1 0 0\n", "e.off:2:", "not an OFF file"},
                                  {"OFF\nmany 0 0\n", "e.off:2:", "counts"},
                                  {"4OFF\n1 0 0\n", "e.off:1:", "not supported"},
                                  {"OFF BINARY\n", "e.off:1:", "binary OFF"},
                              });
}

// --------------------------------------------------------------------------
// pcd

constexpr const char* pcd_ascii =
    "# .PCD v0.7 - Point Cloud Data file format\n"
    "VERSION 0.7\n"
    "FIELDS x y z rgb normal_x normal_y normal_z curvature\n"
    "SIZE 4 4 4 4 4 4 4 4\n"
    "TYPE F F F F F F F F\n"
    "COUNT 1 1 1 1 1 1 1 1\n"
    "WIDTH 3\n"
    "HEIGHT 1\n"
    "VIEWPOINT 0 0 0 1 0 0 0\n"
    "POINTS 3\n"
    "DATA ascii\n"
    "1 2 3 4.2108e+06 0 0 1 0.5\n"
    "nan nan nan nan nan nan nan nan\n"
    "4 5 6 4.2108e+06 1 0 0 0.25\n";

TEST(PointIoPcd, AsciiWithNormalsSkipsOtherFieldsAndNaNPoints) {
  TempFolder folder;
  write_file(folder / "a.pcd", pcd_ascii);
  const PointCloud cloud = read_points(folder / "a.pcd");
  ASSERT_EQ(cloud.size(), 2U);  // the all-NaN point marks "no measurement"
  ASSERT_TRUE(cloud.has_normals());
  EXPECT_EQ(cloud.positions[1], Vec3(4, 5, 6));
  EXPECT_EQ(cloud.normals[1], Vec3(1, 0, 0));
}

TEST(PointIoPcd, BinaryRecordsInFieldOrder) {
  TempFolder folder;
  Bytes bytes;
  bytes.text(
      "VERSION .7\nFIELDS _ y x hist z\nSIZE 1 8 4 2 2\nTYPE U F F I I\nCOUNT 3 1 1 2 1\nWIDTH 2\nHEIGHT 1\n"
      "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\nDATA binary\n");
  const auto record = [&](double y, float x, std::int16_t z) {
    bytes.put<std::uint8_t>(9).put<std::uint8_t>(9).put<std::uint8_t>(9);
    bytes.put(y).put(x).put<std::int16_t>(-1).put<std::int16_t>(7).put(z);
  };
  record(2.5, 1.5F, -3);
  record(-0.125, 100.0F, 12);
  write_file(folder / "b.pcd", bytes.str());
  const PointCloud cloud = read_points(folder / "b.pcd");
  ASSERT_EQ(cloud.size(), 2U);
  EXPECT_FALSE(cloud.has_normals());
  EXPECT_EQ(cloud.positions[0], Vec3(1.5, 2.5, -3));
  EXPECT_EQ(cloud.positions[1], Vec3(100, -0.125, 12));
}

TEST(PointIoPcd, Errors) {
  const std::string header = "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2\nHEIGHT 1\nPOINTS 2\n";
  expect_read_errors(
      "e.pcd", {
                   {header + "DATA binary_compressed\n", "e.pcd: byte 84:", "the file ends before the two sizes"},
                   {header + "DATA ascii\n1 2 3\n", "e.pcd:8:", "promises 2"},
                   {header + "DATA ascii\n1 2 3\n1 2\n", "e.pcd:9:", "expected 3 values"},
                   {header + "DATA ascii\n1 2 3\n1 2 3\n1 2 3\n", "e.pcd:10:", "more data lines"},
                   {header + "DATA ascii\n1 2 3\n1 b 3\n", "e.pcd:9:", "'b'"},
                   {header + "DATA zip\n", "e.pcd:7:", "DATA"},
                   {"FIELDS a y z\nSIZE 4 4 4\nTYPE F F F\nPOINTS 1\nDATA ascii\n1 2 3\n", "e.pcd:1:", "'x'"},
                   {"FIELDS x y z\nSIZE 4 4\nTYPE F F F\nPOINTS 1\nDATA ascii\n1 2 3\n", "e.pcd:2:", "SIZE lists 2"},
                   {"FIELDS x y z\nSIZE 4 4 3\nTYPE F F F\nPOINTS 1\nDATA ascii\n1 2 3\n", "e.pcd:3:", "not supported"},
                   {"FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 3\nPOINTS 2\nDATA ascii\n", "e.pcd:5:", "WIDTH"},
                   {"FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nPOINTS 1\n", "e.pcd:4:", "no DATA line"},
                   {"FIELDS x y z\nCOLOUR red\n", "e.pcd:2:", "unexpected line"},
               });
}

TEST(PointIoPcd, TruncatedBinarySaysWhere) {
  TempFolder folder;
  Bytes bytes;
  bytes.text("FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nPOINTS 3\nDATA binary\n");
  const std::size_t data_start = bytes.size();
  for (int i = 0; i < 2; ++i) bytes.put(1.0F).put(2.0F).put(3.0F);
  bytes.put(1.0F);
  write_file(folder / "t.pcd", bytes.str());
  const std::string message = point_read_error(folder / "t.pcd");
  EXPECT_CONTAINS(message, "t.pcd: byte " + std::to_string(data_start + 24) + ":");
  EXPECT_CONTAINS(message, "point 2");
}

// --------------------------------------------------------------------------
// Writing

TEST(PointIoWrite, OnlyPlyAndXyz) {
  TempFolder folder;
  const PointCloud cloud = random_cloud(3, false, 1);
  EXPECT_THROW(write_points(folder / "a.pcd", cloud), InvalidInputError);
  EXPECT_THROW(write_points(folder / "a.obj", cloud), InvalidInputError);
  EXPECT_THROW(write_points(folder / "a.ply", cloud, {.format = PointFormat::off}), InvalidInputError);
  EXPECT_TRUE(folder.entries().empty());
}

TEST(PointIoWrite, RefusesWhatItCouldNotReadBack) {
  TempFolder folder;
  PointCloud cloud = random_cloud(3, true, 1);
  cloud.normals.pop_back();
  EXPECT_CONTAINS(message_of<InvalidInputError>([&] { write_points(folder / "a.ply", cloud); }),
                  "2 normals for 3 points");
  cloud = random_cloud(3, false, 1);
  cloud.positions[1].y() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_CONTAINS(message_of<InvalidInputError>([&] { write_points(folder / "a.xyz", cloud); }),
                  "a.xyz: cannot write: point 1 has a coordinate that is not finite or beyond +-1e+15");
  cloud.positions[1].y() = -2e15;  // would not read back
  EXPECT_CONTAINS(message_of<InvalidInputError>([&] { write_points(folder / "a.xyz", cloud); }),
                  "a.xyz: cannot write: point 1 has a coordinate that is not finite or beyond +-1e+15");
  EXPECT_TRUE(folder.entries().empty());
}

// --------------------------------------------------------------------------
// Real data (from /work/shared/data, see its README)

class PointIoRealData : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!std::filesystem::is_directory(folder_))
      GTEST_SKIP() << "shared data folder " << folder_ << " is absent; the real-data tests are skipped";
  }
  [[nodiscard]] std::filesystem::path file(const char* relative) const { return folder_ / relative; }

 private:
  std::filesystem::path folder_ = RECON_SHARED_DATA_DIR;
};

TEST_F(PointIoRealData, HoppeFormat) {
  EXPECT_EQ(read_points(file("hoppe_cactus/cactus.pts")).size(), 3318U);
  EXPECT_EQ(read_points(file("hoppe_distcap/distcap.pts")).size(), 12745U);
  const PointCloud curve = read_points(file("hoppe_curve1/curve1.pts"));
  EXPECT_EQ(curve.size(), 126U);
  for (const Vec3& p : curve.positions) EXPECT_EQ(p.x(), 0.0);
}

TEST_F(PointIoRealData, PlainColumns) {
  const PointCloud knot = read_points(file("powercrust_knot/knot.pts"));
  EXPECT_EQ(knot.size(), 1281U);
  EXPECT_FALSE(knot.has_normals());
  EXPECT_EQ(read_points(file("powercrust_hotdogs/hotdogs.pts")).size(), 1748U);
  const PointCloud kitten = read_points(file("cgal_kitten/kitten.xyz"));
  EXPECT_EQ(kitten.size(), 5210U);
  EXPECT_TRUE(kitten.has_normals());
  EXPECT_EQ(read_points(file("cgal_oni/oni.xyz")).size(), 1435U);
}

TEST_F(PointIoRealData, Ply) {
  const PointCloud bunny = read_points(file("stanford_bunny/bun_zipper.ply"));
  EXPECT_EQ(bunny.size(), 35947U);
  EXPECT_FALSE(bunny.has_normals());
  EXPECT_NEAR(bunny.positions[0].x(), -0.0378297, 1e-12);
  const PointCloud armadillo = read_points(file("stanford_armadillo_points/Armadillo.ply"));
  EXPECT_EQ(armadillo.size(), 38294U);
  EXPECT_TRUE(armadillo.has_normals());
}

TEST_F(PointIoRealData, Pcd) {
  const PointCloud lamppost = read_points(file("pcl_lamppost/lamppost.pcd"));
  EXPECT_EQ(lamppost.size(), 1771U);
  EXPECT_FALSE(lamppost.has_normals());
  const PointCloud bun0 = read_points(file("pcl_bun0/bun0.pcd"));
  EXPECT_EQ(bun0.size(), 397U);
  EXPECT_TRUE(bun0.has_normals());
}

TEST_F(PointIoRealData, SurvivesBinaryPlyRoundTrip) {
  TempFolder folder;
  const PointCloud armadillo = read_points(file("stanford_armadillo_points/Armadillo.ply"));
  write_points(folder / "a.ply", armadillo);
  expect_same(armadillo, read_points(folder / "a.ply"));
}

}  // namespace
}  // namespace recon::io
