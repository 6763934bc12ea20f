#include "io_detail.h"

#include "recon/core/detail/float_chars.h"

#include "recon/core/errors.h"
#include "recon/core/resource_usage.h"  // default_memory_limit
#include "recon/io/point_io.h"          // file_being_read

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <system_error>

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

namespace recon::io::detail {

namespace {

// The mapped file being read, for a SIGBUS handler (file_being_read()): a
// plain array, written before the mapping is handed out and cleared when
// it is unmapped, by the thread that reads it.
char being_read[4096] = "";

void note_being_read(const std::string& name) noexcept {
  const std::size_t length = std::min(name.size(), sizeof being_read - 1);
  std::memcpy(being_read, name.data(), length);
  being_read[length] = '\0';
  std::atomic_signal_fence(std::memory_order_release);
}

}  // namespace

FileContent::~FileContent() {
  if (anonymous_length_ != 0) {
    ::munmap(const_cast<void*>(map_), anonymous_length_);
  } else if (map_ != nullptr) {
    being_read[0] = '\0';
    std::atomic_signal_fence(std::memory_order_release);
    ::munmap(const_cast<void*>(map_), size_);
  }
}

void FileContent::let_go(std::size_t begin, std::size_t end) const {
  if (!mapped()) return;  // content read into memory exists nowhere else
  static const auto page = static_cast<std::size_t>(::sysconf(_SC_PAGE_SIZE));
  const std::size_t first = (begin + page - 1) / page * page;  // whole pages only: the map starts on one
  const std::size_t last = std::min(end, size_) / page * page;
  if (last <= first) return;
  // Dropping pages of a private, read-only file map loses nothing: reading them again reads the file.
  static_cast<void>(::madvise(static_cast<char*>(const_cast<void*>(map_)) + first, last - first, MADV_DONTNEED));
}

namespace {

/// A file descriptor closed when it goes out of scope.
class Descriptor {
 public:
  explicit Descriptor(int fd) : fd_(fd) {}
  Descriptor(const Descriptor&) = delete;
  Descriptor& operator=(const Descriptor&) = delete;
  ~Descriptor() {
    if (fd_ >= 0) ::close(fd_);
  }
  [[nodiscard]] int get() const { return fd_; }

 private:
  int fd_;
};

/// Anonymous pages that grow without being copied (mremap moves them), for
/// a stream read whole.
class GrowingPages {
 public:
  GrowingPages(std::size_t length, const std::string& name) : name_(name) { grow_to(length); }
  GrowingPages(const GrowingPages&) = delete;
  GrowingPages& operator=(const GrowingPages&) = delete;
  ~GrowingPages() {
    if (base_ != nullptr) ::munmap(base_, length_);
  }
  [[nodiscard]] char* data() const { return static_cast<char*>(base_); }
  [[nodiscard]] std::size_t length() const { return length_; }
  void grow_to(std::size_t length) {
    void* grown = base_ == nullptr ? ::mmap(nullptr, length, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0)
                                   : ::mremap(base_, length_, length, MREMAP_MAYMOVE);
    if (grown == MAP_FAILED) {
      const int error = errno;
      throw IoError(
          name_ + ": cannot hold " + std::to_string(length) + " bytes of a stream in memory: " + std::strerror(error),
          error);
    }
    base_ = grown;
    length_ = length;
  }
  /// Hands the pages to a FileContent holding `size` bytes of content.
  FileContent release(std::size_t size) {
    FileContent content = FileContent::anonymous(base_, size, length_);
    base_ = nullptr;
    return content;
  }

 private:
  const std::string& name_;
  void* base_ = nullptr;
  std::size_t length_ = 0;
};

}  // namespace

FileContent read_stream(int fd, const std::string& name, std::size_t limit) {
  if (limit == 0) limit = default_memory_limit();
  static const auto page = static_cast<std::size_t>(::sysconf(_SC_PAGE_SIZE));
  constexpr std::size_t chunk = std::size_t{1} << 20;
  // One byte beyond the limit is enough to know the stream exceeds it.
  const std::size_t most = limit < std::numeric_limits<std::size_t>::max() - page
                               ? (limit / page + 1) * page
                               : std::numeric_limits<std::size_t>::max() / page * page;
  GrowingPages pages(std::min(chunk, most), name);
  std::size_t used = 0;
  for (;;) {
    if (used == pages.length()) pages.grow_to(std::min(2 * pages.length(), most));  // below `most`: see the check
    const ssize_t got = ::read(fd, pages.data() + used, std::min(chunk, pages.length() - used));
    if (got < 0) {
      const int error = errno;
      if (error == EINTR) continue;
      throw IoError(name + ": cannot read: " + std::strerror(error), error);
    }
    if (got == 0) break;
    used += static_cast<std::size_t>(got);
    if (used > limit)
      throw IoError(name + ": more than " + std::to_string(limit) +
                    " bytes from a stream, which recon holds whole in memory (a pipe or device, not a file it can "
                    "map): save it to a file first");
  }
  if (used == 0) return FileContent();
  return pages.release(used);
}

FileContent read_file(const std::filesystem::path& path, std::size_t stream_limit) {
  const std::string name = path.string();
  const Descriptor fd(::open(path.c_str(), O_RDONLY | O_CLOEXEC));
  if (fd.get() < 0) {
    // open() succeeds on a folder; EISDIR only comes for other flags, but say it plainly anyway.
    const int error = errno;
    if (error == EISDIR) throw IoError(name + ": cannot open: it is a folder, not a file", EISDIR);
    throw IoError(name + ": cannot open: " + std::strerror(error), error);
  }
  struct stat status {};
  if (::fstat(fd.get(), &status) != 0) {
    const int error = errno;
    throw IoError(name + ": cannot open: " + std::strerror(error), error);
  }
  if (S_ISDIR(status.st_mode)) throw IoError(name + ": cannot open: it is a folder, not a file", EISDIR);
  // Pipes and devices cannot be mapped; files of /proc and the like say they
  // are empty and are not: read those, an empty file reads as empty anyway.
  if (!S_ISREG(status.st_mode) || status.st_size == 0) return read_stream(fd.get(), name, stream_limit);

  const auto size = static_cast<std::size_t>(status.st_size);
  void* map = ::mmap(nullptr, size, PROT_READ, MAP_PRIVATE, fd.get(), 0);
  if (map == MAP_FAILED) return read_stream(fd.get(), name, stream_limit);  // e.g. a file system without mmap
  // The readers walk the file from the front: let the kernel read ahead.
  static_cast<void>(::madvise(map, size, MADV_SEQUENTIAL));
  note_being_read(name);
  return FileContent(map, size);  // the mapping outlives the descriptor
}

namespace {
// "FILE" + separator + location + ": " + what, thrown as a ParseError.
[[noreturn]] void throw_parse_error(std::string_view file, std::string_view location, std::string_view what,
                                    std::string_view separator) {
  std::string message(file);
  if (!location.empty()) {
    message += separator;
    message += location;
  }
  message += ": ";
  message += what;
  throw ParseError(message);
}
}  // namespace

void fail_at_line(std::string_view file, std::size_t line, std::string_view what) {
  throw_parse_error(file, std::to_string(line), what, ":");
}

void fail_at_byte(std::string_view file, std::size_t offset, std::string_view what) {
  throw_parse_error(file, "byte " + std::to_string(offset), what, ": ");
}

void fail_in_file(std::string_view file, std::string_view what) { throw_parse_error(file, {}, what, {}); }

std::string excerpt(std::string_view text) {
  constexpr std::size_t max_length = 40;
  std::string out = "'";
  for (std::size_t i = 0; i < text.size() && i < max_length; ++i) {
    const char c = text[i];
    out += (c >= 0x20 && c < 0x7f) ? c : '?';
  }
  if (text.size() > max_length) out += "...";
  out += '\'';
  return out;
}

namespace {

// For a decimal number that std::from_chars found out of range: true when it
// is too large (rather than too small) for a double. Out-of-range values are
// hundreds of orders of magnitude away from 1, so the decimal exponent of the
// first significant digit is enough.
bool is_overflow(std::string_view text) {
  std::size_t i = 0;
  if (i < text.size() && (text[i] == '-' || text[i] == '+')) ++i;
  long long position = 0;  // decimal exponent of the first non-zero digit, plus one
  bool seen_nonzero = false;
  bool after_point = false;
  for (; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '.') {
      after_point = true;
    } else if (c >= '0' && c <= '9') {
      if (!seen_nonzero && c != '0') seen_nonzero = true;
      if (seen_nonzero && !after_point) ++position;
      if (!seen_nonzero && after_point) --position;
    } else {
      break;
    }
  }
  long long exponent = 0;
  if (i < text.size() && (text[i] == 'e' || text[i] == 'E')) {
    ++i;
    bool negative = false;
    if (i < text.size() && (text[i] == '-' || text[i] == '+')) negative = text[i++] == '-';
    for (; i < text.size() && text[i] >= '0' && text[i] <= '9'; ++i) {
      if (exponent < 1'000'000'000) exponent = exponent * 10 + (text[i] - '0');
    }
    if (negative) exponent = -exponent;
  }
  return position + exponent > 0;
}

}  // namespace

NumberStatus parse_double(std::string_view token, double& value) {
  const char* first = token.data();
  const char* const last = first + token.size();
  if (first != last && *first == '+') {
    ++first;
    if (first != last && *first == '-') return NumberStatus::not_a_number;
  }
  if (first == last) return NumberStatus::not_a_number;
  const auto [end, ec] = recon::detail::float_from_chars(first, last, value);
  if (end != last || ec == std::errc::invalid_argument) return NumberStatus::not_a_number;
  if (ec == std::errc::result_out_of_range) {
    if (is_overflow(std::string_view(first, static_cast<std::size_t>(last - first)))) return NumberStatus::overflow;
    value = *first == '-' ? -0.0 : 0.0;  // below the smallest subnormal
  }
  return NumberStatus::ok;
}

namespace {
/// All of `token`, after an optional '+', as a whole number of type T.
template <typename T>
bool parse_whole_number(std::string_view token, T& value) {
  const char* first = token.data();
  const char* const last = first + token.size();
  if (first != last && *first == '+') ++first;
  if (first == last) return false;
  const auto [end, ec] = std::from_chars(first, last, value);
  return ec == std::errc{} && end == last;
}
}  // namespace

bool parse_integer(std::string_view token, std::int64_t& value) { return parse_whole_number(token, value); }

bool parse_count(std::string_view token, std::uint64_t& value) { return parse_whole_number(token, value); }

std::string describe_bad_number(NumberStatus status, std::string_view token, std::string_view what) {
  std::string message;
  if (status == NumberStatus::overflow) {
    message = excerpt(token) + " for " + std::string(what) + " is too large for a double";
  } else {
    message = "expected a number for " + std::string(what) + ", found " + (token.empty() ? "nothing" : excerpt(token));
  }
  return message;
}

double parse_coordinate(std::string_view file, std::size_t line, std::string_view token, std::string_view what) {
  double value = 0.0;
  const NumberStatus status = parse_double(token, value);
  if (status != NumberStatus::ok) fail_at_line(file, line, describe_bad_number(status, token, what));
  return value;
}

namespace {

/// The values a scalar type holds, as fits_type tests them and describe_range
/// names them.
struct TypeRange {
  double lowest;
  double highest;
  bool highest_excluded;  ///< 2^63 and 2^64 are exactly representable; the largest 64-bit integers are not
  std::string_view text;  ///< the type's name and its range, for messages
};

/// Indexed by ScalarType, in its order.
constexpr std::array<TypeRange, 10> type_ranges = {{
    {-128.0, 127.0, false, "int8 (-128 to 127)"},
    {0.0, 255.0, false, "uint8 (0 to 255)"},
    {-32768.0, 32767.0, false, "int16 (-32768 to 32767)"},
    {0.0, 65535.0, false, "uint16 (0 to 65535)"},
    {-2147483648.0, 2147483647.0, false, "int32 (-2^31 to 2^31 - 1)"},
    {0.0, 4294967295.0, false, "uint32 (0 to 2^32 - 1)"},
    {-0x1p63, 0x1p63, true, "int64 (-2^63 to 2^63 - 1)"},
    {0.0, 0x1p64, true, "uint64 (0 to 2^64 - 1)"},
    {-static_cast<double>(std::numeric_limits<float>::max()), static_cast<double>(std::numeric_limits<float>::max()),
     false, "float32 (magnitude at most 3.4028235e+38)"},
    {std::numeric_limits<double>::lowest(), std::numeric_limits<double>::max(), false, "float64"},
}};
static_assert(type_ranges.size() == static_cast<std::size_t>(ScalarType::float64) + 1);

const TypeRange& range_of(ScalarType type) { return type_ranges[static_cast<std::size_t>(type)]; }

}  // namespace

bool fits_type(double value, ScalarType type) {
  // No ordered comparison with NaN: it raises FE_INVALID (see coordinate_in_range).
  if (!std::isfinite(value)) return !is_integer_type(type);
  const TypeRange& range = range_of(type);
  return value >= range.lowest && (range.highest_excluded ? value < range.highest : value <= range.highest);
}

std::string describe_range(ScalarType type) { return "its type " + std::string(range_of(type).text); }

std::string coordinate_bound() {
  std::string text = "+-";
  append_number(text, max_coordinate);  // "+-1e+15"
  return text;
}

PointChecker::PointChecker(Location location) : location_(location), skip_(SkipInvalidPoints::current()) {}

bool PointChecker::check(const Vec3& v, std::size_t location, const std::string_view (&names)[3],
                         const std::size_t* offsets, bool bounded, Found& found) {
  for (int k = 0; k < 3; ++k) {
    const double value = v[k];
    if (bounded ? coordinate_in_range(value) : std::isfinite(value)) continue;
    if (found.count++ == 0) {
      found.location = location + (offsets != nullptr ? offsets[k] : 0);
      found.first = std::string(names[k]) + " = ";
      append_number(found.first, value);
    }
    return false;  // one point counts once
  }
  return true;
}

std::string PointChecker::describe(const Found& found, std::string_view what, bool vertices) const {
  std::string text = std::to_string(found.count);
  if (vertices) {
    text += found.count == 1 ? " vertex has " : " vertices have ";
  } else {
    text += found.count == 1 ? " point has " : " points have ";
  }
  text += what;
  text += "; the first at " + place(location_, found.location) + " (" + found.first + ")";
  return text;
}

std::string place(PointChecker::Location kind, std::size_t location) {
  static constexpr std::string_view words[] = {"line ", "byte ", "point "};
  return std::string(words[static_cast<std::size_t>(kind)]) + std::to_string(location);
}

void PointChecker::report(std::string_view file, bool vertices) const {
  const std::string bad_position = "a coordinate that is not finite or beyond " + coordinate_bound();
  const bool skipping = skip_ != nullptr && !vertices;
  if (skipping && positions_.count != 0) skip_->found(positions_.count, describe(positions_, bad_position, false));
  std::string message;
  if (positions_.count != 0 && !skipping) message = describe(positions_, bad_position, vertices);
  if (normals_.count != 0) {
    if (!message.empty()) message += "; and ";
    message += describe(normals_, "a normal that is not finite (NaN or infinity)", vertices);
  }
  if (!message.empty()) fail_in_file(file, message);
}

namespace {
thread_local SkipInvalidPoints* innermost_skip = nullptr;
}  // namespace

SkipInvalidPoints::SkipInvalidPoints() : outer_(innermost_skip) { innermost_skip = this; }

SkipInvalidPoints::~SkipInvalidPoints() { innermost_skip = outer_; }

SkipInvalidPoints* SkipInvalidPoints::current() { return innermost_skip; }

SkipInvalidPoints::Hide::Hide() : hidden_(std::exchange(innermost_skip, nullptr)) {}

SkipInvalidPoints::Hide::~Hide() { innermost_skip = hidden_; }

void SkipInvalidPoints::found(std::uint64_t count, std::string description) {
  if (count_ == 0) description_ = std::move(description);
  count_ += count;
}

void append_number(std::string& out, double value) {
  char text[32];
  const auto [end, ec] = recon::detail::float_to_chars(text, text + sizeof text, value);
  out.append(text, ec == std::errc{} ? static_cast<std::size_t>(end - text) : 0);
}

void append_integer(std::string& out, std::uint64_t value) {
  char text[24];
  const auto [end, ec] = std::to_chars(text, text + sizeof text, value);
  out.append(text, ec == std::errc{} ? static_cast<std::size_t>(end - text) : 0);
}

namespace {
bool finite(const Vec3& v) { return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z()); }
/// What the readers accept as a coordinate: finite and within +-max_coordinate.
bool readable(const Vec3& v) {
  return coordinate_in_range(v.x()) && coordinate_in_range(v.y()) && coordinate_in_range(v.z());
}
}  // namespace

std::size_t SkipInvalidPoints::drop_unreadable(PointCloud& cloud) {
  const std::size_t before = cloud.size();
  std::size_t kept = 0;
  for (std::size_t i = 0; i < before; ++i) {
    if (!readable(cloud.positions[i])) continue;
    cloud.positions[kept] = cloud.positions[i];
    if (cloud.has_normals()) cloud.normals[kept] = cloud.normals[i];
    if (cloud.has_colors()) cloud.colors[kept] = cloud.colors[i];
    ++kept;
  }
  cloud.positions.resize(kept);
  if (cloud.has_normals()) cloud.normals.resize(kept);
  if (cloud.has_colors()) cloud.colors.resize(kept);
  return before - kept;
}

void SkipInvalidPoints::conclude(std::string_view file, std::size_t dropped, std::size_t kept, ReadNotes& notes) const {
  if (count_ == 0) return;
  if (kept == 0) fail_in_file(file, "no points: every point is invalid (" + description_ + ")");
  notes.skipped_points += dropped;
  notes.lines.push_back("skipped as invalid: " + description_);
}

void SkipInvalidPoints::remove_from(std::string_view file, PointCloud& cloud, ReadNotes& notes) const {
  if (count_ == 0) return;
  const std::size_t dropped = drop_unreadable(cloud);
  conclude(file, dropped, cloud.size(), notes);
}

namespace {
/// Refuses `count` `what` (normals, colours) that are not one per position:
/// "FILE: cannot write: the cloud has 2 normals for 3 points".
void check_one_per_position(const std::string& name, std::string_view holder, std::size_t count, std::string_view what,
                            std::size_t positions, std::string_view per) {
  if (count != positions)
    throw InvalidInputError(name + ": cannot write: the " + std::string(holder) + " has " + std::to_string(count) +
                            " " + std::string(what) + " for " + std::to_string(positions) + " " + std::string(per));
}

/// Refuses a position that would not read back: "FILE: cannot write: point 1 has ...".
void check_readable(const std::string& name, const std::vector<Vec3>& positions, std::string_view what) {
  for (std::size_t i = 0; i < positions.size(); ++i) {
    if (!readable(positions[i]))
      throw InvalidInputError(name + ": cannot write: " + std::string(what) + " " + std::to_string(i) +
                              " has a coordinate that is not finite or beyond " + coordinate_bound());
  }
}
}  // namespace

void check_cloud_for_writing(std::string_view file, const PointCloud& cloud) {
  const std::string name(file);
  const std::size_t points = cloud.positions.size();
  if (cloud.has_normals()) check_one_per_position(name, "cloud", cloud.normals.size(), "normals", points, "points");
  if (cloud.has_colors()) check_one_per_position(name, "cloud", cloud.colors.size(), "colours", points, "points");
  check_readable(name, cloud.positions, "point");
  for (std::size_t i = 0; i < cloud.normals.size(); ++i) {
    if (!finite(cloud.normals[i]))
      throw InvalidInputError(name + ": cannot write: the normal of point " + std::to_string(i) +
                              " has a non-finite component");
  }
}

void check_mesh_for_writing(std::string_view file, const Mesh& mesh) {
  const std::string name(file);
  const std::size_t vertices = mesh.vertices.size();
  if (mesh.has_colors()) check_one_per_position(name, "mesh", mesh.colors.size(), "colours", vertices, "vertices");
  check_readable(name, mesh.vertices, "vertex");
  if (mesh.has_normals()) {
    check_one_per_position(name, "mesh", mesh.normals.size(), "normals", vertices, "vertices");
    // Finite, as the readers want them (a normal read from another tool's
    // file need not be unit; GLB alone requires it: check_mesh_for_glb).
    for (std::size_t v = 0; v < vertices; ++v)
      if (!std::isfinite(mesh.normals[v].norm()))
        throw InvalidInputError(name + ": cannot write: vertex " + std::to_string(v) + "'s normal is not finite");
  }
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (const std::uint32_t v : mesh.triangles[t]) {
      if (v >= vertices)
        throw InvalidInputError(name + ": cannot write: triangle " + std::to_string(t) + " uses vertex " +
                                std::to_string(v) + ", but the mesh has " + std::to_string(vertices) + " vertices");
    }
  }
}

std::string lower_case(std::string_view text) {
  std::string result(text);
  for (char& c : result) {
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  }
  return result;
}

void fail_unknown_extension(const std::filesystem::path& path, std::string_view extension, std::string_view known) {
  const std::string what =
      extension.empty() ? "has no extension" : "has the unknown extension '" + std::string(extension) + "'";
  throw InvalidInputError(path.string() + ": " + what + "; " + std::string(known));
}

void append_triangles_text(BlockWriter& writer, const std::vector<std::array<std::uint32_t, 3>>& triangles,
                           char keyword, std::uint64_t first) {
  std::string& out = writer.buffer();
  for (const auto& triangle : triangles) {
    out += keyword;
    for (const std::uint32_t v : triangle) {
      out += ' ';
      append_integer(out, v + first);
    }
    out += '\n';
    writer.flush_if_full();
  }
}

void append_normal_text(std::string& out, const Vec3& n) {
  for (int k = 0; k < 3; ++k) {
    if (k > 0) out += ' ';
    char text[24];
    const auto [end, ec] = recon::detail::float_to_chars(text, text + sizeof text, static_cast<float>(n[k]));
    out.append(text, ec == std::errc{} ? static_cast<std::size_t>(end - text) : 0);
  }
}

void append_normal_binary(std::string& out, const Vec3& n) {
  for (int k = 0; k < 3; ++k) append_little_endian(out, static_cast<float>(n[k]));
}

void append_vec3_text(std::string& out, const Vec3& v) {
  append_number(out, v.x());
  out += ' ';
  append_number(out, v.y());
  out += ' ';
  append_number(out, v.z());
}

Vec3 parse_vec3(std::string_view file, std::size_t line, const std::string_view* tokens,
                const std::string_view (&names)[3]) {
  const double x = parse_coordinate(file, line, tokens[0], names[0]);
  const double y = parse_coordinate(file, line, tokens[1], names[1]);
  const double z = parse_coordinate(file, line, tokens[2], names[2]);
  return {x, y, z};
}

}  // namespace recon::io::detail

const char* recon::io::file_being_read() noexcept {
  std::atomic_signal_fence(std::memory_order_acquire);
  return detail::being_read;
}
