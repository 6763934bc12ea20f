#pragma once
// How far a long run has gone: a pair of counters that the running phase
// writes and a display (the program's progress line) reads.
//
// The run writes: as each phase starts, reconstruct() sets `total` to the
// work the phase announces (points to fit, cubes to walk, in the phase's own
// units; 0 when the phase does not count) and `done` to 0; the phase then
// advances `done` in chunks (every 4096 points, every batch of cubes, every
// 65536 vertices of Prim's loop), from any thread. A phase that finds more
// work than it announced (phase I fitting again at a raised k) adds it to
// `total` first, so done <= total holds; a total that is only an estimate
// (the lattice walk's cubes) is advanced with advance_estimated, which
// stays below 99% of it.
//
// The display reads, from any thread, whenever it likes: relaxed atomic
// loads, never a lock. The two values are not read together atomically, so
// a reader taking them as a phase starts may see the new total with the old
// count for a moment.
//
// Cost: a relaxed atomic add per chunk (a few hundred a second); without a
// counter, a null pointer tested per point or per batch.
//
// Reaching the phases: reconstruct() installs options.progress on its own
// thread for the length of the call (ProgressScope), as interruption.h
// installs a check, and a phase asks progress_counter() for it. On other
// threads (OpenMP's workers) progress_counter() is null: a parallel loop
// reads it before its region and its workers advance through the pointer.

#include <atomic>
#include <cstdint>

namespace recon {

struct ProgressCounter {
  std::atomic<std::uint64_t> done{0};
  std::atomic<std::uint64_t> total{0};  ///< 0: the phase does not count (a display shows the time only)

  /// A phase begins: done = 0, total = `work`.
  /// Cost: O(1), two relaxed atomic stores.
  /// Throws: nothing.
  /// Pre: none.
  void start(std::uint64_t work);
  /// n more units done. Callable from any thread.
  void advance(std::uint64_t n) { done.fetch_add(n, std::memory_order_relaxed); }
  /// n more units than announced are to be done.
  void expect(std::uint64_t n) { total.fetch_add(n, std::memory_order_relaxed); }
  /// advance(n), but never past 99% of total: for a total that is an
  /// estimate, which the phase may exceed (only its end says it is done).
  /// Cost: O(1) (a compare-exchange loop, retried only while other threads advance).
  /// Throws: nothing.
  /// Pre: none; callable from any thread.
  void advance_estimated(std::uint64_t n);
};

/// Installs `counter` (may be null: none) on this thread until destroyed;
/// the previous one, if any, comes back then.
/// Cost: O(1).
/// Throws: nothing.
/// Pre: `counter` outlives the scope; destroyed on its thread in the reverse order of installation.
class ProgressScope {
 public:
  explicit ProgressScope(ProgressCounter* counter);
  ~ProgressScope();
  ProgressScope(const ProgressScope&) = delete;
  ProgressScope& operator=(const ProgressScope&) = delete;

 private:
  ProgressCounter* previous_;
};

/// The counter installed on this thread, or null.
/// Cost: O(1), a thread-local load.
/// Throws: nothing.
/// Pre: none.
[[nodiscard]] ProgressCounter* progress_counter();

}  // namespace recon
