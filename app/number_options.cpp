#include "number_options.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <sstream>
#include <string>
#include <utility>

namespace recon::cli {
namespace {

// The number `text` spells in full (a sign, digits, an exponent; also
// "nan" and "inf", which the checks then refuse by name), or nothing.
std::optional<double> number_in(const std::string& text) {
  if (text.empty()) return std::nullopt;
  errno = 0;
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size()) return std::nullopt;
  return value;  // (out of range: +-HUGE_VAL, refused below as not finite)
}

// A bound as a person writes it: 0, 1, 0.25, 4096; never 310 digits.
std::string bound_text(double bound) {
  std::ostringstream out;
  out.precision(15);
  out << bound;
  return out.str();
}

// The check's message for `text`, or "" when `accept` takes its number.
template <class Accept>
CLI::Validator number_check(std::string expected, Accept accept) {
  return CLI::Validator(
      [expected, accept](std::string& text) -> std::string {
        const std::optional<double> value = number_in(text);
        if (value && std::isfinite(*value) && accept(*value)) return {};
        return "expected " + expected + ", found '" + text + "'";
      },
      expected);
}

}  // namespace

CLI::Validator positive_length() {
  return number_check("a finite length greater than 0", [](double v) { return v > 0.0; });
}

CLI::Validator non_negative_length() {
  return number_check("a finite length of 0 or more", [](double v) { return v >= 0.0; });
}

CLI::Validator finite_within(double low, double high) {
  return number_check("a number from " + bound_text(low) + " to " + bound_text(high),
                      [low, high](double v) { return v >= low && v <= high; });
}

CLI::Validator whole_number_up_to(double most) {
  return number_check("a whole number from 0 to " + bound_text(most),
                      [most](double v) { return v >= 0.0 && v <= most && std::floor(v) == v; });
}

std::pair<std::size_t, double> simplify_target_of(const std::string& text) {
  const bool percent = !text.empty() && text.back() == '%';
  const std::optional<double> value = number_in(percent ? text.substr(0, text.size() - 1) : text);
  if (!value || !std::isfinite(*value)) return {0, 0.0};
  if (percent) return {0, *value > 0.0 && *value < 100.0 ? *value / 100.0 : 0.0};
  if (*value > 0.0 && *value < 1.0) return {0, *value};
  if (*value >= 1.0 && *value <= 4e9 && std::floor(*value) == *value) return {static_cast<std::size_t>(*value), 0.0};
  return {0, 0.0};
}

CLI::Validator simplify_target() {
  const std::string expected =
      "a triangle count (a whole number of 1 or more), a ratio between 0 and 1, or a "
      "percentage below 100% (e.g. 5000, 0.1, 10%)";
  return CLI::Validator(
      [expected](std::string& text) -> std::string {
        const auto [count, ratio] = simplify_target_of(text);
        if (count > 0 || ratio > 0.0) return {};
        return "expected " + expected + ", found '" + text + "'";
      },
      "TARGET");
}

}  // namespace recon::cli
