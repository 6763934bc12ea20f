// PLY 1.0 (Turk, Stanford), reading (ply_write.cpp writes): a text header
// declaring elements and their properties, then the elements in the
// declared order, as text or as packed binary records in either byte order.
//
// One reader serves both read_points and read_mesh. It walks every element
// of the body (so elements may come in any order and a truncated file is
// always noticed), keeps the "vertex" element's x, y, z (and nx, ny, nz when
// all three are declared, and red, green, blue or diffuse_red,
// diffuse_green, diffuse_blue when all three are: colors.h says how each
// type becomes 0-255) and, for meshes, the "face" element's
// "vertex_indices" (or "vertex_index") list; every other property and
// element (alpha among them) is skipped. A property name declared twice in
// one element is refused: taking either would drop the other silently.

#include "colors.h"
#include "formats.h"
#include "io_detail.h"
#include "point_parts.h"
#include "text_scanner.h"

#include "recon/core/errors.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

namespace recon::io::detail {
namespace {

enum class PlyEncoding { ascii, binary_little_endian, binary_big_endian };

struct PlyProperty {
  std::string name;
  ScalarType type = ScalarType::float32;  ///< of the value, or of each list item
  bool is_list = false;
  ScalarType count_type = ScalarType::uint8;  ///< lists only
  std::size_t line = 0;                       ///< header line that declares it
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;
  std::size_t line = 0;

  [[nodiscard]] bool has_lists() const {
    return std::any_of(properties.begin(), properties.end(), [](const PlyProperty& p) { return p.is_list; });
  }
  /// Bytes of one binary record; only meaningful without list properties.
  [[nodiscard]] std::size_t record_size() const {
    std::size_t size = 0;
    for (const PlyProperty& p : properties) size += scalar_size(p.type);
    return size;
  }
};

struct PlyHeader {
  PlyEncoding encoding = PlyEncoding::ascii;
  std::vector<PlyElement> elements;
  std::size_t body_offset = 0;      ///< first byte after the end_header line
  std::size_t end_header_line = 0;  ///< the body starts on the next line
};

bool scalar_type_from_name(std::string_view name, ScalarType& type) {
  static constexpr std::pair<std::string_view, ScalarType> names[] = {
      {"char", ScalarType::int8},       {"int8", ScalarType::int8},       {"uchar", ScalarType::uint8},
      {"uint8", ScalarType::uint8},     {"short", ScalarType::int16},     {"int16", ScalarType::int16},
      {"ushort", ScalarType::uint16},   {"uint16", ScalarType::uint16},   {"int", ScalarType::int32},
      {"int32", ScalarType::int32},     {"uint", ScalarType::uint32},     {"uint32", ScalarType::uint32},
      {"float", ScalarType::float32},   {"float32", ScalarType::float32}, {"double", ScalarType::float64},
      {"float64", ScalarType::float64},
  };
  for (const auto& [known, known_type] : names) {
    if (name == known) {
      type = known_type;
      return true;
    }
  }
  return false;
}

constexpr std::string_view known_types =
    "char, uchar, short, ushort, int, uint, float, double, int8, uint8, int16, uint16, int32, uint32, float32, "
    "float64";

/// A "format ENCODING 1.0" line into `header`.
void read_format_line(std::string_view file, std::size_t n, std::string_view line, Fields& fields, bool& have_format,
                      PlyHeader& header) {
  std::string_view encoding;
  std::string_view version;
  if (!fields.next(encoding) || !fields.next(version) || fields.count_rest() != 0)
    fail_at_line(file, n,
                 "bad format line " + excerpt(line) +
                     ": expected 'format ascii 1.0' (or binary_little_endian, binary_big_endian)");
  if (encoding == "ascii") {
    header.encoding = PlyEncoding::ascii;
  } else if (encoding == "binary_little_endian") {
    header.encoding = PlyEncoding::binary_little_endian;
  } else if (encoding == "binary_big_endian") {
    header.encoding = PlyEncoding::binary_big_endian;
  } else {
    fail_at_line(
        file, n,
        "unknown PLY format " + excerpt(encoding) + " (expected ascii, binary_little_endian or binary_big_endian)");
  }
  double number = 0.0;
  if (parse_double(version, number) != NumberStatus::ok || number != 1.0)
    fail_at_line(file, n, "unsupported PLY version " + excerpt(version) + " (only 1.0 exists)");
  if (have_format) fail_at_line(file, n, "a second format line");
  have_format = true;
}

/// An "element NAME COUNT" line: a new element of `header`. `names` holds
/// the names so far (views into the content).
void read_element_line(std::string_view file, std::size_t n, std::string_view line, Fields& fields,
                       std::unordered_set<std::string_view>& names, PlyHeader& header) {
  std::string_view name;
  std::string_view count;
  PlyElement element;
  if (!fields.next(name) || !fields.next(count) || fields.count_rest() != 0 || !parse_count(count, element.count))
    fail_at_line(file, n, "bad element line " + excerpt(line) + ": expected 'element NAME COUNT'");
  // A set, not a scan of the elements so far: a header of millions of
  // elements would otherwise take quadratic time.
  if (!names.insert(name).second) fail_at_line(file, n, "a second element named " + excerpt(name));
  element.name = name;
  element.line = n;
  header.elements.push_back(std::move(element));
}

/// The properties of the element being declared, by name, with the line of
/// each (views into the content): a name declared twice is refused, since a
/// reader taking one of the two would silently drop the other's values.
using PropertyLines = std::unordered_map<std::string_view, std::size_t>;

/// A "property TYPE NAME" or "property list COUNT_TYPE ITEM_TYPE NAME" line:
/// a new property of the last element.
void read_property_line(std::string_view file, std::size_t n, std::string_view line, Fields& fields,
                        PropertyLines& declared, PlyHeader& header) {
  if (header.elements.empty()) fail_at_line(file, n, "a property before any element");
  PlyProperty property;
  property.line = n;
  std::string_view type;
  std::string_view name;
  if (!fields.next(type)) fail_at_line(file, n, "bad property line: expected 'property TYPE NAME'");
  if (type == "list") {
    std::string_view count_type;
    if (!fields.next(count_type) || !fields.next(type) || !fields.next(name) || fields.count_rest() != 0)
      fail_at_line(file, n,
                   "bad list property line " + excerpt(line) + ": expected 'property list COUNT_TYPE ITEM_TYPE NAME'");
    property.is_list = true;
    if (!scalar_type_from_name(count_type, property.count_type))
      fail_at_line(file, n, "unknown type " + excerpt(count_type) + " (known: " + std::string(known_types) + ")");
    if (!is_integer_type(property.count_type))
      fail_at_line(
          file, n,
          "the length of list " + excerpt(name) + " has type " + excerpt(count_type) + "; it must be an integer type");
  } else if (!fields.next(name) || fields.count_rest() != 0) {
    fail_at_line(file, n, "bad property line " + excerpt(line) + ": expected 'property TYPE NAME'");
  }
  if (!scalar_type_from_name(type, property.type))
    fail_at_line(file, n, "unknown type " + excerpt(type) + " (known: " + std::string(known_types) + ")");
  if (const auto [first, added] = declared.emplace(name, n); !added)
    fail_at_line(file, n,
                 "property " + excerpt(name) + " of element " + excerpt(header.elements.back().name) +
                     " is declared twice (first at line " + std::to_string(first->second) + ")");
  property.name = name;
  header.elements.back().properties.push_back(std::move(property));
}

/// The header, line by line up to end_header.
PlyHeader parse_header(std::string_view file, std::string_view content) {
  LineScanner lines(file, content);
  std::string_view line;
  if (!lines.next(line) || trim(line) != "ply") fail_at_line(file, 1, "not a PLY file: the first line must be 'ply'");

  PlyHeader header;
  std::unordered_set<std::string_view> element_names;  // views into the content
  PropertyLines property_lines;                        // of the last element
  bool have_format = false;
  for (;;) {
    if (!lines.next(line)) fail_at_line(file, lines.line_number(), "the PLY header has no 'end_header' line");
    const std::size_t n = lines.line_number();
    Fields fields(line);
    std::string_view keyword;
    if (!fields.next(keyword)) continue;  // blank line
    if (keyword == "comment" || keyword == "obj_info") continue;
    if (keyword == "format") {
      read_format_line(file, n, line, fields, have_format, header);
    } else if (keyword == "element") {
      read_element_line(file, n, line, fields, element_names, header);
      property_lines.clear();
    } else if (keyword == "property") {
      read_property_line(file, n, line, fields, property_lines, header);
    } else if (keyword == "end_header") {
      if (!have_format) fail_at_line(file, n, "the PLY header has no format line");
      header.body_offset = lines.position();
      header.end_header_line = n;
      return header;
    } else {
      fail_at_line(file, n, "unexpected line in the PLY header: " + excerpt(line));
    }
  }
}

// The vertex properties the reader keeps: a slot each.
constexpr std::size_t slot_count = 9;
constexpr std::array<std::string_view, slot_count> slot_names = {"x",  "y",   "z",     "nx",  "ny",
                                                                 "nz", "red", "green", "blue"};
constexpr std::size_t first_normal_slot = 3, first_color_slot = 6;
/// The colours' older names (MeshLab's), used when red, green, blue are not all there.
constexpr std::array<std::string_view, 3> diffuse_names = {"diffuse_red", "diffuse_green", "diffuse_blue"};

// What the reader keeps, and where it finds it.
struct Wanted {
  std::size_t vertex_element = 0;
  /// Per property of the vertex element: its slot (0-2 for x, y, z, 3-5 for
  /// nx, ny, nz, 6-8 for the colours), -1 for a property that is skipped.
  std::vector<int> slot;
  bool normals = false;
  bool colors = false;
  std::array<ScalarType, 3> color_types{};  ///< of red, green, blue (when colors)
  static constexpr std::size_t none = std::numeric_limits<std::size_t>::max();
  std::size_t face_element = none;
  std::size_t face_property = none;

  [[nodiscard]] bool used(std::size_t slot_index) const {
    if (slot_index >= first_color_slot) return colors;
    return slot_index < first_normal_slot || normals;
  }
};

/// The vertex element and the slot of each of its properties.
void find_vertex_slots(std::string_view file, const PlyHeader& header, Wanted& wanted) {
  const auto vertex = std::find_if(header.elements.begin(), header.elements.end(),
                                   [](const PlyElement& e) { return e.name == "vertex"; });
  if (vertex == header.elements.end())
    fail_at_line(file, header.end_header_line, "the PLY header declares no 'vertex' element");
  wanted.vertex_element = static_cast<std::size_t>(vertex - header.elements.begin());

  std::array<std::size_t, slot_count> found{};
  found.fill(Wanted::none);
  std::array<std::size_t, 3> diffuse{};
  diffuse.fill(Wanted::none);
  for (std::size_t p = 0; p < vertex->properties.size(); ++p) {
    const PlyProperty& property = vertex->properties[p];
    if (property.is_list)
      fail_at_line(file, property.line,
                   "list property " + excerpt(property.name) +
                       " on the vertex element is not supported (vertex properties must be scalars)");
    for (std::size_t s = 0; s < slot_names.size(); ++s) {
      if (property.name == slot_names[s] && found[s] == Wanted::none) found[s] = p;
    }
    for (std::size_t c = 0; c < diffuse_names.size(); ++c) {
      if (property.name == diffuse_names[c] && diffuse[c] == Wanted::none) diffuse[c] = p;
    }
  }
  for (std::size_t s = 0; s < 3; ++s) {
    if (found[s] == Wanted::none)
      fail_at_line(file, vertex->line, "the vertex element has no " + excerpt(slot_names[s]) + " property");
  }
  const auto all_found = [](const std::size_t* first) {
    return std::all_of(first, first + 3, [](std::size_t p) { return p != Wanted::none; });
  };
  wanted.normals = all_found(&found[first_normal_slot]);
  if (!all_found(&found[first_color_slot]) && all_found(diffuse.data()))
    std::copy(diffuse.begin(), diffuse.end(), found.begin() + first_color_slot);
  wanted.colors = all_found(&found[first_color_slot]);
  wanted.slot.assign(vertex->properties.size(), -1);
  for (std::size_t s = 0; s < slot_count; ++s) {
    if (wanted.used(s)) wanted.slot[found[s]] = static_cast<int>(s);
  }
  if (wanted.colors) {
    for (std::size_t c = 0; c < 3; ++c) wanted.color_types[c] = vertex->properties[found[first_color_slot + c]].type;
  }
}

/// The face element and its list of vertex indices (meshes only).
void find_face_list(std::string_view file, const PlyHeader& header, Wanted& wanted) {
  const PlyElement& vertex = header.elements[wanted.vertex_element];
  if (vertex.count > std::numeric_limits<std::uint32_t>::max())
    fail_at_line(file, vertex.line, "too many vertices for a mesh (at most 2^32 - 1)");
  const auto face = std::find_if(header.elements.begin(), header.elements.end(),
                                 [](const PlyElement& e) { return e.name == "face"; });
  if (face == header.elements.end())
    fail_at_line(file, header.end_header_line, "the PLY header declares no 'face' element (is this a point cloud?)");
  wanted.face_element = static_cast<std::size_t>(face - header.elements.begin());
  for (std::size_t p = 0; p < face->properties.size(); ++p) {
    const PlyProperty& property = face->properties[p];
    if (property.is_list && (property.name == "vertex_indices" || property.name == "vertex_index")) {
      wanted.face_property = p;
      break;
    }
  }
  if (wanted.face_property == Wanted::none)
    fail_at_line(file, face->line, "the face element has no list property 'vertex_indices' or 'vertex_index'");
}

Wanted find_wanted(std::string_view file, const PlyHeader& header, bool faces) {
  Wanted wanted;
  find_vertex_slots(file, header, wanted);
  if (faces) find_face_list(file, header, wanted);
  return wanted;
}

using Triangles = std::vector<std::array<std::uint32_t, 3>>;

/// The vertices the reader keeps, as they come: their positions (checked),
/// normals and colours go into `parts` (see point_parts.h), the colours
/// through a ColorReader, which converts them when a part is complete.
class PlyVertices {
 public:
  PlyVertices(const Wanted& wanted, PointParts& parts, bool binary)
      : wanted_(wanted), parts_(parts), checker_(binary), colors_(wanted.color_types) {}

  void reserve(std::uint64_t count) {
    const std::size_t room = parts_.room(count);
    parts_.part().positions.reserve(room);
    if (wanted_.normals) parts_.part().normals.reserve(room);
    if (wanted_.colors) colors_.reserve(room);
  }
  /// A vertex of the slot values `values`, read at `location` (a line, or
  /// the byte where its record starts, with the slots' `offsets` in it).
  void add(const std::array<double, slot_count>& values, std::size_t location, const std::size_t* offsets = nullptr) {
    PointCloud& part = parts_.part();
    checker_.position(part.positions.emplace_back(values[0], values[1], values[2]), location, position_names, offsets);
    if (wanted_.normals)
      checker_.normal(part.normals.emplace_back(values[3], values[4], values[5]), location, normal_names,
                      offsets != nullptr ? offsets + first_normal_slot : nullptr);
    if (wanted_.colors) colors_.add(values[6], values[7], values[8]);
  }
  /// After a vertex: hands the part on when it is full; the reader has read
  /// everything before byte `position`.
  void hand_if_full(std::size_t position) {
    if (!parts_.full()) return;
    complete_part();
    parts_.hand(position);
  }
  /// After the body: refuses the bad values found (PointChecker::report;
  /// `mesh`: as vertices) and completes the last part.
  void finish(std::string_view file, bool mesh, std::size_t position) {
    checker_.report(file, mesh);
    complete_part();
    parts_.finish(position);
  }
  [[nodiscard]] PointParts& parts() { return parts_; }
  [[nodiscard]] ColorReader& colors() { return colors_; }

 private:
  void complete_part() {
    if (wanted_.colors) parts_.part().colors = colors_.take();
  }
  const Wanted& wanted_;
  PointParts& parts_;
  PointChecker checker_;
  ColorReader colors_;
};

std::string ends_early(const PlyElement& element, std::uint64_t index) {
  return "the file ends inside " + element.name + " " + std::to_string(index) +
         " (counting from 0), but the header promises " + std::to_string(element.count) + " '" + element.name +
         "' elements";
}

/// Splits polygon `corners` (already checked) into a fan of triangles.
void add_fan(const std::vector<std::uint32_t>& corners, std::vector<std::array<std::uint32_t, 3>>& triangles) {
  for (std::size_t k = 1; k + 1 < corners.size(); ++k) triangles.push_back({corners[0], corners[k], corners[k + 1]});
}

/// A value of `property` (of type `type`: the item type for lists) as text:
/// a number within the range of the type, else ParseError at `line`.
double parse_value(std::string_view file, std::size_t line, std::string_view token, const PlyProperty& property,
                   ScalarType type) {
  double value = 0.0;
  const NumberStatus status = parse_double(token, value);
  if (status == NumberStatus::not_a_number) fail_at_line(file, line, describe_bad_number(status, token, property.name));
  if (status == NumberStatus::overflow || !fits_type(value, type))
    fail_at_line(file, line, excerpt(token) + " for " + property.name + " does not fit " + describe_range(type));
  return value;
}

/// What both body readers share: where the values go (the vertices, and the
/// faces' triangles or nullptr for a point cloud), the file's name for the
/// messages, and the header that says what comes.
class BodyReader {
 protected:
  BodyReader(std::string_view file, const PlyHeader& header, const Wanted& wanted, PlyVertices& vertices,
             Triangles* triangles)
      : file_(file),
        header_(header),
        wanted_(wanted),
        vertices_(vertices),
        triangles_(triangles),
        vertex_count_(header.elements[wanted.vertex_element].count) {}

  std::string_view file_;
  const PlyHeader& header_;
  const Wanted& wanted_;
  PlyVertices& vertices_;
  Triangles* triangles_;  ///< the faces' triangles, or nullptr (a point cloud)
  std::uint64_t vertex_count_;
  std::vector<std::uint32_t> corners_;  ///< the current face's corners
};

/// Reads an ascii body: the values of the elements in the declared order,
/// separated by white space (a record may wrap across lines).
class AsciiBody : BodyReader {
 public:
  AsciiBody(std::string_view file, std::string_view content, const PlyHeader& header, const Wanted& wanted,
            PlyVertices& vertices, Triangles* triangles)
      : BodyReader(file, header, wanted, vertices, triangles),
        tokens_(file, content, header.body_offset, header.end_header_line + 1) {}

  void read() {
    for (std::size_t e = 0; e < header_.elements.size(); ++e) {
      const PlyElement& element = header_.elements[e];
      // An element without properties holds nothing, whatever its count: walking
      // a count of 10^12 such elements would take hours (found by fuzzing).
      if (element.properties.empty()) continue;
      const bool is_vertex = e == wanted_.vertex_element;
      const bool is_face = e == wanted_.face_element;
      if (is_vertex) reserve_vertices(element);
      for (std::uint64_t i = 0; i < element.count; ++i) read_record(element, i, is_vertex, is_face);
    }
    std::string_view token;
    if (tokens_.next(token))
      fail_at_line(file_, tokens_.line_number(),
                   "unexpected " + excerpt(token) +
                       " after the last element: the file holds more values than its header declares");
    vertices_.finish(file_, triangles_ != nullptr, tokens_.position());
  }

 private:
  void reserve_vertices(const PlyElement& element) {
    // Each value takes at least two characters: cap the reservation by the text left.
    const std::uint64_t room = tokens_.bytes_left() / (2 * std::max<std::size_t>(element.properties.size(), 1));
    vertices_.reserve(std::min(element.count, room));
  }

  /// The next value of record `i` of `element`, which must not end here.
  std::string_view next_token(const PlyElement& element, std::uint64_t i) {
    std::string_view token;
    if (!tokens_.next(token)) fail_at_line(file_, tokens_.line_number(), ends_early(element, i));
    return token;
  }

  /// Record `i` of `element`: a vertex is kept, a face's corners are fanned.
  void read_record(const PlyElement& element, std::uint64_t i, bool is_vertex, bool is_face) {
    std::array<double, slot_count> values{};
    for (std::size_t p = 0; p < element.properties.size(); ++p) {
      const PlyProperty& property = element.properties[p];
      const std::string_view token = next_token(element, i);
      if (property.is_list) {
        read_list(element, property, i, token, is_face && p == wanted_.face_property);
        continue;
      }
      const double value = parse_value(file_, tokens_.line_number(), token, property, property.type);
      if (is_vertex && wanted_.slot[p] >= 0) values[static_cast<std::size_t>(wanted_.slot[p])] = value;
    }
    if (is_vertex) {
      // The line of the vertex's last value: a vertex normally stands on one line.
      vertices_.add(values, tokens_.line_number());
      vertices_.hand_if_full(tokens_.position());
    } else {
      vertices_.parts().behind(tokens_.position());
    }
  }

  /// A list whose length is `length_token`; `keep`: the face's corners.
  void read_list(const PlyElement& element, const PlyProperty& property, std::uint64_t i, std::string_view length_token,
                 bool keep) {
    std::uint64_t length = 0;
    if (!parse_count(length_token, length) || !fits_type(static_cast<double>(length), property.count_type))
      fail_at_line(file_, tokens_.line_number(),
                   "expected the length of list " + excerpt(property.name) + " of " + element.name + " " +
                       std::to_string(i) + ", found " + excerpt(length_token));
    if (keep) {
      if (length < 3)
        fail_at_line(
            file_, tokens_.line_number(),
            "face " + std::to_string(i) + " has " + std::to_string(length) + " corners; a polygon needs at least 3");
      corners_.clear();
    }
    for (std::uint64_t k = 0; k < length; ++k) {
      const std::string_view token = next_token(element, i);
      if (keep) {
        corners_.push_back(parse_corner(token, i));
      } else {
        static_cast<void>(parse_value(file_, tokens_.line_number(), token, property, property.type));
      }
    }
    if (keep) add_fan(corners_, *triangles_);
  }

  /// A corner of face `i`: the index of a vertex of the file.
  std::uint32_t parse_corner(std::string_view token, std::uint64_t i) const {
    std::int64_t index = 0;
    if (!parse_integer(token, index))
      fail_at_line(file_, tokens_.line_number(),
                   "expected a vertex index in face " + std::to_string(i) + ", found " + excerpt(token));
    if (index < 0 || static_cast<std::uint64_t>(index) >= vertex_count_)
      fail_at_line(file_, tokens_.line_number(),
                   "face " + std::to_string(i) + " uses vertex " + std::to_string(index) + ", but the file has " +
                       std::to_string(vertex_count_) + " vertices");
    return static_cast<std::uint32_t>(index);
  }

  TokenScanner tokens_;
};

/// Reads a binary body: packed records in the file's byte order. Elements
/// without lists are fixed-size blocks; records with lists are walked.
class BinaryBody : BodyReader {
 public:
  BinaryBody(std::string_view file, std::string_view content, const PlyHeader& header, const Wanted& wanted,
             PlyVertices& vertices, Triangles* triangles)
      : BodyReader(file, header, wanted, vertices, triangles),
        content_(content),
        swap_(needs_swap(header.encoding == PlyEncoding::binary_big_endian)),
        position_(header.body_offset) {}

  void read() {
    for (std::size_t e = 0; e < header_.elements.size(); ++e) {
      const PlyElement& element = header_.elements[e];
      if (element.has_lists()) {
        read_list_records(element, e == wanted_.face_element);
      } else {
        read_fixed_records(element, e == wanted_.vertex_element);
      }
    }
    // Bytes after the last element are ignored (some writers end with a newline).
    vertices_.finish(file_, triangles_ != nullptr, position_);
  }

 private:
  /// Fixed-size records: check the whole block once, then decode or jump.
  void read_fixed_records(const PlyElement& element, bool is_vertex) {
    const std::size_t record = element.record_size();
    if (record == 0) return;
    const std::uint64_t whole_records = (content_.size() - position_) / record;
    if (element.count > whole_records)
      fail_at_byte(file_, position_ + static_cast<std::size_t>(whole_records) * record,
                   ends_early(element, whole_records) + " (each takes " + std::to_string(record) +
                       " bytes; the file has " + std::to_string(content_.size()) + ")");
    const auto count = static_cast<std::size_t>(element.count);
    if (is_vertex) decode_vertices(element, count, record);
    position_ += count * record;
  }

  /// The `count` vertex records of `record` bytes each from position_.
  void decode_vertices(const PlyElement& element, std::size_t count, std::size_t record) {
    // Where x, y, z (and nx, ny, nz, and the colours) stand in a record, and their types.
    std::array<std::size_t, slot_count> offsets{};
    std::array<ScalarType, slot_count> types{};
    std::size_t offset = 0;
    for (std::size_t p = 0; p < element.properties.size(); ++p) {
      if (const int s = wanted_.slot[p]; s >= 0) {
        offsets[static_cast<std::size_t>(s)] = offset;
        types[static_cast<std::size_t>(s)] = element.properties[p].type;
      }
      offset += scalar_size(element.properties[p].type);
    }
    vertices_.reserve(count);
    std::array<double, slot_count> values{};
    for (std::size_t i = 0; i < count; ++i) {
      const std::size_t start = position_ + i * record;
      for (std::size_t s = 0; s < slot_count; ++s) {
        if (wanted_.used(s))
          static_cast<void>(decode_scalar(content_.data() + start + offsets[s], types[s], swap_, values[s]));
      }
      vertices_.add(values, start, offsets.data());
      vertices_.hand_if_full(start + record);
    }
  }

  /// Records with lists: walk them one by one.
  void read_list_records(const PlyElement& element, bool is_face) {
    for (std::uint64_t i = 0; i < element.count; ++i) {
      const std::size_t start = position_;
      for (std::size_t p = 0; p < element.properties.size(); ++p) {
        const PlyProperty& property = element.properties[p];
        if (!property.is_list) {
          need(scalar_size(property.type), element, i, start);
          position_ += scalar_size(property.type);
          continue;
        }
        const std::uint64_t length = read_list_length(element, property, i, start);
        const std::size_t item_size = scalar_size(property.type);
        if (length > (content_.size() - position_) / item_size) fail_at_byte(file_, start, ends_early(element, i));
        if (is_face && p == wanted_.face_property) {
          read_corners(property, i, start, length);
        } else {
          position_ += static_cast<std::size_t>(length) * item_size;
        }
      }
      vertices_.parts().behind(position_);
    }
  }

  /// Fails unless `bytes` more are left in record `i`, which began at `start`.
  void need(std::uint64_t bytes, const PlyElement& element, std::uint64_t i, std::size_t start) const {
    if (bytes > content_.size() - position_) fail_at_byte(file_, start, ends_early(element, i));
  }

  std::uint64_t read_list_length(const PlyElement& element, const PlyProperty& property, std::uint64_t i,
                                 std::size_t start) {
    need(scalar_size(property.count_type), element, i, start);
    double length_value = 0.0;
    static_cast<void>(decode_scalar(content_.data() + position_, property.count_type, swap_, length_value));
    if (length_value < 0)
      fail_at_byte(file_, position_,
                   element.name + " " + std::to_string(i) + ": negative length of list " + excerpt(property.name));
    position_ += scalar_size(property.count_type);
    return static_cast<std::uint64_t>(length_value);
  }

  /// The `length` corners of face `i` (whose record began at `start`), fanned.
  void read_corners(const PlyProperty& property, std::uint64_t i, std::size_t start, std::uint64_t length) {
    const std::size_t item_size = scalar_size(property.type);
    if (length < 3)
      fail_at_byte(
          file_, start,
          "face " + std::to_string(i) + " has " + std::to_string(length) + " corners; a polygon needs at least 3");
    corners_.clear();
    for (std::uint64_t k = 0; k < length; ++k, position_ += item_size) {
      double index = 0.0;
      if (decode_scalar(content_.data() + position_, property.type, swap_, index) != Decoded::finite || index < 0 ||
          index >= static_cast<double>(vertex_count_) || index != std::floor(index))
        fail_at_byte(file_, position_,
                     "face " + std::to_string(i) + ": vertex index is not an integer from 0 to " +
                         std::to_string(vertex_count_) + " - 1");
      corners_.push_back(static_cast<std::uint32_t>(index));
    }
    add_fan(corners_, *triangles_);
  }

  std::string_view content_;
  bool swap_;
  std::size_t position_;
};

/// The body after `header`: the vertices into `vertices`, the faces'
/// triangles into `triangles` (when not nullptr).
void read_body(std::string_view file, std::string_view content, const PlyHeader& header, const Wanted& wanted,
               PlyVertices& vertices, Triangles* triangles) {
  if (header.encoding == PlyEncoding::ascii) {
    AsciiBody(file, content, header, wanted, vertices, triangles).read();
  } else {
    BinaryBody(file, content, header, wanted, vertices, triangles).read();
  }
}

/// Reads the vertices into `parts` and, when `triangles` is not nullptr,
/// the faces. Colours of a floating-point type wait on the whole file
/// (colors.h): read in parts, the file is first surveyed for them.
void read_ply(std::string_view file, std::string_view content, PointParts& parts, Triangles* triangles) {
  const PlyHeader header = parse_header(file, content);
  const Wanted wanted = find_wanted(file, header, triangles != nullptr);
  const bool binary = header.encoding != PlyEncoding::ascii;
  PlyVertices vertices(wanted, parts, binary);
  if (!parts.whole() && wanted.colors && vertices.colors().floating()) {
    survey(parts, [&](PointParts& dropped) {
      PlyVertices all(wanted, dropped, binary);
      read_body(file, content, header, wanted, all, nullptr);
      vertices.colors().assume_beyond_one(all.colors().beyond_one());
    });
  }
  read_body(file, content, header, wanted, vertices, triangles);
}

}  // namespace

void read_ply_points(std::string_view file, std::string_view content, PointParts& parts) {
  read_ply(file, content, parts, nullptr);
  if (parts.count() == 0) fail_in_file(file, "no points: the vertex element is empty");
}

PointCloud read_ply_points(std::string_view file, std::string_view content) {
  PointParts whole;
  read_ply_points(file, content, whole);
  return whole.take_whole();
}

Mesh read_ply_mesh(std::string_view file, std::string_view content) {
  PointParts whole;
  Mesh mesh;
  read_ply(file, content, whole, &mesh.triangles);
  if (mesh.triangles.empty()) fail_in_file(file, "no triangles: the face element is empty");
  PointCloud vertices = whole.take_whole();
  mesh.vertices = std::move(vertices.positions);
  mesh.colors = std::move(vertices.colors);
  mesh.normals = std::move(vertices.normals);
  return mesh;
}

}  // namespace recon::io::detail
