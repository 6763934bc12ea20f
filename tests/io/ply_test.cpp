// PLY point reading and writing: every encoding and scalar type, elements in
// any order, skipped lists, and every way a file can be malformed. (The round
// trips through PLY are in round_trip_test.cpp.)

#include "recon/io/mesh_io.h"
#include "recon/io/point_io.h"

#include "io/io_test_helpers.h"
#include "recon/core/errors.h"

#include <gtest/gtest.h>

#include <chrono>
#include <limits>
#include <string>

namespace recon::io {
namespace {

using namespace testing;  // io_test_helpers.h

TEST(PlyReader, AsciiWithCommentsOtherPropertiesAndFacesFirst) {
  TempFolder folder;
  const PointCloud cloud = write_and_read(folder, "a.ply",
                                          "ply\r\n"
                                          "format ascii 1.0\n"
                                          "comment made by hand\n"
                                          "obj_info nothing to say\n"
                                          "element face 2\n"
                                          "property list uchar int vertex_indices\n"
                                          "property uchar flags\n"
                                          "element vertex 3\n"
                                          "property float x\n"
                                          "property float confidence\n"
                                          "property float y\n"
                                          "property float z\n"
                                          "element edge 1\n"
                                          "property int vertex1\n"
                                          "property int vertex2\n"
                                          "end_header\n"
                                          "3 0 1 2 7\n"
                                          "4 0 1 2 0 1\n"
                                          "1 0.5 2 3\n"
                                          "-4 nan 5.5 6e2\n"  // a NaN in a skipped property is fine
                                          "7 0 8 9\n"
                                          "0 1\n");
  ASSERT_EQ(cloud.size(), 3U);
  EXPECT_FALSE(cloud.has_normals());
  EXPECT_EQ(cloud.positions[0], Vec3(1, 2, 3));
  EXPECT_EQ(cloud.positions[1], Vec3(-4, 5.5, 600));
  EXPECT_EQ(cloud.positions[2], Vec3(7, 8, 9));
}

TEST(PlyReader, AsciiValuesMayWrapAcrossLines) {
  TempFolder folder;
  const PointCloud cloud = write_and_read(folder, "w.ply",
                                          "ply\nformat ascii 1.0\nelement vertex 2\n"
                                          "property double x\nproperty double y\nproperty double z\n"
                                          "end_header\n1 2\n3 4 5\n6\n");
  ASSERT_EQ(cloud.size(), 2U);
  EXPECT_EQ(cloud.positions[1], Vec3(4, 5, 6));
}

TEST(PlyReader, NormalsOnlyWhenAllThreeArePresent) {
  TempFolder folder;
  const std::string start =
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n";
  write_file(folder / "n.ply",
             start + "property float nx\nproperty float ny\nproperty float nz\nend_header\n1 2 3 0 0 1\n");
  PointCloud cloud = read_points(folder / "n.ply");
  ASSERT_TRUE(cloud.has_normals());
  EXPECT_EQ(cloud.normals[0], Vec3(0, 0, 1));
  write_file(folder / "p.ply", start + "property float nx\nproperty float ny\nend_header\n1 2 3 0 1\n");
  cloud = read_points(folder / "p.ply");
  EXPECT_FALSE(cloud.has_normals());
  EXPECT_EQ(cloud.positions[0], Vec3(1, 2, 3));
}

// Every scalar type name, in big-endian order, and a list after the vertices.
TEST(PlyReader, BinaryBigEndianEveryType) {
  TempFolder folder;
  Bytes bytes(true);
  bytes.text(
      "ply\nformat binary_big_endian 1.0\nelement vertex 2\n"
      "property char c\nproperty uchar uc\nproperty short x\nproperty ushort us\nproperty int y\nproperty uint ui\n"
      "property float z\nproperty double d\nproperty int8 i8\nproperty uint8 u8\nproperty int16 i16\n"
      "property uint16 u16\nproperty int32 i32\nproperty uint32 u32\nproperty float32 nx\nproperty float64 ny\n"
      "property float nz\n"
      "element face 1\nproperty list uint8 uint32 vertex_indices\nend_header\n");
  const auto vertex = [&](std::int16_t x, std::int32_t y, float z, float nx, double ny, float nz) {
    bytes.put<std::int8_t>(-1).put<std::uint8_t>(200).put(x).put<std::uint16_t>(60000).put(y);
    bytes.put<std::uint32_t>(4000000000U).put(z).put(1e300).put<std::int8_t>(-5).put<std::uint8_t>(5);
    bytes.put<std::int16_t>(-300).put<std::uint16_t>(300).put<std::int32_t>(-70000).put<std::uint32_t>(70000);
    bytes.put(nx).put(ny).put(nz);
  };
  vertex(-2, -100000, 0.5F, 0.0F, 1.0, 0.0F);
  vertex(32767, 2147483647, -1.25e-3F, 0.6F, 0.0, 0.8F);
  bytes.put<std::uint8_t>(3).put<std::uint32_t>(0).put<std::uint32_t>(1).put<std::uint32_t>(0);
  write_file(folder / "be.ply", bytes.str());

  const PointCloud cloud = read_points(folder / "be.ply");
  ASSERT_EQ(cloud.size(), 2U);
  ASSERT_TRUE(cloud.has_normals());
  EXPECT_EQ(cloud.positions[0], Vec3(-2, -100000, 0.5));
  EXPECT_EQ(cloud.positions[1], Vec3(32767, 2147483647, static_cast<double>(-1.25e-3F)));
  EXPECT_EQ(cloud.normals[0], Vec3(0, 1, 0));
  EXPECT_EQ(cloud.normals[1], Vec3(static_cast<double>(0.6F), 0, static_cast<double>(0.8F)));
}

TEST(PlyReader, BinaryLittleEndianFacesBeforeVertices) {
  TempFolder folder;
  Bytes bytes;
  bytes.text(
      "ply\nformat binary_little_endian 1.0\ncomment faces come first\n"
      "element face 2\nproperty list uchar int vertex_indices\nproperty float quality\n"
      "element material 1\nproperty list ushort double weights\n"
      "element vertex 4\nproperty double x\nproperty double y\nproperty double z\nproperty uchar red\nend_header\n");
  bytes.put<std::uint8_t>(3).put(0).put(1).put(2).put(0.5F);
  bytes.put<std::uint8_t>(4).put(0).put(1).put(2).put(3).put(0.25F);
  bytes.put<std::uint16_t>(2).put(1.0).put(2.0);
  for (int i = 0; i < 4; ++i) bytes.put(1.0 * i).put(-2.0 * i).put(0.1 * i).put<std::uint8_t>(255);
  bytes.text("\n");  // a stray newline after the body is ignored
  write_file(folder / "le.ply", bytes.str());

  const PointCloud cloud = read_points(folder / "le.ply");
  ASSERT_EQ(cloud.size(), 4U);
  EXPECT_FALSE(cloud.has_normals());
  EXPECT_EQ(cloud.positions[3], Vec3(3.0, -6.0, 0.1 * 3));
}

TEST(PlyIo, WrittenHeader) {
  TempFolder folder;
  write_points(folder / "h.ply", random_cloud(2, true, 1));
  const std::string content = testing::read_bytes(folder / "h.ply");
  EXPECT_EQ(content.rfind("ply\nformat binary_little_endian 1.0\n", 0), 0U);
  EXPECT_CONTAINS(content,
                  "element vertex 2\nproperty double x\nproperty double y\nproperty double z\n"
                  "property double nx\nproperty double ny\nproperty double nz\nend_header\n");
  const std::size_t body = content.find("end_header\n") + 11;
  EXPECT_EQ(content.size() - body, 2U * 6U * 8U);
}

TEST(PlyReader, HeaderErrorsNameTheLine) {
  expect_read_errors(
      "e.ply",
      {
          {"plyx\nformat ascii 1.0\n", "e.ply:1:", "not a PLY file"},
          {"PLY\n", "e.ply:1:", "not a PLY file"},
          {"ply\nformat ascii\nend_header\n", "e.ply:2:", "bad format line"},
          {"ply\nformat binary 1.0\nend_header\n", "e.ply:2:", "unknown PLY format 'binary'"},
          {"ply\nformat ascii 2.0\nend_header\n", "e.ply:2:", "version"},
          {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float128 x\nend_header\n",
           "e.ply:4:", "unknown type 'float128'"},
          {"ply\nformat ascii 1.0\nelement vertex 1\nproperty list uchar x\nend_header\n", "e.ply:4:", "list property"},
          {"ply\nformat ascii 1.0\nelement face 1\nproperty list float int vertex_indices\nend_header\n",
           "e.ply:4:", "integer type"},
          {"ply\nformat ascii 1.0\nproperty float x\nend_header\n", "e.ply:3:", "before any element"},
          {"ply\nformat ascii 1.0\nelement vertex many\nend_header\n", "e.ply:3:", "bad element line"},
          {"ply\nformat ascii 1.0\nelement vertex 1\nelement vertex 1\nend_header\n", "e.ply:4:", "second element"},
          {"ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n3 0 1 2\n",
           "e.ply:5:", "no 'vertex' element"},
          {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float z\nend_header\n1 2\n",
           "e.ply:3:", "no 'y' property"},
          {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
           "property list uchar int extra\nend_header\n",
           "e.ply:7:", "list property 'extra' on the vertex element"},
          {"ply\nelement vertex 1\nend_header\n", "e.ply:3:", "no format line"},
          {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n", "e.ply:4:", "no 'end_header'"},
          {"ply\nformat ascii 1.0\nvertex 1\nend_header\n", "e.ply:3:", "unexpected line"},
      });
}

TEST(PlyReader, AsciiBodyErrorsNameTheLine) {
  const std::string header =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n";  // the body starts on line 10
  expect_read_errors(
      "e.ply",
      {
          {header + "1 2 3\n4 5 6\n", "e.ply:11:", "promises 3 'vertex' elements"},
          {header + "1 2 3\n4 5 6\n7 8 9\n3 0 1\n", "e.ply:13:", "promises 1 'face'"},
          {header + "1 2 3\n4 five 6\n7 8 9\n3 0 1 2\n", "e.ply:11:", "expected a number for y, found 'five'"},
          {header + "1 2 1e999\n4 5 6\n7 8 9\n3 0 1 2\n", "e.ply:10:", "'1e999' for z does not fit its type float32"},
          {header + "1 2 3\n4 5 6\n7 8 9\n300 0 1 2\n", "e.ply:13:", "length of list 'vertex_indices'"},
          {header + "1 2 3\n4 5 6\n7 8 9\nthree 0 1 2\n", "e.ply:13:", "length of list 'vertex_indices'"},
          {header + "1 2 3\n4 5 6\n7 8 9\n3 0 1 x\n", "e.ply:13:", "'x'"},
          {header + "1 2 3\n4 5 6\n7 8 9\n3 0 1 2\n\n5\n", "e.ply:15:", "after the last element"},
      });
}

TEST(PlyReader, TruncatedBinarySaysWhichVertexAndByte) {
  TempFolder folder;
  Bytes bytes;
  bytes.text(
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nend_header\n");
  const std::size_t body = bytes.size();
  bytes.put(1.0F).put(2.0F).put(3.0F).put(4.0F).put(5.0F).put(6.0F).put(7.0F).put(8.0F);
  write_file(folder / "t.ply", bytes.str());
  const std::string message = point_read_error(folder / "t.ply");
  EXPECT_CONTAINS(message, "t.ply: byte " + std::to_string(body + 24) + ":");
  EXPECT_CONTAINS(message, "inside vertex 2");
  EXPECT_CONTAINS(message, "promises 3 'vertex'");
}

TEST(PlyReader, TruncatedBinaryListElement) {
  TempFolder folder;
  Bytes bytes(true);
  bytes.text(
      "ply\nformat binary_big_endian 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
      "property float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n");
  bytes.put(1.0F).put(2.0F).put(3.0F);
  const std::size_t second_face = bytes.size() + 13;
  bytes.put<std::uint8_t>(3).put(0).put(0).put(0);
  bytes.put<std::uint8_t>(3).put(0).put(0);
  write_file(folder / "t.ply", bytes.str());
  const std::string message = point_read_error(folder / "t.ply");
  EXPECT_CONTAINS(message, "t.ply: byte " + std::to_string(second_face) + ":");
  EXPECT_CONTAINS(message, "inside face 1");
}

TEST(PlyReader, HugeCountOfAnElementWithoutPropertiesCostsNothing) {
  // Found by fuzzing (fuzz_ply_mesh, a timeout): an element without
  // properties holds no values, so a count of 10^12 must not be walked.
  TempFolder folder;
  const std::string header =
      "ply\nformat ascii 1.0\nelement nothing 1000000000000\nelement vertex 3\nproperty float x\n"
      "property float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  write_file(folder / "a.ply", header);
  const auto start = std::chrono::steady_clock::now();
  EXPECT_EQ(read_points(folder / "a.ply").size(), 3U);
  EXPECT_EQ(read_mesh(folder / "a.ply").triangles.size(), 1U);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 1.0);
}

TEST(PlyReader, AHeaderOfManyElementsTakesLinearTime) {
  // Each element name is checked against the ones before it; a scan of them
  // would make 100,000 elements take billions of comparisons.
  TempFolder folder;
  std::string header = "ply\nformat ascii 1.0\n";
  for (int i = 0; i < 100000; ++i) header += "element e" + std::to_string(i) + " 0\n";
  header += "element vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n1 2 3\n";
  write_file(folder / "many.ply", header);
  const auto start = std::chrono::steady_clock::now();
  EXPECT_EQ(read_points(folder / "many.ply").size(), 1U);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 1.0);
}

TEST(PlyReader, HugeCountsInTheHeaderAllocateNothing) {
  TempFolder folder;
  const std::string binary =
      "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000000000\nproperty double x\n"
      "property double y\nproperty double z\nend_header\n0123456789";
  write_file(folder / "b.ply", binary);
  EXPECT_CONTAINS(point_read_error(folder / "b.ply"), "b.ply: byte ");
  const std::string ascii =
      "ply\nformat ascii 1.0\nelement vertex 1000000000000000\nproperty double x\n"
      "property double y\nproperty double z\nend_header\n1 2 3\n";
  write_file(folder / "a.ply", ascii);
  EXPECT_CONTAINS(point_read_error(folder / "a.ply"), "a.ply:8:");
  const std::string list =
      "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty double x\n"
      "property double y\nproperty double z\nproperty uint count\nelement face 1\n"
      "property list uint int vertex_indices\nend_header\n";
  Bytes bytes;
  bytes.text(list).put(1.0).put(2.0).put(3.0).put<std::uint32_t>(0).put<std::uint32_t>(4000000000U).put(0);
  write_file(folder / "l.ply", bytes.str());
  EXPECT_CONTAINS(point_read_error(folder / "l.ply"), "l.ply: byte ");
}

TEST(PlyReader, APropertyDeclaredTwiceIsRefused) {
  // Reading the first x and skipping the second would drop values silently.
  expect_read_errors(
      "e.ply", {
                   {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
                    "property float x\nend_header\n1 2 3 4\n",
                    "e.ply:7:", "property 'x' of element 'vertex' is declared twice (first at line 4)"},
                   {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
                    "property uchar red\nproperty double red\nend_header\n1 2 3 4 5\n",
                    "e.ply:8:", "property 'red' of element 'vertex' is declared twice"},
                   // Any element: a face with two index lists.
                   {"ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\n"
                    "element face 0\nproperty list uchar int vertex_indices\nproperty list uchar int vertex_indices\n"
                    "end_header\n",
                    "e.ply:9:", "property 'vertex_indices' of element 'face' is declared twice"},
               });
  // The same name in two elements is no duplicate.
  TempFolder folder;
  write_file(folder / "ok.ply",
             "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
             "element extra 1\nproperty float x\nend_header\n1 2 3\n4\n");
  EXPECT_EQ(read_points(folder / "ok.ply").size(), 1U);
}

}  // namespace
}  // namespace recon::io
