#pragma once
// Thread control for the parallel phases (OpenMP underneath when built
// with it), and atomic access for their shared counters. Results never
// depend on the thread count.

#include <atomic>
#include <version>

namespace recon {

/// Sets the threads the parallel loops use; n <= 0 means all cores. The
/// limit is there because the OpenMP runtime starts every thread it is asked
/// for, and at some tens of thousands it runs out of stacks or mappings and
/// crashes the process (SIGSEGV inside libgomp), a Python interpreter included.
/// Cost: O(1) (the threads start at the next parallel region).
/// Throws: InvalidInputError (the count unchanged) when n > max_thread_count().
/// Pre: called outside any parallel region.
void set_thread_count(int n);
/// The threads the next parallel loop will use (1 without OpenMP).
/// Cost: O(1).
/// Throws: nothing.
/// Pre: none.
[[nodiscard]] int thread_count();
/// The most threads set_thread_count accepts: 64 a core, at most 4096.
/// More than a few a core only wait for each other (results never depend
/// on the count); 4096 threads still start and run here (2 cores: 8.6 s
/// for 2000 points, against 0.4 s at 256), 70000 crash.
/// Cost: O(1).
/// Throws: nothing.
/// Pre: none.
[[nodiscard]] int max_thread_count();

#if defined(__cpp_lib_atomic_ref)
/// Atomic access to a plain variable shared by the threads of a parallel loop.
template <class T>
using AtomicRef = std::atomic_ref<T>;
#else
// Standard libraries without std::atomic_ref (Emscripten 3.1's libc++, for
// the WebAssembly playground) build recon single-threaded, where plain
// access is all the loops need.
#if defined(_OPENMP)
#error "recon's parallel phases need std::atomic_ref (C++20) when built with OpenMP"
#endif
template <class T>
class AtomicRef {
 public:
  explicit AtomicRef(T& value) : value_(value) {}
  T load(std::memory_order = std::memory_order_seq_cst) const { return value_; }
  bool compare_exchange_weak(T& expected, T desired, std::memory_order = std::memory_order_seq_cst) {
    if (value_ != expected) {
      expected = value_;
      return false;
    }
    value_ = desired;
    return true;
  }
  T fetch_add(T increment, std::memory_order = std::memory_order_seq_cst) {
    const T old = value_;
    value_ += increment;
    return old;
  }

 private:
  T& value_;
};
#endif

}  // namespace recon
