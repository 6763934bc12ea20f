#pragma once
// A one-line progress display on a terminal: after a phase has run for a
// second, "recon: <phase> ... 3.2 s" is redrawn on stderr a few times a
// second, and cleared when the run moves on. Silent when stderr is not a
// terminal or with --quiet.

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>

namespace recon::cli {

class Progress {
 public:
  explicit Progress(bool enabled);
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  /// The phase now running; an empty name clears the line (between phases,
  /// before printing).
  void phase(const std::string& name);
  /// Clears the line and stops.
  void stop();

 private:
  void run();

  bool enabled_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::string phase_;
  std::chrono::steady_clock::time_point started_;
  bool drawn_ = false;
  bool stopping_ = false;
  std::thread thread_;
};

}  // namespace recon::cli
