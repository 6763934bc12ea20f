// Binary STL: an 80-byte header (which must not start with "solid", or
// readers take the file for ASCII STL), a little-endian uint32 triangle
// count, then 50 bytes a triangle: facet normal, three corners (twelve
// float32) and a zero uint16. The format has no shared vertices and stores
// floats, so it is for export only. Colours are not written: STL has no
// standard place for them (the attribute word's colour is a vendor
// extension that readers interpret differently).

#include "formats.h"
#include "io_detail.h"

#include <Eigen/Geometry>

#include <cstdint>
#include <string>

namespace recon::io::detail {

void write_stl_mesh(std::ostream& stream, const Mesh& mesh) {
  BlockWriter writer(stream);
  std::string& out = writer.buffer();
  std::string header = "binary STL written by recon";
  header.resize(80, ' ');
  out += header;
  append_little_endian(out, static_cast<std::uint32_t>(mesh.triangles.size()));
  const auto append_vec3 = [&out](const Vec3& v) {
    append_little_endian(out, static_cast<float>(v.x()));
    append_little_endian(out, static_cast<float>(v.y()));
    append_little_endian(out, static_cast<float>(v.z()));
  };
  for (const auto& triangle : mesh.triangles) {
    const Vec3& a = mesh.vertices[triangle[0]];
    const Vec3& b = mesh.vertices[triangle[1]];
    const Vec3& c = mesh.vertices[triangle[2]];
    // The facet normal follows the corner order (counter-clockwise seen from
    // outside); a degenerate triangle gets a zero normal.
    Vec3 normal = (b - a).cross(c - a);
    const double length = normal.norm();
    normal = length > 0.0 ? Vec3(normal / length) : Vec3::Zero();
    append_vec3(normal);
    append_vec3(a);
    append_vec3(b);
    append_vec3(c);
    append_little_endian(out, std::uint16_t{0});
    writer.flush_if_full();
  }
  writer.finish();
}

}  // namespace recon::io::detail
