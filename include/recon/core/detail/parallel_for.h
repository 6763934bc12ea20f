#pragma once
// The loops of the parallel phases, for the library's own sources (which are
// built with OpenMP when it is on; the pragmas below need its flags).
//
// Each runs body(i) once for every i in [0, n) on the threads that
// set_thread_count() chose (serially without OpenMP). The body must not
// throw, and must write only what belongs to i (or use AtomicRef), so that
// the result is the same for any thread count.
//   parallel_for:          equal static shares, for bodies of equal cost;
//   parallel_for_dynamic:  chunks of `chunk` indices handed out as threads
//                          free up, for bodies whose cost varies;
//   parallel_count:        the sum of the integers body(i) returns (the same
//                          sum in any order), chunked as parallel_for_dynamic.

#include <cstddef>
#include <cstdint>
#include <type_traits>

namespace recon::detail {

template <class Body>
void parallel_for(std::size_t n, Body&& body) {
  const auto count = static_cast<std::int64_t>(n);
#pragma omp parallel for schedule(static)
  for (std::int64_t s = 0; s < count; ++s) body(static_cast<std::size_t>(s));
}

template <class Body>
void parallel_for_dynamic(std::size_t n, [[maybe_unused]] int chunk, Body&& body) {
  const auto count = static_cast<std::int64_t>(n);
#pragma omp parallel for schedule(dynamic, chunk)
  for (std::int64_t s = 0; s < count; ++s) body(static_cast<std::size_t>(s));
}

template <class Body>
[[nodiscard]] std::size_t parallel_count(std::size_t n, [[maybe_unused]] int chunk, Body&& body) {
  static_assert(std::is_integral_v<std::invoke_result_t<Body&, std::size_t>>, "parallel_count adds integers");
  const auto count = static_cast<std::int64_t>(n);
  std::size_t total = 0;
#pragma omp parallel for schedule(dynamic, chunk) reduction(+ : total)
  for (std::int64_t s = 0; s < count; ++s) total += static_cast<std::size_t>(body(static_cast<std::size_t>(s)));
  return total;
}

}  // namespace recon::detail
