// Floating-point traps: that they trap, in every thread; and, in a build with
// RECON_TRAP_FP, the switch that turns them on for every test of the suite.

#include "recon/core/fp_traps.h"
#include "recon/core/parallel.h"

#include <gtest/gtest.h>

#include <cmath>

namespace recon {
namespace {

#ifdef RECON_TRAP_FP
// Before the first test, so a NaN or an infinity born anywhere in the
// library stops the test where it is born (SIGFPE; a sanitizer build prints
// the stack).
class FpTrapsForEveryTest : public ::testing::Environment {
 public:
  void SetUp() override { ASSERT_TRUE(set_fp_traps(true)); }
};
const ::testing::Environment* const fp_traps_for_every_test =
    ::testing::AddGlobalTestEnvironment(new FpTrapsForEveryTest);
#endif

/// Sets the traps for a scope, and back as they were.
class FpTrapsSetTo {
 public:
  explicit FpTrapsSetTo(bool on) : before_(fp_traps_enabled()) { set_fp_traps(on); }
  ~FpTrapsSetTo() { set_fp_traps(before_); }
  FpTrapsSetTo(const FpTrapsSetTo&) = delete;
  FpTrapsSetTo& operator=(const FpTrapsSetTo&) = delete;

 private:
  bool before_;
};

/// Whether this platform can trap (setting the traps as they are tells).
bool traps_supported() { return set_fp_traps(fp_traps_enabled()); }

TEST(FpTraps, ReachEveryThreadOfTheParallelPhases) {
  if (!traps_supported()) GTEST_SKIP() << "no floating-point traps on this platform";
  const int threads = thread_count();
  set_thread_count(3);
  {
    const FpTrapsSetTo on(true);
    EXPECT_TRUE(fp_traps_enabled());
    set_thread_count(4);  // the pool grows after the traps are set: the new thread copies them
    EXPECT_TRUE(fp_traps_enabled());
    {
      const FpTrapsSetTo off(false);
      EXPECT_FALSE(fp_traps_enabled());
    }
    EXPECT_TRUE(fp_traps_enabled());
  }
  set_thread_count(threads);
}

TEST(FpTraps, ZeroOverZeroStopsTheProgram) {
  if (!traps_supported()) GTEST_SKIP() << "no floating-point traps on this platform";
  ::testing::FLAGS_gtest_death_test_style = "threadsafe";  // OpenMP's threads are running
  volatile double zero = 0.0;                              // volatile: divided at run time, not folded
  volatile double quotient = 1.0;
  EXPECT_DEATH(
      {
        set_fp_traps(true);
        quotient = zero / zero;
      },
      "");
  const FpTrapsSetTo off(false);
  quotient = zero / zero;
  EXPECT_TRUE(std::isnan(quotient));
}

}  // namespace
}  // namespace recon
