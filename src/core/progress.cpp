#include "recon/core/progress.h"

#include <algorithm>

namespace recon {
namespace {
thread_local ProgressCounter* installed = nullptr;
}  // namespace

void ProgressCounter::start(std::uint64_t work) {
  done.store(0, std::memory_order_relaxed);
  total.store(work, std::memory_order_relaxed);
}

void ProgressCounter::advance_estimated(std::uint64_t n) {
  const std::uint64_t work = total.load(std::memory_order_relaxed);
  const std::uint64_t limit = work - (work + 99) / 100;  // 99% of work, rounded down
  std::uint64_t now = done.load(std::memory_order_relaxed);
  while (now < limit && !done.compare_exchange_weak(now, std::min(limit, now + n), std::memory_order_relaxed)) {
  }
}

ProgressScope::ProgressScope(ProgressCounter* counter) : previous_(installed) { installed = counter; }

ProgressScope::~ProgressScope() { installed = previous_; }

ProgressCounter* progress_counter() { return installed; }

}  // namespace recon
