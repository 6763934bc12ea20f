// progress.h: the counter a run advances and a display reads. A
// reconstruction ends every phase with done <= total, counts in every phase
// that announces a total, and gives the same mesh with a counter as without.

#include "recon/core/progress.h"

#include "recon/core/shapes.h"
#include "recon/estimate_normals.h"
#include "recon/reconstruct.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <functional>
#include <string>
#include <thread>
#include <vector>

namespace recon {
namespace {

TEST(Progress, StartResetsTheCountAndExpectRaisesTheTotal) {
  ProgressCounter counter;
  counter.start(100);
  counter.advance(30);
  counter.expect(50);
  EXPECT_EQ(counter.done.load(), 30u);
  EXPECT_EQ(counter.total.load(), 150u);
  counter.start(7);
  EXPECT_EQ(counter.done.load(), 0u);
  EXPECT_EQ(counter.total.load(), 7u);
}

TEST(Progress, AnEstimatedTotalIsNeverReached) {
  ProgressCounter counter;
  counter.start(1000);
  counter.advance_estimated(500);
  EXPECT_EQ(counter.done.load(), 500u);
  counter.advance_estimated(800);  // past the estimate: held at 99%
  EXPECT_EQ(counter.done.load(), 990u);
  counter.advance_estimated(1);
  EXPECT_EQ(counter.done.load(), 990u);
  counter.start(50);  // small totals too: 99% of 50, rounded down
  counter.advance_estimated(60);
  EXPECT_EQ(counter.done.load(), 49u);
  counter.start(0);
  counter.advance_estimated(3);
  EXPECT_EQ(counter.done.load(), 0u);
}

TEST(Progress, TheCounterIsInstalledOnItsOwnThreadOnlyAndUntilItsScopeEnds) {
  EXPECT_EQ(progress_counter(), nullptr);
  ProgressCounter outer, inner;
  {
    ProgressScope scope(&outer);
    EXPECT_EQ(progress_counter(), &outer);
    ProgressCounter* seen_elsewhere = &inner;
    std::thread other([&seen_elsewhere] { seen_elsewhere = progress_counter(); });
    other.join();
    EXPECT_EQ(seen_elsewhere, nullptr);
    {
      ProgressScope nested(&inner);
      EXPECT_EQ(progress_counter(), &inner);
    }
    EXPECT_EQ(progress_counter(), &outer);
  }
  EXPECT_EQ(progress_counter(), nullptr);
}

// What a counter held as each phase ended (on_phase runs just before the
// counter is started for the next phase; the last phase is read after the run).
struct PhaseCount {
  std::string phase;
  std::uint64_t done = 0, total = 0;
};

std::vector<PhaseCount> counted_phases(std::function<void(ProgressCounter&, std::function<void(const char*)>)> run) {
  ProgressCounter counter;
  std::vector<PhaseCount> phases;
  auto record = [&](const char* phase) {
    if (!phases.empty()) phases.back() = {phases.back().phase, counter.done.load(), counter.total.load()};
    phases.push_back({phase, 0, 0});
  };
  run(counter, record);
  if (!phases.empty()) phases.back() = {phases.back().phase, counter.done.load(), counter.total.load()};
  return phases;
}

void expect_each_phase_counted(const std::vector<PhaseCount>& phases, const std::vector<std::string>& uncounted) {
  ASSERT_FALSE(phases.empty());
  for (const PhaseCount& p : phases) {
    SCOPED_TRACE(p.phase);
    EXPECT_LE(p.done, p.total);
    if (std::find(uncounted.begin(), uncounted.end(), p.phase) != uncounted.end()) {
      EXPECT_EQ(p.total, 0u);
    } else {
      EXPECT_GT(p.done, 0u);
      EXPECT_GE(p.done, p.total / 2) << "most of the announced work is counted";
    }
  }
}

TEST(Progress, AReconstructionCountsEveryPhaseWithinItsTotal) {
  const PointCloud cloud = make_shape("sphere")->sample(40000, 3);
  for (const Method method : {Method::refined, Method::hoppe92}) {
    SCOPED_TRACE(method_name(method));
    Reconstruction r;
    const auto phases = counted_phases([&](ProgressCounter& counter, std::function<void(const char*)> record) {
      ReconstructionOptions options;
      options.method = method;
      options.progress = &counter;
      options.on_phase = std::move(record);
      r = reconstruct(cloud, options);
    });
    EXPECT_EQ(phases.size(), method == Method::refined ? 5u : 4u);
    expect_each_phase_counted(phases, {"signed distance"});
    // The walk's total is an estimate; the count stops short of it.
    EXPECT_EQ(phases[3].phase, "contouring");
    EXPECT_LE(phases[3].done, phases[3].total - phases[3].total / 100);
  }
}

TEST(Progress, PhaseIFittingAgainAtARaisedKRaisesItsTotal) {
  PointCloud cloud = make_shape("sphere")->sample(40000, 4);
  add_noise(cloud, 0.003, 5);
  Reconstruction r;
  const auto phases = counted_phases([&](ProgressCounter& counter, std::function<void(const char*)> record) {
    ReconstructionOptions options;
    options.progress = &counter;
    options.on_phase = std::move(record);
    r = reconstruct(cloud, options);
  });
  ASSERT_GT(r.planes.k, r.planes.k_requested);  // the case in question
  ASSERT_EQ(phases[0].phase, "tangent planes");
  EXPECT_EQ(phases[0].total, 3 * cloud.size());  // planes twice, then the fits
  expect_each_phase_counted(phases, {"signed distance"});
}

TEST(Progress, NormalEstimationCountsBothPhases) {
  const PointCloud cloud = make_shape("torus")->sample(30000, 6);
  const auto phases = counted_phases([&](ProgressCounter& counter, std::function<void(const char*)> record) {
    NormalEstimationOptions options;
    options.progress = &counter;
    options.on_phase = std::move(record);
    (void)estimate_normals(cloud, options);
  });
  ASSERT_EQ(phases.size(), 2u);
  expect_each_phase_counted(phases, {});
}

TEST(Progress, CountingDoesNotChangeTheMesh) {
  const PointCloud cloud = make_shape("torus")->sample(50000, 7);
  ProgressCounter counter;
  ReconstructionOptions counted;
  counted.progress = &counter;
  const Reconstruction with = reconstruct(cloud, counted);
  const Reconstruction without = reconstruct(cloud);
  EXPECT_GT(counter.done.load(), 0u);
  EXPECT_TRUE(with.mesh().vertices == without.mesh().vertices);
  EXPECT_TRUE(with.mesh().triangles == without.mesh().triangles);
  EXPECT_GT(with.mesh().triangles.size(), 10000u);
}

}  // namespace
}  // namespace recon
