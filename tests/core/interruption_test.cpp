// interruption.h: the check runs on the thread that installed it, at points
// inside the phases (not only between them), and a throwing check stops a
// run cleanly.

#include "recon/core/interruption.h"

#include "recon/core/shapes.h"
#include "recon/reconstruct.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace recon {
namespace {

struct Stopped : std::runtime_error {
  Stopped() : std::runtime_error("stopped") {}
};

TEST(Interruption, NothingHappensWithoutACheck) { interruption_point(); }

TEST(Interruption, TheCheckRunsOnItsOwnThreadOnlyAndUntilItsScopeEnds) {
  int calls = 0;
  {
    InterruptionCheck check([&calls] { ++calls; });
    interruption_point();
    std::thread other([] { interruption_point(); });
    other.join();
    {
      int inner = 0;
      InterruptionCheck nested([&inner] { ++inner; });
      interruption_point();
      EXPECT_EQ(inner, 1);
    }
    interruption_point();  // the outer check is back
  }
  interruption_point();
  EXPECT_EQ(calls, 2);
}

TEST(Interruption, AReconstructionIsCheckedWithinItsPhases) {
  const PointCloud cloud = make_shape("sphere")->sample(200000, 5);
  std::vector<std::string> phases;
  int calls = 0;
  ReconstructionOptions options;
  options.on_phase = [&phases](const char* phase) { phases.emplace_back(phase); };
  InterruptionCheck check([&calls] { ++calls; });
  const Reconstruction r = reconstruct(cloud, options);
  // Between the steps of phases I, II, IV and V, in Prim's loop and per
  // batch of cubes: more points than phases.
  EXPECT_GT(calls, static_cast<int>(phases.size()) + 4);
  EXPECT_GT(r.mesh().triangles.size(), 0U);
}

TEST(Interruption, AThrowingCheckStopsTheRunAtEachPoint) {
  const PointCloud cloud = make_shape("torus")->sample(100000, 6);
  int points = 0;
  {
    InterruptionCheck count([&points] { ++points; });
    static_cast<void>(reconstruct(cloud));
  }
  ASSERT_GT(points, 0);
  // Stop at each point in turn: the run ends with the check's exception
  // (through the helper thread beside Prim too), and a run afterwards is
  // whole and the same.
  const Mesh whole = reconstruct(cloud).mesh();
  for (int stop_at = 1; stop_at <= points; ++stop_at) {
    int seen = 0;
    InterruptionCheck check([&seen, stop_at] {
      if (++seen == stop_at) throw Stopped();
    });
    EXPECT_THROW(static_cast<void>(reconstruct(cloud)), Stopped) << "point " << stop_at << " of " << points;
  }
  EXPECT_EQ(reconstruct(cloud).mesh().vertices, whole.vertices);
}

}  // namespace
}  // namespace recon
