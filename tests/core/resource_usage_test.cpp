// StepPeaks (resource_usage.h): each step's peak is sampled, and the
// kernel's high-water mark, which getrusage and /usr/bin/time report, is
// never reset. Runs under ThreadSanitizer (the sampling thread).

#include "recon/core/resource_usage.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <string>
#include <thread>

#include <sys/mman.h>
#include <sys/resource.h>

namespace recon {
namespace {

constexpr std::size_t mib = std::size_t{1} << 20;

// `bytes` of fresh pages, each touched so that it is resident, given back
// on destruction (mmap: no allocator keeps them, sanitizers' included).
class TouchedPages {
 public:
  explicit TouchedPages(std::size_t bytes) : bytes_(bytes) {
    void* at = ::mmap(nullptr, bytes_, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (at == MAP_FAILED) return;
    data_ = static_cast<char*>(at);
    for (std::size_t i = 0; i < bytes_; i += 4096) data_[i] = 1;
  }
  ~TouchedPages() {
    if (data_) ::munmap(data_, bytes_);
  }
  TouchedPages(const TouchedPages&) = delete;
  TouchedPages& operator=(const TouchedPages&) = delete;
  [[nodiscard]] bool ok() const { return data_ != nullptr; }

 private:
  std::size_t bytes_;
  char* data_ = nullptr;
};

// A few sampling intervals: long enough for the sampler to see a size.
void hold() { std::this_thread::sleep_for(std::chrono::milliseconds(6 * StepPeaks::sample_interval_ms)); }

double largest_peak_mib(const StepPeaks& memory) {
  double largest = 0.0;
  for (const auto& [step, peak] : memory.peaks()) largest = std::max(largest, peak);
  return largest;
}

// Bytes that raise the process's high-water mark by `above` over its
// current value, from the resident size now.
std::size_t past_the_high_water(std::size_t above) {
  const std::size_t now = resident_bytes().value_or(0), high = peak_resident_bytes().value_or(0);
  return (high > now ? high - now : 0) + above;
}

// The step that allocates N MB and gives them back before it ends: only the
// samples can see it, the high-water mark having been raised higher before.
TEST(StepPeaks, SampledPeakOfAStepHoldsWhatItTouched) {
  if (!resident_bytes() || !peak_resident_bytes()) GTEST_SKIP() << "no /proc here";
  {
    const TouchedPages spike(past_the_high_water(64 * mib));  // the record, set outside any step
    ASSERT_TRUE(spike.ok());
  }
  StepPeaks memory;
  const std::size_t before = resident_bytes().value_or(0);
  memory.start("touch 32 MiB");
  {
    const TouchedPages pages(32 * mib);
    ASSERT_TRUE(pages.ok());
    hold();
  }
  memory.start("nothing");
  memory.finish();
  ASSERT_EQ(memory.peaks().size(), 2u);
  EXPECT_EQ(memory.peaks()[0].first, "touch 32 MiB");
  EXPECT_GE(memory.peaks()[0].second * mib, static_cast<double>(before + 30 * mib))
      << "MiB; resident before the step: " << static_cast<double>(before) / mib;
  EXPECT_LT(memory.peaks()[1].second, memory.peaks()[0].second - 16.0) << "the step after holds nothing more";
}

// After a run of steps, getrusage's ru_maxrss (what /usr/bin/time -v
// reports) is at least the largest step's peak: the high-water mark was
// not reset as the later steps started.
TEST(StepPeaks, HighWaterMarkIsTheWholeRunsPeak) {
  if (!resident_bytes() || !peak_resident_bytes()) GTEST_SKIP() << "no /proc here";
  StepPeaks memory;
  memory.start("the record");
  {
    const TouchedPages pages(past_the_high_water(48 * mib));
    ASSERT_TRUE(pages.ok());
  }
  memory.start("after");
  hold();
  memory.start("last");
  memory.finish();
  const double largest = largest_peak_mib(memory);
  rusage usage{};
  ASSERT_EQ(::getrusage(RUSAGE_SELF, &usage), 0);
  const double maxrss_mib = static_cast<double>(usage.ru_maxrss) / 1024.0;  // (KiB on Linux)
  EXPECT_GE(maxrss_mib, largest - 0.5) << "ru_maxrss below a step's peak: the high-water mark was reset";
  EXPECT_GE(static_cast<double>(peak_resident_bytes().value_or(0)) / mib, largest - 0.5);
  EXPECT_EQ(memory.peaks().front().second, largest);
}

// The sampling thread stops when told, by finish() or the destructor: a
// thread that missed the stop would hang here (under the test's timeout).
TEST(StepPeaks, FinishAndDestructionStopTheThread) {
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < 20; ++i) {
    StepPeaks memory;
    memory.start("a");
    memory.start("b");
    if (i % 2 == 0) memory.finish();  // else the destructor stops it
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_LT(seconds, 0.5) << "20 runs of two steps";
}

}  // namespace
}  // namespace recon
