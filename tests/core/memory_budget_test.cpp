#include "recon/core/memory_budget.h"

#include "recon/core/errors.h"
#include "recon/core/resource_usage.h"

#include <gtest/gtest.h>

#include <string>

namespace recon {
namespace {

TEST(MemoryBudget, EstimatesGrowWithPointsNeighboursAndFits) {
  const double base = estimated_bytes_planes_and_graph(1'000'000, 20);
  EXPECT_DOUBLE_EQ(estimated_bytes_planes_and_graph(2'000'000, 20), 2.0 * base);  // per point
  EXPECT_GT(estimated_bytes_planes_and_graph(1'000'000, 40), base);
  EXPECT_GT(estimated_bytes_planes_and_graph(1'000'000, 20, true), base);
  EXPECT_EQ(estimated_bytes_planes_and_graph(0, 20), 0.0);
  // Measured: a million points at k = 20 peak near 350 MB in phase II; the
  // estimate is an upper one, but not wildly so.
  EXPECT_GT(base, 350e6);
  EXPECT_LT(base, 500e6);
  EXPECT_GT(estimated_bytes_lattice(1'000'000, 2e6), estimated_bytes_lattice(1'000'000, 1e6));
}

// The walks' limits are the largest counts the estimates allow.
TEST(MemoryBudget, WalkLimitsAreTheLargestThatFit) {
  const std::size_t limit = 2'000'000'000, points = 1'000'000;
  const std::size_t cubes = max_cubes_within(limit, points);
  EXPECT_LE(estimated_bytes_lattice(points, static_cast<double>(cubes)), static_cast<double>(limit));
  EXPECT_GT(estimated_bytes_lattice(points, static_cast<double>(cubes + 1)), static_cast<double>(limit));
  EXPECT_EQ(max_cubes_within(1000, points), 0u);  // the points alone exceed it
  EXPECT_GT(max_squares_within(limit), 0u);
  EXPECT_LT(max_squares_within(limit), max_squares_within(2 * limit));
}

TEST(MemoryBudget, RefusalSaysWhatWhyAndWhatToChange) {
  EXPECT_NO_THROW(check_memory(1e6, 2'000'000, "a thing", "do less"));
  try {
    check_memory(3e9, 1'000'000'000, "a lattice", "use a larger --cell");
    FAIL() << "not refused";
  } catch (const ResourceLimitError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("a lattice would need about 3 GB"), std::string::npos) << message;
    EXPECT_NE(message.find("more than the 1 GB allowed (--max-memory"), std::string::npos) << message;
    EXPECT_NE(message.find("use a larger --cell, or raise --max-memory"), std::string::npos) << message;
  }
  EXPECT_THROW(check_memory_planes_and_graph(100'000'000, 20, 1'000'000'000), ResourceLimitError);
  EXPECT_NO_THROW(check_memory_planes_and_graph(1000, 20, 1'000'000'000));
}

TEST(MemoryBudget, NoLimitMeansTheDefault) {
  EXPECT_EQ(memory_limit_or_default(0), default_memory_limit());
  EXPECT_EQ(memory_limit_or_default(12345), 12345u);
}

// A tiled run's statistics sample drawn within --max-memory: too few points
// for phase I is the memory limit's fault, and the message says so with the
// figures (it said "only 0 points; k = 20 needs at least 21").
TEST(MemoryBudget, StatisticsSampleTooSmallForPhaseOneBlamesTheLimit) {
  EXPECT_NO_THROW(check_statistics_sample(21, 265, 300'000, 20, 1'000'000));  // k + 1 drawn
  EXPECT_NO_THROW(check_statistics_sample(10, 265, 10, 20, 1'000'000));       // the whole cloud: phase I says lower k
  try {
    check_statistics_sample(0, 2127, 300'000, 20, 8'000'000);
    FAIL() << "not refused";
  } catch (const ResourceLimitError& e) {
    const std::string message = e.what();
    for (const char* part : {"the memory limit is too small for the cloud-wide statistics of a tiled run",
                             "the 8 MB allowed (--max-memory) hold a sample of 2127 of the 300000 points",
                             "0 drawn, and phase I needs at least 21 (k + 1 with k = 20); raise --max-memory"})
      EXPECT_NE(message.find(part), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace recon
