#pragma once
// What each column of delimited text holds, for the xyz reader (xyz.cpp):
// the layout of the file (a byte-order mark, its line ends, its separator,
// a header line) and the meaning of every column, taken from the header,
// from ReadPointsOptions::columns (--columns), or, in a file with neither,
// from the number of columns and the values in them.
//
// The rules (point_io.h states them for users):
//   - The first line that is not blank or a comment is a header when it
//     starts with "//" (as CloudCompare writes it) or holds no number. Its
//     names (any case) may be separated by blanks, commas or semicolons:
//     x y z; nx ny nz (also normal_x ...); r g b (also red green blue);
//     any other name (intensity, scalar_*, ...) is a column recon ignores.
//     Normals and colours are used only when all three are named.
//   - The first line of numbers decides the separator for the whole file: a
//     semicolon when it holds one (a comma inside a number is then its
//     decimal mark, as European spreadsheets write), else a comma when it
//     holds one, else blanks (spaces and tabs).
//   - With neither a header nor --columns the count decides: 3 columns are
//     x y z; 4 are x y z and a value recon ignores (an intensity); 6 are
//     x y z and a triple, 7 x y z, a value and a triple (before or after
//     it), 9 x y z and two triples. Whether a triple holds normals or
//     colours, the whole file's values decide (decide_columns);
//     other counts, and values that leave doubt, are refused, naming
//     --columns.
//   - Colours are integers 0 to 255, or fractions 0 to 1 (scaled to 0-255),
//     one or the other for the whole file (a file with only 0s and 1s is
//     read as fractions: 1 is 255).
//
// Reading keeps the file mapped and parses it once: columns whose meaning
// waits on the whole file (colours, and the triples of a file without a
// header) are held as doubles while the evidence about them is gathered,
// and turned into normals or colours at the end. Read in chunks
// (point_stream.h), such a file is parsed twice: a survey gathers the
// evidence and decides, and the second pass turns each part's held values
// into normals or colours as it hands the part on.

#include "io_detail.h"
#include "text_scanner.h"

#include "recon/io/point_io.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace recon::io::detail {

/// Where the data of a delimited text file begins and how it is split,
/// found from its first lines.
struct TextLayout {
  std::size_t start = 0;                   ///< the first byte after a UTF-8 byte-order mark
  LineEnds line_ends = LineEnds::newline;  ///< see detect_line_ends
  Separator separator = Separator::blanks;
  std::size_t header_line = 0;      ///< the header's line number; 0: no header
  std::vector<std::string> header;  ///< its names as written, "//" removed
  std::size_t first_line = 0;       ///< the first line of numbers; 0: none
  std::size_t columns = 0;          ///< how many fields that line has
  std::string_view first_data;      ///< that line without its comment (a view into the content)
};

/// Finds the layout of `content` (see the rules above). Throws ParseError
/// "FILE:LINE: ..." for a line too long or a NUL byte.
[[nodiscard]] TextLayout find_text_layout(std::string_view file, std::string_view content);

/// True when `data` (a line without its comment) is a header line: it
/// starts with "//" or holds no number.
[[nodiscard]] bool is_header_line(std::string_view data);

/// A LineScanner over the lines of `content` laid out as `layout` says.
[[nodiscard]] inline LineScanner layout_lines(std::string_view file, std::string_view content,
                                              const TextLayout& layout) {
  return LineScanner(file, content, layout.start, 1, layout.line_ends);
}

/// True when `data` (a line without its comment) holds only blanks.
[[nodiscard]] inline bool is_blank_line(std::string_view data) {
  return std::all_of(data.begin(), data.end(), is_blank);
}

/// Throws ParseError "FILE:LINE: ..." for a field that is not a number:
/// empty (two separators in a row), holding another separator than the
/// file's, or not a number or too large (describe_bad_number).
[[noreturn]] void fail_text_field(std::string_view file, std::size_t line, std::string_view field,
                                  std::string_view what, NumberStatus status, const TextLayout& layout);

/// Parses a field of delimited text as a number `what` ("x", "red", ...),
/// accepting a decimal comma in a file separated by semicolons, or throws
/// (fail_text_field). NaN and infinity are returned as they are.
[[nodiscard]] double parse_number_with_decimal_comma(std::string_view file, std::size_t line, std::string_view field,
                                                     std::string_view what, const TextLayout& layout);
[[nodiscard]] inline double parse_text_field(std::string_view file, std::size_t line, std::string_view field,
                                             std::string_view what, const TextLayout& layout) {
  double value = 0.0;
  if (parse_double(field, value) == NumberStatus::ok) return value;
  return parse_number_with_decimal_comma(file, line, field, what, layout);
}

/// What a column holds.
enum class ColumnRole : std::uint8_t { ignored, x, y, z, nx, ny, nz, r, g, b };

/// The role a header or --columns name stands for (case-insensitive):
/// x, y, z, nx/normal_x, ..., r/red, ...; `ignored` for any other name.
[[nodiscard]] ColumnRole role_named(std::string_view name);

/// How one field of a data line is read.
struct FieldTarget {
  enum class Kind : std::uint8_t { skip, position, normal, held };
  Kind kind = Kind::skip;
  std::uint8_t index = 0;  ///< the coordinate (position, normal) or the slot among the held values
};

/// How the columns of a file are read.
struct ColumnPlan {
  std::vector<ColumnRole> roles;          ///< one per column; in a guessed plan decided at the end
  std::vector<FieldTarget> fields;        ///< one per column
  std::vector<std::string> names;         ///< one per column, for messages ("x", "red", "column 5")
  std::vector<std::size_t> held_columns;  ///< the column of each held slot
  /// Where the roles come from: --columns, the header line, or (no names)
  /// the count and the values, the held values being columns 4 and on.
  enum class Source : std::uint8_t { option, header, values };
  Source source = Source::values;
  std::size_t header_line = 0;       ///< the header's line (Source::header)
  std::vector<std::string> remarks;  ///< said after the columns in the note (ignored names, ...)
  [[nodiscard]] std::size_t held() const { return held_columns.size(); }
  [[nodiscard]] bool guessed() const { return source == Source::values; }
};

/// The plan for a file: from `columns` (--columns) when given, else from the
/// header, else from the number of columns. Throws InvalidInputError for
/// bad --columns names, ParseError "FILE:LINE: ..." for a header without x,
/// y and z (naming --columns), and, without either, for a first line of
/// numbers with an empty field or mixed separators (its count would be
/// wrong) or a count that cannot be read without names (naming --columns).
/// A count that --columns or the header does not match is found by the
/// reader, on the line.
[[nodiscard]] ColumnPlan plan_columns(std::string_view file, const TextLayout& layout,
                                      const std::vector<std::string>& columns);

/// What one held column's values allow it to be, gathered line by line:
/// the first value (and its line) that rules out each reading.
struct ColumnEvidence {
  struct Found {
    std::size_t line = 0;  ///< 0: none found
    double value = 0.0;
  };
  Found not_colour;  ///< neither an integer 0 to 255 nor within 0 to 1
  Found fraction;    ///< strictly between 0 and 1, not an integer
  Found above_one;   ///< an integer 2 to 255

  void add(double value, std::size_t line) {
    if (not_colour.line != 0) return;  // no colour column, whatever comes (a column of normals, soon)
    if (!std::isfinite(value) || value < 0.0 || value > 255.0) {
      note(not_colour, value, line);
    } else if (value != std::floor(value)) {
      note(value < 1.0 ? fraction : not_colour, value, line);
    } else if (value > 1.0) {
      note(above_one, value, line);
    }
  }

 private:
  static void note(Found& found, double value, std::size_t line) {
    if (found.line == 0) found = {line, value};
  }
};

/// Whether three held columns hold unit vectors on every line. A triple
/// with a NaN or infinite component does not count against it (it would be
/// a normal PointChecker refuses).
struct TripleEvidence {
  /// |n| may differ from 1 by this much (writers round normals to a few digits).
  static constexpr double tolerance = 0.01;
  std::size_t not_unit_line = 0;  ///< the first line with another length; 0: none
  double not_unit_length = 0.0;

  void add(double x, double y, double z, std::size_t line) {
    if (not_unit_line != 0 || !std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) return;
    // Scaled by the largest component, so that squaring 1e300 cannot
    // overflow; beyond 1e300 the largest component stands for the length.
    const double largest = std::max({std::abs(x), std::abs(y), std::abs(z)});
    const double scaled =
        largest == 0.0 ? 0.0 : std::sqrt(square(x / largest) + square(y / largest) + square(z / largest));
    const double length = largest > 1e300 ? largest : largest * scaled;
    if (std::abs(length - 1.0) > tolerance) {
      not_unit_line = line;
      not_unit_length = length;
    }
  }

 private:
  static double square(double v) { return v * v; }
};

/// What the held values become.
struct HeldUse {
  int normals = -1;           ///< the slot of nx (ny, nz follow), or -1
  int colours = -1;           ///< the slot of red (green, blue follow), or -1
  double colour_scale = 1.0;  ///< a colour byte is value * colour_scale (1: 0-255 integers, 255: fractions)
};

/// Decides what the held values of `plan` become from the evidence about
/// each held column and, in a guessed plan, each triple of held columns
/// (triples[s] starts at slot s), sets plan.roles accordingly, and appends
/// the note that says what was read (none for three columns without a
/// header). Throws ParseError "FILE: ...", naming --columns, when a guessed
/// plan's values leave doubt, and "FILE:LINE: ..." for named colours out
/// of range.
[[nodiscard]] HeldUse decide_columns(std::string_view file, ColumnPlan& plan,
                                     const std::vector<ColumnEvidence>& columns,
                                     const std::vector<TripleEvidence>& triples, ReadNotes& notes);

}  // namespace recon::io::detail
