// Round trips, one table per kind: clouds that recon writes (xyz, PLY in
// ascii and binary, with and without normals and colours) and reads back bit
// for bit; clouds written the way other programs write them (Hoppe's pts,
// OBJ, NOFF, binary PCD); meshes through PLY, OBJ and OFF, with and without
// colours. Each row of a table is a test of its own.

#include "recon/io/mesh_io.h"
#include "recon/io/point_io.h"

#include "io/io_test_helpers.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>

namespace recon::io {
namespace {

using namespace testing;  // io_test_helpers.h

/// The format, ascii or binary (PLY), and what else a row holds: the name of its test.
std::string describe(const char* file, bool ascii, bool normals, bool colors) {
  std::string name(file);
  name = name.substr(name.find('.') + 1);
  if (name == "ply") name += ascii ? "_ascii" : "_binary";
  if (normals) name += "_normals";
  if (colors) name += "_colours";
  return name;
}

// --------------------------------------------------------------------------
// Clouds recon writes

struct WrittenCloud {
  const char* file;  ///< its extension chooses the format
  bool ascii;        ///< PLY only
  bool normals;
  bool colors;
  std::size_t size;
  std::uint64_t seed;
};

class CloudRoundTrip : public ::testing::TestWithParam<WrittenCloud> {};

TEST_P(CloudRoundTrip, ReadsBackBitForBit) {
  const WrittenCloud& row = GetParam();
  TempFolder folder;
  PointCloud cloud = random_cloud(row.size, row.normals, row.seed);
  if (row.colors) cloud.colors = random_colors(cloud.size(), 4);
  WritePointsOptions options;
  options.ascii = row.ascii;
  write_points(folder / row.file, cloud, options);
  const PointCloud back = read_points(folder / row.file);
  ASSERT_EQ(back.has_normals(), row.normals);
  // Binary doubles are bit for bit; the text is the shortest that reads back exactly.
  expect_same(cloud, back);
  EXPECT_TRUE(back.colors == cloud.colors);
}

INSTANTIATE_TEST_SUITE_P(Formats, CloudRoundTrip,
                         ::testing::Values(WrittenCloud{"r.xyz", false, false, false, 500, 7},
                                           WrittenCloud{"r.xyz", false, true, false, 500, 7},
                                           WrittenCloud{"r.ply", false, false, false, 1000, 2},
                                           WrittenCloud{"r.ply", true, false, false, 1000, 2},
                                           WrittenCloud{"r.ply", false, true, false, 1000, 1},
                                           WrittenCloud{"r.ply", true, true, false, 1000, 1},
                                           WrittenCloud{"c.ply", false, false, true, 500, 3},
                                           WrittenCloud{"c.ply", true, false, true, 500, 3},
                                           WrittenCloud{"c.ply", false, true, true, 500, 3},
                                           WrittenCloud{"c.ply", true, true, true, 500, 3}),
                         [](const ::testing::TestParamInfo<WrittenCloud>& test) {
                           const WrittenCloud& row = test.param;
                           return describe(row.file, row.ascii, row.normals, row.colors);
                         });

// --------------------------------------------------------------------------
// Clouds written the way other programs write them

std::string number(double value) {
  char text[40];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

std::string vec(const Vec3& v) { return number(v.x()) + " " + number(v.y()) + " " + number(v.z()); }

std::string hoppe_pts(const PointCloud& cloud) {
  std::string text = "# test\nd 0 0 0\n";
  for (const Vec3& p : cloud.positions) text += "p " + vec(p) + "\n";
  return text;
}

std::string obj_vertices_and_normals(const PointCloud& cloud) {
  std::string text;
  for (const Vec3& p : cloud.positions) text += "v " + vec(p) + "\n";
  for (const Vec3& n : cloud.normals) text += "vn " + vec(n) + "\n";
  return text;
}

std::string noff(const PointCloud& cloud) {
  std::string text = "NOFF\n" + std::to_string(cloud.size()) + " 0 0\n";
  for (std::size_t i = 0; i < cloud.size(); ++i) text += vec(cloud.positions[i]) + " " + vec(cloud.normals[i]) + "\n";
  return text;
}

std::string binary_pcd_with_normals(const PointCloud& cloud) {
  Bytes bytes;
  bytes.text("FIELDS x y z normal_x normal_y normal_z\nSIZE 8 8 8 8 8 8\nTYPE F F F F F F\nWIDTH " +
             std::to_string(cloud.size()) + "\nDATA binary\n");
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    for (int k = 0; k < 3; ++k) bytes.put(cloud.positions[i][k]);
    for (int k = 0; k < 3; ++k) bytes.put(cloud.normals[i][k]);
  }
  return bytes.str();
}

// Same values to a relative 1e-15 (for text written by the tests themselves).
void expect_close(const PointCloud& expected, const PointCloud& actual) {
  ASSERT_EQ(actual.size(), expected.size());
  ASSERT_EQ(actual.normals.size(), expected.normals.size());
  const auto close = [](const Vec3& a, const Vec3& b) {
    for (int k = 0; k < 3; ++k) {
      if (std::abs(a[k] - b[k]) > 1e-15 * std::max(std::abs(a[k]), std::abs(b[k]))) return false;
    }
    return true;
  };
  for (std::size_t i = 0; i < expected.size(); ++i) {
    ASSERT_TRUE(close(expected.positions[i], actual.positions[i])) << "point " << i;
    if (expected.has_normals()) {
      ASSERT_TRUE(close(expected.normals[i], actual.normals[i])) << "normal " << i;
    }
  }
}

struct ForeignCloud {
  const char* name;  ///< of the test
  const char* file;
  std::size_t size;
  bool normals;
  std::uint64_t seed;
  std::string (*content)(const PointCloud& cloud);
  bool binary;  ///< bit for bit; text of 17 digits reads back to 1e-15
};

class CloudReadBack : public ::testing::TestWithParam<ForeignCloud> {};

TEST_P(CloudReadBack, ReadsTheValuesWritten) {
  const ForeignCloud& row = GetParam();
  TempFolder folder;
  const PointCloud cloud = random_cloud(row.size, row.normals, row.seed);
  write_file(folder / row.file, row.content(cloud));
  if (row.binary) {
    expect_same(cloud, read_points(folder / row.file));
  } else {
    expect_close(cloud, read_points(folder / row.file));
  }
}

INSTANTIATE_TEST_SUITE_P(Formats, CloudReadBack,
                         ::testing::Values(ForeignCloud{"HoppePts", "r.pts", 200, false, 3, hoppe_pts, false},
                                           ForeignCloud{"Obj", "r.obj", 100, true, 11, obj_vertices_and_normals, false},
                                           ForeignCloud{"Noff", "r.off", 100, true, 12, noff, false},
                                           ForeignCloud{"BinaryPcd", "n.pcd", 50, true, 5, binary_pcd_with_normals,
                                                        true}),
                         [](const ::testing::TestParamInfo<ForeignCloud>& test) { return test.param.name; });

// --------------------------------------------------------------------------
// Meshes

struct WrittenMesh {
  const char* file;
  bool ascii;    ///< PLY only
  bool colored;  ///< colored_mesh(), else random_mesh()
};

class MeshRoundTrip : public ::testing::TestWithParam<WrittenMesh> {};

TEST_P(MeshRoundTrip, ReadsBackBitForBit) {
  const WrittenMesh& row = GetParam();
  TempFolder folder;
  const std::filesystem::path path = folder / row.file;
  const Mesh mesh = row.colored ? colored_mesh(300, 7) : random_mesh(300, 500, 21);
  WriteMeshOptions options;
  options.ascii = row.ascii;
  write_mesh(path, mesh, options);
  const Mesh back = read_mesh(path);
  expect_same(mesh, back);
  if (row.colored) {
    EXPECT_TRUE(back.colors == mesh.colors) << "OBJ's 4 decimals read back as the same byte";
    // Its vertices read as a coloured cloud too.
    EXPECT_TRUE(read_points(path).colors == mesh.colors);
  }
}

INSTANTIATE_TEST_SUITE_P(Formats, MeshRoundTrip,
                         ::testing::Values(WrittenMesh{"m.ply", false, false}, WrittenMesh{"a.ply", true, false},
                                           WrittenMesh{"m.obj", false, false}, WrittenMesh{"m.off", false, false},
                                           WrittenMesh{"m.ply", false, true}, WrittenMesh{"m.ply", true, true},
                                           WrittenMesh{"m.obj", false, true}),
                         [](const ::testing::TestParamInfo<WrittenMesh>& test) {
                           const WrittenMesh& row = test.param;
                           return describe(row.file, row.ascii, false, row.colored);
                         });

}  // namespace
}  // namespace recon::io
