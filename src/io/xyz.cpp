// Plain text point lists: .xyz (also .txt, .asc, .pwn) and .pts.
//
// xyz: one point a line, "x y z" or "x y z nx ny nz". The first data line
//   decides which, and every other line must have the same count. Numbers
//   are separated by blanks, or by a single comma with optional blanks around
//   it ("1.5, 2, 3" as exported by spreadsheets). '#' starts a comment, on its
//   own line or after the numbers; blank lines are skipped.
// xy (2D, read by read_points_2d): the same text with two numbers a line.
// pts: either Hoppe's format, records of one letter and numbers where
//   "p x y z" is a point and every other one-letter record ("d", "s", "g",
//   "n", ...) is ignored, or plain columns read as xyz. The first record
//   decides: a letter means Hoppe's format.

#include "colors.h"
#include "formats.h"
#include "io_detail.h"
#include "text_scanner.h"

#include <array>
#include <string>
#include <utility>
#include <vector>

namespace recon::io::detail {
namespace {

constexpr std::size_t max_numbers = 8;
using Numbers = std::array<std::string_view, max_numbers>;

/// Splits a data line (comment removed) into its numbers and returns how
/// many there are; the first max_numbers are stored in `numbers`.
std::size_t split_numbers(std::string_view file, std::size_t line_number, std::string_view line, Numbers& numbers) {
  std::size_t count = 0;
  std::size_t i = 0;
  bool after_comma = false;
  for (;;) {
    while (i < line.size() && is_blank(line[i])) ++i;
    if (i == line.size()) {
      if (after_comma) fail_at_line(file, line_number, "a comma at the end of the line; a number must follow it");
      return count;
    }
    if (line[i] == ',') {
      if (count == 0 || after_comma) fail_at_line(file, line_number, "a comma where a number belongs");
      after_comma = true;
      ++i;
      continue;
    }
    const std::size_t begin = i;
    while (i < line.size() && !is_blank(line[i]) && line[i] != ',') ++i;
    if (count < max_numbers) numbers[count] = line.substr(begin, i - begin);
    ++count;
    after_comma = false;
  }
}


}  // namespace

PointCloud read_xyz_points(std::string_view file, std::string_view content) {
  PointCloud cloud;
  PointChecker checker(false);
  LineScanner lines(file, content);
  std::string_view line;
  Numbers numbers;
  std::size_t columns = 0;
  std::size_t first_line = 0;
  while (lines.next(line)) {
    const std::size_t n = lines.line_number();
    const std::size_t count = split_numbers(file, n, without_comment(line), numbers);
    if (count == 0) continue;
    if (columns == 0) {
      if (count != 3 && count != 6)
        fail_at_line(file, n,
                     "expected 3 numbers (x y z) or 6 (x y z nx ny nz) on a line, found " + std::to_string(count) +
                         (count == 2 ? " (two columns are 2D points: recon reconstruct makes curves of them)" : ""));
      columns = count;
      first_line = n;
    } else if (count != columns) {
      fail_at_line(file, n,
                   "found " + std::to_string(count) + " numbers, but line " + std::to_string(first_line) + " has " +
                       std::to_string(columns) + "; every line must have the same count");
    }
    checker.position(cloud.positions.emplace_back(parse_vec3(file, n, numbers.data(), position_names)), n,
                     position_names);
    if (columns == 6)
      checker.normal(cloud.normals.emplace_back(parse_vec3(file, n, numbers.data() + 3, normal_names)), n,
                     normal_names);
  }
  if (cloud.positions.empty()) fail_in_file(file, "no points: the file holds only comments and blank lines");
  checker.report(file);
  return cloud;
}

std::size_t xyz_column_count(std::string_view file, std::string_view content) {
  LineScanner lines(file, content);
  std::string_view line;
  Numbers numbers;
  while (lines.next(line)) {
    const std::size_t count = split_numbers(file, lines.line_number(), without_comment(line), numbers);
    if (count != 0) return count;
  }
  return 0;
}

std::vector<Vec2> read_xy_points(std::string_view file, std::string_view content) {
  std::vector<Vec2> points;
  PointChecker checker(false);
  LineScanner lines(file, content);
  std::string_view line;
  Numbers numbers;
  while (lines.next(line)) {
    const std::size_t n = lines.line_number();
    const std::size_t count = split_numbers(file, n, without_comment(line), numbers);
    if (count == 0) continue;
    if (count != 2)
      fail_at_line(file, n,
                   "expected 2 numbers (x y) on a line, found " + std::to_string(count) +
                       " (the first line of points has 2, so the file was read as 2D points)");
    const Vec2 p(parse_coordinate(file, n, numbers[0], position_names[0]),
                 parse_coordinate(file, n, numbers[1], position_names[1]));
    checker.position(Vec3(p.x(), p.y(), 0.0), n, position_names);
    points.push_back(p);
  }
  if (points.empty()) fail_in_file(file, "no points: the file holds only comments and blank lines");
  checker.report(file);
  return points;
}

namespace {
bool is_letter(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z'); }

// The first field of the first record of a .pts file and its line (an
// empty field when the file has none).
std::pair<std::string_view, std::size_t> first_pts_field(std::string_view file, std::string_view content) {
  LineScanner lines(file, content);
  std::string_view line, first;
  while (lines.next(line))
    if (Fields(without_comment(line)).next(first)) return {first, lines.line_number()};
  return {{}, 0};
}
}  // namespace

bool pts_has_records(std::string_view file, std::string_view content) {
  const std::string_view first = first_pts_field(file, content).first;
  return !first.empty() && is_letter(first[0]);
}

PointCloud read_xyz_points(std::string_view file, std::string_view content, const ReadPointsOptions& /*options*/,
                           ReadNotes& /*notes*/) {
  return read_xyz_points(file, content);
}

PointCloud read_pts_points(std::string_view file, std::string_view content) {
  if (!pts_has_records(file, content)) return read_xyz_points(file, content);
  const std::size_t first_line = first_pts_field(file, content).second;

  PointCloud cloud;
  PointChecker checker(false);
  LineScanner lines(file, content);
  std::string_view line;
  while (lines.next(line)) {
    const std::size_t n = lines.line_number();
    Fields fields(without_comment(line));
    std::string_view record;
    if (!fields.next(record)) continue;
    if (record == "p") {
      std::array<std::string_view, 3> xyz;
      std::size_t count = 0;
      for (std::string_view token; fields.next(token); ++count) {
        if (count < 3) xyz[count] = token;
      }
      if (count != 3) fail_at_line(file, n, "a 'p' record needs 3 numbers (p x y z), found " + std::to_string(count));
      checker.position(cloud.positions.emplace_back(parse_vec3(file, n, xyz.data(), position_names)), n,
                       position_names);
    } else if (record.size() != 1 || !is_letter(record[0])) {
      fail_at_line(file, n,
                   "expected a one-letter record such as 'p x y z', found " + excerpt(record) +
                       " (the file was read as Hoppe's .pts format because line " + std::to_string(first_line) +
                       " starts with a letter)");
    }
  }
  if (cloud.positions.empty()) fail_in_file(file, "no points: the file has no 'p x y z' record");
  checker.report(file);
  return cloud;
}

void write_xyz_points(std::ostream& stream, const PointCloud& cloud) {
  BlockWriter writer(stream);
  std::string& out = writer.buffer();
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Vec3& p = cloud.positions[i];
    append_vec3_text(out, p);
    if (cloud.has_normals()) {
      const Vec3& v = cloud.normals[i];
      out += ' ';
      append_vec3_text(out, v);
    }
    if (cloud.has_colors()) {
      out += ' ';
      append_color_bytes(out, cloud.colors[i]);
    }
    out += '\n';
    writer.flush_if_full();
  }
  writer.finish();
}

void write_text_curves(std::ostream& stream, const PolylineSet& curves) {
  BlockWriter writer(stream);
  std::string& out = writer.buffer();
  out += "# written by recon: ";
  out += std::to_string(curves.polylines.size());
  out += " curves, \"x y\" a line, a blank line between curves; a closed curve repeats its first vertex at the end\n";
  for (std::size_t c = 0; c < curves.polylines.size(); ++c) {
    const Polyline& line = curves.polylines[c];
    if (c > 0) out += '\n';
    out += "# curve " + std::to_string(c + 1) + ": " + (line.closed ? "closed, " : "open, ") +
           std::to_string(line.vertices.size()) + " vertices\n";
    auto vertex = [&](std::uint32_t v) {
      append_number(out, curves.vertices[v].x());
      out += ' ';
      append_number(out, curves.vertices[v].y());
      out += '\n';
      writer.flush_if_full();
    };
    for (const std::uint32_t v : line.vertices) vertex(v);
    if (line.closed && !line.vertices.empty()) vertex(line.vertices.front());
  }
  writer.finish();
}

}  // namespace recon::io::detail
