#include "colors.h"

#include "recon/core/detail/float_chars.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <string_view>
#include <utility>

namespace recon::io::detail {
namespace {

std::uint8_t to_byte(double value) { return static_cast<std::uint8_t>(std::lround(std::clamp(value, 0.0, 255.0))); }

// NaN as 0 and the infinities clamped, so that nothing below compares a
// NaN (an ordered comparison with NaN raises FE_INVALID, which the
// sanitize build traps).
double finite_or_clamped(double value) {
  if (std::isnan(value)) return 0.0;
  return std::isinf(value) ? (value > 0.0 ? 255.0 : 0.0) : value;
}

std::uint8_t integer_channel(double value, ScalarType type) {
  const bool sixteen_bits = type == ScalarType::uint16 || type == ScalarType::int16;
  return to_byte(sixteen_bits ? value / 257.0 : value);
}

}  // namespace

ColorReader::ColorReader(const std::array<ScalarType, 3>& types)
    : types_(types),
      floating_(std::any_of(types.begin(), types.end(), [](ScalarType t) { return !is_integer_type(t); })) {}

void ColorReader::reserve(std::size_t points) {
  if (floating_) {
    floats_.reserve(points);
  } else {
    colors_.reserve(points);
  }
}

void ColorReader::add(double red, double green, double blue) {
  const std::array<double, 3> values = {finite_or_clamped(red), finite_or_clamped(green), finite_or_clamped(blue)};
  if (!floating_) {
    Color& c = colors_.emplace_back();
    for (std::size_t k = 0; k < 3; ++k) c[k] = integer_channel(values[k], types_[k]);
    return;
  }
  std::array<float, 3>& f = floats_.emplace_back();
  for (std::size_t k = 0; k < 3; ++k) {
    beyond_one_ = beyond_one_ || values[k] > 1.0;
    f[k] = static_cast<float>(std::clamp(values[k], 0.0, 255.0));
  }
}

std::vector<Color> ColorReader::take() {
  std::vector<Color> colors;
  colors.swap(colors_);
  if (floating_) {
    const double scale = beyond_one_ ? 1.0 : 255.0;
    colors.reserve(floats_.size());
    for (const auto& f : floats_)
      colors.push_back({to_byte(scale * static_cast<double>(f[0])), to_byte(scale * static_cast<double>(f[1])),
                        to_byte(scale * static_cast<double>(f[2]))});
    floats_.clear();
  }
  return colors;
}

void append_color_bytes(std::string& out, const Color& color) {
  for (std::size_t k = 0; k < 3; ++k) {
    if (k > 0) out += ' ';
    append_integer(out, color[k]);
  }
}

void append_color_unit(std::string& out, const Color& color) {
  // Neighbouring values differ by 1/255 = 0.0039: four decimals tell them
  // apart, and 255 * v rounds back to the byte.
  for (std::size_t k = 0; k < 3; ++k) {
    if (k > 0) out += ' ';
    char text[16];
    const auto [end, ec] = recon::detail::float_to_chars(
        text, text + sizeof text, static_cast<double>(color[k]) / 255.0, std::chars_format::fixed, 4);
    std::string_view digits(text, ec == std::errc{} ? static_cast<std::size_t>(end - text) : 0);
    while (digits.size() > 1 && digits.back() == '0') digits.remove_suffix(1);  // "0.5000" -> "0.5", "1.0000" -> "1."
    if (!digits.empty() && digits.back() == '.') digits.remove_suffix(1);
    out += digits;
  }
}

}  // namespace recon::io::detail
