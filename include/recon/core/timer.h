#pragma once
// Wall-clock stopwatch for the per-phase statistics.

#include <chrono>

namespace recon {

class Timer {
 public:
  Timer() : start_(clock::now()), lap_(start_) {}
  /// Seconds since construction.
  [[nodiscard]] double elapsed() const { return seconds(clock::now() - start_); }
  /// Seconds since the previous lap (or construction), and starts a new lap.
  double lap() {
    const auto now = clock::now();
    const double s = seconds(now - lap_);
    lap_ = now;
    return s;
  }

 private:
  using clock = std::chrono::steady_clock;
  static double seconds(clock::duration d) { return std::chrono::duration<double>(d).count(); }
  clock::time_point start_, lap_;
};

}  // namespace recon
