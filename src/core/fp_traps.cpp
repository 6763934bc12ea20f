#include "recon/core/fp_traps.h"

#include <cfenv>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace recon {
namespace {

#if defined(__GLIBC__)
constexpr int trapped = FE_INVALID | FE_DIVBYZERO | FE_OVERFLOW;

// The floating-point environment belongs to a thread.
void set_in_this_thread(bool on) {
  std::feclearexcept(FE_ALL_EXCEPT);  // flags raised before must not trap at once
  if (on)
    feenableexcept(trapped);
  else
    fedisableexcept(trapped);
}

bool on_in_this_thread() { return (fegetexcept() & trapped) == trapped; }
#endif

}  // namespace

bool set_fp_traps(bool on) {
#if defined(__GLIBC__)
  set_in_this_thread(on);
#ifdef _OPENMP
  // Each thread of the pool sets its own (threads started later copy this
  // thread's).
#pragma omp parallel
  set_in_this_thread(on);
#endif
  return true;
#else
  (void)on;
  return false;
#endif
}

bool fp_traps_enabled() {
#if defined(__GLIBC__)
  bool all = on_in_this_thread();
#ifdef _OPENMP
#pragma omp parallel reduction(&& : all)
  all = all && on_in_this_thread();
#endif
  return all;
#else
  return false;
#endif
}

}  // namespace recon
