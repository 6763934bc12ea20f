// Plain text point lists: .xyz (also .txt, .asc, .pwn, .csv) and .pts.
//
// xyz: delimited text, one point a line. What each column holds comes from
//   a header line, from --columns, or from the column count and the values
//   (text_columns.h states the rules); the separator (blanks, commas or
//   semicolons) from the first line of numbers. '#' starts a comment, on its
//   own line or after the numbers; blank lines are skipped; a UTF-8
//   byte-order mark is skipped; lines end with "\n", "\r\n" or "\r".
//   The file is parsed once, straight from its memory map (twice when read
//   in chunks and the values decide what columns hold: text_columns.h).
// xy (2D, read by read_points_2d): the same text with two numbers a line,
//   x y (a header naming them is allowed).
// pts: either Hoppe's format, records of one letter and numbers where
//   "p x y z" is a point and every other one-letter record ("d", "s", "g",
//   "n", ...) is ignored, or plain columns read as xyz. The first record
//   decides: a letter means Hoppe's format.

#include "colors.h"
#include "formats.h"
#include "io_detail.h"
#include "text_columns.h"
#include "text_scanner.h"

#include "recon/core/errors.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace recon::io::detail {
namespace {

/// Reads the data lines of a delimited text file as `plan` says, in one
/// pass: positions (and named normals) go straight into the part (see
/// point_parts.h); held values (colours, the undecided columns of a file
/// without a header) are kept as doubles, with the evidence about them,
/// until the end decides what they are, or, when a survey of the file has
/// decided that before (`decided`), until the part is complete.
class ColumnReader {
 public:
  ColumnReader(std::string_view file, const TextLayout& layout, ColumnPlan& plan, PointParts& parts,
               std::optional<HeldUse> decided = std::nullopt)
      : file_(file),
        layout_(layout),
        plan_(plan),
        parts_(parts),
        decided_(decided),
        triples_per_point_((plan.held() + 2) / 3),
        columns_(plan.held()) {
    has_normals_ = std::any_of(plan.fields.begin(), plan.fields.end(),
                               [](const FieldTarget& t) { return t.kind == FieldTarget::Kind::normal; });
    if (plan.guessed() && plan.held() >= 3) {
      triples_.resize(plan.held() - 2);
      triple_checks_.assign(plan.held() - 2, PointChecker(false));
    }
  }

  void read(std::string_view content) {
    LineScanner lines = layout_lines(file_, content, layout_);
    for (std::string_view line; lines.next(line);) {
      const std::string_view data = without_comment(line);
      if (lines.line_number() == layout_.header_line || is_blank_line(data)) continue;
      read_line(data, lines.line_number());
      if (parts_.full()) hand_part(lines.position());
    }
    end_ = lines.position();
  }

  /// After read(): refuses what is wrong in the whole file, completes the
  /// last part and returns what the held values are.
  HeldUse finish(ReadNotes& notes) {
    if (parts_.count() == 0)
      fail_in_file(file_, layout_.header_line == 0
                              ? "no points: the file holds only comments and blank lines"
                              : "no points: the file holds only a header line, comments and blank lines");
    const HeldUse use = decided_ ? *decided_ : decide_columns(file_, plan_, columns_, triples_, notes);
    if (use.normals >= 0 && plan_.guessed())
      checker_.take_normals(triple_checks_[static_cast<std::size_t>(use.normals)]);
    checker_.report(file_);
    complete_part(use);
    parts_.finish(end_);
    return use;
  }

 private:
  static constexpr std::size_t max_held = 6;

  /// Hands a full part on, its held values made normals and colours as
  /// decided (a survey, which has not decided yet, drops them).
  void hand_part(std::size_t position) {
    if (decided_) complete_part(*decided_);
    held_.clear();
    parts_.hand(position);
  }

  void complete_part(const HeldUse& use) {
    PointCloud& part = parts_.part();
    if (use.normals >= 0) part.normals = held_triple(static_cast<std::size_t>(use.normals));
    if (use.colours >= 0) part.colors = held_colours(static_cast<std::size_t>(use.colours), use.colour_scale);
    held_.clear();
  }

  /// One data line (its comment removed): every field in its place, the
  /// count checked against the plan's.
  void read_line(std::string_view data, std::size_t line) {
    Fields fields(data, layout_.separator);
    Vec3 position = Vec3::Zero(), normal = Vec3::Zero();
    std::array<double, max_held> held{};
    const std::size_t columns = plan_.fields.size();
    std::size_t i = 0;
    for (std::string_view field; fields.next(field); ++i) {
      if (i == columns) fail_count(line, columns + 1 + fields.count_rest());
      const FieldTarget target = plan_.fields[i];
      if (target.kind == FieldTarget::Kind::skip) continue;
      const double value = parse_text_field(file_, line, field, plan_.names[i], layout_);
      if (target.kind == FieldTarget::Kind::position) {
        position[target.index] = value;
      } else if (target.kind == FieldTarget::Kind::normal) {
        normal[target.index] = value;
      } else {
        held[target.index] = value;
      }
    }
    if (i != columns) fail_count(line, i);
    PointCloud& part = parts_.part();
    checker_.position(part.positions.emplace_back(position), line, position_names);
    if (has_normals_) checker_.normal(part.normals.emplace_back(normal), line, normal_names);
    if (!columns_.empty()) hold(held, line);
  }

  /// Keeps a line's held values and adds them to the evidence: per column
  /// (colours?) and, in a guessed plan, per triple (unit vectors?). A point
  /// left out for its position (skip_invalid) is no evidence.
  void hold(const std::array<double, max_held>& values, std::size_t line) {
    if (!checker_.skips_last_point()) {
      for (std::size_t s = 0; s < columns_.size(); ++s) columns_[s].add(values[s], line);
      for (std::size_t s = 0; s < triples_.size(); ++s) {
        triples_[s].add(values[s], values[s + 1], values[s + 2], line);
        triple_checks_[s].normal(Vec3(values[s], values[s + 1], values[s + 2]), line, normal_names);
      }
    }
    for (std::size_t t = 0; t < triples_per_point_; ++t)
      held_.emplace_back(values[3 * t], values[3 * t + 1], values[3 * t + 2]);
  }

  /// The held value of point `point` in slot `slot`.
  [[nodiscard]] double held_value(std::size_t point, std::size_t slot) const {
    return held_[point * triples_per_point_ + slot / 3][static_cast<Eigen::Index>(slot % 3)];
  }

  /// The held triple at `slot` of every point of the part (moved out when it is all that is held).
  std::vector<Vec3> held_triple(std::size_t slot) {
    if (slot == 0 && triples_per_point_ == 1) return std::exchange(held_, {});
    std::vector<Vec3> triple(parts_.part().size());
    for (std::size_t i = 0; i < triple.size(); ++i)
      triple[i] = Vec3(held_value(i, slot), held_value(i, slot + 1), held_value(i, slot + 2));
    return triple;
  }

  std::vector<Color> held_colours(std::size_t slot, double scale) const {
    std::vector<Color> colours(parts_.part().size());
    for (std::size_t i = 0; i < colours.size(); ++i)
      for (std::size_t k = 0; k < 3; ++k)
        colours[i][k] = static_cast<std::uint8_t>(std::lround(held_value(i, slot + k) * scale));
    return colours;
  }

  [[noreturn]] void fail_count(std::size_t line, std::size_t found) const {
    const std::string columns = std::to_string(plan_.fields.size());
    const std::string has = ", but this line has " + std::to_string(found);
    if (plan_.source == ColumnPlan::Source::option)
      fail_at_line(file_, line, "--columns names " + columns + " columns" + has);
    if (plan_.source == ColumnPlan::Source::header) {
      const std::string header = "the header on line " + std::to_string(plan_.header_line);
      fail_at_line(file_, line, header + " names " + columns + " columns" + has);
    }
    fail_at_line(file_, line,
                 "found " + std::to_string(found) + " numbers, but line " + std::to_string(layout_.first_line) +
                     " has " + columns + "; every line must have the same count");
  }

  std::string_view file_;
  const TextLayout& layout_;
  ColumnPlan& plan_;
  PointParts& parts_;
  std::optional<HeldUse> decided_;
  std::size_t triples_per_point_;  ///< Vec3s of held_ per point
  bool has_normals_ = false;
  std::size_t end_ = 0;  ///< the end of the text, once read
  PointChecker checker_{false};
  std::vector<Vec3> held_;
  std::vector<ColumnEvidence> columns_;      ///< per held slot
  std::vector<TripleEvidence> triples_;      ///< per held slot where a triple starts (guessed plans)
  std::vector<PointChecker> triple_checks_;  ///< those triples as normals (guessed plans)
};

}  // namespace

void read_xyz_points(std::string_view file, std::string_view content, const ReadPointsOptions& options,
                     ReadNotes& notes, PointParts& parts) {
  const TextLayout layout = find_text_layout(file, content);
  if (layout.first_line == 0)
    fail_in_file(file, layout.header_line == 0
                           ? "no points: the file holds only comments and blank lines"
                           : "no points: the file holds only a header line, comments and blank lines");
  ColumnPlan plan = plan_columns(file, layout, options.columns);
  std::optional<HeldUse> decided;
  if (!parts.whole() && plan.held() != 0) {
    survey(parts, [&](PointParts& dropped) {
      ColumnReader all(file, layout, plan, dropped);
      all.read(content);
      decided = all.finish(notes);
    });
  }
  ColumnReader reader(file, layout, plan, parts, decided);
  reader.read(content);
  static_cast<void>(reader.finish(notes));
}

PointCloud read_xyz_points(std::string_view file, std::string_view content, const ReadPointsOptions& options,
                           ReadNotes& notes) {
  PointParts whole;
  read_xyz_points(file, content, options, notes, whole);
  return whole.take_whole();
}

PointCloud read_xyz_points(std::string_view file, std::string_view content) {
  ReadNotes ignored;
  return read_xyz_points(file, content, ReadPointsOptions{}, ignored);
}

std::size_t xyz_column_count(std::string_view file, std::string_view content) {
  return find_text_layout(file, content).columns;
}

namespace {

/// Splits a line of 2D points (comment removed) into its numbers and
/// returns how many there are; the first two are stored in `numbers`.
/// Blanks separate numbers, and so does a single comma with optional blanks
/// around it, on any line (2D files have mixed them: a wrong count is
/// refused anyway); in a file separated by semicolons, a semicolon does.
std::size_t split_xy(std::string_view file, std::size_t line_number, std::string_view line, const TextLayout& layout,
                     std::array<std::string_view, 2>& numbers) {
  std::size_t count = 0;
  if (layout.separator == Separator::semicolon) {
    Fields fields(line, layout.separator);
    for (std::string_view field; fields.next(field); ++count)
      if (count < 2) numbers[count] = field;
    return count;
  }
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
    if (count < 2) numbers[count] = line.substr(begin, i - begin);
    ++count;
    after_comma = false;
  }
}

}  // namespace

std::vector<Vec2> read_xy_points(std::string_view file, std::string_view content) {
  const TextLayout layout = find_text_layout(file, content);
  if (layout.header_line != 0 && (layout.header.size() != 2 || role_named(layout.header[0]) != ColumnRole::x ||
                                  role_named(layout.header[1]) != ColumnRole::y))
    fail_at_line(file, layout.header_line, "the header line of 2D points must name two columns, x y");
  std::vector<Vec2> points;
  PointChecker checker(false);
  LineScanner lines = layout_lines(file, content, layout);
  std::array<std::string_view, 2> xy;
  for (std::string_view line; lines.next(line);) {
    const std::size_t n = lines.line_number();
    const std::string_view data = without_comment(line);
    if (n == layout.header_line || is_blank_line(data)) continue;
    const std::size_t count = split_xy(file, n, data, layout, xy);
    if (count != 2)
      fail_at_line(file, n,
                   "expected 2 numbers (x y) on a line, found " + std::to_string(count) +
                       " (the first line of points has 2, so the file was read as 2D points)");
    const Vec2 p(parse_text_field(file, n, xy[0], position_names[0], layout),
                 parse_text_field(file, n, xy[1], position_names[1], layout));
    checker.position(Vec3(p.x(), p.y(), 0.0), n, position_names);
    points.push_back(p);
  }
  if (points.empty()) fail_in_file(file, "no points: the file holds only comments and blank lines");
  checker.report(file);
  return points;
}

namespace {
bool is_letter(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z'); }

/// The lines of a .pts file, after a byte-order mark, with their line ends.
LineScanner pts_lines(std::string_view file, std::string_view content) {
  const std::size_t start = byte_order_mark_length(content);
  return LineScanner(file, content, start, 1, detect_line_ends(content, start));
}

// The first record of a .pts file, without its comment, and its line (an
// empty record when the file has none).
std::pair<std::string_view, std::size_t> first_pts_record(std::string_view file, std::string_view content) {
  LineScanner lines = pts_lines(file, content);
  for (std::string_view line; lines.next(line);)
    if (!is_blank_line(without_comment(line))) return {without_comment(line), lines.line_number()};
  return {{}, 0};
}
}  // namespace

bool pts_has_records(std::string_view file, std::string_view content) {
  // "p 1 2 3" is a record; "x y z" (no number) is a header of plain columns.
  const std::string_view record = first_pts_record(file, content).first;
  std::string_view first;
  return Fields(record).next(first) && is_letter(first[0]) && !is_header_line(record);
}

PointCloud read_pts_points(std::string_view file, std::string_view content, const ReadPointsOptions& options,
                           ReadNotes& notes) {
  if (!pts_has_records(file, content)) return read_xyz_points(file, content, options, notes);
  if (!options.columns.empty())
    throw InvalidInputError(std::string(file) +
                            ": --columns applies to plain columns, but this .pts file holds Hoppe's 'p x y z' "
                            "records (line " +
                            std::to_string(first_pts_record(file, content).second) + "); drop --columns");
  return read_pts_points(file, content);
}

PointCloud read_pts_points(std::string_view file, std::string_view content) {
  if (!pts_has_records(file, content)) return read_xyz_points(file, content);
  const std::size_t first_line = first_pts_record(file, content).second;

  PointCloud cloud;
  PointChecker checker(false);
  LineScanner lines = pts_lines(file, content);
  for_each_statement(lines, [&](std::size_t n, std::string_view record, Fields& fields) {
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
  });
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
  out += written_by_recon(std::to_string(curves.polylines.size()) +
                          " curves, \"x y\" a line, a blank line between curves; a closed curve repeats its first "
                          "vertex at the end");
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
