// PCD v0.7, the Point Cloud Library's format: a text header (VERSION,
// FIELDS, SIZE, TYPE, COUNT, WIDTH, HEIGHT, VIEWPOINT, POINTS, DATA, in any
// order, '#' comments) and then the points, one text line each (DATA ascii)
// or packed little-endian records with the fields in header order (DATA
// binary). x, y, z may have any type (F 4/8, I or U 1/2/4/8);
// normal_x, normal_y, normal_z are read when all three are present; other
// fields (rgb, curvature, padding "_", histograms with COUNT > 1) are skipped.
//
// PCL marks a point without a measurement (in organized clouds from depth
// cameras) by x = y = z = NaN; such points are skipped. Any other NaN or
// infinity in x, y, z or the normal, or a coordinate beyond max_coordinate,
// is counted and refused at the end (PointChecker). DATA binary_compressed
// (LZF) is refused with a hint to convert the file.

#include "formats.h"
#include "io_detail.h"
#include "text_scanner.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace recon::io::detail {
namespace {

struct PcdField {
  std::string_view name;
  ScalarType type = ScalarType::float32;
  std::size_t count = 1;
  std::size_t byte_offset = 0;  ///< in a binary record
  std::size_t column = 0;       ///< first value on an ascii line
};

struct PcdHeader {
  std::vector<PcdField> fields;
  std::uint64_t points = 0;
  bool binary = false;
  std::size_t data_offset = 0;  ///< first byte after the DATA line
  std::size_t data_line = 0;
  std::size_t record_size = 0;  ///< bytes of a binary record
  std::size_t columns = 0;      ///< values on an ascii line
  /// Field index of x, y, z, normal_x, normal_y, normal_z; the normals are
  /// only used when `normals`.
  std::array<std::size_t, 6> wanted{};
  bool normals = false;
};

constexpr std::array<std::string_view, 6> wanted_names = {"x", "y", "z", "normal_x", "normal_y", "normal_z"};
constexpr std::string_view pcd_normal_names[3] = {"normal_x", "normal_y", "normal_z"};

bool scalar_type_from_pcd(std::string_view type, std::uint64_t size, ScalarType& result) {
  struct Known {
    std::string_view type;
    std::uint64_t size;
    ScalarType scalar;
  };
  static constexpr Known known[] = {
      {"F", 4, ScalarType::float32}, {"F", 8, ScalarType::float64}, {"I", 1, ScalarType::int8},
      {"I", 2, ScalarType::int16},   {"I", 4, ScalarType::int32},   {"I", 8, ScalarType::int64},
      {"U", 1, ScalarType::uint8},   {"U", 2, ScalarType::uint16},  {"U", 4, ScalarType::uint32},
      {"U", 8, ScalarType::uint64},
  };
  for (const Known& k : known) {
    if (k.type == type && k.size == size) {
      result = k.scalar;
      return true;
    }
  }
  return false;
}

PcdHeader parse_header(std::string_view file, std::string_view content) {
  struct Entry {
    std::vector<std::string_view> values;
    std::size_t line = 0;  // 0: absent
  };
  Entry names, sizes, types, counts, width, height, points;
  LineScanner lines(file, content);
  std::string_view line;
  PcdHeader header;
  for (;;) {
    if (!lines.next(line)) fail_at_line(file, lines.line_number(), "the PCD header has no DATA line");
    const std::size_t n = lines.line_number();
    Fields fields(without_comment(line));
    std::string_view keyword;
    if (!fields.next(keyword)) continue;
    std::vector<std::string_view> values;
    for (std::string_view value; fields.next(value);) values.push_back(value);

    if (keyword == "VERSION" || keyword == "VIEWPOINT") continue;
    const std::pair<std::string_view, Entry*> entries[] = {
        {"FIELDS", &names}, {"SIZE", &sizes},    {"TYPE", &types},    {"COUNT", &counts},
        {"WIDTH", &width},  {"HEIGHT", &height}, {"POINTS", &points},
    };
    Entry* entry = nullptr;
    for (const auto& [key, target] : entries) {
      if (keyword == key) entry = target;
    }
    if (entry != nullptr) {
      if (entry->line != 0) fail_at_line(file, n, "a second " + std::string(keyword) + " line");
      *entry = {std::move(values), n};
      continue;
    }
    if (keyword != "DATA") fail_at_line(file, n, "unexpected line in the PCD header: " + excerpt(line));

    header.data_line = n;
    header.data_offset = lines.position();
    if (values.size() == 1 && values[0] == "binary_compressed")
      fail_at_line(file, n,
                   "DATA binary_compressed is not supported: convert the file to binary or ascii first, "
                   "e.g. with PCL's tool: pcl_convert_pcd_ascii_binary IN.pcd OUT.pcd 1");
    if (values.size() != 1 || (values[0] != "ascii" && values[0] != "binary"))
      fail_at_line(file, n, "bad DATA line " + excerpt(line) + ": expected 'DATA ascii' or 'DATA binary'");
    header.binary = values[0] == "binary";
    break;
  }

  if (names.line == 0) fail_at_line(file, header.data_line, "the PCD header has no FIELDS line");
  const std::size_t field_count = names.values.size();
  const auto check_length = [&](const Entry& e, std::string_view key) {
    if (e.line == 0) fail_at_line(file, header.data_line, "the PCD header has no " + std::string(key) + " line");
    if (e.values.size() != field_count)
      fail_at_line(file, e.line,
                   std::string(key) + " lists " + std::to_string(e.values.size()) + " values, but FIELDS names " +
                       std::to_string(field_count));
  };
  check_length(sizes, "SIZE");
  check_length(types, "TYPE");
  if (counts.line != 0) check_length(counts, "COUNT");

  header.fields.resize(field_count);
  for (std::size_t f = 0; f < field_count; ++f) {
    PcdField& field = header.fields[f];
    field.name = names.values[f];
    std::uint64_t size = 0;
    if (!parse_count(sizes.values[f], size) || !scalar_type_from_pcd(types.values[f], size, field.type))
      fail_at_line(file, types.line,
                   "field " + excerpt(field.name) + ": TYPE " + excerpt(types.values[f]) + " with SIZE " +
                       excerpt(sizes.values[f]) + " is not supported (F 4/8, I or U 1/2/4/8)");
    std::uint64_t count = 1;
    if (counts.line != 0 && (!parse_count(counts.values[f], count) || count == 0 || count > (1U << 20)))
      fail_at_line(file, counts.line, "field " + excerpt(field.name) + ": bad COUNT " + excerpt(counts.values[f]));
    field.count = static_cast<std::size_t>(count);
    field.byte_offset = header.record_size;
    field.column = header.columns;
    header.record_size += scalar_size(field.type) * field.count;
    header.columns += field.count;
  }
  // A text line holds at most max_line_length / 2 values ("0 0 0 ..."): more
  // columns cannot be read, and sizing the per-column tables by them would
  // let a short header ask for gigabytes.
  if (!header.binary && header.columns > max_line_length / 2)
    fail_at_line(file, counts.line != 0 ? counts.line : names.line,
                 "the fields add up to " + std::to_string(header.columns) + " values a point, more than a line of " +
                     std::to_string(max_line_length) + " bytes can hold");

  std::array<bool, 6> found{};
  for (std::size_t w = 0; w < wanted_names.size(); ++w) {
    for (std::size_t f = 0; f < field_count; ++f) {
      if (header.fields[f].name == wanted_names[w]) {
        header.wanted[w] = f;
        found[w] = true;
        break;
      }
    }
  }
  for (std::size_t w = 0; w < 3; ++w) {
    if (!found[w]) fail_at_line(file, names.line, "the PCD file has no " + excerpt(wanted_names[w]) + " field");
  }
  header.normals = found[3] && found[4] && found[5];
  for (std::size_t w = 0; w < (header.normals ? 6U : 3U); ++w) {
    if (header.fields[header.wanted[w]].count != 1)
      fail_at_line(file, counts.line, "field " + excerpt(wanted_names[w]) + " must have COUNT 1");
  }

  const auto single_count = [&](const Entry& e, std::string_view key) {
    std::uint64_t value = 0;
    if (e.values.size() != 1 || !parse_count(e.values[0], value))
      fail_at_line(file, e.line, "bad " + std::string(key) + " line: expected one whole number");
    return value;
  };
  if (points.line != 0) {
    header.points = single_count(points, "POINTS");
    if (width.line != 0) {
      const std::uint64_t w = single_count(width, "WIDTH");
      const std::uint64_t h = height.line != 0 ? single_count(height, "HEIGHT") : 1;
      if (h != 0 && (w > std::numeric_limits<std::uint64_t>::max() / h || w * h != header.points))
        fail_at_line(file, points.line,
                     "POINTS " + std::to_string(header.points) + " differs from WIDTH x HEIGHT = " + std::to_string(w) +
                         " x " + std::to_string(h));
    }
  } else if (width.line != 0) {
    const std::uint64_t w = single_count(width, "WIDTH");
    const std::uint64_t h = height.line != 0 ? single_count(height, "HEIGHT") : 1;
    if (h != 0 && w > std::numeric_limits<std::uint64_t>::max() / h)
      fail_at_line(file, width.line, "WIDTH x HEIGHT is too large");
    header.points = w * h;
  } else {
    fail_at_line(file, header.data_line, "the PCD header has neither POINTS nor WIDTH");
  }
  return header;
}

void read_ascii_data(std::string_view file, std::string_view content, const PcdHeader& header, PointCloud& cloud) {
  LineScanner lines(file, content, header.data_offset, header.data_line + 1);
  PointChecker checker(false);
  // A value takes at least two characters: cap the reservation by the text left.
  const std::uint64_t room = (content.size() - header.data_offset) / (2 * header.columns) + 1;
  cloud.positions.reserve(static_cast<std::size_t>(std::min(header.points, room)));
  if (header.normals) cloud.normals.reserve(cloud.positions.capacity());

  // Which slot (0-5) each column fills, or -1, and the type of its field.
  std::vector<int> slot_of_column(header.columns, -1);
  std::vector<ScalarType> type_of_column;
  type_of_column.reserve(header.columns);
  for (const PcdField& field : header.fields) type_of_column.insert(type_of_column.end(), field.count, field.type);
  const std::size_t slots = header.normals ? 6 : 3;
  for (std::size_t s = 0; s < slots; ++s) slot_of_column[header.fields[header.wanted[s]].column] = static_cast<int>(s);

  std::uint64_t read = 0;
  std::string_view line;
  while (lines.next(line)) {
    const std::size_t n = lines.line_number();
    Fields fields(line);
    std::array<double, 6> values{};
    std::size_t column = 0;
    for (std::string_view token; fields.next(token); ++column) {
      if (column >= header.columns) continue;  // counted for the message below, not parsed
      double value = 0.0;
      const NumberStatus status = parse_double(token, value);
      if (status != NumberStatus::ok) fail_at_line(file, n, describe_bad_number(status, token, "a PCD value"));
      if (!fits_type(value, type_of_column[column]))
        fail_at_line(file, n, excerpt(token) + " in column " + std::to_string(column + 1) + " does not fit " +
                                  describe_range(type_of_column[column]));
      if (const int s = slot_of_column[column]; s >= 0) values[static_cast<std::size_t>(s)] = value;
    }
    if (column == 0) continue;  // blank line
    if (read == header.points)
      fail_at_line(file, n,
                   "more data lines than the " + std::to_string(header.points) + " points the header declares");
    if (column != header.columns)
      fail_at_line(file, n,
                   "expected " + std::to_string(header.columns) +
                       " values on a line (one per field, times its COUNT), found " + std::to_string(column));
    ++read;
    if (std::isnan(values[0]) && std::isnan(values[1]) && std::isnan(values[2])) continue;  // no measurement
    checker.position(cloud.positions.emplace_back(values[0], values[1], values[2]), n, position_names);
    if (header.normals)
      checker.normal(cloud.normals.emplace_back(values[3], values[4], values[5]), n, pcd_normal_names);
  }
  if (read != header.points)
    fail_at_line(file, lines.line_number(),
                 "the file ends after " + std::to_string(read) + " points; the header promises " +
                     std::to_string(header.points));
  checker.report(file);
}

void read_binary_data(std::string_view file, std::string_view content, const PcdHeader& header, PointCloud& cloud) {
  const std::size_t record = header.record_size;
  const std::uint64_t whole_records = (content.size() - header.data_offset) / record;
  if (header.points > whole_records)
    fail_at_byte(file, header.data_offset + static_cast<std::size_t>(whole_records) * record,
                 "the file ends early: the header promises " + std::to_string(header.points) + " points of " +
                     std::to_string(record) + " bytes, but the file ends inside point " +
                     std::to_string(whole_records) + " (counting from 0)");
  const auto count = static_cast<std::size_t>(header.points);
  cloud.positions.reserve(count);
  if (header.normals) cloud.normals.reserve(count);
  const bool swap = needs_swap(false);  // PCL writes the memory of little-endian machines
  const std::size_t slots = header.normals ? 6 : 3;
  std::array<std::size_t, 6> offsets{};
  for (std::size_t s = 0; s < slots; ++s) offsets[s] = header.fields[header.wanted[s]].byte_offset;
  PointChecker checker(true);
  for (std::size_t i = 0; i < count; ++i) {
    const std::size_t start = header.data_offset + i * record;
    std::array<double, 6> values{};
    std::array<Decoded, 6> kinds{};
    for (std::size_t s = 0; s < slots; ++s) {
      const PcdField& field = header.fields[header.wanted[s]];
      kinds[s] = decode_scalar(content.data() + start + offsets[s], field.type, swap, values[s]);
    }
    if (kinds[0] == Decoded::nan && kinds[1] == Decoded::nan && kinds[2] == Decoded::nan) continue;  // no measurement
    checker.position(cloud.positions.emplace_back(values[0], values[1], values[2]), start, position_names,
                     offsets.data());
    if (header.normals)
      checker.normal(cloud.normals.emplace_back(values[3], values[4], values[5]), start, pcd_normal_names,
                     offsets.data() + 3);
  }
  checker.report(file);
}

}  // namespace

PointCloud read_pcd_points(std::string_view file, std::string_view content) {
  const PcdHeader header = parse_header(file, content);
  if (header.points == 0) fail_in_file(file, "no points: the header declares 0 points");
  PointCloud cloud;
  if (header.binary) {
    read_binary_data(file, content, header, cloud);
  } else {
    read_ascii_data(file, content, header, cloud);
  }
  if (cloud.positions.empty())
    fail_in_file(file, "no points: all " + std::to_string(header.points) + " points are NaN (no measurement)");
  return cloud;
}

PointCloud read_pcd_points(std::string_view file, std::string_view content, const ReadPointsOptions& /*options*/,
                           ReadNotes& /*notes*/) {
  return read_pcd_points(file, content);
}

}  // namespace recon::io::detail
