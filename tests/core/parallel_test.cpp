// set_thread_count's bound (parallel.h): a thread count past the machine is
// refused before any thread starts (70000 crashed inside libgomp).

#include "recon/core/parallel.h"

#include "recon/core/errors.h"

#include <gtest/gtest.h>

#include <string>

namespace recon {
namespace {

TEST(ThreadCount, PastTheBoundIsRefusedAndTheCountKept) {
  const int before = thread_count();
  const int most = max_thread_count();
  EXPECT_GE(most, 64);
  EXPECT_LE(most, 4096);
  for (const int n : {most + 1, 70000, 2147483647}) {
    try {
      set_thread_count(n);
      ADD_FAILURE() << n << " threads accepted";
    } catch (const InvalidInputError& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find("a thread count of " + std::to_string(n)), std::string::npos) << message;
      EXPECT_NE(message.find("at most " + std::to_string(most)), std::string::npos) << message;
    }
    EXPECT_EQ(thread_count(), before);
  }
#ifdef _OPENMP
  set_thread_count(most);  // the bound itself is accepted (no thread starts until a parallel loop)
  EXPECT_EQ(thread_count(), most);
#endif
  set_thread_count(before);
}

}  // namespace
}  // namespace recon
