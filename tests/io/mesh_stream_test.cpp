// PlyMeshStream against write_mesh, its oracle: the same mesh written both
// ways gives the same bytes, with and without colours, small and large
// enough to fill several blocks; an unfinished stream leaves nothing behind;
// and its errors are typed and name the file.

#include "recon/io/mesh_stream.h"

#include "io/io_test_helpers.h"
#include "recon/core/errors.h"
#include "recon/io/mesh_io.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace recon::io {
namespace {

using namespace testing;  // io_test_helpers.h

std::uint32_t last_corner(const std::array<std::uint32_t, 3>& t) { return std::max({t[0], t[1], t[2]}); }

/// `mesh` with its triangles in the order of their last corner (stable).
Mesh by_last_corner(Mesh mesh) {
  std::stable_sort(mesh.triangles.begin(), mesh.triangles.end(),
                   [](const auto& a, const auto& b) { return last_corner(a) < last_corner(b); });
  return mesh;
}

/// Writes `mesh`, whose triangles come in the order of their last corner,
/// through a PlyMeshStream, the triangles interleaved with the vertices
/// (each as soon as its last corner is there, as a tiled writer would), and
/// returns the file's bytes.
std::string streamed_bytes(const std::filesystem::path& path, const Mesh& mesh) {
  PlyMeshStream stream(path, mesh.has_colors());
  std::size_t t = 0;
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    const std::uint32_t index =
        mesh.has_colors() ? stream.add_vertex(mesh.vertices[v], mesh.colors[v]) : stream.add_vertex(mesh.vertices[v]);
    EXPECT_EQ(index, v);
    for (; t < mesh.triangles.size() && last_corner(mesh.triangles[t]) == v; ++t)
      stream.add_triangle(mesh.triangles[t]);
  }
  EXPECT_EQ(t, mesh.triangles.size());
  EXPECT_EQ(stream.vertex_count(), mesh.vertices.size());
  EXPECT_EQ(stream.triangle_count(), mesh.triangles.size());
  stream.finish();
  return read_bytes(path);
}

std::string written_bytes(const std::filesystem::path& path, const Mesh& mesh) {
  write_mesh(path, mesh);
  return read_bytes(path);
}

TEST(PlyMeshStream, WritesTheBytesOfWriteMesh) {
  TempFolder folder;
  const std::vector<Mesh> meshes = {
      by_last_corner(random_mesh(50, 80, 1)),
      colored_mesh(60, 2),
      by_last_corner(random_mesh(120'000, 250'000, 3)),  // several blocks of each part
      colored_mesh(150'000, 4),
      Mesh{},  // no vertex, no triangle
  };
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    SCOPED_TRACE("mesh " + std::to_string(m));
    const std::string expected = written_bytes(folder / "expected.ply", meshes[m]);
    const std::string streamed = streamed_bytes(folder / "streamed.ply", meshes[m]);
    EXPECT_EQ(streamed.size(), expected.size());
    EXPECT_TRUE(streamed == expected) << "the files differ";
    EXPECT_EQ(folder.entries(), (std::vector<std::string>{"expected.ply", "streamed.ply"}));  // no temporary left
  }
}

TEST(PlyMeshStream, UnfinishedLeavesNoFileAndNoTemporary) {
  TempFolder folder;
  const Mesh mesh = colored_mesh(200'000, 5);
  {
    PlyMeshStream stream(folder / "m.ply", true);
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v) stream.add_vertex(mesh.vertices[v], mesh.colors[v]);
    for (const auto& t : mesh.triangles) stream.add_triangle(t);
    EXPECT_EQ(folder.entries().size(), 3U);  // the output's temporary and the two parts
  }
  EXPECT_TRUE(folder.entries().empty());
  // An older file at the path stays as it was.
  write_file(folder / "m.ply", "old");
  {
    PlyMeshStream stream(folder / "m.ply", false);
    stream.add_vertex(Vec3(1, 2, 3));
  }
  EXPECT_EQ(folder.entries(), std::vector<std::string>{"m.ply"});
  EXPECT_EQ(read_bytes(folder / "m.ply"), "old");
}

TEST(PlyMeshStream, ErrorsAreTypedAndNameTheFile) {
  TempFolder folder;
  const std::filesystem::path nowhere = folder / "missing" / "m.ply";
  EXPECT_CONTAINS(message_of<IoError>([&] { PlyMeshStream stream(nowhere, false); }), nowhere.string());

  const std::filesystem::path path = folder / "m.ply";
  PlyMeshStream stream(path, false);
  EXPECT_CONTAINS(message_of<InvalidInputError>([&] { stream.add_vertex(Vec3(0, std::nan(""), 0)); }),
                  path.string() + ": cannot write: vertex 0 has a coordinate that is not finite");
  EXPECT_CONTAINS(message_of<InvalidInputError>([&] { stream.add_vertex(Vec3(2e15, 0, 0)); }), "beyond");
  EXPECT_CONTAINS(message_of<InvalidInputError>([&] {
                    stream.add_vertex(Vec3(0, 0, 0), Color{1, 2, 3});
                  }),
                  "opened without colours");
  stream.add_vertex(Vec3(0, 0, 0));
  stream.add_vertex(Vec3(1, 0, 0));
  stream.add_triangle({0, 1, 5});
  stream.add_triangle({0, 1, 7});
  stream.add_triangle({7, 1, 0});
  stream.add_vertex(Vec3(0, 1, 0));
  EXPECT_CONTAINS(message_of<InvalidInputError>([&] { stream.finish(); }),
                  path.string() + ": cannot write: triangle 1 uses vertex 7, but the mesh has 3 vertices");
  EXPECT_FALSE(std::filesystem::exists(path));
  // The vertices may still come.
  for (int v = 3; v <= 7; ++v) stream.add_vertex(Vec3(v, 0, 0));
  stream.finish();
  EXPECT_TRUE(std::filesystem::exists(path));
  EXPECT_CONTAINS(message_of<InvalidInputError>([&] { stream.add_vertex(Vec3(0, 0, 1)); }), "finished");

  PlyMeshStream colored(folder / "c.ply", true);
  EXPECT_CONTAINS(message_of<InvalidInputError>([&] { colored.add_vertex(Vec3(0, 0, 0)); }), "has no colour");
}

}  // namespace
}  // namespace recon::io
