#include "recon/core/resource_usage.h"

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <mutex>
#include <sstream>
#include <string>
#include <string_view>
#include <thread>

#include <fcntl.h>
#include <pthread.h>
#include <unistd.h>

namespace recon {
namespace {

// A "kB" field of /proc/self/status.
std::optional<std::size_t> status_field(std::string_view field) {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.size() > field.size() && line.compare(0, field.size(), field) == 0 && line[field.size()] == ':') {
      std::istringstream value(line.substr(field.size() + 1));
      std::size_t kib = 0;
      if (value >> kib) return kib * 1024;
    }
  }
  return std::nullopt;
}

// The resident size from /proc/self/statm ("size resident shared ..." in
// pages): a short read with no allocation, cheap enough to sample.
std::optional<std::size_t> statm_resident_bytes() {
  const int fd = ::open("/proc/self/statm", O_RDONLY | O_CLOEXEC);
  if (fd < 0) return std::nullopt;
  char text[128];
  const ssize_t length = ::read(fd, text, sizeof text - 1);
  ::close(fd);
  if (length <= 0) return std::nullopt;
  text[length] = '\0';
  unsigned long long size = 0, resident = 0;
  if (std::sscanf(text, "%llu %llu", &size, &resident) != 2) return std::nullopt;
  const long page = ::sysconf(_SC_PAGE_SIZE);
  if (page <= 0) return std::nullopt;
  return static_cast<std::size_t>(resident) * static_cast<std::size_t>(page);
}

double mebibytes(std::size_t bytes) { return static_cast<double>(bytes) / (1024.0 * 1024.0); }

}  // namespace

std::optional<std::size_t> resident_bytes() { return status_field("VmRSS"); }

std::optional<std::size_t> peak_resident_bytes() { return status_field("VmHWM"); }

bool reset_peak_resident() {
  std::ofstream clear("/proc/self/clear_refs");
  clear << "5";
  clear.flush();
  return static_cast<bool>(clear);
}

// The sampling thread. It reads the resident size every interval until
// stopped; take_largest() hands over the largest read since the last call
// and starts the next step's from the size now.
class StepPeaks::Sampler {
 public:
  Sampler() : largest_(statm_resident_bytes().value_or(0)), thread_([this] { run(); }) {}
  ~Sampler() {
    {
      const std::lock_guard lock(mutex_);
      stop_ = true;
    }
    wake_.notify_one();
    thread_.join();
  }
  Sampler(const Sampler&) = delete;
  Sampler& operator=(const Sampler&) = delete;

  std::size_t take_largest() {
    const std::size_t now = statm_resident_bytes().value_or(0);
    const std::lock_guard lock(mutex_);
    const std::size_t largest = std::max(largest_, now);
    largest_ = now;
    return largest;
  }

 private:
  void run() {
    // Signals go to the program's other threads, as they did before this one
    // existed (the interrupt handlers, Python's Ctrl-C).
    sigset_t all;
    sigfillset(&all);
    pthread_sigmask(SIG_BLOCK, &all, nullptr);
    std::unique_lock lock(mutex_);
    while (!wake_.wait_for(lock, std::chrono::milliseconds(sample_interval_ms), [this] { return stop_; })) {
      lock.unlock();
      const std::optional<std::size_t> now = statm_resident_bytes();
      lock.lock();
      if (now) largest_ = std::max(largest_, *now);
    }
  }

  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  std::size_t largest_;
  std::thread thread_;  // last: starts once the members above are set
};

StepPeaks::StepPeaks() = default;
StepPeaks::~StepPeaks() = default;
StepPeaks::StepPeaks(StepPeaks&&) noexcept = default;
StepPeaks& StepPeaks::operator=(StepPeaks&&) noexcept = default;

void StepPeaks::start(std::string step) {
  end_step();
  if (!statm_resident_bytes()) return;  // no /proc: no figures, no thread
  if (!sampler_) sampler_ = std::make_unique<Sampler>();
  static_cast<void>(sampler_->take_largest());  // the new step's samples start now
  step_ = std::move(step);
  high_water_at_start_ = peak_resident_bytes();
}

void StepPeaks::finish() {
  end_step();
  sampler_.reset();
}

// A step's peak: the largest sample, or the high-water mark when the step
// raised it (it reached that mark, exactly, during the step).
void StepPeaks::end_step() {
  if (step_.empty()) return;
  std::size_t peak = sampler_->take_largest();
  const std::optional<std::size_t> high_water = peak_resident_bytes();
  if (high_water && high_water_at_start_ && *high_water > *high_water_at_start_) peak = std::max(peak, *high_water);
  peaks_.emplace_back(step_, mebibytes(peak));
  step_.clear();
}

std::size_t physical_memory_bytes() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGE_SIZE);
  return pages > 0 && page > 0 ? static_cast<std::size_t>(pages) * static_cast<std::size_t>(page) : 0;
}

std::size_t default_memory_limit() {
  const std::size_t physical = physical_memory_bytes();
  return physical > 0 ? physical / 2 : std::size_t{4'000'000'000};
}

}  // namespace recon
