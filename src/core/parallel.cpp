#include "recon/core/parallel.h"

#include "recon/core/errors.h"

#include <algorithm>
#include <string>
#include <thread>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace recon {
namespace {

int core_count() {
#ifdef _OPENMP
  return std::max(1, omp_get_num_procs());
#else
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
#endif
}

}  // namespace

int max_thread_count() { return std::min(64 * core_count(), 4096); }

void set_thread_count(int n) {
  if (n > max_thread_count())
    throw InvalidInputError("a thread count of " + std::to_string(n) + " is more than this machine can use: at most " +
                            std::to_string(max_thread_count()) + " (64 a core, " + std::to_string(core_count()) +
                            " cores here; at most 4096); the default, all cores, is the fastest");
#ifdef _OPENMP
  omp_set_num_threads(n > 0 ? n : omp_get_num_procs());
#else
  (void)n;
#endif
}

int thread_count() {
#ifdef _OPENMP
  return omp_get_max_threads();
#else
  return 1;
#endif
}

}  // namespace recon
