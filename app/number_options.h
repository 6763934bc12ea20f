#pragma once
// Checks for the command line's numeric options, used in place of CLI11's
// PositiveNumber, NonNegativeNumber and Range(double): those let "nan"
// through (every comparison with NaN is false) and print their bounds with
// %f, the largest double as a 310-digit number. Each check here refuses NaN,
// infinities and values out of range, in one line that says what the
// option expects and what it was given:
//   --cell: expected a finite length greater than 0, found 'inf'
// (CLI11 puts the option's name in front.) They run on the text, before
// CLI11 converts it; the conversion's own errors stay CLI11's.

#include <CLI/CLI.hpp>

namespace recon::cli {

/// A finite number greater than 0: a length (--rho, --cell, --tile-size).
[[nodiscard]] CLI::Validator positive_length();
/// A finite number of 0 or more: a length that may be 0 (--delta).
[[nodiscard]] CLI::Validator non_negative_length();
/// A finite number from `low` to `high`, both included (--noise).
[[nodiscard]] CLI::Validator finite_within(double low, double high);
/// A whole number from 0 to `most` (--threads, the lab's point limits).
[[nodiscard]] CLI::Validator whole_number_up_to(double most);

/// --simplify's value: a whole number of 1 or more (a triangle count), a
/// number between 0 and 1 (a ratio), or a percentage between 0 and 100
/// ("10%"), both exclusive; the check refuses anything else in one line.
[[nodiscard]] CLI::Validator simplify_target();
/// The count (first) or ratio (second) a checked --simplify value gives.
[[nodiscard]] std::pair<std::size_t, double> simplify_target_of(const std::string& text);

}  // namespace recon::cli
