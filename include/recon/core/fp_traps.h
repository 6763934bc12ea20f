#pragma once
// Floating-point exception traps, a debugging aid: with them on, an invalid
// operation (0/0, inf - inf, 0 * inf, the square root of a negative number,
// an ordered comparison such as < with a NaN), a division by zero or an
// overflow stops the program with SIGFPE at the instruction that did it,
// instead of a NaN or an infinity surfacing phases later. Underflow and
// inexact results are normal in geometry and never trap.
//
// The test suite runs with them on when built with RECON_TRAP_FP (the
// sanitize preset does), and `recon --trap-fp` runs the program so.

namespace recon {

/// Turns the traps on or off in the calling thread and in the threads of the
/// parallel phases (OpenMP's pool, and the threads it starts later, which
/// inherit the caller's floating-point environment). Returns false, and
/// changes nothing, where the platform cannot trap (glibc's feenableexcept
/// is needed).
/// Cost: O(threads).
/// Throws: nothing.
/// Pre: called from the thread that runs the phases, outside any parallel region.
bool set_fp_traps(bool on);

/// Whether the traps are on in the calling thread and in every thread a
/// parallel phase would use now.
/// Cost: O(threads).
/// Throws: nothing.
/// Pre: called outside any parallel region.
[[nodiscard]] bool fp_traps_enabled();

}  // namespace recon
