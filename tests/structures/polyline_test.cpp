// Polylines (polyline.h): counts of closed and open lines, length with and
// without the closing segment, and the shoelace area's sign and precision.

#include "recon/structures/polyline.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

namespace recon {
namespace {

// The unit square's corners, counter-clockwise, as one set of vertices.
PolylineSet unit_square() {
  PolylineSet set;
  set.vertices = {Vec2(0, 0), Vec2(1, 0), Vec2(1, 1), Vec2(0, 1)};
  return set;
}

TEST(Polyline, CountsClosedAndOpenLines) {
  PolylineSet set = unit_square();
  EXPECT_EQ(set.closed_count(), 0u);
  EXPECT_EQ(set.open_count(), 0u);
  set.polylines = {{{0, 1, 2, 3}, true}, {{0, 1}, false}, {{2, 3, 0}, true}, {{}, false}};
  EXPECT_EQ(set.closed_count(), 2u);
  EXPECT_EQ(set.open_count(), 2u);
}

TEST(Polyline, LengthAddsTheClosingSegmentOnlyWhenClosed) {
  const PolylineSet set = unit_square();
  EXPECT_DOUBLE_EQ(length(set, {{0, 1, 2, 3}, false}), 3.0);
  EXPECT_DOUBLE_EQ(length(set, {{0, 1, 2, 3}, true}), 4.0);
  EXPECT_DOUBLE_EQ(length(set, {{0, 2}, false}), std::numbers::sqrt2);
  EXPECT_DOUBLE_EQ(length(set, {{0, 2}, true}), 2.0 * std::numbers::sqrt2);  // there and back
  EXPECT_EQ(length(set, {{3}, true}), 0.0);
  EXPECT_EQ(length(set, {{}, true}), 0.0);
}

TEST(Polyline, SignedAreaIsPositiveCounterClockwiseAndZeroWhenOpen) {
  const PolylineSet set = unit_square();
  EXPECT_DOUBLE_EQ(signed_area(set, {{0, 1, 2, 3}, true}), 1.0);
  EXPECT_DOUBLE_EQ(signed_area(set, {{3, 2, 1, 0}, true}), -1.0);  // clockwise: around a hole
  EXPECT_DOUBLE_EQ(signed_area(set, {{1, 2, 3, 0}, true}), 1.0);   // any starting vertex
  EXPECT_DOUBLE_EQ(signed_area(set, {{0, 1, 2}, true}), 0.5);
  EXPECT_EQ(signed_area(set, {{0, 1, 2, 3}, false}), 0.0);
  EXPECT_EQ(signed_area(set, {{}, true}), 0.0);
}

// A regular polygon's area (n/2 sin(2 pi / n) r^2) and perimeter (2 n r
// sin(pi / n)), also far from the origin, where raw coordinates would
// cancel away the area's digits.
TEST(Polyline, RegularPolygonsFarFromTheOriginKeepTheirArea) {
  std::mt19937 rng(16);
  std::uniform_real_distribution<double> far(-1e6, 1e6);
  for (const int n : {3, 7, 100}) {
    for (int trial = 0; trial < 5; ++trial) {
      const Vec2 centre = trial == 0 ? Vec2::Zero() : Vec2(far(rng), far(rng));
      const double r = 0.01;
      PolylineSet set;
      Polyline line{{}, true};
      for (int i = 0; i < n; ++i) {
        const double angle = 2.0 * std::numbers::pi * i / n;
        set.vertices.push_back(centre + r * Vec2(std::cos(angle), std::sin(angle)));
        line.vertices.push_back(static_cast<std::uint32_t>(i));
      }
      const double area = 0.5 * n * std::sin(2.0 * std::numbers::pi / n) * r * r;
      EXPECT_NEAR(signed_area(set, line), area, 1e-6 * area) << n << " at " << centre.transpose();
      EXPECT_NEAR(length(set, line), 2.0 * n * r * std::sin(std::numbers::pi / n), 1e-6 * r) << n;
    }
  }
}

}  // namespace
}  // namespace recon
