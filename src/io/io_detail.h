#pragma once
// Helpers shared by the format readers and writers in src/io (not installed,
// not part of the public interface): reading a whole file, building the error
// messages, parsing and printing numbers, and binary scalars in either byte
// order.

#include "recon/core/point_cloud.h"
#include "recon/io/point_io.h"
#include "recon/structures/mesh.h"

#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <ostream>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

namespace recon::io::detail {

// ---------------------------------------------------------------------------
// Files and error messages

/// The content of a file, seen as one block of bytes. A regular file is
/// mapped read-only (mmap, MAP_PRIVATE) rather than copied: the readers touch
/// only the pages they parse, so a multi-gigabyte file of garbage costs a few
/// pages before it is refused, and a large valid file is not held twice. A
/// pipe or another file that cannot be mapped is read into memory instead:
/// into anonymous pages grown by mremap, which moves pages rather than
/// copying them, so a stream of N bytes never holds more than N bytes and a
/// megabyte (a doubling buffer would hold up to 2N, and 3N while it copies).
/// The view is valid while the object lives; the file must not be shortened
/// meanwhile: reading a page cut off the end of a mapped file raises
/// SIGBUS, which the program turns into an error naming the file (see
/// file_being_read() in point_io.h).
class FileContent {
 public:
  FileContent() = default;
  explicit FileContent(std::string bytes) : buffer_(std::move(bytes)) {}
  FileContent(const void* map, std::size_t size) : map_(map), size_(size) {}
  /// Anonymous memory (a stream read whole) of `length` bytes, `size` of them content; owned from now on.
  static FileContent anonymous(void* memory, std::size_t size, std::size_t length) {
    FileContent content(memory, size);
    content.anonymous_length_ = length;
    return content;
  }
  FileContent(FileContent&& other) noexcept { swap(other); }
  FileContent& operator=(FileContent&& other) noexcept {
    swap(other);
    return *this;
  }
  FileContent(const FileContent&) = delete;
  FileContent& operator=(const FileContent&) = delete;
  ~FileContent();

  [[nodiscard]] std::string_view view() const {
    return map_ != nullptr ? std::string_view(static_cast<const char*>(map_), size_) : std::string_view(buffer_);
  }
  /// True when the content is a map of the file, false when it was read into memory.
  [[nodiscard]] bool mapped() const { return map_ != nullptr && anonymous_length_ == 0; }
  /// Bytes of memory the content holds apart from the file's own pages: 0
  /// for a map of the file, else what was allocated to read it (an empty
  /// string's inline capacity is no allocation).
  [[nodiscard]] std::size_t held_bytes() const {
    return anonymous_length_ + (buffer_.empty() ? 0 : buffer_.capacity());
  }
  /// Gives the whole pages of bytes [begin, end) back to the kernel
  /// (madvise MADV_DONTNEED): they no longer count in the resident memory of
  /// the process, and a later read of them reads the file again. A reader
  /// streaming through a file that is larger than the memory lets go of what
  /// lies behind it. Nothing happens for content read into memory.
  void let_go(std::size_t begin, std::size_t end) const;

 private:
  void swap(FileContent& other) noexcept {
    std::swap(map_, other.map_);
    std::swap(size_, other.size_);
    std::swap(anonymous_length_, other.anonymous_length_);
    std::swap(buffer_, other.buffer_);
  }
  const void* map_ = nullptr;
  std::size_t size_ = 0;
  std::size_t anonymous_length_ = 0;  ///< of the anonymous pages at map_, 0 for a map of the file
  std::string buffer_;
};

/// The content of the file at `path` (see FileContent). Throws IoError
/// "FILE: cannot open: reason" when the file is missing, is a folder or
/// cannot be read, and "FILE: more than N bytes ..." when a stream (a pipe,
/// a device: what is read whole, not mapped) goes on beyond `stream_limit`
/// bytes (0: default_memory_limit(), half the physical memory).
/// While a mapped file's content lives, file_being_read() names it.
[[nodiscard]] FileContent read_file(const std::filesystem::path& path, std::size_t stream_limit = 0);

/// Reads `fd` to its end into anonymous memory (see FileContent), refusing
/// more than `limit` bytes (0: default_memory_limit()) as soon as they are
/// read: IoError "NAME: more than LIMIT bytes from a stream ...". The memory
/// held stays within the bytes read and a megabyte (held_bytes()). Cost: one
/// read() a megabyte, and log2(N) mremap() calls.
[[nodiscard]] FileContent read_stream(int fd, const std::string& name, std::size_t limit);

/// The longest line the text readers accept, in bytes. Real point files have
/// lines of a few dozen bytes; a longer line means binary data or garbage,
/// and the limit keeps a scan for the end of a line from running through a
/// whole multi-gigabyte file.
inline constexpr std::size_t max_line_length = std::size_t{1} << 20;

/// Throw ParseError "FILE:LINE: what" (text content).
[[noreturn]] void fail_at_line(std::string_view file, std::size_t line, std::string_view what);
/// Throw ParseError "FILE: byte OFFSET: what" (binary content).
[[noreturn]] void fail_at_byte(std::string_view file, std::size_t offset, std::string_view what);
/// Throw ParseError "FILE: what" (the file as a whole: empty, no points, ...).
[[noreturn]] void fail_in_file(std::string_view file, std::string_view what);

/// A piece of the file quoted for an error message: at most 40 characters,
/// bytes that are not printable ASCII shown as '?'.
[[nodiscard]] std::string excerpt(std::string_view text);

/// `text` with A-Z made a-z: format names, extensions and column names are
/// matched without regard to case.
[[nodiscard]] std::string lower_case(std::string_view text);
/// Throws InvalidInputError "PATH: has the unknown extension '.vtk'; KNOWN"
/// ("PATH: has no extension; KNOWN" when `extension` is empty); `known` lists
/// the formats: "known mesh formats: .ply, .obj, .off, .stl".
[[noreturn]] void fail_unknown_extension(const std::filesystem::path& path, std::string_view extension,
                                         std::string_view known);

// ---------------------------------------------------------------------------
// Numbers in text

enum class NumberStatus { ok, not_a_number, overflow };

/// Parses all of `token` as a decimal floating-point number with
/// std::from_chars. A leading '+' is accepted. "nan" and "inf" parse (the
/// caller decides whether non-finite values are allowed); a value too small
/// for a double becomes zero or a subnormal; a value too large is `overflow`.
[[nodiscard]] NumberStatus parse_double(std::string_view token, double& value);

/// Parses all of `token` as a decimal integer (leading '+' or '-' allowed).
[[nodiscard]] bool parse_integer(std::string_view token, std::int64_t& value);

/// Parses all of `token` as a non-negative decimal integer.
[[nodiscard]] bool parse_count(std::string_view token, std::uint64_t& value);

/// Describes a failed parse_double of `token` for an error message, e.g.
/// "expected a number for x, found 'abc'" or "'1e999' for x is too large for a double".
[[nodiscard]] std::string describe_bad_number(NumberStatus status, std::string_view token, std::string_view what);

/// Parses a coordinate or normal component `what` ("x", "nz", ...) from
/// text, or throws ParseError "FILE:LINE: ..." when it is not a number or is
/// too large for a double. NaN and infinity are returned as they are: the
/// reader counts them with a PointChecker and refuses them at the end.
[[nodiscard]] double parse_coordinate(std::string_view file, std::size_t line, std::string_view token,
                                      std::string_view what);

/// Appends the shortest decimal text that reads back as exactly `value`
/// (at most 17 significant digits).
void append_number(std::string& out, double value);
/// Appends an unsigned integer in decimal.
void append_integer(std::string& out, std::uint64_t value);
/// Appends "x y z" with append_number.
void append_vec3_text(std::string& out, const Vec3& v);
/// A unit normal as three floats (the precision shading needs; 12 bytes):
/// text with the shortest decimals that read back as the same floats, or
/// little-endian binary. Meshes' normals are written so (PLY, OBJ, GLB).
void append_normal_text(std::string& out, const Vec3& n);
void append_normal_binary(std::string& out, const Vec3& n);

/// Field names used in messages about a position or a normal.
inline constexpr std::string_view position_names[3] = {"x", "y", "z"};
inline constexpr std::string_view normal_names[3] = {"nx", "ny", "nz"};
/// Three coordinates from tokens[0..2] with parse_coordinate.
[[nodiscard]] Vec3 parse_vec3(std::string_view file, std::size_t line, const std::string_view* tokens,
                              const std::string_view (&names)[3]);

// ---------------------------------------------------------------------------
// Binary scalars

/// The scalar types of PLY and PCD.
enum class ScalarType : std::uint8_t { int8, uint8, int16, uint16, int32, uint32, int64, uint64, float32, float64 };

[[nodiscard]] constexpr std::size_t scalar_size(ScalarType type) {
  switch (type) {
    case ScalarType::int8:
    case ScalarType::uint8:
      return 1;
    case ScalarType::int16:
    case ScalarType::uint16:
      return 2;
    case ScalarType::int32:
    case ScalarType::uint32:
    case ScalarType::float32:
      return 4;
    case ScalarType::int64:
    case ScalarType::uint64:
    case ScalarType::float64:
      return 8;
  }
  return 0;
}

[[nodiscard]] constexpr bool is_integer_type(ScalarType type) {
  return type != ScalarType::float32 && type != ScalarType::float64;
}

constexpr std::uint16_t byte_swap(std::uint16_t v) { return static_cast<std::uint16_t>((v << 8) | (v >> 8)); }
constexpr std::uint32_t byte_swap(std::uint32_t v) {
  return ((v & 0x000000ffU) << 24) | ((v & 0x0000ff00U) << 8) | ((v & 0x00ff0000U) >> 8) | ((v & 0xff000000U) >> 24);
}
constexpr std::uint64_t byte_swap(std::uint64_t v) {
  return (std::uint64_t{byte_swap(static_cast<std::uint32_t>(v))} << 32) |
         byte_swap(static_cast<std::uint32_t>(v >> 32));
}

/// True when data stored with the given byte order must be swapped on this machine.
[[nodiscard]] constexpr bool needs_swap(bool data_is_big_endian) {
  return data_is_big_endian != (std::endian::native == std::endian::big);
}

enum class Decoded { finite, nan, infinite };

/// Sets `value` to a quiet NaN or to an infinity of the given sign.
inline Decoded non_finite(bool is_nan, bool negative, double& value) {
  if (is_nan) {
    value = std::numeric_limits<double>::quiet_NaN();
    return Decoded::nan;
  }
  value = negative ? -std::numeric_limits<double>::infinity() : std::numeric_limits<double>::infinity();
  return Decoded::infinite;
}

/// The raw bits of a B-sized scalar at `bytes` (no alignment needed), in the
/// machine's byte order after swapping when `swap`.
template <class B>
B load_bits(const char* bytes, bool swap) {
  B bits = 0;
  std::memcpy(&bits, bytes, sizeof(B));
  if constexpr (sizeof(B) > 1) {
    if (swap) bits = byte_swap(bits);
  }
  return bits;
}

/// Reads one scalar of `type` at `bytes` (no alignment needed), swapping the
/// byte order when `swap`. Floating-point values are classified from their
/// bits before any conversion, so a signalling NaN in a file raises no
/// floating-point exception: `value` is then a quiet NaN or an infinity of
/// the same sign.
inline Decoded decode_scalar(const char* bytes, ScalarType type, bool swap, double& value) {
  switch (type) {
    case ScalarType::int8:
      value = static_cast<std::int8_t>(load_bits<std::uint8_t>(bytes, swap));
      return Decoded::finite;
    case ScalarType::uint8:
      value = load_bits<std::uint8_t>(bytes, swap);
      return Decoded::finite;
    case ScalarType::int16:
      value = static_cast<std::int16_t>(load_bits<std::uint16_t>(bytes, swap));
      return Decoded::finite;
    case ScalarType::uint16:
      value = load_bits<std::uint16_t>(bytes, swap);
      return Decoded::finite;
    case ScalarType::int32:
      value = static_cast<std::int32_t>(load_bits<std::uint32_t>(bytes, swap));
      return Decoded::finite;
    case ScalarType::uint32:
      value = load_bits<std::uint32_t>(bytes, swap);
      return Decoded::finite;
    case ScalarType::int64:
      value = static_cast<double>(static_cast<std::int64_t>(load_bits<std::uint64_t>(bytes, swap)));
      return Decoded::finite;
    case ScalarType::uint64:
      value = static_cast<double>(load_bits<std::uint64_t>(bytes, swap));
      return Decoded::finite;
    case ScalarType::float32: {
      const auto bits = load_bits<std::uint32_t>(bytes, swap);
      if ((bits & 0x7f800000U) == 0x7f800000U) return non_finite((bits & 0x007fffffU) != 0, (bits >> 31) != 0, value);
      float f = 0.0F;
      std::memcpy(&f, &bits, 4);
      value = static_cast<double>(f);
      return Decoded::finite;
    }
    case ScalarType::float64: {
      const auto bits = load_bits<std::uint64_t>(bytes, swap);
      constexpr std::uint64_t exponent = 0x7ff0000000000000ULL;
      if ((bits & exponent) == exponent)
        return non_finite((bits & ~(exponent | (1ULL << 63))) != 0, (bits >> 63) != 0, value);
      std::memcpy(&value, &bits, 8);
      return Decoded::finite;
    }
  }
  return Decoded::nan;
}

/// The value of type T stored at `bytes` in little-endian byte order (no
/// alignment needed): LAS headers and records, PCD's compressed sizes.
template <typename T>
[[nodiscard]] T read_little_endian(const char* bytes) {
  static_assert(std::is_trivially_copyable_v<T> &&
                (sizeof(T) == 1 || sizeof(T) == 2 || sizeof(T) == 4 || sizeof(T) == 8));
  char raw[sizeof(T)];
  std::memcpy(raw, bytes, sizeof(T));
  if constexpr (std::endian::native == std::endian::big) {
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(raw[i], raw[sizeof(T) - 1 - i]);
  }
  T value;
  std::memcpy(&value, raw, sizeof(T));
  return value;
}

/// Appends `value` to `out` in little-endian byte order.
template <typename T>
void append_little_endian(std::string& out, T value) {
  static_assert(std::is_trivially_copyable_v<T> &&
                (sizeof(T) == 1 || sizeof(T) == 2 || sizeof(T) == 4 || sizeof(T) == 8));
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  if constexpr (std::endian::native == std::endian::big) {
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(bytes[i], bytes[sizeof(T) - 1 - i]);
  }
  out.append(bytes, sizeof(T));
}

// ---------------------------------------------------------------------------
// Values recon refuses

/// "+-1e+15", for messages.
[[nodiscard]] std::string coordinate_bound();
/// True when |value| <= max_coordinate (false for NaN and infinity).
[[nodiscard]] inline bool coordinate_in_range(double value) {
  // isfinite first: an ordered comparison with NaN raises FE_INVALID, which
  // the floating-point traps of the sanitize build turn into a crash.
  return std::isfinite(value) && std::abs(value) <= max_coordinate;
}

/// True when a number read as text for a value of `type` is within the
/// type's range: an integer type's limits, or float's largest magnitude.
/// Fractions are not checked (the value is kept as a double); NaN and
/// infinity fit the floating-point types (PointChecker decides on them).
[[nodiscard]] bool fits_type(double value, ScalarType type);
/// "its type uint8 (0 to 255)", ... for messages about a value that does not fit.
[[nodiscard]] std::string describe_range(ScalarType type);

class SkipInvalidPoints;

/// Counts, while a reader goes on reading, the points whose position has a
/// coordinate that is NaN, infinite or beyond +-max_coordinate, and those
/// whose normal has a component that is NaN or infinite, remembering where
/// the first of each is; report() then refuses them all in one message.
/// Reading on costs nothing for a good file and tells the user of a bad one
/// how much is wrong, not only the first problem.
///
/// A checker made while a SkipInvalidPoints lives on the same thread (see
/// below) does not refuse the positions of a point cloud: report() hands
/// them to it instead, and the normals of those points are not checked.
class PointChecker {
 public:
  /// How a message places the first bad value: "line 17", "byte 356" or
  /// "point 12" (data whose bytes are not the file's, such as decompressed
  /// data).
  enum class Location { line, byte, point };

  /// `binary`: locations are byte offsets, else line numbers.
  explicit PointChecker(bool binary) : PointChecker(binary ? Location::byte : Location::line) {}
  explicit PointChecker(Location location);

  /// Checks a position read at `location`; `names` name its coordinates in
  /// messages. Binary readers may give the byte offset of each coordinate
  /// from `location` in `offsets`, so the message points at the bad value.
  void position(const Vec3& p, std::size_t location, const std::string_view (&names)[3],
                const std::size_t* offsets = nullptr) {
    last_position_bad_ = !check(p, location, names, offsets, true, positions_);
  }
  /// Checks a normal (only finiteness: its length does not matter). Call it
  /// after the position of the same point.
  void normal(const Vec3& n, std::size_t location, const std::string_view (&names)[3],
              const std::size_t* offsets = nullptr) {
    if (skip_ != nullptr && last_position_bad_) return;  // the point is left out
    static_cast<void>(check(n, location, names, offsets, false, normals_));
  }
  /// True when the last position checked was bad and is to be left out
  /// (ReadPointsOptions::skip_invalid): the rest of that point needs no check.
  [[nodiscard]] bool skips_last_point() const { return skip_ != nullptr && last_position_bad_; }
  /// Adopts what `other` found in normals (OBJ checks its normals apart and
  /// keeps them only when there is one per point).
  void take_normals(const PointChecker& other) { normals_ = other.normals_; }
  /// Throws ParseError "FILE: 3 points have a coordinate that is not finite
  /// or beyond +-1e+15; the first at line 17 (z = inf)" (and the same for
  /// normals) when anything was found; "vertices" for a mesh reader, whose
  /// positions are always refused (leaving a vertex out would break faces).
  void report(std::string_view file, bool vertices = false) const;

 private:
  struct Found {
    std::uint64_t count = 0;
    std::size_t location = 0;
    std::string first;  ///< "z = inf"
  };
  /// False when `v` has a bad value (then counted in `found`).
  bool check(const Vec3& v, std::size_t location, const std::string_view (&names)[3], const std::size_t* offsets,
             bool bounded, Found& found);
  /// "3 points have WHAT; the first at line 17 (z = inf)".
  [[nodiscard]] std::string describe(const Found& found, std::string_view what, bool vertices) const;
  Location location_;
  SkipInvalidPoints* skip_;  ///< the scope that takes bad positions, or nullptr
  bool last_position_bad_ = false;
  Found positions_;
  Found normals_;
};

/// "line 17", "byte 356" or "point 12": a place in a message.
[[nodiscard]] std::string place(PointChecker::Location kind, std::size_t location);

/// ReadPointsOptions::skip_invalid for every reader at once: while an object
/// of this class lives, the PointCheckers made on the same thread leave the
/// points whose position is not finite or beyond +-max_coordinate to it
/// instead of refusing them, so the readers themselves need not know the
/// option. They return those points in the cloud, and read_points removes
/// them with remove_from(). Scopes nest; the innermost one is used.
class SkipInvalidPoints {
 public:
  SkipInvalidPoints();
  SkipInvalidPoints(const SkipInvalidPoints&) = delete;
  SkipInvalidPoints& operator=(const SkipInvalidPoints&) = delete;
  ~SkipInvalidPoints();

  /// The innermost scope open on this thread, or nullptr.
  [[nodiscard]] static SkipInvalidPoints* current();

  /// While a Hide lives, current() is nullptr on its thread: code of the
  /// caller's run in the middle of a read (read_points_in_chunks' `take`)
  /// reads other files as if no scope were open.
  class Hide {
   public:
    Hide();
    Hide(Hide&&) = delete;  // and so neither copied nor assigned
    ~Hide();

   private:
    SkipInvalidPoints* hidden_;
  };

  /// Called by PointChecker::report(): `count` points were found invalid,
  /// `description` says so in its words ("3 points have ...; the first ...").
  void found(std::uint64_t count, std::string description);

  /// Removes from `cloud` the points with a position that is not finite or
  /// beyond +-max_coordinate, with their normals and colours, and tells
  /// `notes` how many and where the first was. Throws ParseError "FILE: no
  /// points: ..." when none is left.
  void remove_from(std::string_view file, PointCloud& cloud, ReadNotes& notes) const;

  /// Removes from `cloud` the points with a position that is not finite or
  /// beyond +-max_coordinate, with their normals and colours; returns how
  /// many. A cloud read in parts goes through this part by part.
  static std::size_t drop_unreadable(PointCloud& cloud);
  /// After all parts, `dropped` points dropped and `kept` kept: tells `notes`
  /// (as remove_from does), or throws ParseError "FILE: no points: ..." when
  /// none is kept.
  void conclude(std::string_view file, std::size_t dropped, std::size_t kept, ReadNotes& notes) const;

 private:
  SkipInvalidPoints* outer_;
  std::uint64_t count_ = 0;
  std::string description_;  ///< of the first report with bad positions
};

// ---------------------------------------------------------------------------
// Output

/// Collects output in memory and hands it to the stream in blocks of about
/// a megabyte (one write call per block instead of one per number).
class BlockWriter {
 public:
  explicit BlockWriter(std::ostream& out) : out_(out) { buffer_.reserve(block_size + 4096); }
  BlockWriter(const BlockWriter&) = delete;
  BlockWriter& operator=(const BlockWriter&) = delete;
  ~BlockWriter() = default;  // deliberately no flush: finish() must be called on success

  std::string& buffer() { return buffer_; }
  void flush_if_full() {
    if (buffer_.size() >= block_size) flush();
  }
  /// Writes what is left. Stream errors are found by AtomicFile::commit().
  void finish() { flush(); }

 private:
  static constexpr std::size_t block_size = std::size_t{1} << 20;
  void flush() {
    out_.write(buffer_.data(), static_cast<std::streamsize>(buffer_.size()));
    buffer_.clear();
  }
  std::ostream& out_;
  std::string buffer_;
};

/// The comment line that opens the text files recon writes with a summary
/// (OBJ, curve text): "# written by recon: ", then `summary` (what the file
/// holds, with its counts).
[[nodiscard]] inline std::string written_by_recon(std::string_view summary) {
  return "# written by recon: " + std::string(summary) + '\n';
}

/// Writes each triangle as a text line: `keyword`, then its three vertex
/// indices plus `first` ("f 1 2 3" in OBJ, counted from 1; "3 0 1 2" in OFF
/// and ascii PLY, counted from 0).
void append_triangles_text(BlockWriter& writer, const std::vector<std::array<std::uint32_t, 3>>& triangles,
                           char keyword, std::uint64_t first);

// ---------------------------------------------------------------------------
// Checks before writing

/// Throws InvalidInputError "FILE: ..." when the cloud cannot be written
/// faithfully or would not read back: normals or colours present but not
/// one per position, a non-finite value, or a coordinate beyond max_coordinate.
void check_cloud_for_writing(std::string_view file, const PointCloud& cloud);
/// Throws InvalidInputError "FILE: ..." for colours present but not one per
/// vertex, a vertex coordinate that is not finite or beyond max_coordinate,
/// or a vertex index out of range.
void check_mesh_for_writing(std::string_view file, const Mesh& mesh);

}  // namespace recon::io::detail
