#pragma once
// Thread control for the parallel phases (OpenMP underneath when built
// with it). Results never depend on the thread count.

namespace recon {

/// Threads the parallel loops use; n <= 0 means all cores.
void set_thread_count(int n);
[[nodiscard]] int thread_count();

}  // namespace recon
