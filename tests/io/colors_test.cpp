// Colours through the formats (src/io/colors.h): PLY's red, green, blue of
// every scalar type and the rule that makes them 0-255, where PLY writes them,
// OBJ's "v x y z r g b", OFF's COFF, xyz's columns, STL's lack of them, and
// the checks before writing. (The round trips of coloured clouds and meshes
// through PLY and OBJ are in round_trip_test.cpp.)

#include "recon/io/mesh_io.h"
#include "recon/io/point_io.h"

#include "io/io_test_helpers.h"
#include "recon/core/errors.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace recon::io {
namespace {

using namespace testing;  // io_test_helpers.h

// One triangle, its vertices red-ish, a dark blue and black.
Mesh colored_triangle() {
  Mesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1.5, 0}};
  mesh.triangles = {{0, 1, 2}};
  mesh.colors = {{255, 0, 128}, {1, 254, 51}, {0, 0, 0}};
  return mesh;
}

// An ascii PLY of two vertices whose colours are stored as `type`, with
// the values given (three a vertex), and an alpha after them.
std::string ascii_ply(const std::string& type, const std::string& first, const std::string& second,
                      const std::string& names = "red green blue") {
  std::string header =
      "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n";
  std::size_t start = 0;
  for (int c = 0; c < 3; ++c) {
    const std::size_t end = names.find(' ', start);
    header += "property " + type + " " + names.substr(start, end - start) + "\n";
    start = end + 1;
  }
  return header + "property " + type + " alpha\nend_header\n0 0 0 " + first + " 0\n1 1 1 " + second + " 0\n";
}

TEST(ColorRead, EachTypeBecomesZeroTo255ByItsRule) {
  TempFolder folder;
  struct Case {
    const char* type;
    const char* first;
    const char* second;
    Color expected_first, expected_second;
  };
  for (const Case& c : {
           Case{"uchar", "0 128 255", "1 2 3", {0, 128, 255}, {1, 2, 3}},
           Case{"char", "-5 0 127", "1 2 3", {0, 0, 127}, {1, 2, 3}},                 // negative: 0
           Case{"ushort", "0 257 65535", "32896 128 129", {0, 1, 255}, {128, 0, 1}},  // v / 257, rounded
           Case{"short", "-1 257 32767", "0 0 0", {0, 1, 127}, {0, 0, 0}},
           Case{"int", "0 200 300", "-7 12 255", {0, 200, 255}, {0, 12, 255}},         // as they are, clamped
           Case{"float", "0 0.5 1", "0.25 0.002 0.998", {0, 128, 255}, {64, 1, 254}},  // x 255, rounded
           Case{"double", "0 0.5 1", "nan -0.5 0.1", {0, 128, 255}, {0, 0, 26}},       // NaN 0, clamped
           // A value above 1: the file's floating-point colours are 0-255.
           Case{"float", "0 0.5 1", "2 128 255", {0, 1, 1}, {2, 128, 255}},
       }) {
    write_file(folder / "c.ply", ascii_ply(c.type, c.first, c.second));
    const PointCloud cloud = read_points(folder / "c.ply");
    ASSERT_TRUE(cloud.has_colors()) << c.type;
    ASSERT_EQ(cloud.colors.size(), 2U);
    EXPECT_EQ(cloud.colors[0], c.expected_first) << c.type << ": " << c.first;
    EXPECT_EQ(cloud.colors[1], c.expected_second) << c.type << ": " << c.second;
  }
}

TEST(ColorRead, DiffuseNamesAndOnlyWhenAllThreeArePresent) {
  TempFolder folder;
  write_file(folder / "d.ply", ascii_ply("uchar", "1 2 3", "4 5 6", "diffuse_red diffuse_green diffuse_blue"));
  PointCloud cloud = read_points(folder / "d.ply");
  ASSERT_TRUE(cloud.has_colors());
  EXPECT_EQ(cloud.colors[1], (Color{4, 5, 6}));
  // red and green only: no colours, and the file reads.
  write_file(folder / "p.ply", ascii_ply("uchar", "1 2 3", "4 5 6", "red green confidence"));
  cloud = read_points(folder / "p.ply");
  EXPECT_FALSE(cloud.has_colors());
  EXPECT_EQ(cloud.size(), 2U);
  // The plain names win over the diffuse ones when both are there.
  write_file(folder / "b.ply",
             "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
             "property uchar diffuse_red\nproperty uchar diffuse_green\nproperty uchar diffuse_blue\n"
             "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n0 0 0 1 2 3 7 8 9\n");
  cloud = read_points(folder / "b.ply");
  ASSERT_TRUE(cloud.has_colors());
  EXPECT_EQ(cloud.colors[0], (Color{7, 8, 9}));
}

// Binary records in both byte orders, the colours among other properties
// and in another order than red, green, blue.
TEST(ColorRead, BinaryUcharUshortAndFloatInEitherByteOrder) {
  TempFolder folder;
  for (const bool big : {false, true}) {
    Bytes bytes(big);
    bytes.ply_header(
        "element vertex 2\nproperty ushort blue\nproperty double x\nproperty uchar red\n"
        "property double y\nproperty float green\nproperty double z\nproperty uchar alpha\n");
    bytes.put<std::uint16_t>(65535).put(1.0).put<std::uint8_t>(10).put(2.0).put(0.5F).put(3.0).put<std::uint8_t>(9);
    bytes.put<std::uint16_t>(0).put(4.0).put<std::uint8_t>(255).put(5.0).put(1.0F).put(6.0).put<std::uint8_t>(9);
    write_file(folder / "b.ply", bytes.str());
    const PointCloud cloud = read_points(folder / "b.ply");
    ASSERT_EQ(cloud.size(), 2U);
    EXPECT_EQ(cloud.positions[1], Vec3(4, 5, 6));
    ASSERT_TRUE(cloud.has_colors());
    // One channel is a float: all three follow the floating-point rule,
    // and with values above 1 they are 0-255 as they are.
    EXPECT_EQ(cloud.colors[0], (Color{10, 1, 255})) << (big ? "big" : "little") << " endian";
    EXPECT_EQ(cloud.colors[1], (Color{255, 1, 0}));
  }
  Bytes bytes;
  bytes.text(
      "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
      "property float z\nproperty ushort red\nproperty ushort green\nproperty ushort blue\nend_header\n");
  bytes.put(1.0F).put(2.0F).put(3.0F).put<std::uint16_t>(65535).put<std::uint16_t>(32768).put<std::uint16_t>(128);
  write_file(folder / "u.ply", bytes.str());
  EXPECT_EQ(read_points(folder / "u.ply").colors[0], (Color{255, 128, 0}));
}

TEST(ColorIo, PlyWritesTheColoursAfterTheOtherVertexProperties) {
  TempFolder folder;
  for (const bool normals : {false, true}) {
    for (const bool ascii : {false, true}) {
      PointCloud cloud = random_cloud(500, normals, 3);
      cloud.colors = random_colors(cloud.size(), 4);
      WritePointsOptions options;
      options.ascii = ascii;
      write_points(folder / "c.ply", cloud, options);
      const std::string content = read_bytes(folder / "c.ply");
      EXPECT_CONTAINS(content, std::string(normals ? "property double nz\n" : "property double z\n") +
                                   "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n");
      if (!ascii) {
        EXPECT_EQ(content.size() - (content.find("end_header\n") + 11), 500U * ((normals ? 48U : 24U) + 3U));
      }
    }
  }
  // Without colours, no colour properties.
  write_points(folder / "n.ply", random_cloud(5, false, 5));
  EXPECT_EQ(read_bytes(folder / "n.ply").find("red"), std::string::npos);
}

TEST(ColorIo, ObjWritesColoursInZeroToOne) {
  TempFolder folder;
  Mesh mesh = colored_triangle();
  write_mesh(folder / "m.obj", mesh);
  const std::string content = read_bytes(folder / "m.obj");
  EXPECT_CONTAINS(content, "\nv 0 0 0 1 0 0.502\nv 1 0 0 0.0039 0.9961 0.2\nv 0 1.5 0 0 0 0\nf 1 2 3\n");
  mesh.colors.clear();
  write_mesh(folder / "plain.obj", mesh);
  EXPECT_CONTAINS(read_bytes(folder / "plain.obj"), "\nv 0 0 0\nv 1 0 0\nv 0 1.5 0\nf 1 2 3\n");
}

TEST(ColorRead, ObjColoursOnlyWhenEveryVertexHasThem) {
  TempFolder folder;
  PointCloud cloud = write_and_read(folder, "a.obj", "v 0 0 0 1 0 0\nv 1 0 0 0 0.5 1\nv 0 1 0 0 0 0\n");
  ASSERT_TRUE(cloud.has_colors());
  EXPECT_EQ(cloud.colors[1], (Color{0, 128, 255}));
  // A w weight, a vertex without a colour, or something other than numbers: none.
  for (const char* content : {"v 0 0 0 1\nv 1 0 0 1\nv 0 1 0 1\n", "v 0 0 0 1 0 0\nv 1 0 0\nv 0 1 0 1 0 0\n",
                              "v 0 0 0 1 0 0\nv 1 0 0 1 0 x\nv 0 1 0 1 0 0\n", "v 0 0 0 1 0 0 1\nv 1 0 0 1 0 0 1\n"}) {
    write_file(folder / "b.obj", content);
    cloud = read_points(folder / "b.obj");
    EXPECT_FALSE(cloud.has_colors()) << content;
    EXPECT_GE(cloud.size(), 2U);
  }
}

TEST(ColorIo, OffWritesCoffAndStlDropsTheColours) {
  TempFolder folder;
  Mesh mesh = colored_triangle();
  write_mesh(folder / "m.off", mesh);
  const std::string off = read_bytes(folder / "m.off");
  EXPECT_EQ(off.rfind("COFF\n", 0), 0U);
  EXPECT_CONTAINS(off, "\n3 1 0\n0 0 0 255 0 128 255\n1 0 0 1 254 51 255\n0 1.5 0 0 0 0 255\n3 0 1 2\n");
  const Mesh back = read_mesh(folder / "m.off");  // read without its colours
  EXPECT_TRUE(back.vertices == mesh.vertices);
  EXPECT_TRUE(back.triangles == mesh.triangles);

  write_mesh(folder / "c.stl", mesh);
  mesh.colors.clear();
  write_mesh(folder / "p.stl", mesh);
  EXPECT_EQ(read_bytes(folder / "c.stl"), read_bytes(folder / "p.stl"));
  write_mesh(folder / "p.off", mesh);
  EXPECT_EQ(read_bytes(folder / "p.off").rfind("OFF\n", 0), 0U);
}

TEST(ColorIo, XyzWritesThreeByteColumnsAfterTheNormals) {
  TempFolder folder;
  PointCloud cloud;
  cloud.positions = {{1, 2, 3}, {-4, 5.5, 6}};
  cloud.colors = {{255, 0, 7}, {1, 2, 3}};
  write_points(folder / "c.xyz", cloud);
  EXPECT_EQ(read_bytes(folder / "c.xyz"), "1 2 3 255 0 7\n-4 5.5 6 1 2 3\n");
  cloud.normals = {{0, 0, 1}, {1, 0, 0}};
  write_points(folder / "n.xyz", cloud);
  EXPECT_EQ(read_bytes(folder / "n.xyz"), "1 2 3 0 0 1 255 0 7\n-4 5.5 6 1 0 0 1 2 3\n");
}

TEST(ColorIo, WritersRefuseColoursThatAreNotOnePerPointOrVertex) {
  TempFolder folder;
  PointCloud cloud = random_cloud(4, false, 1);
  cloud.colors = random_colors(3, 1);
  for (const char* name : {"c.ply", "c.xyz"})
    EXPECT_CONTAINS(message_of<InvalidInputError>([&] { write_points(folder / name, cloud); }),
                    "3 colours for 4 points");
  Mesh mesh = colored_mesh(5, 2);
  mesh.colors.pop_back();
  for (const char* name : {"m.ply", "m.obj", "m.off", "m.stl"})
    EXPECT_CONTAINS(message_of<InvalidInputError>([&] { write_mesh(folder / name, mesh); }),
                    "4 colours for 5 vertices");
  EXPECT_TRUE(folder.entries().empty());
}

}  // namespace
}  // namespace recon::io
