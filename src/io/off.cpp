// Geomview OFF, the 3D text variants.
//
// Header keyword [ST][C][N]OFF (texture coordinates, colours, normals); the
// keyword may be missing, as Geomview allows. The counts "V F E" follow on
// the same line or on the next data line (E is optional and ignored). Then
// one vertex a line, "x y z" with "nx ny nz" after it for NOFF (further
// numbers such as colours are ignored), then one face a line, "n i1 ... in"
// (anything after the n indices, such as a colour, is ignored). '#' starts a
// comment. 4OFF, nOFF and binary OFF are refused. Reading points stops after
// the vertices; faces are neither read nor checked.
//
// A mesh with colours is written as COFF, "x y z r g b a" with each of
// r g b a an integer 0 to 255 (alpha 255), as MeshLab and Open3D write and
// read it. (Geomview's own COFF has floats in [0, 1]; readers tell the two
// apart by the values.) Reading ignores the colours, as it always has.

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

struct OffReader {
  std::string_view file;
  std::string_view content;
  LineScanner lines;
  bool normals = false;
  std::uint64_t vertex_count = 0;
  std::uint64_t face_count = 0;

  /// The next line with data on it (comments removed); false at the end.
  bool next_data_line(std::string_view& line) {
    while (lines.next(line)) {
      line = trim(without_comment(line));
      if (!line.empty()) return true;
    }
    return false;
  }

  void read_counts(Fields& fields, std::string_view first) {
    std::vector<std::string_view> tokens;
    if (!first.empty()) tokens.push_back(first);
    for (std::string_view token; fields.next(token);) tokens.push_back(token);
    std::array<std::uint64_t, 3> counts{};
    for (std::size_t k = 0; k < tokens.size() && k < counts.size(); ++k) {
      if (!parse_count(tokens[k], counts[k]))
        fail_at_line(file, lines.line_number(),
                     "expected the counts 'VERTICES FACES EDGES', found " + excerpt(tokens[k]));
    }
    if (tokens.size() < 2 || tokens.size() > 3)
      fail_at_line(file, lines.line_number(),
                   "expected the counts 'VERTICES FACES EDGES', found " + std::to_string(tokens.size()) + " numbers");
    vertex_count = counts[0];
    face_count = counts[1];
  }

  void read_header() {
    std::string_view line;
    if (!next_data_line(line)) fail_in_file(file, "no points: the file holds only comments and blank lines");
    Fields fields(line);
    std::string_view keyword;
    static_cast<void>(fields.next(keyword));
    if (std::uint64_t ignored = 0; parse_count(keyword, ignored)) {
      read_counts(fields, keyword);  // no keyword: the counts come first
      return;
    }
    if (keyword.size() < 3 || keyword.substr(keyword.size() - 3) != "OFF")
      fail_at_line(file, lines.line_number(),
                   "not an OFF file: expected 'OFF' (or NOFF, COFF, ...), found " + excerpt(keyword));
    std::string_view prefix = keyword.substr(0, keyword.size() - 3);
    if (prefix.starts_with("ST")) prefix.remove_prefix(2);
    if (prefix.starts_with("C")) prefix.remove_prefix(1);
    if (prefix.starts_with("N")) {
      normals = true;
      prefix.remove_prefix(1);
    }
    if (prefix.find_first_of("4n") != std::string_view::npos)
      fail_at_line(file, lines.line_number(), excerpt(keyword) + " is not supported: only 3D OFF variants are read");
    if (!prefix.empty())
      fail_at_line(file, lines.line_number(), "not an OFF file: unknown header keyword " + excerpt(keyword));

    std::string_view token;
    if (fields.next(token)) {
      if (token == "BINARY") fail_at_line(file, lines.line_number(), "binary OFF is not supported; convert it to text");
      read_counts(fields, token);  // the counts share the header line
      return;
    }
    if (!next_data_line(line)) fail_at_line(file, lines.line_number(), "the file ends before the counts line");
    Fields count_fields(line);
    read_counts(count_fields, {});
  }

  /// The vertices (and their normals for NOFF); non-finite or huge values
  /// are counted and refused after the last vertex (called points or
  /// vertices in the message, as the caller reads a cloud or a mesh).
  std::vector<Vec3> read_vertices(std::vector<Vec3>& normal_list, bool for_mesh) {
    std::vector<Vec3> positions;
    // A vertex line takes at least five bytes ("0 0 0"): never reserve more than the file can hold.
    const std::uint64_t room = (content.size() - lines.position()) / 5 + 1;
    positions.reserve(static_cast<std::size_t>(std::min(vertex_count, room)));
    if (normals) normal_list.reserve(positions.capacity());
    static constexpr std::array<std::string_view, 6> names = {"x", "y", "z", "nx", "ny", "nz"};
    const std::size_t wanted = normals ? 6 : 3;
    PointChecker checker(false);
    std::string_view line;
    for (std::uint64_t i = 0; i < vertex_count; ++i) {
      if (!next_data_line(line))
        fail_at_line(file, lines.line_number(),
                     "the file ends after " + std::to_string(i) + " vertices; the header promises " +
                         std::to_string(vertex_count));
      Fields fields(line);
      std::array<double, 6> values{};
      for (std::size_t k = 0; k < wanted; ++k) {
        std::string_view token;
        if (!fields.next(token))
          fail_at_line(file, lines.line_number(),
                       "a vertex line needs " + std::to_string(wanted) + " numbers" +
                           (normals ? " (x y z nx ny nz)" : " (x y z)") + ", found " + std::to_string(k));
        values[k] = parse_coordinate(file, lines.line_number(), token, names[k]);
      }
      checker.position(positions.emplace_back(values[0], values[1], values[2]), lines.line_number(), position_names);
      if (normals)
        checker.normal(normal_list.emplace_back(values[3], values[4], values[5]), lines.line_number(), normal_names);
    }
    checker.report(file, for_mesh);
    return positions;
  }

  std::vector<std::array<std::uint32_t, 3>> read_faces() {
    if (vertex_count > std::numeric_limits<std::uint32_t>::max())
      fail_in_file(file, "too many vertices for a mesh (at most 2^32 - 1)");
    std::vector<std::array<std::uint32_t, 3>> triangles;
    std::vector<std::uint32_t> corners;
    std::string_view line;
    for (std::uint64_t f = 0; f < face_count; ++f) {
      if (!next_data_line(line))
        fail_at_line(
            file, lines.line_number(),
            "the file ends after " + std::to_string(f) + " faces; the header promises " + std::to_string(face_count));
      const std::size_t n = lines.line_number();
      Fields fields(line);
      std::string_view token;
      std::uint64_t corner_count = 0;
      if (!fields.next(token) || !parse_count(token, corner_count))
        fail_at_line(file, n,
                     "expected the number of corners of face " + std::to_string(f) + ", found " + excerpt(token));
      if (corner_count < 3)
        fail_at_line(file, n,
                     "face " + std::to_string(f) + " has " + std::to_string(corner_count) +
                         " corners; a polygon needs at least 3");
      corners.clear();
      for (std::uint64_t k = 0; k < corner_count; ++k) {
        std::uint64_t index = 0;
        if (!fields.next(token))
          fail_at_line(file, n,
                       "face " + std::to_string(f) + " promises " + std::to_string(corner_count) +
                           " corners but lists " + std::to_string(k));
        if (!parse_count(token, index) || index >= vertex_count)
          fail_at_line(file, n,
                       "face " + std::to_string(f) + ": " + excerpt(token) + " is not a vertex number from 0 to " +
                           std::to_string(vertex_count) + " - 1");
        corners.push_back(static_cast<std::uint32_t>(index));
      }
      for (std::size_t k = 1; k + 1 < corners.size(); ++k)
        triangles.push_back({corners[0], corners[k], corners[k + 1]});
    }
    return triangles;
  }
};

OffReader start(std::string_view file, std::string_view content) {
  OffReader reader{file, content, LineScanner(file, content)};
  reader.read_header();
  return reader;
}

}  // namespace

PointCloud read_off_points(std::string_view file, std::string_view content) {
  OffReader reader = start(file, content);
  if (reader.vertex_count == 0) fail_in_file(file, "no points: the header declares 0 vertices");
  PointCloud cloud;
  cloud.positions = reader.read_vertices(cloud.normals, false);
  return cloud;
}

Mesh read_off_mesh(std::string_view file, std::string_view content) {
  OffReader reader = start(file, content);
  if (reader.face_count == 0) fail_in_file(file, "no triangles: the header declares 0 faces");
  Mesh mesh;
  std::vector<Vec3> ignored_normals;
  mesh.vertices = reader.read_vertices(ignored_normals, true);
  mesh.triangles = reader.read_faces();
  return mesh;
}

void write_off_mesh(std::ostream& stream, const Mesh& mesh) {
  BlockWriter writer(stream);
  std::string& out = writer.buffer();
  out += mesh.has_colors() ? "COFF\n" : "OFF\n";
  out += "# written by recon\n";
  out += std::to_string(mesh.vertices.size());
  out += ' ';
  out += std::to_string(mesh.triangles.size());
  out += " 0\n";
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    append_vec3_text(out, mesh.vertices[i]);
    if (mesh.has_colors()) {
      out += ' ';
      append_color_bytes(out, mesh.colors[i]);
      out += " 255";
    }
    out += '\n';
    writer.flush_if_full();
  }
  append_triangles_text(writer, mesh.triangles, '3', 0);
  writer.finish();
}

}  // namespace recon::io::detail
