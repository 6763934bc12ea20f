#pragma once
// "step NAME SECONDS s" lines on stdout, one per finished step, for the
// peer programs' logs (bench/peers.sh reads them into its report).

#include <chrono>
#include <cstdio>

namespace peers {

class Steps {
 public:
  void done(const char* name) {
    const auto now = std::chrono::steady_clock::now();
    std::printf("step %-16s %9.3f s\n", name, std::chrono::duration<double>(now - last_).count());
    std::fflush(stdout);
    last_ = now;
  }

 private:
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

}  // namespace peers
