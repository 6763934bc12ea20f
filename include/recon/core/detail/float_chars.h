#pragma once
// std::from_chars and std::to_chars for floating point, where the standard
// library has them, and the same results where it does not.
//
// Why: the readers parse numbers, and the writers and the reports print
// them, with <charconv>'s floating-point forms (exact, locale-free, the
// shortest text that reads back). Emscripten 3.1.6's libc++ (Debian's, which
// builds the web pages web/playground and web/webapp) declares them deleted.
// There, these functions give the same results through strtod and snprintf,
// which are exact in the "C" locale a WebAssembly module runs in:
//   - from_chars: the same grammar (no leading blank, no '+', no hex; "inf",
//     "infinity" and "nan" in any case), result_out_of_range for a value
//     beyond the type's range or below its smallest subnormal;
//   - to_chars (shortest): the fewest significant digits that read back,
//     written fixed or scientific, whichever is shorter (fixed on a tie);
//   - to_chars (fixed, precision): printf's %.*f.
// Cost: a call of std:: natively; under Emscripten a strtod, and up to 17
// snprintf and strtod calls per number printed (only the outputs print).
// Throws nothing; results as std::from_chars/std::to_chars (ec set, ptr
// as they say).

#include <charconv>

namespace recon::detail {

/// The forms through strtod and snprintf, compiled everywhere (the tests
/// compare them with <charconv>'s, tests/core/float_chars_test.cpp).
std::from_chars_result portable_from_chars(const char* first, const char* last, double& value);
std::to_chars_result portable_to_chars(char* first, char* last, double value);
std::to_chars_result portable_to_chars(char* first, char* last, float value);
std::to_chars_result portable_to_chars(char* first, char* last, double value, std::chars_format format, int precision);

#if defined(__EMSCRIPTEN__)  // its libc++ has no floating-point <charconv>
inline std::from_chars_result float_from_chars(const char* first, const char* last, double& value) {
  return portable_from_chars(first, last, value);
}
inline std::to_chars_result float_to_chars(char* first, char* last, double value) {
  return portable_to_chars(first, last, value);
}
inline std::to_chars_result float_to_chars(char* first, char* last, float value) {
  return portable_to_chars(first, last, value);
}
inline std::to_chars_result float_to_chars(char* first, char* last, double value, std::chars_format format,
                                           int precision) {
  return portable_to_chars(first, last, value, format, precision);
}
#else
inline std::from_chars_result float_from_chars(const char* first, const char* last, double& value) {
  return std::from_chars(first, last, value);
}
inline std::to_chars_result float_to_chars(char* first, char* last, double value) {
  return std::to_chars(first, last, value);
}
inline std::to_chars_result float_to_chars(char* first, char* last, float value) {
  return std::to_chars(first, last, value);
}
inline std::to_chars_result float_to_chars(char* first, char* last, double value, std::chars_format format,
                                           int precision) {
  return std::to_chars(first, last, value, format, precision);
}
#endif

}  // namespace recon::detail
