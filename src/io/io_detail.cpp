#include "io_detail.h"

#include "recon/errors.h"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <memory>
#include <system_error>

namespace recon::io::detail {

std::string read_file(const std::filesystem::path& path) {
  const std::string name = path.string();
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw IoError(name + ": cannot open: it is a folder, not a file");

  struct CloseFile {
    void operator()(std::FILE* f) const { std::fclose(f); }
  };
  const std::unique_ptr<std::FILE, CloseFile> file(std::fopen(path.c_str(), "rb"));
  if (!file) throw IoError(name + ": cannot open: " + std::strerror(errno));

  // Size the buffer from the file size when it is known, then keep reading
  // until the end (the size is only a hint: pipes have none).
  std::string content;
  const std::uintmax_t size_hint = std::filesystem::file_size(path, ec);
  std::size_t chunk = ec ? std::size_t{1} << 20 : static_cast<std::size_t>(size_hint) + 1;
  std::size_t used = 0;
  for (;;) {
    content.resize(used + chunk);
    const std::size_t got = std::fread(content.data() + used, 1, chunk, file.get());
    used += got;
    if (got < chunk) break;
    chunk = std::max<std::size_t>(chunk, std::size_t{1} << 20);
  }
  if (std::ferror(file.get()) != 0) throw IoError(name + ": cannot read: " + std::strerror(errno));
  content.resize(used);
  return content;
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
  const auto [end, ec] = std::from_chars(first, last, value);
  if (end != last || ec == std::errc::invalid_argument) return NumberStatus::not_a_number;
  if (ec == std::errc::result_out_of_range) {
    if (is_overflow(std::string_view(first, static_cast<std::size_t>(last - first)))) return NumberStatus::overflow;
    value = *first == '-' ? -0.0 : 0.0;  // below the smallest subnormal
  }
  return NumberStatus::ok;
}

bool parse_integer(std::string_view token, std::int64_t& value) {
  const char* first = token.data();
  const char* const last = first + token.size();
  if (first != last && *first == '+') ++first;
  if (first == last) return false;
  const auto [end, ec] = std::from_chars(first, last, value);
  return ec == std::errc{} && end == last;
}

bool parse_count(std::string_view token, std::uint64_t& value) {
  const char* first = token.data();
  const char* const last = first + token.size();
  if (first != last && *first == '+') ++first;
  if (first == last) return false;
  const auto [end, ec] = std::from_chars(first, last, value);
  return ec == std::errc{} && end == last;
}

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
  if (!std::isfinite(value))
    fail_at_line(
        file, line,
        "non-finite value " + excerpt(token) + " for " + std::string(what) + " (NaN and infinity are not allowed)");
  return value;
}

void append_number(std::string& out, double value) {
  char text[32];
  const auto [end, ec] = std::to_chars(text, text + sizeof text, value);
  out.append(text, ec == std::errc{} ? static_cast<std::size_t>(end - text) : 0);
}

void append_integer(std::string& out, std::uint64_t value) {
  char text[24];
  const auto [end, ec] = std::to_chars(text, text + sizeof text, value);
  out.append(text, ec == std::errc{} ? static_cast<std::size_t>(end - text) : 0);
}

namespace {
bool finite(const Vec3& v) { return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z()); }
}  // namespace

void check_cloud_for_writing(std::string_view file, const PointCloud& cloud) {
  const std::string name(file);
  if (cloud.has_normals() && cloud.normals.size() != cloud.positions.size())
    throw InvalidInputError(name + ": cannot write: the cloud has " + std::to_string(cloud.normals.size()) +
                            " normals for " + std::to_string(cloud.positions.size()) + " points");
  for (std::size_t i = 0; i < cloud.positions.size(); ++i) {
    if (!finite(cloud.positions[i]))
      throw InvalidInputError(name + ": cannot write: point " + std::to_string(i) + " has a non-finite coordinate");
  }
  for (std::size_t i = 0; i < cloud.normals.size(); ++i) {
    if (!finite(cloud.normals[i]))
      throw InvalidInputError(name + ": cannot write: the normal of point " + std::to_string(i) +
                              " has a non-finite component");
  }
}

void check_mesh_for_writing(std::string_view file, const Mesh& mesh) {
  const std::string name(file);
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    if (!finite(mesh.vertices[i]))
      throw InvalidInputError(name + ": cannot write: vertex " + std::to_string(i) + " has a non-finite coordinate");
  }
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (const std::uint32_t v : mesh.triangles[t]) {
      if (v >= mesh.vertices.size())
        throw InvalidInputError(name + ": cannot write: triangle " + std::to_string(t) + " uses vertex " +
                                std::to_string(v) + ", but the mesh has " + std::to_string(mesh.vertices.size()) +
                                " vertices");
    }
  }
}

void append_vec3_text(std::string& out, const Vec3& v) {
  append_number(out, v.x());
  out += ' ';
  append_number(out, v.y());
  out += ' ';
  append_number(out, v.z());
}

Vec3 parse_vec3(std::string_view file, std::size_t line, const std::string_view* tokens, const char* const names[3]) {
  const double x = parse_coordinate(file, line, tokens[0], names[0]);
  const double y = parse_coordinate(file, line, tokens[1], names[1]);
  const double z = parse_coordinate(file, line, tokens[2], names[2]);
  return {x, y, z};
}

}  // namespace recon::io::detail
