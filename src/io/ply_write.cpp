// PLY 1.0, writing (ply_read.cpp reads): a header, then the vertices and
// faces as text or as little-endian binary records.

#include "colors.h"
#include "formats.h"
#include "io_detail.h"

#include <array>
#include <cstdint>
#include <ostream>
#include <string>

namespace recon::io::detail {
namespace {

void append_vec3_binary(std::string& out, const Vec3& v) {
  append_little_endian(out, v.x());
  append_little_endian(out, v.y());
  append_little_endian(out, v.z());
}

std::string header_start(bool ascii, std::size_t vertices, bool normals, bool colors) {
  std::string header = "ply\nformat ";
  header += ascii ? "ascii" : "binary_little_endian";
  header += " 1.0\ncomment written by recon\nelement vertex ";
  header += std::to_string(vertices);
  header += "\nproperty double x\nproperty double y\nproperty double z\n";
  if (normals) header += "property double nx\nproperty double ny\nproperty double nz\n";
  if (colors) header += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  return header;
}

/// A vertex's colour after its other properties ("r g b" in ascii, 3 bytes in binary).
void append_color(std::string& out, const Color& color, bool ascii) {
  if (ascii) {
    out += ' ';
    append_color_bytes(out, color);
  } else {
    for (const std::uint8_t c : color) append_little_endian(out, c);
  }
}

}  // namespace

void write_ply_points(std::ostream& stream, const PointCloud& cloud, bool ascii) {
  BlockWriter writer(stream);
  std::string& out = writer.buffer();
  out += header_start(ascii, cloud.size(), cloud.has_normals(), cloud.has_colors());
  out += "end_header\n";
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (ascii) {
      append_vec3_text(out, cloud.positions[i]);
      if (cloud.has_normals()) {
        out += ' ';
        append_vec3_text(out, cloud.normals[i]);
      }
    } else {
      append_vec3_binary(out, cloud.positions[i]);
      if (cloud.has_normals()) append_vec3_binary(out, cloud.normals[i]);
    }
    if (cloud.has_colors()) append_color(out, cloud.colors[i], ascii);
    if (ascii) out += '\n';
    writer.flush_if_full();
  }
  writer.finish();
}

std::string ply_mesh_header(bool ascii, std::size_t vertices, std::size_t triangles, bool colors, bool normals) {
  // Indices are written as "int", which every PLY reader knows, unless the
  // mesh is too large for it.
  const bool signed_indices = vertices <= static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max());
  std::string header = header_start(ascii, vertices, false, false);
  if (normals) header += "property float nx\nproperty float ny\nproperty float nz\n";
  if (colors) header += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  header += "element face ";
  header += std::to_string(triangles);
  header +=
      signed_indices ? "\nproperty list uchar int vertex_indices\n" : "\nproperty list uchar uint vertex_indices\n";
  header += "end_header\n";
  return header;
}

void append_ply_vertex(std::string& out, const Vec3& position, const Color* color, bool ascii, const Vec3* normal) {
  if (ascii) {
    append_vec3_text(out, position);
    if (normal != nullptr) {
      out += ' ';
      append_normal_text(out, *normal);
    }
  } else {
    append_vec3_binary(out, position);
    if (normal != nullptr) append_normal_binary(out, *normal);
  }
  if (color != nullptr) append_color(out, *color, ascii);
  if (ascii) out += '\n';
}

void append_ply_triangle_binary(std::string& out, const std::array<std::uint32_t, 3>& triangle) {
  append_little_endian(out, std::uint8_t{3});
  for (const std::uint32_t v : triangle) append_little_endian(out, v);  // same bytes as int for v < 2^31
}

void write_ply_mesh(std::ostream& stream, const Mesh& mesh, bool ascii) {
  BlockWriter writer(stream);
  std::string& out = writer.buffer();
  out += ply_mesh_header(ascii, mesh.vertices.size(), mesh.triangles.size(), mesh.has_colors(), mesh.has_normals());
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    append_ply_vertex(out, mesh.vertices[i], mesh.has_colors() ? &mesh.colors[i] : nullptr, ascii,
                      mesh.has_normals() ? &mesh.normals[i] : nullptr);
    writer.flush_if_full();
  }
  if (ascii) {
    append_triangles_text(writer, mesh.triangles, '3', 0);
  } else {
    for (const auto& triangle : mesh.triangles) {
      append_ply_triangle_binary(out, triangle);
      writer.flush_if_full();
    }
  }
  writer.finish();
}

}  // namespace recon::io::detail
