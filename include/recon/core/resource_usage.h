#pragma once
// How much memory the process holds, for the per-phase figures of --stats
// and the benchmarks. Linux only (/proc); elsewhere the figures are absent.
//
// The whole run's peak is VmHWM, the kernel's high-water mark of the
// resident set (the figure getrusage's ru_maxrss and /usr/bin/time report).
// recon never resets it: a reset (writing 5 to /proc/self/clear_refs) would
// make those tools report the last phase's peak instead of the run's. A
// step's own peak is sampled instead (StepPeaks).

#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace recon {

/// Resident memory now (VmRSS), in bytes; empty where /proc cannot say.
/// Cost: one read of /proc/self/status.
/// Throws: nothing.
/// Pre: none.
[[nodiscard]] std::optional<std::size_t> resident_bytes();
/// Peak resident memory (VmHWM) since the process started (or the last reset), in bytes; empty where
/// /proc cannot say.
/// Cost: one read of /proc/self/status.
/// Throws: nothing.
/// Pre: none.
[[nodiscard]] std::optional<std::size_t> peak_resident_bytes();
/// Sets the peak back to the current resident size; false where refused.
/// For tests and benchmarks that measure one call in a process of their
/// own; the library and the program never call it (see above).
/// Cost: one write to /proc/self/clear_refs.
/// Throws: nothing.
/// Pre: none.
bool reset_peak_resident();
/// Physical memory of the machine, in bytes (0 if unknown).
/// Cost: O(1) (sysconf).
/// Throws: nothing.
/// Pre: none.
[[nodiscard]] std::size_t physical_memory_bytes();
/// What recon lets one run hold unless told otherwise: half the physical
/// memory (4 GB when it cannot be read). reconstruct() refuses work
/// estimated beyond it (ReconstructionOptions::max_memory), the readers a
/// stream longer than it (ReadPointsOptions::max_stream_bytes).
/// Cost: O(1) (sysconf).
/// Throws: nothing.
/// Pre: none.
[[nodiscard]] std::size_t default_memory_limit();

/// The peak of each step of a run: start(step) ends the step before (taking
/// its peak) and begins the new one; finish() ends the last.
///
/// While a step runs, a thread of its own reads the resident size every
/// `sample_interval_ms` and keeps the largest. A step during which the
/// process's high-water mark rose has that mark as its peak, exactly; for
/// the others the samples are the figure, which can miss a spike shorter
/// than the interval. The largest of the steps' peaks is the whole run's
/// peak whenever the steps cover the run. The thread wakes at once to stop,
/// so finish() and the destructor return within a read.
/// Cost: one read of /proc/self/statm per interval (microseconds) while a step runs.
/// Throws: start() throws std::system_error when the sampling thread cannot start; nothing else does.
/// Pre: start and finish are called from one thread (the class is not itself thread-safe).
class StepPeaks {
 public:
  static constexpr int sample_interval_ms = 5;

  StepPeaks();
  ~StepPeaks();  // stops the sampling thread
  StepPeaks(StepPeaks&&) noexcept;
  StepPeaks& operator=(StepPeaks&&) noexcept;

  void start(std::string step);
  /// Ends the last step and stops the thread.
  void finish();
  /// (step, peak in MiB), in order; a step is left out where /proc cannot say.
  [[nodiscard]] const std::vector<std::pair<std::string, double>>& peaks() const { return peaks_; }

 private:
  class Sampler;  // the thread and the largest size it has read
  void end_step();
  std::unique_ptr<Sampler> sampler_;
  std::string step_;
  std::optional<std::size_t> high_water_at_start_;
  std::vector<std::pair<std::string, double>> peaks_;
};

}  // namespace recon
