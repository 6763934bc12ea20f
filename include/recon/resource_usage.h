#pragma once
// How much memory the process holds, for the per-phase figures of --stats
// and the benchmarks. Linux only (/proc); elsewhere the figures are absent.
//
// The peak is VmHWM, the high-water mark of the resident set of the whole
// process. Resetting it (writing 5 to /proc/self/clear_refs, Linux 4.0 and
// later) sets it back to the current resident size, so a peak read after a
// phase and a reset before it is the peak reached during that phase.

#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace recon {

/// Resident memory now, in bytes.
[[nodiscard]] std::optional<std::size_t> resident_bytes();
/// Peak resident memory since the process started or the last reset, in bytes.
[[nodiscard]] std::optional<std::size_t> peak_resident_bytes();
/// Sets the peak back to the current resident size; false where refused.
bool reset_peak_resident();
/// Physical memory of the machine, in bytes (0 if unknown).
[[nodiscard]] std::size_t physical_memory_bytes();
/// What recon lets one run hold unless told otherwise: half the physical
/// memory (4 GB when it cannot be read). reconstruct() refuses work
/// estimated beyond it (ReconstructionOptions::max_memory), the readers a
/// stream longer than it (ReadPointsOptions::max_stream_bytes).
[[nodiscard]] std::size_t default_memory_limit();

/// The peak of each step of a run: start(step) ends the step before (taking
/// its peak) and resets the peak for the new one; finish() ends the last.
class StepPeaks {
 public:
  void start(std::string step);
  void finish();
  /// (step, peak in MiB), in order; a step is left out where /proc cannot say.
  [[nodiscard]] const std::vector<std::pair<std::string, double>>& peaks() const { return peaks_; }

 private:
  std::string step_;
  std::vector<std::pair<std::string, double>> peaks_;
};

}  // namespace recon
