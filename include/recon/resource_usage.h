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

namespace recon {

/// Resident memory now, in bytes.
[[nodiscard]] std::optional<std::size_t> resident_bytes();
/// Peak resident memory since the process started or the last reset, in bytes.
[[nodiscard]] std::optional<std::size_t> peak_resident_bytes();
/// Sets the peak back to the current resident size; false where refused.
bool reset_peak_resident();
/// Physical memory of the machine, in bytes (0 if unknown).
[[nodiscard]] std::size_t physical_memory_bytes();

}  // namespace recon
