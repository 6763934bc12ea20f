// PCD v0.7, the Point Cloud Library's format: a text header (VERSION,
// FIELDS, SIZE, TYPE, COUNT, WIDTH, HEIGHT, VIEWPOINT, POINTS, DATA, in any
// order, '#' comments) and then the points:
//   DATA ascii              one text line a point;
//   DATA binary             packed little-endian records, the fields in
//                           header order;
//   DATA binary_compressed  two uint32 (the compressed and the uncompressed
//                           size), then an LZF stream (lzf.h) that
//                           decompresses to the fields one after another,
//                           column by column: all x, then all y, ... (each
//                           block POINTS * SIZE * COUNT bytes; padding
//                           fields "_" are not stored).
// x, y, z may have any type (F 4/8, I or U 1/2/4/8); normal_x, normal_y,
// normal_z are read when all three are present; rgb (or else rgba) of SIZE
// 4 gives the colours, packed as 0x00RRGGBB (0xAARRGGBB) in its bits, a
// float's or an integer's (in ascii data, PCL writes a float rgb as the
// integer of its bits; a decimal fraction is taken as the float). Other
// fields (curvature, intensity, padding "_", histograms with COUNT > 1) are
// skipped and never checked. A name FIELDS lists twice (but the padding
// "_") is refused: taking one of the two would drop the other silently.
//
// NaN means "no value" (PCL's mark for what a sensor did not measure):
//   - a point with a NaN coordinate in an organized cloud (HEIGHT > 1: a
//     depth image), or with all three NaN in any cloud, has no position and
//     is skipped; a ReadNotes line counts them and places the first;
//   - a NaN normal component: the point has no normal, and the normals of the
//     whole cloud are dropped (recon estimates its own), said in a note; a
//     NaN colour (ascii only) drops the colours the same way.
// Any other NaN or infinity in x, y, z (a NaN in some but not all of them
// in an unorganized cloud), an infinite normal component, or a coordinate
// beyond max_coordinate, is counted and refused at the end (PointChecker).

#include "formats.h"
#include "io_detail.h"
#include "lzf.h"
#include "text_scanner.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace recon::io::detail {
namespace {

struct PcdField {
  std::string_view name;
  ScalarType type = ScalarType::float32;
  std::size_t count = 1;
  std::size_t byte_offset = 0;    ///< in a binary record
  std::size_t column = 0;         ///< first value on an ascii line
  std::uint64_t block_start = 0;  ///< of its column in decompressed binary_compressed data, per point
};

enum class PcdData { ascii, binary, compressed };

/// The slots of a point recon reads, and the fields they come from.
enum Slot : std::size_t { x, y, z, normal_x, normal_y, normal_z, color, slot_count };

struct PcdHeader {
  std::vector<PcdField> fields;
  std::uint64_t points = 0;
  std::uint64_t width = 0;  ///< points in a row of an organized cloud
  bool organized = false;   ///< HEIGHT > 1: a depth image, NaN marks a pixel without a return
  PcdData data = PcdData::ascii;
  std::size_t data_offset = 0;  ///< first byte after the DATA line
  std::size_t data_line = 0;
  std::size_t record_size = 0;  ///< bytes of a binary record
  std::size_t stored_size = 0;  ///< bytes of a point without the padding fields "_" (binary_compressed)
  std::size_t columns = 0;      ///< values on an ascii line
  /// Field index of each slot; the normals are only used when `normals`,
  /// the colour only when `colors`.
  std::array<std::size_t, slot_count> wanted{};
  bool normals = false;
  bool colors = false;
  [[nodiscard]] const PcdField& field(std::size_t slot) const { return fields[wanted[slot]]; }
  [[nodiscard]] std::size_t slots() const { return normals ? 6 : 3; }
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

/// A header line as read: its values, and where it stands.
struct HeaderEntry {
  std::vector<std::string_view> values;
  std::size_t line = 0;  // 0: absent
};

/// The header's lines, before they are checked against each other.
struct HeaderLines {
  HeaderEntry names, sizes, types, counts, width, height, points;
};

/// The DATA line's kind into `header`.
void read_data_line(std::string_view file, std::size_t n, std::string_view line,
                    const std::vector<std::string_view>& values, PcdHeader& header) {
  const std::pair<std::string_view, PcdData> kinds[] = {
      {"ascii", PcdData::ascii}, {"binary", PcdData::binary}, {"binary_compressed", PcdData::compressed}};
  const auto kind = std::find_if(std::begin(kinds), std::end(kinds),
                                 [&](const auto& k) { return values.size() == 1 && values[0] == k.first; });
  if (kind == std::end(kinds))
    fail_at_line(
        file, n,
        "bad DATA line " + excerpt(line) + ": expected 'DATA ascii', 'DATA binary' or 'DATA binary_compressed'");
  header.data = kind->second;
}

/// Reads the header up to its DATA line: the lines recon uses are returned,
/// the kind of data and where it starts go into `header`.
HeaderLines read_header_lines(std::string_view file, std::string_view content, PcdHeader& header) {
  HeaderLines entries;
  LineScanner lines(file, content);
  std::string_view line;
  for (;;) {
    if (!lines.next(line)) fail_at_line(file, lines.line_number(), "the PCD header has no DATA line");
    const std::size_t n = lines.line_number();
    Fields fields(without_comment(line));
    std::string_view keyword;
    if (!fields.next(keyword)) continue;
    std::vector<std::string_view> values;
    for (std::string_view value; fields.next(value);) values.push_back(value);

    if (keyword == "VERSION" || keyword == "VIEWPOINT") continue;
    const std::pair<std::string_view, HeaderEntry*> known[] = {
        {"FIELDS", &entries.names},  {"SIZE", &entries.sizes},  {"TYPE", &entries.types},
        {"COUNT", &entries.counts},  {"WIDTH", &entries.width}, {"HEIGHT", &entries.height},
        {"POINTS", &entries.points},
    };
    HeaderEntry* entry = nullptr;
    for (const auto& [key, target] : known) {
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
    read_data_line(file, n, line, values, header);
    return entries;
  }
}

/// Each field's type, count and place (in a record, on a line, in
/// decompressed data), from FIELDS, SIZE, TYPE and COUNT.
void lay_out_fields(std::string_view file, const HeaderLines& entries, PcdHeader& header) {
  const HeaderEntry& names = entries.names;
  const HeaderEntry& sizes = entries.sizes;
  const HeaderEntry& types = entries.types;
  const HeaderEntry& counts = entries.counts;
  if (names.line == 0) fail_at_line(file, header.data_line, "the PCD header has no FIELDS line");
  const std::size_t field_count = names.values.size();
  const auto check_length = [&](const HeaderEntry& e, std::string_view key) {
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
  std::unordered_map<std::string_view, std::size_t> first_of_name;  // a set: FIELDS may be long
  for (std::size_t f = 0; f < field_count; ++f) {
    PcdField& field = header.fields[f];
    field.name = names.values[f];
    if (const auto [first, added] = first_of_name.emplace(field.name, f); !added && field.name != "_")
      fail_at_line(file, names.line,
                   "FIELDS names " + excerpt(field.name) + " twice (fields " + std::to_string(first->second) + " and " +
                       std::to_string(f) + "); '_' is the only name that may repeat (padding)");
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
    field.block_start = header.stored_size;
    header.record_size += scalar_size(field.type) * field.count;
    if (field.name != "_") header.stored_size += scalar_size(field.type) * field.count;
    header.columns += field.count;
  }
  // A text line holds at most max_line_length / 2 values ("0 0 0 ..."): more
  // columns cannot be read, and sizing the per-column tables by them would
  // let a short header ask for gigabytes.
  if (header.data == PcdData::ascii && header.columns > max_line_length / 2)
    fail_at_line(file, counts.line != 0 ? counts.line : names.line,
                 "the fields add up to " + std::to_string(header.columns) + " values a point, more than a line of " +
                     std::to_string(max_line_length) + " bytes can hold");
}

/// The fields of x, y, z (required), of the normals and of the colour.
void find_slots(std::string_view file, const HeaderLines& entries, PcdHeader& header) {
  std::array<bool, 6> found{};
  for (std::size_t w = 0; w < wanted_names.size(); ++w) {
    for (std::size_t f = 0; f < header.fields.size(); ++f) {
      if (header.fields[f].name == wanted_names[w]) {
        header.wanted[w] = f;
        found[w] = true;
        break;
      }
    }
  }
  for (std::size_t w = 0; w < 3; ++w) {
    if (!found[w]) fail_at_line(file, entries.names.line, "the PCD file has no " + excerpt(wanted_names[w]) + " field");
  }
  header.normals = found[3] && found[4] && found[5];
  for (std::size_t w = 0; w < header.slots(); ++w) {
    if (header.field(w).count != 1)
      fail_at_line(file, entries.counts.line, "field " + excerpt(wanted_names[w]) + " must have COUNT 1");
  }
  // Colours: rgb, or else rgba, of 4 bytes; a field of another shape is not a packed colour and is skipped.
  for (const std::string_view name : {"rgb", "rgba"}) {
    const auto f = std::find_if(header.fields.begin(), header.fields.end(),
                                [&](const PcdField& field) { return field.name == name; });
    if (f == header.fields.end() || f->count != 1 || scalar_size(f->type) != 4) continue;
    header.wanted[color] = static_cast<std::size_t>(f - header.fields.begin());
    header.colors = true;
    break;
  }
}

/// The number of points, from POINTS or WIDTH x HEIGHT (which must agree
/// when both are given), and whether the cloud is organized.
void count_points(std::string_view file, const HeaderLines& entries, PcdHeader& header) {
  const HeaderEntry& width = entries.width;
  const HeaderEntry& height = entries.height;
  const HeaderEntry& points = entries.points;
  const auto single_count = [&](const HeaderEntry& e, std::string_view key) {
    std::uint64_t value = 0;
    if (e.values.size() != 1 || !parse_count(e.values[0], value))
      fail_at_line(file, e.line, "bad " + std::string(key) + " line: expected one whole number");
    return value;
  };
  const std::uint64_t h = height.line != 0 ? single_count(height, "HEIGHT") : 1;
  header.organized = h > 1;
  if (width.line != 0) header.width = single_count(width, "WIDTH");
  if (points.line != 0) {
    header.points = single_count(points, "POINTS");
    if (width.line != 0) {
      const std::uint64_t w = header.width;
      if (h != 0 && (w > std::numeric_limits<std::uint64_t>::max() / h || w * h != header.points))
        fail_at_line(file, points.line,
                     "POINTS " + std::to_string(header.points) + " differs from WIDTH x HEIGHT = " + std::to_string(w) +
                         " x " + std::to_string(h));
    }
  } else if (width.line != 0) {
    const std::uint64_t w = header.width;
    if (h != 0 && w > std::numeric_limits<std::uint64_t>::max() / h)
      fail_at_line(file, width.line, "WIDTH x HEIGHT is too large");
    header.points = w * h;
  } else {
    fail_at_line(file, header.data_line, "the PCD header has neither POINTS nor WIDTH");
  }
}

/// The header: its lines, then the fields they lay out, the ones recon
/// reads, and the number of points.
PcdHeader parse_header(std::string_view file, std::string_view content) {
  PcdHeader header;
  const HeaderLines entries = read_header_lines(file, content, header);
  lay_out_fields(file, entries, header);
  find_slots(file, entries, header);
  count_points(file, entries, header);
  return header;
}

/// Something some points lack (a position, a normal, a colour): how many,
/// and where the first one is.
struct Missing {
  std::uint64_t count = 0;
  std::size_t location = 0;
  std::uint64_t index = 0;  ///< of the first, counted from 0 in the file

  void add(std::size_t where, std::uint64_t point) {
    if (count++ == 0) {
      location = where;
      index = point;
    }
  }
};

/// One point as the file gives it, before the NaN rules.
struct PcdPoint {
  std::array<double, 6> values{};  ///< x y z normal_x normal_y normal_z
  std::uint32_t color = 0;         ///< packed 0x??RRGGBB
  bool color_missing = false;      ///< NaN or infinity in ascii data
};

std::string count_of(std::uint64_t n, std::string_view one, std::string_view many) {
  return std::to_string(n) + " " + std::string(n == 1 ? one : many);
}

/// Builds the cloud from the points in file order, applying the NaN rules
/// (see the top of the file), and tells the notes what it skipped or dropped.
class CloudBuilder {
 public:
  CloudBuilder(const PcdHeader& header, PointChecker::Location location)
      : header_(header), location_(location), checker_(location) {}

  void reserve(std::size_t n) {
    cloud_.positions.reserve(n);
    if (header_.normals) cloud_.normals.reserve(n);
    if (header_.colors) cloud_.colors.reserve(n);
  }

  /// Point `index` (counted from 0 in the file), found at `location`;
  /// `offsets`, when given, place each slot's value from there (bytes).
  void add(const PcdPoint& point, std::uint64_t index, std::size_t location, const std::size_t* offsets = nullptr) {
    const auto& v = point.values;
    const int nans = int{std::isnan(v[x])} + int{std::isnan(v[y])} + int{std::isnan(v[z])};
    if (nans == 3 || (nans > 0 && header_.organized)) {
      no_position_.add(location, index);
      return;
    }
    checker_.position(cloud_.positions.emplace_back(v[x], v[y], v[z]), location, position_names, offsets);
    if (header_.normals) {
      const Vec3& n = cloud_.normals.emplace_back(v[normal_x], v[normal_y], v[normal_z]);
      if (n.array().isNaN().any()) {
        no_normal_.add(location, index);
      } else {
        checker_.normal(n, location, pcd_normal_names, offsets != nullptr ? offsets + normal_x : nullptr);
      }
    }
    if (header_.colors) {
      if (point.color_missing) no_color_.add(location, index);
      const std::uint32_t c = point.color;
      cloud_.colors.push_back(
          {static_cast<std::uint8_t>(c >> 16), static_cast<std::uint8_t>(c >> 8), static_cast<std::uint8_t>(c)});
    }
  }

  PointCloud finish(std::string_view file, ReadNotes& notes) {
    checker_.report(file);
    if (cloud_.positions.empty())
      fail_in_file(file, "no points: all " + std::to_string(header_.points) + " points are NaN (no measurement)");
    if (no_position_.count != 0) {
      notes.skipped_points += no_position_.count;
      notes.lines.push_back("skipped " + count_of(no_position_.count, "point", "points") +
                            " with no position (NaN x y z" + (header_.organized ? " in an organized cloud" : "") +
                            "); the first at " + where(no_position_));
    }
    if (no_normal_.count != 0) {
      cloud_.normals = {};
      notes.lines.push_back("normals dropped: " + count_of(no_normal_.count, "point has", "points have") +
                            " no normal (NaN), the first at " + where(no_normal_) + "; recon estimates its own");
    }
    if (no_color_.count != 0) {
      cloud_.colors = {};
      notes.lines.push_back("colours dropped: " + count_of(no_color_.count, "point has", "points have") +
                            " no colour (not a number), the first at " + where(no_color_));
    }
    return std::move(cloud_);
  }

 private:
  /// "line 12", "byte 356" or "point 7", and the pixel of an organized cloud.
  [[nodiscard]] std::string where(const Missing& m) const {
    std::string text = place(location_, m.location);
    if (header_.organized && header_.width != 0)
      text += " (row " + std::to_string(m.index / header_.width) + ", column " +
              std::to_string(m.index % header_.width) + ")";
    return text;
  }

  const PcdHeader& header_;
  PointChecker::Location location_;
  PointChecker checker_;
  PointCloud cloud_;
  Missing no_position_;
  Missing no_normal_;
  Missing no_color_;
};

/// A packed colour written as text: PCL writes the integer of its bits, even
/// for a float field; a decimal fraction or exponent is a float whose bits
/// hold it. False for NaN or infinity.
bool packed_color_from_text(std::string_view token, double value, ScalarType type, std::uint32_t& packed) {
  if (!std::isfinite(value)) return false;
  const bool integer_text = token.find_first_of(".eE") == std::string_view::npos && value >= 0.0;
  if (type == ScalarType::float32 && !integer_text) {
    const float bits = static_cast<float>(value);  // within float's range: fits_type
    std::memcpy(&packed, &bits, sizeof packed);    // (std::bit_cast: not in Emscripten 3.1.6's libc++)
  } else if (value < 0.0) {
    packed = static_cast<std::uint32_t>(static_cast<std::int32_t>(value));  // I 4
  } else if (value <= 4294967295.0) {
    packed = static_cast<std::uint32_t>(value);
  } else {
    return false;  // an integer beyond 32 bits in a float field: no packed colour
  }
  return true;
}

void read_ascii_data(std::string_view file, std::string_view content, const PcdHeader& header, CloudBuilder& builder) {
  LineScanner lines(file, content, header.data_offset, header.data_line + 1);
  // A value takes at least two characters: cap the reservation by the text left.
  const std::uint64_t room = (content.size() - header.data_offset) / (2 * header.columns) + 1;
  builder.reserve(static_cast<std::size_t>(std::min(header.points, room)));

  // Which slot each column fills, or -1, and the type of its field.
  std::vector<int> slot_of_column(header.columns, -1);
  std::vector<ScalarType> type_of_column;
  type_of_column.reserve(header.columns);
  for (const PcdField& field : header.fields) type_of_column.insert(type_of_column.end(), field.count, field.type);
  for (std::size_t s = 0; s < header.slots(); ++s) slot_of_column[header.field(s).column] = static_cast<int>(s);
  if (header.colors) slot_of_column[header.field(color).column] = static_cast<int>(color);

  std::uint64_t read = 0;
  std::string_view line;
  while (lines.next(line)) {
    const std::size_t n = lines.line_number();
    Fields fields(line);
    PcdPoint point;
    std::size_t column = 0;
    for (std::string_view token; fields.next(token); ++column) {
      if (column >= header.columns) continue;  // counted for the message below, not parsed
      double value = 0.0;
      const NumberStatus status = parse_double(token, value);
      if (status != NumberStatus::ok) fail_at_line(file, n, describe_bad_number(status, token, "a PCD value"));
      if (!fits_type(value, type_of_column[column]))
        fail_at_line(file, n,
                     excerpt(token) + " in column " + std::to_string(column + 1) + " does not fit " +
                         describe_range(type_of_column[column]));
      const int s = slot_of_column[column];
      if (s == static_cast<int>(color)) {
        point.color_missing = !packed_color_from_text(token, value, type_of_column[column], point.color);
      } else if (s >= 0) {
        point.values[static_cast<std::size_t>(s)] = value;
      }
    }
    if (column == 0) continue;  // blank line
    if (read == header.points)
      fail_at_line(file, n,
                   "more data lines than the " + std::to_string(header.points) + " points the header declares");
    if (column != header.columns)
      fail_at_line(file, n,
                   "expected " + std::to_string(header.columns) +
                       " values on a line (one per field, times its COUNT), found " + std::to_string(column));
    builder.add(point, read++, n);
  }
  if (read != header.points)
    fail_at_line(file, lines.line_number(),
                 "the file ends after " + std::to_string(read) + " points; the header promises " +
                     std::to_string(header.points));
}

/// Decodes the points of binary data held at `data`: records in field order
/// (`columns` false: DATA binary, the file's own bytes, placed by byte) or
/// one column per field (`columns` true: decompressed binary_compressed
/// data, placed by point number).
void read_binary_points(const PcdHeader& header, const char* data, bool columns, CloudBuilder& builder) {
  const auto count = static_cast<std::size_t>(header.points);
  builder.reserve(count);
  const bool swap = needs_swap(false);  // PCL writes the memory of little-endian machines
  const std::size_t slots = header.slots() + (header.colors ? 1 : 0);
  const auto slot_field = [&](std::size_t k) { return k < header.slots() ? header.field(k) : header.field(color); };
  // Byte k of point i is at start[k] + i * stride[k].
  std::array<std::size_t, slot_count> start{};
  std::array<std::size_t, slot_count> stride{};
  for (std::size_t k = 0; k < slots; ++k) {
    const PcdField& field = slot_field(k);
    start[k] = columns ? static_cast<std::size_t>(field.block_start * header.points) : field.byte_offset;
    stride[k] = columns ? scalar_size(field.type) * field.count : header.record_size;
  }
  for (std::size_t i = 0; i < count; ++i) {
    PcdPoint point;
    for (std::size_t k = 0; k < header.slots(); ++k)
      static_cast<void>(decode_scalar(data + start[k] + i * stride[k], header.field(k).type, swap, point.values[k]));
    if (header.colors) {
      const std::size_t k = header.slots();
      point.color = read_little_endian<std::uint32_t>(data + start[k] + i * stride[k]);
    }
    if (columns) {
      builder.add(point, i, i);
    } else {
      builder.add(point, i, header.data_offset + i * header.record_size, start.data());
    }
  }
}

void read_binary_data(std::string_view file, std::string_view content, const PcdHeader& header, CloudBuilder& builder) {
  const std::size_t record = header.record_size;
  const std::uint64_t whole_records = (content.size() - header.data_offset) / record;
  if (header.points > whole_records)
    fail_at_byte(file, header.data_offset + static_cast<std::size_t>(whole_records) * record,
                 "the file ends early: the header promises " + std::to_string(header.points) + " points of " +
                     std::to_string(record) + " bytes, but the file ends inside point " +
                     std::to_string(whole_records) + " (counting from 0)");
  read_binary_points(header, content.data() + header.data_offset, false, builder);
}

void read_compressed_data(std::string_view file, std::string_view content, const PcdHeader& header,
                          CloudBuilder& builder) {
  const std::size_t at = header.data_offset;
  if (content.size() - at < 8)
    fail_at_byte(file, at, "the file ends before the two sizes (4 bytes each) that start DATA binary_compressed data");
  const auto compressed = read_little_endian<std::uint32_t>(content.data() + at);
  const auto uncompressed = read_little_endian<std::uint32_t>(content.data() + at + 4);
  const std::uint64_t point_bytes = header.stored_size;  // x, y, z at least: never 0
  if (header.points > uncompressed / point_bytes || header.points * point_bytes != uncompressed)
    fail_at_byte(file, at + 4,
                 "the uncompressed size " + std::to_string(uncompressed) + " is not " + std::to_string(header.points) +
                     " points of " + std::to_string(point_bytes) + " bytes (the fields without padding)");
  const std::size_t left = content.size() - at - 8;
  if (compressed > left)
    fail_at_byte(file, at,
                 "the compressed size " + std::to_string(compressed) + " goes beyond the end of the file (" +
                     std::to_string(left) + " bytes after the sizes)");
  // Sized from the header only when the data could hold it.
  if (uncompressed > std::uint64_t{compressed} * lzf_max_expansion)
    fail_at_byte(file, at + 4,
                 std::to_string(compressed) + " compressed bytes cannot become the " + std::to_string(uncompressed) +
                     " bytes the uncompressed size gives (LZF expands at most " + std::to_string(lzf_max_expansion) +
                     "-fold)");
  std::vector<char> data(uncompressed);
  const LzfResult result = lzf_decompress(content.substr(at + 8, compressed), data);
  if (!result.ok()) fail_at_byte(file, at + 8 + result.offset, "bad LZF data: " + result.problem);
  read_binary_points(header, data.data(), true, builder);
}

}  // namespace

PointCloud read_pcd_points(std::string_view file, std::string_view content, const ReadPointsOptions& /*options*/,
                           ReadNotes& notes) {
  const PcdHeader header = parse_header(file, content);
  if (header.points == 0) fail_in_file(file, "no points: the header declares 0 points");
  switch (header.data) {
    case PcdData::ascii: {
      CloudBuilder builder(header, PointChecker::Location::line);
      read_ascii_data(file, content, header, builder);
      return builder.finish(file, notes);
    }
    case PcdData::binary: {
      CloudBuilder builder(header, PointChecker::Location::byte);
      read_binary_data(file, content, header, builder);
      return builder.finish(file, notes);
    }
    case PcdData::compressed: {
      CloudBuilder builder(header, PointChecker::Location::point);
      read_compressed_data(file, content, header, builder);
      return builder.finish(file, notes);
    }
  }
  return {};
}

}  // namespace recon::io::detail
