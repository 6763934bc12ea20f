// glTF 2.0 binary (GLB), the format web viewers, Blender and game engines
// load: one file holding a JSON description and one binary buffer.
//
// What is written: one scene, one node, one mesh of one triangle primitive
// (mode 4) with
//   - POSITION: float VEC3, relative to the centre of the mesh's bounding
//     box, which the node's translation (doubles in the JSON) adds back: a
//     scan in georeferenced coordinates (a LiDAR tile at x = 4e6 m) keeps
//     its detail, where floats of the coordinates themselves would round
//     them to a quarter of a metre. With the min and max the specification
//     requires (each the exact decimal of the float, so any reader agrees);
//   - NORMAL: float VEC3, unit; always (GLB viewers shade with them): the
//     mesh's own, or the area-weighted ones (vertex_normals.h) when it has
//     none;
//   - COLOR_0 when the mesh has colours: unsigned bytes, normalized, VEC3,
//     in a buffer view of stride 4 (vertex attributes must start on 4-byte
//     boundaries: one padding byte a vertex);
//   - indices: UNSIGNED_INT (32-bit), three a triangle.
// No material: a viewer uses the specification's default (white, or the
// vertex colours). The buffer holds positions, normals, colours, indices in
// that order, each a multiple of 4 bytes long; the JSON chunk is padded to 4
// bytes with spaces, the BIN chunk with zeros (the specification's rules).
//
// A mesh with no triangle: a valid GLB of an empty scene (no mesh, no
// buffer): glTF accessors cannot be empty. (reconstruct() never gives one:
// it refuses an empty contour first.)
//
// Limits refused before anything is written (InvalidInputError): a
// coordinate beyond float range, a normal that is not unit, or a file of
// 4 GiB or more (GLB's lengths are 32-bit).

#include "formats.h"
#include "io_detail.h"

#include "recon/core/detail/float_chars.h"
#include "recon/core/errors.h"
#include "recon/core/version.h"
#include "recon/phase5_refine/vertex_normals.h"

#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

namespace recon::io::detail {
namespace {

constexpr std::uint32_t glb_magic = 0x46546C67;   // "glTF"
constexpr std::uint32_t json_chunk = 0x4E4F534A;  // "JSON"
constexpr std::uint32_t bin_chunk = 0x004E4942;   // "BIN\0"
constexpr int array_buffer = 34962, element_array_buffer = 34963;
constexpr int component_float = 5126, component_unsigned_byte = 5121, component_unsigned_int = 5125;

// The shortest decimal that reads back as exactly this double.
void append_double_exactly(std::string& out, double value) {
  char text[32];
  const auto [end, ec] = recon::detail::float_to_chars(text, text + sizeof text, value);
  out.append(text, ec == std::errc{} ? static_cast<std::size_t>(end - text) : 0);
}

// The exact decimal of a float (as a double, which reads back as the float).
void append_float_exactly(std::string& out, float value) { append_double_exactly(out, static_cast<double>(value)); }

void pad_to_4(std::string& bytes, char with) {
  while (bytes.size() % 4 != 0) bytes += with;
}

// The binary buffer and where each part of it starts.
struct Buffer {
  std::string bytes;
  std::size_t positions = 0, normals = 0, colors = 0, indices = 0;
  std::array<float, 3> min{}, max{};
  Vec3 centre = Vec3::Zero();  ///< the bounding box's, the node's translation
};

// The centre of the vertices' bounding box (the midpoint of its extremes,
// in doubles).
Vec3 box_centre(const std::vector<Vec3>& vertices) {
  Vec3 low = vertices.front(), high = vertices.front();
  for (const Vec3& v : vertices) {
    low = low.cwiseMin(v);
    high = high.cwiseMax(v);
  }
  return 0.5 * (low + high);
}

Buffer make_buffer(const Mesh& mesh, const std::vector<Vec3>& normals) {
  Buffer b;
  const std::size_t n = mesh.vertices.size();
  b.bytes.reserve(n * (mesh.has_colors() ? 28 : 24) + mesh.triangles.size() * 12);
  b.min.fill(std::numeric_limits<float>::infinity());
  b.max.fill(-std::numeric_limits<float>::infinity());
  b.centre = box_centre(mesh.vertices);
  for (const Vec3& v : mesh.vertices)
    for (int k = 0; k < 3; ++k) {
      const auto x = static_cast<float>(v[k] - b.centre[k]);
      append_little_endian(b.bytes, x);
      b.min[static_cast<std::size_t>(k)] = std::min(b.min[static_cast<std::size_t>(k)], x);
      b.max[static_cast<std::size_t>(k)] = std::max(b.max[static_cast<std::size_t>(k)], x);
    }
  b.normals = b.bytes.size();
  for (const Vec3& normal : normals) append_normal_binary(b.bytes, normal);
  b.colors = b.bytes.size();
  for (const Color& c : mesh.colors) {
    for (const std::uint8_t channel : c) b.bytes += static_cast<char>(channel);
    b.bytes += '\0';  // (stride 4)
  }
  b.indices = b.bytes.size();
  for (const auto& t : mesh.triangles)
    for (const std::uint32_t v : t) append_little_endian(b.bytes, v);
  return b;
}

void append_view(std::string& json, std::size_t offset, std::size_t length, int target, int stride = 0) {
  json += "{\"buffer\":0,\"byteOffset\":" + std::to_string(offset) + ",\"byteLength\":" + std::to_string(length);
  if (stride > 0) json += ",\"byteStride\":" + std::to_string(stride);
  json += ",\"target\":" + std::to_string(target) + "}";
}

void append_accessor(std::string& json, int view, int component, std::size_t count, const char* type,
                     bool normalized = false) {
  json += "{\"bufferView\":" + std::to_string(view) + ",\"componentType\":" + std::to_string(component) +
          ",\"count\":" + std::to_string(count) + ",\"type\":\"" + type + "\"";
  if (normalized) json += ",\"normalized\":true";
}

void append_vec3(std::string& json, const std::array<float, 3>& v) {
  json += '[';
  for (std::size_t k = 0; k < 3; ++k) {
    if (k > 0) json += ',';
    append_float_exactly(json, v[k]);
  }
  json += ']';
}

// asset.generator names the writer and its version (recon::version(), the
// one the program, the package and the stats give).
std::string asset() {
  return "\"asset\":{\"version\":\"2.0\",\"generator\":\"recon " + std::string(recon::version()) + "\"}";
}

// The JSON of a mesh with triangles, over the buffer `b`.
std::string describe(const Mesh& mesh, const Buffer& b) {
  const std::size_t n = mesh.vertices.size();
  const bool colors = mesh.has_colors();
  std::string json =
      "{" + asset() + ",\"scene\":0,\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0,\"translation\":[";
  for (int k = 0; k < 3; ++k) {
    if (k > 0) json += ',';
    append_double_exactly(json, b.centre[k]);
  }
  json += "]}],";
  json += "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0,\"NORMAL\":1";
  if (colors) json += ",\"COLOR_0\":2";
  json += "},\"indices\":" + std::to_string(colors ? 3 : 2) + ",\"mode\":4}]}],";
  json += "\"buffers\":[{\"byteLength\":" + std::to_string(b.bytes.size()) + "}],\"bufferViews\":[";
  append_view(json, b.positions, b.normals - b.positions, array_buffer);
  json += ',';
  append_view(json, b.normals, b.colors - b.normals, array_buffer);
  if (colors) {
    json += ',';
    append_view(json, b.colors, b.indices - b.colors, array_buffer, 4);
  }
  json += ',';
  append_view(json, b.indices, b.bytes.size() - b.indices, element_array_buffer);
  json += "],\"accessors\":[";
  append_accessor(json, 0, component_float, n, "VEC3");
  json += ",\"min\":";
  append_vec3(json, b.min);
  json += ",\"max\":";
  append_vec3(json, b.max);
  json += "},";
  append_accessor(json, 1, component_float, n, "VEC3");
  json += "},";
  if (colors) {
    append_accessor(json, 2, component_unsigned_byte, n, "VEC3", true);
    json += "},";
  }
  append_accessor(json, colors ? 3 : 2, component_unsigned_int, 3 * mesh.triangles.size(), "SCALAR");
  json += "}]}";
  return json;
}

void put_u32(std::ostream& out, std::uint32_t value) {
  std::string bytes;
  append_little_endian(bytes, value);
  out.write(bytes.data(), 4);
}

// Unit within 1e-3. (isfinite first: an ordered comparison with a NaN
// raises the invalid-operation flag, which the test runs trap.)
bool unit(const Vec3& n) {
  const double norm = n.norm();
  return std::isfinite(norm) && std::abs(norm - 1.0) < 1e-3;
}

void refuse_too_large(std::string_view file, std::size_t total) {
  if (total > std::numeric_limits<std::uint32_t>::max())
    throw InvalidInputError(std::string(file) + ": cannot write: the GLB would take " + std::to_string(total) +
                            " bytes, and GLB's lengths are 32-bit (at most 4 GiB); write PLY instead");
}

}  // namespace

void check_mesh_for_glb(std::string_view file, const Mesh& mesh) {
  constexpr auto largest = static_cast<double>(std::numeric_limits<float>::max());
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
    if (mesh.vertices[i].cwiseAbs().maxCoeff() > largest)
      throw InvalidInputError(std::string(file) + ": cannot write: vertex " + std::to_string(i) +
                              " is too large for the float coordinates of GLB");
  // glTF: "NORMAL ... unit" (the validator checks it).
  for (std::size_t v = 0; v < mesh.normals.size(); ++v)
    if (!unit(mesh.normals[v]))
      throw InvalidInputError(std::string(file) + ": cannot write: vertex " + std::to_string(v) +
                              "'s normal is not a unit vector (length " + std::to_string(mesh.normals[v].norm()) +
                              "), as GLB requires");
  const std::size_t n = mesh.vertices.size(), t = mesh.triangles.size();
  // JSON is under 2 KB; the buffer as make_buffer lays it out.
  refuse_too_large(file, 4096 + n * (mesh.has_colors() ? 28 : 24) + t * 12);
}

void write_glb_mesh(std::ostream& out, const Mesh& mesh) {
  std::string json;
  Buffer b;
  if (mesh.triangles.empty()) {
    json = "{" + asset() + ",\"scene\":0,\"scenes\":[{}]}";
  } else if (mesh.has_normals()) {
    b = make_buffer(mesh, mesh.normals);
    json = describe(mesh, b);
  } else {
    Mesh shaded;  // (a copy of the geometry only: the normals need the triangles)
    shaded.vertices = mesh.vertices;
    shaded.triangles = mesh.triangles;
    (void)fill_face_normals(shaded);
    b = make_buffer(mesh, shaded.normals);
    json = describe(mesh, b);
  }
  pad_to_4(json, ' ');
  pad_to_4(b.bytes, '\0');
  const std::size_t total = 12 + 8 + json.size() + (b.bytes.empty() ? 0 : 8 + b.bytes.size());
  put_u32(out, glb_magic);
  put_u32(out, 2);
  put_u32(out, static_cast<std::uint32_t>(total));
  put_u32(out, static_cast<std::uint32_t>(json.size()));
  put_u32(out, json_chunk);
  out.write(json.data(), static_cast<std::streamsize>(json.size()));
  if (!b.bytes.empty()) {
    put_u32(out, static_cast<std::uint32_t>(b.bytes.size()));
    put_u32(out, bin_chunk);
    out.write(b.bytes.data(), static_cast<std::streamsize>(b.bytes.size()));
  }
}

}  // namespace recon::io::detail
