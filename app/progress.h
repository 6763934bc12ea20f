#pragma once
// A one-line progress display on a terminal. After a phase has run for a
// second, its line is redrawn on stderr a few times a second, and cleared
// when the run moves on. A phase that counts its work (a ProgressCounter
// with a total, recon/core/progress.h) shows a bar, the counts and the time left
// at the rate since it started:
//
//   recon: orientation [########............]  42%  (1234567 / 2900000)  ~1 min 10 s left
//   recon: tiles [########............]  40%  (8 / 20 tiles)  ~3 min left
//
// one that does not, the time it has taken: "recon: signed distance ... 3.2 s".
// Silent when stderr is not a terminal or with --quiet.

#include "recon/core/progress.h"

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>

namespace recon::cli {

/// What the line shows at one moment.
struct ProgressState {
  std::string phase;
  std::uint64_t done = 0;
  std::uint64_t total = 0;  ///< 0: the phase does not count (the line shows the time)
  double seconds = 0.0;     ///< since the phase started
  std::string unit;         ///< what is counted ("tiles"), shown after the counts; may be empty
};

/// The line for `state`, within `width` - 1 characters (the terminal's
/// columns; a full line would wrap on some terminals): the bar narrows, then
/// goes, then the line is cut. A count past the total shows as the total
/// (100%); the time left is left out in the first second, while nothing is
/// done, and once everything is.
[[nodiscard]] std::string progress_line(const ProgressState& state, std::size_t width);

/// "~42 s left", "~1 min 10 s left" (to 10 s under 10 minutes), "~25 min
/// left", "~2 h 5 min left".
[[nodiscard]] std::string time_left_text(double seconds);

class Progress {
 public:
  explicit Progress(bool enabled);
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  /// Whether anything will be shown (a terminal, not --quiet): without it a
  /// run need not count.
  [[nodiscard]] bool enabled() const { return enabled_; }
  /// The phase now running, the counter it advances (null: it does not
  /// count) and what it counts (`unit`, may be empty). An empty name clears
  /// the line (between phases, before printing). The counter is read until
  /// the next call or stop().
  void phase(const std::string& name, const ProgressCounter* counter = nullptr, const std::string& unit = {});
  /// Clears the line and stops.
  void stop();

 private:
  void run();

  bool enabled_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::string phase_, unit_;
  const ProgressCounter* counter_ = nullptr;
  std::chrono::steady_clock::time_point started_;
  bool drawn_ = false;
  bool stopping_ = false;
  std::thread thread_;
};

}  // namespace recon::cli
