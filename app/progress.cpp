#include "progress.h"

#include <cstdio>

#include <unistd.h>

namespace recon::cli {

Progress::Progress(bool enabled) : enabled_(enabled && ::isatty(STDERR_FILENO) != 0) {
  if (enabled_) thread_ = std::thread([this] { run(); });
}

Progress::~Progress() { stop(); }

void Progress::phase(const std::string& name) {
  if (!enabled_) return;
  std::lock_guard lock(mutex_);
  phase_ = name;
  started_ = std::chrono::steady_clock::now();
  if (drawn_) {  // clear the old line before anything else is printed
    std::fprintf(stderr, "\r\033[K");
    std::fflush(stderr);
    drawn_ = false;
  }
}

void Progress::stop() {
  if (!thread_.joinable()) return;
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

void Progress::run() {
  std::unique_lock lock(mutex_);
  while (!stopping_) {
    wake_.wait_for(lock, std::chrono::milliseconds(250));
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
    if (stopping_ || phase_.empty() || seconds < 1.0) continue;
    std::fprintf(stderr, "\r\033[Krecon: %s ... %.1f s", phase_.c_str(), seconds);
    std::fflush(stderr);
    drawn_ = true;
  }
  if (drawn_) {
    std::fprintf(stderr, "\r\033[K");
    std::fflush(stderr);
  }
}

}  // namespace recon::cli
