#pragma once
// Stopping a long run from outside: Ctrl-C in the Python package.
//
// The phases call interruption_point() between their steps (and every 65536
// vertices in Prim's loop, every batch of cubes in the lattice walk), always
// outside their parallel regions. A caller that wants to be able to stop
// them installs a check on its thread for the length of a call:
//
//   InterruptionCheck check([] { if (stop_requested()) throw Stopped(); });
//   Reconstruction r = reconstruct(cloud);   // may throw Stopped
//
// interruption_point() runs the check installed on the calling thread, if
// any; on other threads (OpenMP's workers, a helper thread) it does nothing.
// A check that throws stops the run there: the exception leaves the phase
// as any other would (every phase is exception-safe at these points).
// Without a check, interruption_point() costs a thread-local load and a
// branch.

#include <functional>

namespace recon {

class InterruptionCheck {
 public:
  /// Installs `check` on this thread until destroyed (the previous one,
  /// if any, comes back then).
  /// Cost: O(1).
  /// Throws: nothing.
  /// Pre: destroyed on the thread that made it, in the reverse order of installation (a scope object).
  explicit InterruptionCheck(std::function<void()> check);
  ~InterruptionCheck();
  InterruptionCheck(const InterruptionCheck&) = delete;
  InterruptionCheck& operator=(const InterruptionCheck&) = delete;

 private:
  std::function<void()> check_;
  const std::function<void()>* previous_;
};

/// Runs the check installed on this thread, if any.
/// Cost: O(1) and the check's own; a thread-local load and a branch without one.
/// Throws: whatever the installed check throws; nothing without one.
/// Pre: none.
void interruption_point();

}  // namespace recon
