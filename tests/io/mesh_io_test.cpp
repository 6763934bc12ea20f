// read_mesh / write_mesh: the bytes of binary STL, the polygon and index
// variants of each reader, and their errors. (The round trips through PLY,
// OBJ and OFF are in round_trip_test.cpp.)

#include "recon/io/mesh_io.h"
#include "recon/io/point_io.h"

#include "recon/structures/mesh.h"

#include "io/io_test_helpers.h"
#include "recon/core/errors.h"

#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <random>
#include <string>

namespace recon::io {
namespace {

using namespace testing;  // io_test_helpers.h

TEST(MeshIo, FormatFromExtension) {
  expect_formats<MeshFormat>(
      mesh_format_from_path,
      {{"a.ply", MeshFormat::ply}, {"a.OBJ", MeshFormat::obj}, {"a.off", MeshFormat::off}, {"a.stl", MeshFormat::stl}});
  expect_message<InvalidInputError>([] { static_cast<void>(mesh_format_from_path("a.vtk")); },
                                    {"a.vtk", ".ply, .obj, .off, .stl"});
}

TEST(MeshIo, NamedFormatOverridesTheExtension) {
  TempFolder folder;
  const Mesh mesh = random_mesh(300, 500, 21);
  write_mesh(folder / "named.txt", mesh, {.format = MeshFormat::off});
  EXPECT_EQ(testing::read_bytes(folder / "named.txt").rfind("OFF\n", 0), 0U);
}

TEST(MeshIo, MeshPlyReadsAsAPointCloudToo) {
  TempFolder folder;
  const Mesh mesh = random_mesh(50, 80, 4);
  write_mesh(folder / "m.ply", mesh);
  EXPECT_EQ(read_mesh(folder / "m.ply").vertices.size(), 50U);
}

TEST(MeshIo, BinaryStlBytes) {
  TempFolder folder;
  Mesh mesh;
  mesh.vertices = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {0, 0, 2}};
  mesh.triangles = {{0, 1, 2}, {0, 0, 3}};  // the second is degenerate: zero normal
  write_mesh(folder / "m.stl", mesh);
  const std::string bytes = testing::read_bytes(folder / "m.stl");
  ASSERT_EQ(bytes.size(), 84U + 2U * 50U);
  EXPECT_NE(bytes.rfind("solid", 0), 0U);
  std::uint32_t count = 0;
  std::memcpy(&count, bytes.data() + 80, 4);
  EXPECT_EQ(count, 2U);
  float values[12];
  std::memcpy(values, bytes.data() + 84, sizeof values);
  const float expected[12] = {0, 0, 1, 0, 0, 0, 2, 0, 0, 0, 2, 0};
  for (int k = 0; k < 12; ++k) EXPECT_EQ(values[k], expected[k]) << k;
  std::memcpy(values, bytes.data() + 134, sizeof values);
  EXPECT_EQ(values[0], 0.0F);
  EXPECT_EQ(values[1], 0.0F);
  EXPECT_EQ(values[2], 0.0F);
  EXPECT_EQ(values[11], 2.0F);
}

TEST(MeshIo, StlRefusesCoordinatesBeyondFloat) {
  TempFolder folder;
  Mesh mesh;
  mesh.vertices = {{0, 0, 0}, {1e39, 0, 0}, {0, 1, 0}};
  mesh.triangles = {{0, 1, 2}};
  EXPECT_THROW(write_mesh(folder / "m.stl", mesh), InvalidInputError);
  EXPECT_TRUE(folder.entries().empty());
}

TEST(MeshIo, ReadingStlIsRefused) {
  EXPECT_CONTAINS(message_of<InvalidInputError>([] { static_cast<void>(read_mesh("m.stl")); }), "STL");
}

TEST(MeshIo, WriteRefusesBadMeshes) {
  TempFolder folder;
  Mesh mesh = random_mesh(4, 2, 1);
  mesh.triangles.push_back({0, 1, 4});
  EXPECT_CONTAINS(message_of<InvalidInputError>([&] { write_mesh(folder / "m.ply", mesh); }), "uses vertex 4");
  mesh = random_mesh(4, 2, 1);
  mesh.vertices[2].z() = std::numeric_limits<double>::infinity();
  EXPECT_CONTAINS(message_of<InvalidInputError>([&] { write_mesh(folder / "m.obj", mesh); }), "vertex 2");
  EXPECT_TRUE(folder.entries().empty());
}

TEST(MeshIo, ObjCornerFormsNegativeIndicesAndPolygons) {
  TempFolder folder;
  write_file(folder / "a.obj",
             "# square and a triangle\n"
             "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
             "vt 0 0\nvn 0 0 1\n"
             "g square\nusemtl red\ns off\n"
             "f 1/1/1 2/1/1 3/1/1 4/1/1\n"
             "v 2 0 0\n"
             "f -1//1 -4//1 -3//1\n"
             "f 1/1 2 5\n");
  const Mesh mesh = read_mesh(folder / "a.obj");
  ASSERT_EQ(mesh.vertices.size(), 5U);
  ASSERT_EQ(mesh.triangles.size(), 4U);
  EXPECT_EQ(mesh.triangles[0], (std::array<std::uint32_t, 3>{0, 1, 2}));
  EXPECT_EQ(mesh.triangles[1], (std::array<std::uint32_t, 3>{0, 2, 3}));
  EXPECT_EQ(mesh.triangles[2], (std::array<std::uint32_t, 3>{4, 1, 2}));
  EXPECT_EQ(mesh.triangles[3], (std::array<std::uint32_t, 3>{0, 1, 4}));
}

TEST(MeshIo, OffPolygonsWithColours) {
  TempFolder folder;
  write_file(folder / "a.off", "OFF 5 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n2 0 0\n4 0 1 2 3 255 0 0\n3 1 4 2\n");
  const Mesh mesh = read_mesh(folder / "a.off");
  ASSERT_EQ(mesh.triangles.size(), 3U);
  EXPECT_EQ(mesh.triangles[1], (std::array<std::uint32_t, 3>{0, 2, 3}));
  EXPECT_EQ(mesh.triangles[2], (std::array<std::uint32_t, 3>{1, 4, 2}));
}

TEST(MeshIo, PlyFacesFirstWithOtherIndexTypes) {
  TempFolder folder;
  for (const bool big : {false, true}) {
    Bytes bytes(big);
    bytes.ply_header(
        "element face 2\nproperty uchar flags\nproperty list ushort uchar vertex_index\n"
        "element vertex 4\nproperty float x\nproperty float y\nproperty float z\n");
    bytes.put<std::uint8_t>(1).put<std::uint16_t>(3).put<std::uint8_t>(0).put<std::uint8_t>(1).put<std::uint8_t>(2);
    bytes.put<std::uint8_t>(1).put<std::uint16_t>(4).put<std::uint8_t>(3).put<std::uint8_t>(2).put<std::uint8_t>(1);
    bytes.put<std::uint8_t>(0);
    for (int i = 0; i < 4; ++i) bytes.put(1.0F * static_cast<float>(i)).put(0.0F).put(0.0F);
    write_file(folder / "f.ply", bytes.str());
    const Mesh mesh = read_mesh(folder / "f.ply");
    ASSERT_EQ(mesh.vertices.size(), 4U);
    ASSERT_EQ(mesh.triangles.size(), 3U);
    EXPECT_EQ(mesh.triangles[2], (std::array<std::uint32_t, 3>{3, 1, 0}));
  }
}

TEST(MeshIo, PlyAsciiMesh) {
  TempFolder folder;
  write_file(folder / "a.ply",
             "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\n"
             "element face 1\nproperty list uint int vertex_indices\nproperty float quality\nend_header\n"
             "0 0 0\n1 0 0\n0 1 0\n3 2 1 0 0.5\n");
  const Mesh mesh = read_mesh(folder / "a.ply");
  ASSERT_EQ(mesh.triangles.size(), 1U);
  EXPECT_EQ(mesh.triangles[0], (std::array<std::uint32_t, 3>{2, 1, 0}));
}

TEST(MeshIo, Errors) {
  const std::string ply_header =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\n"
      "property double z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n";
  const bool mesh = true;
  expect_read_errors(
      "e.ply",
      {
          {ply_header + "3 0 1 3\n", "e.ply:13:", "uses vertex 3"},
          {ply_header + "3 0 -1 2\n", "e.ply:13:", "uses vertex -1"},
          {ply_header + "2 0 1\n", "e.ply:13:", "at least 3"},
          {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float "
           "z\nend_header\n1 2 3\n",
           "e.ply:7:", "no 'face' element"},
          {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
           "element face 0\nproperty list uchar int corners\nend_header\n1 2 3\n",
           "e.ply:7:", "'vertex_indices'"},
      },
      mesh);
  expect_read_errors(
      "e.obj",
      {
          {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\nv 1 1 1\nv 2 2 2\nf 1 2 7\n", "e.obj:7:", "uses vertex 7"},
          {"v 0 0 0\nv 1 0 0\nf 1 2 -3\n", "e.obj:3:", "refers back 3"},
          {"v 0 0 0\nv 1 0 0\nf 1 2 0\n", "e.obj:3:", "'0'"},
          {"v 0 0 0\nv 1 0 0\nf 1 2\n", "e.obj:3:", "at least 3"},
          {"v 0 0 0\nv 1 0 0\nv 0 1 0\n", "e.obj", "no triangles"},
      },
      mesh);
  expect_read_errors("e.off",
                     {
                         {"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", "e.off:6:", "not a vertex number"},
                         {"OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "e.off:6:", "promises 2"},
                         {"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4 0 1 2\n", "e.off:6:", "lists 3"},
                         {"OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n", "e.off", "no triangles"},
                     },
                     mesh);
}

// A mesh reader counts bad coordinates as vertices; the point reader of the
// same file counts them as points.
TEST(MeshIo, NonFiniteCoordinatesAreCountedAsVertices) {
  TempFolder folder;
  const std::pair<const char*, std::string> files[] = {
      {"v.ply",
       "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\n"
       "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 nan 0\n0 1 inf\n3 0 1 2\n"},
      {"v.obj", "v 0 0 0\nv 1 nan 0\nv 0 1 inf\nf 1 2 3\n"},
      {"v.off", "OFF\n3 1 0\n0 0 0\n1 nan 0\n0 1 inf\n3 0 1 2\n"},
  };
  for (const auto& [name, content] : files) {
    write_file(folder / name, content);
    EXPECT_CONTAINS(mesh_read_error(folder / name),
                    ": 2 vertices have a coordinate that is not finite or beyond +-1e+15");
    const std::string as_points = message_of<ParseError>([&] { static_cast<void>(read_points(folder / name)); });
    EXPECT_CONTAINS(as_points, ": 2 points have a coordinate that is not finite or beyond +-1e+15");
  }
  write_file(folder / "one.obj", "v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n");
  EXPECT_CONTAINS(mesh_read_error(folder / "one.obj"), ": 1 vertex has a coordinate");
  // Binary PLY too.
  Mesh mesh;
  mesh.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  mesh.triangles = {{0, 1, 2}};
  write_mesh(folder / "b.ply", mesh);
  std::string bytes = read_bytes(folder / "b.ply");
  const std::size_t body = bytes.find("end_header\n") + 11;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::memcpy(bytes.data() + body + 3 * sizeof(double), &nan, sizeof nan);  // vertex 1's x
  write_file(folder / "b.ply", bytes);
  EXPECT_CONTAINS(mesh_read_error(folder / "b.ply"), ": 1 vertex has a coordinate that is not finite");
}

TEST(MeshIo, BinaryPlyIndexOutOfRangeSaysWhere) {
  TempFolder folder;
  Bytes bytes;
  bytes.text(
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n");
  for (int i = 0; i < 9; ++i) bytes.put(0.0F);
  const std::size_t face = bytes.size();
  bytes.put<std::uint8_t>(3).put(0).put(1).put(3);
  write_file(folder / "b.ply", bytes.str());
  const std::string message = mesh_read_error(folder / "b.ply");
  EXPECT_CONTAINS(message, "b.ply: byte " + std::to_string(face + 9) + ":");
  EXPECT_CONTAINS(message, "face 0");
}

TEST(MeshIoRealData, StanfordBunnyAsAMesh) {
  const std::filesystem::path path = std::filesystem::path(RECON_SHARED_DATA_DIR) / "stanford_bunny" / "bun_zipper.ply";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is absent; the real-data test is skipped";
  const Mesh bunny = read_mesh(path);
  EXPECT_EQ(bunny.vertices.size(), 35947U);
  EXPECT_EQ(bunny.triangles.size(), 69451U);
  // One piece of genus 0 with five holes in its base: chi = 2 - 5. (Some
  // vertices of the scan are used by no triangle.)
  const MeshTopology topology = analyze_topology(bunny);
  EXPECT_EQ(topology.components, 1U);
  EXPECT_EQ(topology.boundary_loops, 5U);
  EXPECT_EQ(topology.euler_characteristic, -3);
  EXPECT_EQ(topology.non_manifold_edges, 0U);
  EXPECT_EQ(topology.inconsistent_edges, 0U);
  EXPECT_GT(topology.signed_volume, 0.0);

  TempFolder folder;
  write_mesh(folder / "bunny.ply", bunny);
  expect_same(bunny, read_mesh(folder / "bunny.ply"));
}

}  // namespace
}  // namespace recon::io
