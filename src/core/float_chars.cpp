#include "recon/core/detail/float_chars.h"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <system_error>

namespace recon::detail {
namespace {

bool starts_with_word(const char* first, const char* last, const char* word) {
  const std::size_t n = std::strlen(word);
  if (static_cast<std::size_t>(last - first) < n) return false;
  for (std::size_t i = 0; i < n; ++i)
    if (std::tolower(static_cast<unsigned char>(first[i])) != word[i]) return false;
  return true;
}

// The end of the longest prefix of [first, last) that from_chars reads as a
// number in general format: [-] digits [. digits] [e [+-] digits], or inf,
// infinity, nan (with an optional "(chars)"); `first` when there is none.
const char* number_end(const char* first, const char* last) {
  const char* p = first;
  if (p != last && *p == '-') ++p;
  if (starts_with_word(p, last, "infinity")) return p + 8;
  if (starts_with_word(p, last, "inf")) return p + 3;
  if (starts_with_word(p, last, "nan")) {
    p += 3;
    if (p != last && *p == '(') {
      const char* q = p + 1;
      while (q != last && (std::isalnum(static_cast<unsigned char>(*q)) || *q == '_')) ++q;
      if (q != last && *q == ')') return q + 1;
    }
    return p;
  }
  const char* digits = p;
  while (p != last && std::isdigit(static_cast<unsigned char>(*p))) ++p;
  bool any = p != digits;
  if (p != last && *p == '.') {
    const char* fraction = ++p;
    while (p != last && std::isdigit(static_cast<unsigned char>(*p))) ++p;
    any = any || p != fraction;
  }
  if (!any) return first;
  if (p != last && (*p == 'e' || *p == 'E')) {
    const char* q = p + 1;
    if (q != last && (*q == '+' || *q == '-')) ++q;
    const char* exponent = q;
    while (q != last && std::isdigit(static_cast<unsigned char>(*q))) ++q;
    if (q != exponent) p = q;
  }
  return p;
}

// Copies `text` to `out` unless it does not fit.
std::to_chars_result put(char* first, char* last, const std::string& text) {
  if (static_cast<std::size_t>(last - first) < text.size()) return {last, std::errc::value_too_large};
  std::memcpy(first, text.data(), text.size());
  return {first + text.size(), std::errc{}};
}

// The shortest significant digits of `value` (finite, > 0) that read back
// through `reads_back`, and its decimal exponent.
template <class ReadsBack>
void shortest_digits(double value, int most, ReadsBack reads_back, std::string& digits, int& exponent) {
  char text[64];
  for (int precision = 1; precision <= most; ++precision) {
    std::snprintf(text, sizeof text, "%.*e", precision - 1, value);
    if (precision == most || reads_back(text)) break;
  }
  // text is d[.ddd]e[+-]XX
  const char* e = std::strchr(text, 'e');
  exponent = std::atoi(e + 1);
  digits.clear();
  for (const char* p = text; p != e; ++p)
    if (*p != '.') digits += *p;
  while (digits.size() > 1 && digits.back() == '0') digits.pop_back();
}

// Fixed and scientific forms of `magnitude`, whose shortest digits are
// digits * 10^(exponent - digits + 1); the shorter. A whole number is
// written fixed with all its digits, exactly (as <charconv> does: the
// shortest digits padded with zeros would be another number).
std::string shortest_form(double magnitude, const std::string& digits, int exponent) {
  const int n = static_cast<int>(digits.size());
  std::string fixed;
  if (exponent >= n - 1) {
    char whole[400];
    std::snprintf(whole, sizeof whole, "%.0f", magnitude);
    fixed = whole;
  } else if (exponent >= 0) {
    fixed = digits.substr(0, static_cast<std::size_t>(exponent + 1)) + "." +
            digits.substr(static_cast<std::size_t>(exponent + 1));
  } else {
    fixed = "0." + std::string(static_cast<std::size_t>(-exponent - 1), '0') + digits;
  }
  std::string scientific = digits.substr(0, 1);
  if (n > 1) scientific += "." + digits.substr(1);
  char power[16];
  std::snprintf(power, sizeof power, "e%c%02d", exponent < 0 ? '-' : '+', exponent < 0 ? -exponent : exponent);
  scientific += power;
  return scientific.size() < fixed.size() ? scientific : fixed;
}

template <class T>
std::to_chars_result shortest(char* first, char* last, T value) {
  if (std::isnan(value)) return put(first, last, std::signbit(value) ? "-nan" : "nan");
  std::string sign = std::signbit(value) ? "-" : "";
  if (std::isinf(value)) return put(first, last, sign + "inf");
  if (value == 0) return put(first, last, sign + "0");
  const double magnitude = std::fabs(static_cast<double>(value));
  std::string digits;
  int exponent = 0;
  const auto reads_back = [&](const char* text) {
    if constexpr (sizeof(T) == sizeof(float)) {
      return std::strtof(text, nullptr) == static_cast<float>(magnitude);
    } else {
      return std::strtod(text, nullptr) == magnitude;
    }
  };
  shortest_digits(magnitude, std::numeric_limits<T>::max_digits10, reads_back, digits, exponent);
  return put(first, last, sign + shortest_form(magnitude, digits, exponent));
}

}  // namespace

std::from_chars_result portable_from_chars(const char* first, const char* last, double& value) {
  const char* end = number_end(first, last);
  if (end == first) return {first, std::errc::invalid_argument};
  const std::string text(first, end);
  errno = 0;
  const double parsed = std::strtod(text.c_str(), nullptr);
  if (errno == ERANGE && (std::isinf(parsed) || parsed == 0.0))  // (a subnormal reads as itself, as in std::)
    return {end, std::errc::result_out_of_range};
  value = parsed;
  return {end, std::errc{}};
}

std::to_chars_result portable_to_chars(char* first, char* last, double value) { return shortest(first, last, value); }

std::to_chars_result portable_to_chars(char* first, char* last, float value) { return shortest(first, last, value); }

std::to_chars_result portable_to_chars(char* first, char* last, double value, std::chars_format format, int precision) {
  char text[400];
  const char* form = format == std::chars_format::fixed        ? "%.*f"
                     : format == std::chars_format::scientific ? "%.*e"
                                                               : "%.*g";
  std::snprintf(text, sizeof text, form, precision, value);
  return put(first, last, text);
}

}  // namespace recon::detail
