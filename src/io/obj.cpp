// Wavefront OBJ, the geometry statements only.
//
// "v x y z" is a vertex. A fourth number, the optional w weight of the OBJ
// specification, is ignored (it weighs rational curves and surfaces and is 1
// for polygon vertices, so it is not divided by). "v x y z r g b", the
// per-vertex colour of MeshLab, Open3D and many scanners (r g b in [0, 1]),
// gives the colours when every "v" line has one (a colour for only some
// points cannot be matched to the rest); other counts are ignored. The
// colours follow the floating-point rule of colors.h. recon writes the same
// form.
// "vn nx ny nz" lines become the cloud's normals only when there are exactly
// as many as "v" lines: OBJ ties normals to face corners, not to vertices, so
// any other count cannot be matched to the points.
// "f" corners are "v", "v/vt", "v/vt/vn" or "v//vn", counted from 1, or from
// the end of the vertices read so far when negative; polygons are fanned.
// Every other statement (vt, g, o, usemtl, l, ...) is ignored.

#include "colors.h"
#include "formats.h"
#include "io_detail.h"
#include "text_scanner.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace recon::io::detail {
namespace {

/// The colours' channels in the text: numbers, taken by the floating-point rule.
constexpr std::array<ScalarType, 3> color_types = {ScalarType::float64, ScalarType::float64, ScalarType::float64};

struct ObjContent {
  std::vector<Vec3> positions;
  std::vector<Vec3> normals;
  ColorReader colors{color_types};
  bool every_vertex_colored = true;  ///< so far; colours are read while it holds
  std::vector<std::array<std::uint32_t, 3>> triangles;
  PointChecker position_checker{false};
  PointChecker normal_checker{false};  ///< taken into position_checker only when the normals are kept
};

/// OBJ ignores statements it does not know, so a binary or garbage file
/// would be walked to its end; a statement keyword is letters, digits and
/// '_' (v, vt, usemtl, c_interp, curv2, ...), and anything else is refused.
bool is_keyword(std::string_view word) {
  return std::all_of(word.begin(), word.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
  });
}

Vec3 parse_three(std::string_view file, std::size_t line, Fields& fields, std::string_view keyword,
                 const std::string_view (&names)[3]) {
  std::array<std::string_view, 3> tokens;
  for (std::size_t k = 0; k < 3; ++k) {
    if (!fields.next(tokens[k]))
      fail_at_line(file, line, "a '" + std::string(keyword) + "' line needs 3 numbers, found " + std::to_string(k));
  }
  return parse_vec3(file, line, tokens.data(), names);
}

/// The colour after a vertex's z: true when exactly three numbers follow it.
bool parse_color(Fields& fields, std::array<double, 3>& rgb) {
  std::size_t count = 0;
  for (std::string_view token; fields.next(token); ++count) {
    if (count >= 3 || parse_double(token, rgb[count]) != NumberStatus::ok) return false;
  }
  return count == 3;
}

/// A "v x y z [r g b]" line: the position, and its colour while every vertex has one.
void read_vertex(std::string_view file, std::size_t n, Fields& fields, std::string_view keyword, ObjContent& obj) {
  obj.position_checker.position(obj.positions.emplace_back(parse_three(file, n, fields, keyword, position_names)), n,
                                position_names);
  if (!obj.every_vertex_colored) return;
  std::array<double, 3> rgb{};
  if (parse_color(fields, rgb)) {
    obj.colors.add(rgb[0], rgb[1], rgb[2]);
  } else {
    obj.every_vertex_colored = false;
    obj.colors = ColorReader(color_types);  // none kept
  }
}

/// The largest forward (positive) vertex number the faces use, and its
/// line: checked at the end, when all vertices are known.
struct ForwardReference {
  std::uint64_t index = 0;
  std::size_t line = 0;
};

/// A face corner ("v", "v/vt", "v/vt/vn" or "v//vn") as a vertex index from
/// 0; `defined` vertices stand before this line.
std::uint32_t parse_corner(std::string_view file, std::size_t n, std::string_view corner, std::size_t defined,
                           ForwardReference& largest) {
  const std::string_view vertex = corner.substr(0, corner.find('/'));
  std::int64_t index = 0;
  if (!parse_integer(vertex, index) || index == 0)
    fail_at_line(file, n, "expected a vertex number (1, 2, ... or -1, -2, ...) in face corner " + excerpt(corner));
  std::uint64_t zero_based = 0;
  if (index < 0) {
    const auto back = static_cast<std::uint64_t>(-(index + 1)) + 1;  // no overflow for INT64_MIN
    if (back > defined)
      fail_at_line(file, n,
                   "face corner " + excerpt(corner) + " refers back " + std::to_string(back) + " vertices, but only " +
                       std::to_string(defined) + " are defined before this line");
    zero_based = defined - back;
  } else {
    zero_based = static_cast<std::uint64_t>(index) - 1;
    if (zero_based >= largest.index) largest = {zero_based, n};
  }
  if (zero_based >= std::numeric_limits<std::uint32_t>::max())
    fail_at_line(file, n, "vertex number in " + excerpt(corner) + " is too large");
  return static_cast<std::uint32_t>(zero_based);
}

/// An "f" line: its polygon, fanned into triangles.
void read_face(std::string_view file, std::size_t n, Fields& fields, ObjContent& obj,
               std::vector<std::uint32_t>& corners, ForwardReference& largest) {
  corners.clear();
  for (std::string_view corner; fields.next(corner);)
    corners.push_back(parse_corner(file, n, corner, obj.positions.size(), largest));
  if (corners.size() < 3)
    fail_at_line(file, n, "a face needs at least 3 corners, found " + std::to_string(corners.size()));
  for (std::size_t k = 1; k + 1 < corners.size(); ++k)
    obj.triangles.push_back({corners[0], corners[k], corners[k + 1]});
}

ObjContent parse_obj(std::string_view file, std::string_view content, bool faces) {
  ObjContent obj;
  LineScanner lines(file, content);
  std::vector<std::uint32_t> corners;
  ForwardReference largest;
  for_each_statement(lines, [&](std::size_t n, std::string_view keyword, Fields& fields) {
    if (keyword == "v") {
      read_vertex(file, n, fields, keyword, obj);
    } else if (keyword == "vn") {
      obj.normal_checker.normal(obj.normals.emplace_back(parse_three(file, n, fields, keyword, normal_names)), n,
                                normal_names);
    } else if (!is_keyword(keyword)) {
      fail_at_line(file, n, "expected an OBJ statement (v, vn, f, ...), found " + excerpt(keyword));
    } else if (keyword == "f" && faces) {
      read_face(file, n, fields, obj, corners, largest);
    }
  });
  if (largest.line != 0 && largest.index >= obj.positions.size())
    fail_at_line(file, largest.line,
                 "a face uses vertex " + std::to_string(largest.index + 1) + ", but the file has " +
                     std::to_string(obj.positions.size()) + " vertices");
  return obj;
}

}  // namespace

PointCloud read_obj_points(std::string_view file, std::string_view content) {
  ObjContent obj = parse_obj(file, content, false);
  if (obj.positions.empty()) fail_in_file(file, "no points: the file has no 'v x y z' line");
  const bool keep_normals = obj.normals.size() == obj.positions.size();
  if (keep_normals) obj.position_checker.take_normals(obj.normal_checker);
  obj.position_checker.report(file);
  PointCloud cloud;
  cloud.positions = std::move(obj.positions);
  if (keep_normals) cloud.normals = std::move(obj.normals);
  cloud.colors = obj.colors.take();
  return cloud;
}

Mesh read_obj_mesh(std::string_view file, std::string_view content) {
  ObjContent obj = parse_obj(file, content, true);
  if (obj.triangles.empty()) fail_in_file(file, "no triangles: the file has no 'f' line");
  obj.position_checker.report(file, true);
  Mesh mesh;
  mesh.vertices = std::move(obj.positions);
  mesh.triangles = std::move(obj.triangles);
  mesh.colors = obj.colors.take();
  // As for points: only a normal per vertex can be matched to them (the
  // form recon writes, "f a//a b//b c//c").
  if (obj.normals.size() == mesh.vertices.size()) mesh.normals = std::move(obj.normals);
  return mesh;
}

namespace {

// "f a//a b//b c//c": each corner's vertex and its normal (1-based, the same number).
void append_triangles_with_normals(BlockWriter& writer, const std::vector<std::array<std::uint32_t, 3>>& triangles) {
  std::string& out = writer.buffer();
  for (const auto& triangle : triangles) {
    out += 'f';
    for (const std::uint32_t v : triangle) {
      out += ' ';
      append_integer(out, std::uint64_t{v} + 1);
      out += "//";
      append_integer(out, std::uint64_t{v} + 1);
    }
    out += '\n';
    writer.flush_if_full();
  }
}

}  // namespace

void write_obj_mesh(std::ostream& stream, const Mesh& mesh) {
  BlockWriter writer(stream);
  std::string& out = writer.buffer();
  out += written_by_recon(std::to_string(mesh.vertices.size()) + " vertices, " + std::to_string(mesh.triangles.size()) +
                          " triangles");
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    out += "v ";
    append_vec3_text(out, mesh.vertices[i]);
    if (mesh.has_colors()) {
      out += ' ';
      append_color_unit(out, mesh.colors[i]);
    }
    out += '\n';
    if (mesh.has_normals()) {  // vertex i's normal is normal i: OBJ counts "vn" lines on their own
      out += "vn ";
      append_normal_text(out, mesh.normals[i]);
      out += '\n';
    }
    writer.flush_if_full();
  }
  if (mesh.has_normals()) {
    append_triangles_with_normals(writer, mesh.triangles);
  } else {
    append_triangles_text(writer, mesh.triangles, 'f', 1);
  }
  writer.finish();
}

void write_obj_curves(std::ostream& stream, const PolylineSet& curves) {
  BlockWriter writer(stream);
  std::string& out = writer.buffer();
  out +=
      written_by_recon(std::to_string(curves.polylines.size()) + " curves (" + std::to_string(curves.closed_count()) +
                       " closed), " + std::to_string(curves.vertices.size()) +
                       " vertices in the z = 0 plane; a closed curve's 'l' line ends at its first vertex");
  for (const Vec2& v : curves.vertices) {
    out += "v ";
    append_vec3_text(out, Vec3(v.x(), v.y(), 0.0));
    out += '\n';
    writer.flush_if_full();
  }
  for (const Polyline& line : curves.polylines) {
    out += 'l';
    for (const std::uint32_t v : line.vertices) {
      out += ' ';
      append_integer(out, std::uint64_t{v} + 1);
      writer.flush_if_full();
    }
    if (line.closed && !line.vertices.empty()) {
      out += ' ';
      append_integer(out, std::uint64_t{line.vertices.front()} + 1);
    }
    out += '\n';
  }
  writer.finish();
}

}  // namespace recon::io::detail
