// write_mesh to .glb (src/io/glb.cpp): the file parsed back by hand (the
// header, the chunks and their alignment, the JSON's views and accessors)
// and its buffer compared with the mesh value for value. The Khronos
// validator and three.js check the program's files too (web/tests/glb_*).

#include "recon/io/mesh_io.h"
#include "recon/phase5_refine/vertex_normals.h"

#include "io/io_test_helpers.h"
#include "recon/core/errors.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace recon::io {
namespace {

using namespace testing;  // io_test_helpers.h

std::uint32_t u32_at(const std::string& bytes, std::size_t at) {
  std::uint32_t v = 0;
  for (std::size_t i = 0; i < 4; ++i) v |= std::uint32_t{static_cast<std::uint8_t>(bytes[at + i])} << (8 * i);
  return v;
}

float float_at(const std::string& bytes, std::size_t at) {
  const std::uint32_t bits = u32_at(bytes, at);
  float f = 0.0f;
  std::memcpy(&f, &bits, 4);
  return f;
}

struct Accessor {
  std::size_t view = 0, component = 0, count = 0;
  std::string type;
};
struct View {
  std::size_t offset = 0, length = 0, stride = 0;
};

// A GLB file taken apart: its JSON, its buffer, the views and accessors.
struct Glb {
  std::string json, bin;
  std::vector<View> views;
  std::vector<Accessor> accessors;
};

// The JSON is read with plain string searches (std::regex trips GCC 12's
// -Wmaybe-uninitialized in the sanitizer build): each object that starts
// with `start`, up to its first '}' (the writer's objects of views and
// accessors hold no nested object before their fields end).
std::vector<std::string> objects_from(const std::string& json, const std::string& start) {
  std::vector<std::string> objects;
  for (std::size_t at = json.find(start); at != std::string::npos; at = json.find(start, at + 1))
    objects.push_back(json.substr(at, json.find('}', at) - at));
  return objects;
}

// The number after "key": in `object` (0 when the key is absent).
double number_of(const std::string& object, const std::string& key) {
  const std::size_t at = object.find("\"" + key + "\":");
  return at == std::string::npos ? 0.0 : std::strtod(object.c_str() + at + key.size() + 3, nullptr);
}
std::size_t whole(const std::string& object, const std::string& key) {
  return static_cast<std::size_t>(number_of(object, key));
}

// The string after "key": in `object`.
std::string text_of(const std::string& object, const std::string& key) {
  const std::size_t at = object.find("\"" + key + "\":\"");
  if (at == std::string::npos) return {};
  const std::size_t from = at + key.size() + 4;
  return object.substr(from, object.find('"', from) - from);
}

// The three numbers of the array after "key":[ in `json`.
std::array<double, 3> triple_of(const std::string& json, const std::string& key) {
  std::array<double, 3> values{};
  const std::size_t at = json.find("\"" + key + "\":[");
  EXPECT_NE(at, std::string::npos) << key;
  if (at == std::string::npos) return values;
  const char* p = json.c_str() + at + key.size() + 4;
  for (double& v : values) {
    char* end = nullptr;
    v = std::strtod(p, &end);
    p = end + 1;  // past the ',' or ']'
  }
  return values;
}

Glb parse(const std::string& file) {
  Glb g;
  EXPECT_GE(file.size(), 20u);
  EXPECT_EQ(u32_at(file, 0), 0x46546C67u) << "magic glTF";
  EXPECT_EQ(u32_at(file, 4), 2u) << "version";
  EXPECT_EQ(u32_at(file, 8), file.size()) << "total length";
  const std::uint32_t json_length = u32_at(file, 12);
  EXPECT_EQ(u32_at(file, 16), 0x4E4F534Au) << "JSON chunk";
  EXPECT_EQ(json_length % 4, 0u);
  g.json = file.substr(20, json_length);
  const std::size_t bin_at = 20 + json_length;
  if (bin_at < file.size()) {
    const std::uint32_t bin_length = u32_at(file, bin_at);
    EXPECT_EQ(u32_at(file, bin_at + 4), 0x004E4942u) << "BIN chunk";
    EXPECT_EQ(bin_length % 4, 0u);
    EXPECT_EQ(bin_at + 8 + bin_length, file.size());
    g.bin = file.substr(bin_at + 8, bin_length);
  }
  for (const std::string& view : objects_from(g.json, "{\"buffer\":0,"))
    g.views.push_back({whole(view, "byteOffset"), whole(view, "byteLength"), whole(view, "byteStride")});
  for (const std::string& accessor : objects_from(g.json, "{\"bufferView\":"))
    g.accessors.push_back({whole(accessor, "bufferView"), whole(accessor, "componentType"), whole(accessor, "count"),
                           text_of(accessor, "type")});
  return g;
}

std::vector<Color> some_colors(std::size_t n) {
  std::vector<Color> colors(n);
  for (std::size_t v = 0; v < n; ++v)
    colors[v] = {static_cast<std::uint8_t>(v * 7), static_cast<std::uint8_t>(255 - v),
                 static_cast<std::uint8_t>(v * v)};
  return colors;
}

// Random vertices within +-1000 (where float rounding shows) and triangles
// of three distinct random corners, with unit normals: the faces' for most
// vertices, another for every seventh.
Mesh unit_normals(std::size_t vertices, std::size_t triangles, std::uint64_t seed) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> coordinate(-1000.0, 1000.0);
  std::uniform_int_distribution<std::uint32_t> index(0, static_cast<std::uint32_t>(vertices - 1));
  Mesh mesh;
  for (std::size_t v = 0; v < vertices; ++v)
    mesh.vertices.emplace_back(coordinate(random), coordinate(random), coordinate(random));
  while (mesh.triangles.size() < triangles) {
    const std::array<std::uint32_t, 3> t{index(random), index(random), index(random)};
    if (t[0] != t[1] && t[1] != t[2] && t[2] != t[0]) mesh.triangles.push_back(t);
  }
  (void)fill_face_normals(mesh);
  for (std::size_t v = 0; v < mesh.normals.size(); v += 7) mesh.normals[v] = Vec3(0.6, 0.0, -0.8);  // not the faces'
  return mesh;
}

// Positions, normals (and colours), indices: each view, each accessor,
// every value as the mesh has it.
void expect_glb_holds(const Glb& g, const Mesh& mesh, const std::vector<Vec3>& normals) {
  const std::size_t n = mesh.vertices.size();
  const bool colors = mesh.has_colors();
  ASSERT_EQ(g.views.size(), colors ? 4u : 3u);
  ASSERT_EQ(g.accessors.size(), g.views.size());
  for (const View& v : g.views) EXPECT_EQ(v.offset % 4, 0u) << "views start on 4-byte boundaries";
  EXPECT_NE(g.json.find("\"byteLength\":" + std::to_string(g.bin.size()) + "}"), std::string::npos);
  EXPECT_NE(g.json.find("\"asset\":{\"version\":\"2.0\",\"generator\":\"recon "), std::string::npos);
  const std::string attributes = colors ? "\"attributes\":{\"POSITION\":0,\"NORMAL\":1,\"COLOR_0\":2},\"indices\":3"
                                        : "\"attributes\":{\"POSITION\":0,\"NORMAL\":1},\"indices\":2";
  EXPECT_NE(g.json.find(attributes), std::string::npos) << g.json;
  const Accessor &position = g.accessors[0], &normal = g.accessors[1], &index = g.accessors.back();
  EXPECT_EQ(position.count, n);
  EXPECT_EQ(position.component, 5126u);
  EXPECT_EQ(position.type, "VEC3");
  EXPECT_EQ(normal.count, n);
  EXPECT_EQ(index.count, 3 * mesh.triangles.size());
  EXPECT_EQ(index.component, 5125u) << "32-bit indices";
  EXPECT_EQ(index.type, "SCALAR");
  // min and max: the floats' own, written exactly.
  std::array<float, 3> low{}, high{};
  low.fill(std::numeric_limits<float>::infinity());
  high.fill(-std::numeric_limits<float>::infinity());
  // Positions are stored relative to the bounding box's centre, the node's
  // translation (written exactly).
  Vec3 low_d = mesh.vertices.front(), high_d = mesh.vertices.front();
  for (const Vec3& v : mesh.vertices) {
    low_d = low_d.cwiseMin(v);
    high_d = high_d.cwiseMax(v);
  }
  const Vec3 centre = 0.5 * (low_d + high_d);
  const std::array<double, 3> translation = triple_of(g.json, "translation");
  for (std::size_t k = 0; k < 3; ++k) EXPECT_EQ(translation[k], centre[static_cast<Eigen::Index>(k)]);
  for (std::size_t v = 0; v < n; ++v)
    for (std::size_t k = 0; k < 3; ++k) {
      const auto x =
          static_cast<float>(mesh.vertices[v][static_cast<Eigen::Index>(k)] - centre[static_cast<Eigen::Index>(k)]);
      EXPECT_EQ(float_at(g.bin, g.views[0].offset + 12 * v + 4 * k), x);
      EXPECT_EQ(float_at(g.bin, g.views[1].offset + 12 * v + 4 * k),
                static_cast<float>(normals[v][static_cast<Eigen::Index>(k)]));
      low[k] = std::min(low[k], x);
      high[k] = std::max(high[k], x);
    }
  const std::array<double, 3> min = triple_of(g.json, "min"), max = triple_of(g.json, "max");
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(min[k], static_cast<double>(low[k]));
    EXPECT_EQ(max[k], static_cast<double>(high[k]));
  }
  EXPECT_EQ(g.views[0].length, 12 * n);
  EXPECT_EQ(g.views[1].length, 12 * n);
  if (colors) {
    EXPECT_EQ(g.accessors[2].component, 5121u);
    EXPECT_EQ(g.accessors[2].count, n);
    EXPECT_EQ(g.accessors[2].type, "VEC3");
    EXPECT_NE(g.json.find("\"normalized\":true"), std::string::npos);
    EXPECT_EQ(g.views[2].stride, 4u);
    for (std::size_t v = 0; v < n; ++v)
      for (std::size_t c = 0; c < 3; ++c)
        EXPECT_EQ(static_cast<std::uint8_t>(g.bin[g.views[2].offset + 4 * v + c]), mesh.colors[v][c]);
  }
  const View& indices = g.views.back();
  EXPECT_EQ(indices.length, 12 * mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (std::size_t c = 0; c < 3; ++c) EXPECT_EQ(u32_at(g.bin, indices.offset + 12 * t + 4 * c), mesh.triangles[t][c]);
}

TEST(Glb, HoldsTheMeshValueForValueWithAndWithoutColours) {
  TempFolder folder;
  Mesh mesh = unit_normals(301, 499, 31);  // 301 vertices: lengths not multiples of 8
  write_mesh(folder / "a.glb", mesh);
  const Glb plain = parse(read_bytes(folder / "a.glb"));
  expect_glb_holds(plain, mesh, mesh.normals);
  mesh.colors = some_colors(mesh.vertices.size());
  write_mesh(folder / "b.GLB", mesh);  // (any case)
  const Glb g = parse(read_bytes(folder / "b.GLB"));
  expect_glb_holds(g, mesh, mesh.normals);
  // The JSON is padded with spaces (parse checked the 4-byte length); at
  // least one of the two needs padding, so the rule is exercised.
  std::size_t padded = 0;
  for (const Glb* glb : {&plain, &g}) {
    const std::size_t end = glb->json.find_last_not_of(' ');
    EXPECT_EQ(glb->json[end], '}');
    padded += glb->json.size() - 1 - end;
  }
  EXPECT_GT(padded, 0u) << "neither JSON needed padding: change the meshes";
}

// A scan in georeferenced coordinates (a LiDAR tile 4,000 km from its
// origin): floats of the coordinates would round them to a quarter of a
// metre; positions relative to the node's translation keep them to within
// a float of the tile's own size.
TEST(Glb, FarFromTheOriginKeepsItsDetail) {
  Mesh mesh = unit_normals(300, 400, 11);
  for (Vec3& v : mesh.vertices) v = Vec3(4.0e6, 5.0e5, 120.0) + 1e-3 * v;  // a tile of about 2 m
  TempFolder dir;
  io::write_mesh(dir.path() / "far.glb", mesh);
  const Glb g = parse(read_bytes(dir.path() / "far.glb"));
  const std::array<double, 3> t = triple_of(g.json, "translation");
  double worst = 0.0;
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
    for (std::size_t k = 0; k < 3; ++k) {
      const double drawn = t[k] + static_cast<double>(float_at(g.bin, g.views[0].offset + 12 * v + 4 * k));
      worst = std::max(worst, std::abs(drawn - mesh.vertices[v][static_cast<Eigen::Index>(k)]));
    }
  EXPECT_LT(worst, 1e-6) << "metres off where the scan was";
}

TEST(Glb, AMeshWithoutNormalsGetsTheAreaWeightedOnes) {
  TempFolder folder;
  Mesh mesh = unit_normals(200, 400, 33);
  mesh.normals.clear();
  write_mesh(folder / "a.glb", mesh);
  Mesh shaded = mesh;
  (void)fill_face_normals(shaded);
  expect_glb_holds(parse(read_bytes(folder / "a.glb")), mesh, shaded.normals);
}

TEST(Glb, AMeshWithoutTrianglesIsAnEmptyScene) {
  TempFolder folder;
  Mesh mesh;
  mesh.vertices = {Vec3(0, 0, 0)};
  write_mesh(folder / "empty.glb", mesh);
  const Glb g = parse(read_bytes(folder / "empty.glb"));
  EXPECT_TRUE(g.bin.empty());
  EXPECT_EQ(g.json.find("meshes"), std::string::npos);
  EXPECT_NE(g.json.find("\"scenes\":[{}]"), std::string::npos);
}

// Written as every output is (atomic_file.h): through a symbolic link,
// which stays a link, and into a stream such as /dev/null.
TEST(Glb, FollowsTheOutputRules) {
  TempFolder folder;
  const Mesh mesh = unit_normals(30, 40, 39);
  write_file(folder / "target.glb", "old");
  std::filesystem::create_symlink("target.glb", folder / "link.glb");
  write_mesh(folder / "link.glb", mesh);
  EXPECT_TRUE(std::filesystem::is_symlink(folder / "link.glb"));
  expect_glb_holds(parse(read_bytes(folder / "target.glb")), mesh, mesh.normals);
  write_mesh("/dev/null", mesh, {.format = MeshFormat::glb});
}

TEST(Glb, RefusesCoordinatesBeyondFloatAndLeavesTheOldFile) {
  TempFolder folder;
  Mesh mesh = random_mesh(10, 10, 34);
  write_file(folder / "old.glb", "previous");
  mesh.vertices[3].y() = 1e39;
  const std::string message = message_of<InvalidInputError>([&] { write_mesh(folder / "old.glb", mesh); });
  EXPECT_CONTAINS(message, "old.glb");
  EXPECT_CONTAINS(message, "vertex 3");
  EXPECT_EQ(read_bytes(folder / "old.glb"), "previous");
  EXPECT_THROW((void)read_mesh(folder / "old.glb"), InvalidInputError);
}

// ---------------------------------------------------------------------------
// Normals in PLY and OBJ.

TEST(MeshNormals, PlyBinaryAndAsciiWriteFloatNormalsThatReadBack) {
  TempFolder folder;
  Mesh mesh = unit_normals(50, 80, 35);
  mesh.colors = some_colors(mesh.vertices.size());
  for (const bool ascii : {false, true}) {
    const auto path = folder / (ascii ? "a.ply" : "b.ply");
    write_mesh(path, mesh, {.ascii = ascii});
    const std::string bytes = read_bytes(path);
    EXPECT_CONTAINS(bytes,
                    "property double z\nproperty float nx\nproperty float ny\nproperty float nz\n"
                    "property uchar red\n");
    const Mesh back = read_mesh(path);
    ASSERT_EQ(back.normals.size(), mesh.normals.size());
    for (std::size_t v = 0; v < mesh.normals.size(); ++v)
      EXPECT_LT((back.normals[v] - mesh.normals[v]).norm(), 2e-7) << v;  // floats
    EXPECT_TRUE(back.vertices == mesh.vertices);
    EXPECT_TRUE(back.colors == mesh.colors);
  }
  Mesh plain = mesh;
  plain.normals.clear();
  write_mesh(folder / "plain.ply", plain);
  EXPECT_EQ(read_bytes(folder / "plain.ply").find("nx"), std::string::npos);
  EXPECT_EQ(read_bytes(folder / "b.ply").size(),
            read_bytes(folder / "plain.ply").size() + 12 * mesh.vertices.size() + 54)
      << "12 bytes a vertex and three header lines";
}

TEST(MeshNormals, ObjWritesVnLinesAndFacesNamingThem) {
  TempFolder folder;
  const Mesh mesh = unit_normals(20, 30, 37);
  write_mesh(folder / "a.obj", mesh);
  const std::string text = read_bytes(folder / "a.obj");
  const auto& t = mesh.triangles[0];
  const auto corner = [](std::uint32_t v) { return std::to_string(v + 1) + "//" + std::to_string(v + 1); };
  EXPECT_CONTAINS(text, "\nf " + corner(t[0]) + " " + corner(t[1]) + " " + corner(t[2]) + "\n");
  const Mesh back = read_mesh(folder / "a.obj");
  ASSERT_EQ(back.normals.size(), mesh.normals.size());
  for (std::size_t v = 0; v < mesh.normals.size(); ++v)
    EXPECT_LT((back.normals[v] - mesh.normals[v]).norm(), 2e-7) << v;  // floats
  EXPECT_TRUE(back.triangles == mesh.triangles);
  Mesh plain = mesh;
  plain.normals.clear();
  write_mesh(folder / "plain.obj", plain);
  EXPECT_EQ(read_bytes(folder / "plain.obj").find("vn"), std::string::npos);
  EXPECT_EQ(read_bytes(folder / "plain.obj").find("//"), std::string::npos);
}

TEST(MeshNormals, RefusesNormalsNotOnePerVertexNotFiniteOrInGlbNotUnit) {
  TempFolder folder;
  Mesh mesh = unit_normals(20, 30, 38);
  mesh.normals.pop_back();
  EXPECT_CONTAINS(message_of<InvalidInputError>([&] { write_mesh(folder / "a.ply", mesh); }), "normals");
  mesh = unit_normals(20, 30, 38);
  mesh.normals[4] = Vec3(0, 0, 2);
  const std::string message = message_of<InvalidInputError>([&] { write_mesh(folder / "a.glb", mesh); });
  EXPECT_CONTAINS(message, "vertex 4's normal is not a unit vector");
  EXPECT_FALSE(std::filesystem::exists(folder / "a.glb"));
  write_mesh(folder / "a.ply", mesh);  // PLY and OBJ hold any finite normal (another tool's, read back)
  mesh.normals[5] = Vec3(0, std::nan(""), 0);
  EXPECT_CONTAINS(message_of<InvalidInputError>([&] { write_mesh(folder / "b.obj", mesh); }),
                  "vertex 5's normal is not finite");
  EXPECT_FALSE(std::filesystem::exists(folder / "b.obj"));
}

}  // namespace
}  // namespace recon::io
