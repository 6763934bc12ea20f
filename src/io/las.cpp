// LAS 1.0-1.4, the ASPRS LiDAR exchange format (uncompressed; LAZ is refused).
//
// A LAS file is little-endian binary: a public header block, variable-length
// records (skipped), then the point records, all of one point data record
// format (0-10) and one length, and in 1.4 possibly extended records after
// them (ignored). The header gives where each part starts, so nothing is
// assumed: its own size (at least 227 bytes; 235 from 1.3 on, which adds
// the waveform start; 375 from 1.4 on, which adds a 64-bit point count),
// the offset to the point data, the record length (at least the format's
// size; more is "extra bytes" per point, skipped) and the point count (32
// bits at byte 107; in 1.4 also 64 bits at byte 247, which wins when set).
//
// A record starts with X, Y, Z as int32; a coordinate is X * scale + offset,
// with scale and offset from the header (doubles at bytes 131 and 155),
// computed in double: with scale 0.001 and an offset of 4.5e6 (a geo-
// referenced survey in millimetres) every point is exact to well below a
// millimetre. Formats 2, 3, 5, 7, 8 and 10 also hold red, green and blue as
// uint16 at a fixed place in the record.
//
// 16-bit colours to 8 bits: writers disagree on what the 16 bits mean. The
// specification scales colours to 0-65535, but many writers store 0-255 in
// the 16-bit fields. So when every value of the file is at most 255, the
// values are taken as they are; otherwise each is scaled down by taking its
// high byte (value >> 8), which is exact for both ways writers widen 8 bits
// (v * 256 and v * 257), where PLY's v / 257 would make 0xFF00 254. A
// ReadNotes line says which was done. The largest value is found by a first
// walk over the colours of the records, so that the points can be read
// (and, read in chunks, handed on) with their final colours.

#include "formats.h"
#include "io_detail.h"

#include "recon/core/errors.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace recon::io::detail {
namespace {

constexpr std::size_t smallest_header = 227;  // LAS 1.0 to 1.2
constexpr std::size_t point_format_byte = 104;

/// Bytes of a record of each point data record format, 0 to 10.
constexpr std::array<std::size_t, 11> format_record_size = {20, 28, 26, 34, 57, 63, 30, 36, 38, 59, 67};
/// Where red, green, blue start in a record of each format; 0: no colour.
constexpr std::array<std::size_t, 11> format_color_offset = {0, 0, 20, 28, 0, 28, 0, 30, 30, 0, 30};

struct LasHeader {
  unsigned minor_version = 0;  ///< 1.minor
  std::size_t point_offset = 0;
  unsigned format = 0;
  std::size_t record_length = 0;
  std::uint64_t points = 0;
  std::array<double, 3> scale{};
  std::array<double, 3> offset{};
};

/// The size of the public header block of LAS 1.minor.
std::size_t header_size_of(unsigned minor) {
  if (minor >= 4) return 375;
  if (minor == 3) return 235;
  return smallest_header;
}

template <typename T>
T field(std::string_view content, std::size_t at) {
  return read_little_endian<T>(content.data() + at);
}

void check_signature_and_version(std::string_view file, std::string_view content, LasHeader& header) {
  if (content.substr(0, 4) != "LASF")
    fail_at_byte(file, 0, "not a LAS file: it starts with " + excerpt(content.substr(0, 4)) + ", not 'LASF'");
  if (content.size() < smallest_header)
    fail_at_byte(
        file, content.size(),
        "the file ends inside the LAS header, which takes at least " + std::to_string(smallest_header) + " bytes");
  const auto major = static_cast<unsigned>(field<std::uint8_t>(content, 24));
  header.minor_version = field<std::uint8_t>(content, 25);
  if (major != 1 || header.minor_version > 4)
    fail_at_byte(file, 24,
                 "LAS version " + std::to_string(major) + "." + std::to_string(header.minor_version) +
                     " is not known: recon reads LAS 1.0 to 1.4");
}

void check_header_size(std::string_view file, std::string_view content, const LasHeader& header) {
  const std::size_t size = field<std::uint16_t>(content, 94);
  const std::size_t needed = header_size_of(header.minor_version);
  if (size < needed)
    fail_at_byte(file, 94,
                 "the header size " + std::to_string(size) + " is smaller than the " + std::to_string(needed) +
                     " bytes of a LAS 1." + std::to_string(header.minor_version) + " header");
  if (content.size() < size)
    fail_at_byte(file, content.size(), "the file ends inside the LAS header of " + std::to_string(size) + " bytes");
}

void read_point_format(std::string_view file, std::string_view content, LasHeader& header) {
  const auto format = static_cast<unsigned>(field<std::uint8_t>(content, point_format_byte));
  // laszip marks compressed data by setting bit 7 (and bit 6 for the 1.4
  // formats) of this byte, over a valid format in the low bits: other values
  // with those bits (255, say) are just not a format.
  const unsigned low_bits = format & 0x3FU;
  const bool compressed = (format & 0xC0U) != 0 && low_bits < format_record_size.size();
  if (compressed) fail_at_byte(file, point_format_byte, laz_advice());
  if (format >= format_record_size.size())
    fail_at_byte(file, point_format_byte,
                 "point data record format " + std::to_string(format) + " is not known (LAS defines 0 to 10)" +
                     ((format & 0xC0U) != 0 ? "; nor is it LAZ, which sets bit 7 or 6 over one of them" : ""));
  header.format = format;
  header.record_length = field<std::uint16_t>(content, 105);
  if (header.record_length < format_record_size[format])
    fail_at_byte(file, 105,
                 "point records of " + std::to_string(header.record_length) + " bytes are shorter than the " +
                     std::to_string(format_record_size[format]) + " bytes of point format " + std::to_string(format));
}

void read_point_count(std::string_view file, std::string_view content, LasHeader& header) {
  const std::uint64_t legacy = field<std::uint32_t>(content, 107);
  header.points = legacy;
  if (header.minor_version >= 4) {
    const auto count = field<std::uint64_t>(content, 247);
    if (count != 0 && legacy != 0 && count != legacy)
      fail_at_byte(file, 247,
                   "the point count " + std::to_string(count) + " differs from the legacy point count " +
                       std::to_string(legacy) + " at byte 107");
    if (count != 0) header.points = count;
  }
  if (header.points == 0) fail_in_file(file, "no points: the header declares 0 points");
}

void read_scale_and_offset(std::string_view file, std::string_view content, LasHeader& header) {
  for (std::size_t k = 0; k < 3; ++k) {
    const std::size_t scale_at = 131 + 8 * k;
    const std::size_t offset_at = 155 + 8 * k;
    header.scale[k] = field<double>(content, scale_at);
    header.offset[k] = field<double>(content, offset_at);
    // isfinite first: comparing a NaN raises FE_INVALID, which the sanitize build traps.
    if (!std::isfinite(header.scale[k]) || header.scale[k] == 0.0) {
      std::string what = "the " + std::string(position_names[k]) + " scale factor is ";
      append_number(what, header.scale[k]);
      fail_at_byte(file, scale_at, what + ": it must be a finite number other than 0");
    }
    if (!std::isfinite(header.offset[k]))
      fail_at_byte(file, offset_at, "the " + std::string(position_names[k]) + " offset is not a finite number");
  }
}

/// Where the points start, checked against the header and the file: the
/// records the header promises must all be in the file (so the count never
/// sizes an allocation beyond what the file holds).
void check_point_data(std::string_view file, std::string_view content, LasHeader& header) {
  const std::size_t header_size = field<std::uint16_t>(content, 94);
  header.point_offset = field<std::uint32_t>(content, 96);
  if (header.point_offset < header_size)
    fail_at_byte(file, 96,
                 "the point data would start at byte " + std::to_string(header.point_offset) + ", inside the " +
                     std::to_string(header_size) + "-byte header");
  if (header.point_offset > content.size())
    fail_at_byte(file, 96,
                 "the point data would start at byte " + std::to_string(header.point_offset) +
                     ", beyond the end of the file (" + std::to_string(content.size()) + " bytes)");
  const std::uint64_t whole_records = (content.size() - header.point_offset) / header.record_length;
  if (header.points > whole_records)
    fail_at_byte(file, header.point_offset + static_cast<std::size_t>(whole_records) * header.record_length,
                 "the file ends early: the header promises " + std::to_string(header.points) + " points of " +
                     std::to_string(header.record_length) + " bytes from byte " + std::to_string(header.point_offset) +
                     ", but the file holds only " + std::to_string(whole_records) + " whole points");
}

LasHeader read_header(std::string_view file, std::string_view content) {
  LasHeader header;
  check_signature_and_version(file, content, header);
  check_header_size(file, content, header);
  read_point_format(file, content, header);
  read_point_count(file, content, header);
  read_scale_and_offset(file, content, header);
  check_point_data(file, content, header);
  return header;
}

/// The largest red, green or blue value of the file's records, whose
/// colours start `color_offset` bytes into each.
std::uint16_t largest_color(std::string_view content, const LasHeader& header, std::size_t color_offset,
                            PageRelease pages) {
  std::uint16_t largest = 0;
  for (std::uint64_t i = 0; i < header.points; ++i) {
    const std::size_t at = header.point_offset + static_cast<std::size_t>(i) * header.record_length + color_offset;
    for (std::size_t k = 0; k < 3; ++k) largest = std::max(largest, field<std::uint16_t>(content, at + 2 * k));
    pages.behind(at);
  }
  return largest;
}

/// How far 16-bit LAS colours are shifted to 8 bits when the largest value
/// of the file is `largest` (see the top of the file), and the note that
/// says so.
unsigned color_shift(std::uint16_t largest, std::string& note) {
  if (largest <= 255) {
    note = "colours: the 16-bit LAS values are all 0 to 255, taken as 8-bit values as they are";
    return 0;
  }
  note = "colours: the 16-bit LAS values (up to " + std::to_string(largest) +
         ") are reduced to 8 bits by taking their high byte";
  return 8;
}

/// The position of the record that starts at byte `start`.
Vec3 record_position(std::string_view content, const LasHeader& header, std::size_t start) {
  Vec3 p;
  for (std::size_t k = 0; k < 3; ++k) {
    const auto integer = field<std::int32_t>(content, start + 4 * k);
    p[static_cast<Eigen::Index>(k)] = static_cast<double>(integer) * header.scale[k] + header.offset[k];
  }
  return p;
}

/// The 8-bit colour of 16-bit values at byte `at`, shifted by `shift`.
Color record_color(std::string_view content, std::size_t at, unsigned shift) {
  Color c;
  for (std::size_t k = 0; k < 3; ++k)
    c[k] = static_cast<std::uint8_t>(field<std::uint16_t>(content, at + 2 * k) >> shift);
  return c;
}

/// Every record into `parts`; the colours (when `color_offset` is not 0)
/// shifted by `shift`.
void read_records(std::string_view file, std::string_view content, const LasHeader& header, std::size_t color_offset,
                  unsigned shift, PointParts& parts) {
  PointCloud& part = parts.part();
  part.positions.reserve(parts.room(header.points));
  if (color_offset != 0) part.colors.reserve(parts.room(header.points));
  constexpr std::size_t coordinate_offsets[3] = {0, 4, 8};
  PointChecker checker(true);
  std::size_t start = header.point_offset;
  for (std::uint64_t i = 0; i < header.points; ++i, start += header.record_length) {
    checker.position(part.positions.emplace_back(record_position(content, header, start)), start, position_names,
                     coordinate_offsets);
    if (color_offset != 0) part.colors.push_back(record_color(content, start + color_offset, shift));
    if (parts.full()) parts.hand(start + header.record_length);
  }
  checker.report(file);
  parts.finish(start);
}

}  // namespace

std::string laz_advice() {
  return "LAZ (compressed LAS) is not read by recon, and no Debian package decodes it; decompress it first, e.g. "
         "'laszip -i IN -o out.las', 'pdal translate IN out.las' or 'las2las -i IN -o out.las', and read the .las "
         "file";
}

std::string laz_refusal(std::string_view file) { return std::string(file) + ": " + laz_advice(); }

void read_las_points(std::string_view file, std::string_view content, ReadNotes& notes, PointParts& parts) {
  const LasHeader header = read_header(file, content);  // all its points are in the file: check_point_data
  const std::size_t color_offset = format_color_offset[header.format];
  std::string note;
  const unsigned shift =
      color_offset != 0 ? color_shift(largest_color(content, header, color_offset, parts.pages()), note) : 0;
  read_records(file, content, header, color_offset, shift, parts);
  if (color_offset != 0) notes.lines.push_back(std::move(note));
}

PointCloud read_las_points(std::string_view file, std::string_view content, const ReadPointsOptions& /*options*/,
                           ReadNotes& notes) {
  PointParts whole;
  read_las_points(file, content, notes, whole);
  return whole.take_whole();
}

}  // namespace recon::io::detail
