// Marching squares against analytic functions: signed distances to circles
// (whose zero sets are known exactly), bilinear saddles (where the
// asymptotic decider has one right answer), undefined regions, seams, and
// a random field that exercises every configuration.

#include "recon/phase4_contour/marching_squares.h"

#include "recon/core/errors.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <numbers>
#include <random>
#include <set>
#include <vector>

namespace recon {
namespace {

MarchingSquaresOptions with_cell(double cell) {
  MarchingSquaresOptions options;
  options.cell = cell;
  return options;
}

std::vector<Vec2> circle_seeds(const Vec2& centre, double radius, int count) {
  std::vector<Vec2> seeds;
  for (int i = 0; i < count; ++i) {
    const double t = 2.0 * std::numbers::pi * i / count;
    seeds.push_back(centre + radius * Vec2(std::cos(t), std::sin(t)));
  }
  return seeds;
}

// Every vertex is used by exactly one polyline, once; polylines have at
// least two vertices; consecutive vertices are at most a square's diagonal
// apart (a segment never leaves its square).
void expect_well_formed(const MarchingSquaresResult& r) {
  const PolylineSet& curves = r.curves;
  std::vector<int> uses(curves.vertices.size(), 0);
  for (const Polyline& line : curves.polylines) {
    EXPECT_GE(line.vertices.size(), 2U);
    for (std::size_t j = 0; j < line.vertices.size(); ++j) {
      ASSERT_LT(line.vertices[j], curves.vertices.size());
      ++uses[line.vertices[j]];
      const bool has_next = j + 1 < line.vertices.size() || line.closed;
      if (!has_next) continue;
      const Vec2& a = curves.vertices[line.vertices[j]];
      const Vec2& b = curves.vertices[line.vertices[(j + 1) % line.vertices.size()]];
      EXPECT_LE((b - a).norm(), std::sqrt(2.0) * r.cell * (1.0 + 1e-12));
    }
  }
  for (std::size_t v = 0; v < uses.size(); ++v) EXPECT_EQ(uses[v], 1) << "vertex " << v;
}

// A vertex is where f's linear interpolation along a lattice side vanishes.
// For f = |p - c| - r, f's second derivative along any line is at most
// 1 / |p - c|, so the interpolant misses f by at most h^2 / (8 (r - h))
// within a square of side h of the circle; |f| is exactly the distance to
// the circle. The clamp keeping vertices 1/1000 of a side off the corners
// can add 1e-3 h.
double circle_vertex_tolerance(double radius, double h) { return h * h / (8.0 * (radius - h)) + 1e-3 * h; }

TEST(MarchingSquares, CircleIsOneClosedCounterClockwiseCurveOnTheCircle) {
  const Vec2 centre(0.3, -0.7);
  const double radius = 1.25, h = 0.05;
  auto f = [&](const Vec2& p) -> std::optional<double> { return (p - centre).norm() - radius; };
  const MarchingSquaresResult r = marching_squares(f, circle_seeds(centre, radius, 40), with_cell(h));
  ASSERT_EQ(r.curves.polylines.size(), 1U);
  const Polyline& line = r.curves.polylines[0];
  EXPECT_TRUE(line.closed);
  expect_well_formed(r);
  const double tolerance = circle_vertex_tolerance(radius, h);
  for (const Vec2& v : r.curves.vertices) EXPECT_LE(std::abs((v - centre).norm() - radius), tolerance);
  // Inside (f < 0) on the left: counter-clockwise, enclosing about pi r^2.
  // A polygon inscribed with chords of at most sqrt(2) h misses the disc
  // by the chords' segments, about (sqrt(2) h)^2 / (6 r^2) of its area
  // (0.05 % here), and the vertices' offsets above add at most twice the
  // tolerance over r (0.04 %): 0.2 % holds with room.
  const double area = signed_area(r.curves, line);
  EXPECT_NEAR(area, std::numbers::pi * radius * radius, 2e-3 * std::numbers::pi * radius * radius);
  EXPECT_EQ(r.undefined_squares, 0U);
  EXPECT_EQ(r.saddle_squares, 0U);
  // Only squares near the curve are visited: the ring of width ~2 h around
  // the circle, far fewer than the lattice's squares.
  EXPECT_LT(static_cast<double>(r.visited_squares), 4.0 * 2.0 * std::numbers::pi * radius / h);
  EXPECT_GT(static_cast<double>(r.size[0]) * r.size[1], 4.0 * static_cast<double>(r.visited_squares));
}

TEST(MarchingSquares, VerticesAreSharedBetweenNeighbouringSquares) {
  const double radius = 1.0, h = 0.1;
  auto f = [&](const Vec2& p) -> std::optional<double> { return p.norm() - radius; };
  const MarchingSquaresResult r = marching_squares(f, circle_seeds(Vec2::Zero(), radius, 20), with_cell(h));
  ASSERT_EQ(r.curves.polylines.size(), 1U);
  // A closed chain of n segments has n vertices, each shared by two
  // squares: no vertex is duplicated.
  EXPECT_EQ(r.curves.polylines[0].vertices.size(), r.curves.vertices.size());
  std::set<std::pair<double, double>> distinct;
  for (const Vec2& v : r.curves.vertices) distinct.insert({v.x(), v.y()});
  EXPECT_EQ(distinct.size(), r.curves.vertices.size());
}

TEST(MarchingSquares, AnnulusGivesTwoLoopsOfOppositeTurn) {
  // Inside = the ring between radii 0.5 and 1: the outer loop turns
  // counter-clockwise, the inner one (around a hole) clockwise.
  auto f = [](const Vec2& p) -> std::optional<double> { return std::max(p.norm() - 1.0, 0.5 - p.norm()); };
  std::vector<Vec2> seeds = circle_seeds(Vec2::Zero(), 1.0, 30);
  for (const Vec2& p : circle_seeds(Vec2::Zero(), 0.5, 15)) seeds.push_back(p);
  const MarchingSquaresResult r = marching_squares(f, seeds, with_cell(0.04));
  ASSERT_EQ(r.curves.polylines.size(), 2U);
  expect_well_formed(r);
  std::vector<double> areas;
  for (const Polyline& line : r.curves.polylines) {
    EXPECT_TRUE(line.closed);
    areas.push_back(signed_area(r.curves, line));
  }
  std::sort(areas.begin(), areas.end());
  EXPECT_NEAR(areas[0], -std::numbers::pi * 0.25, 0.01);
  EXPECT_NEAR(areas[1], std::numbers::pi, 0.01);
}

// f = (x - x0)(y - y0) + c is bilinear, so along every lattice side it is
// linear and the vertices lie exactly on its zero set. With the saddle
// (x0, y0) at the centre of a square, that square's corners have the
// diagonal sign pattern, and the bilinear saddle value is exactly c: the
// decider must join the inside corners when c < 0 and cut them apart when
// c > 0, which is what the hyperbola's branches do.
TEST(MarchingSquares, SaddleSquaresFollowTheBilinearInterpolant) {
  const double h = 0.1;
  for (const double c : {-1e-3, 1e-3}) {
    SCOPED_TRACE("c = " + std::to_string(c));
    // One seed: the lattice origin sits lattice_margin squares below it,
    // so the seed's square has its centre at seed - (frac(margin) - 0.5) h.
    const Vec2 seed(0.0, 0.0);
    const MarchingSquaresResult probe =
        marching_squares([](const Vec2&) -> std::optional<double> { return 1.0; }, std::span(&seed, 1), with_cell(h));
    const Vec2 corner = probe.origin + h * Vec2(std::floor((seed.x() - probe.origin.x()) / h),
                                                std::floor((seed.y() - probe.origin.y()) / h));
    const Vec2 saddle = corner + Vec2(0.5 * h, 0.5 * h);
    auto f = [&](const Vec2& p) -> std::optional<double> { return (p.x() - saddle.x()) * (p.y() - saddle.y()) + c; };
    const MarchingSquaresResult r = marching_squares(f, std::span(&seed, 1), with_cell(h));
    EXPECT_EQ(r.saddle_squares, 1U);
    expect_well_formed(r);
    // Two branches, each ending at the lattice's edge (open).
    ASSERT_EQ(r.curves.polylines.size(), 2U);
    for (const Polyline& line : r.curves.polylines) {
      EXPECT_FALSE(line.closed);
      // Each branch stays in one pair of opposite quadrants of the saddle:
      // (x - x0)(y - y0) = -c has the sign of -c on the whole zero set.
      for (const std::uint32_t v : line.vertices) {
        const Vec2 d = r.curves.vertices[v] - saddle;
        EXPECT_NEAR(d.x() * d.y(), -c, 1e-12);
      }
      // ...and on one side of the saddle: a branch does not cross from one
      // quadrant to the opposite one.
      const Vec2 first = r.curves.vertices[line.vertices.front()] - saddle;
      for (const std::uint32_t v : line.vertices) {
        const Vec2 d = r.curves.vertices[v] - saddle;
        EXPECT_GT(d.x() * first.x(), 0.0);
      }
    }
  }
}

TEST(MarchingSquares, RandomFieldGivesWellFormedChainsWithEveryConfiguration) {
  // Values at lattice corners from a seeded table: every one of the 16
  // configurations occurs, saddles both ways. Curves close or end at the
  // lattice's edge; nothing else may happen.
  std::mt19937_64 random(11);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  std::map<std::pair<long, long>, double> table;
  const double h = 1.0;
  auto f = [&](const Vec2& p) -> std::optional<double> {
    const std::pair<long, long> key{std::lround(p.x() * 8.0), std::lround(p.y() * 8.0)};
    auto [at, inserted] = table.try_emplace(key, 0.0);
    if (inserted) at->second = value(random);
    return at->second;
  };
  std::vector<Vec2> seeds;
  for (int i = 0; i < 40; ++i) seeds.emplace_back(i * 0.5, (i % 7) * 0.7);
  const MarchingSquaresResult r = marching_squares(f, seeds, with_cell(h));
  EXPECT_GT(r.saddle_squares, 5U);
  expect_well_formed(r);
  auto on_lattice_edge = [&](const Vec2& v) {
    const Vec2 low = r.origin, high = r.origin + h * Vec2(r.size[0], r.size[1]);
    const double eps = 1e-9;
    return std::abs(v.x() - low.x()) < eps || std::abs(v.y() - low.y()) < eps || std::abs(v.x() - high.x()) < eps ||
           std::abs(v.y() - high.y()) < eps;
  };
  for (const Polyline& line : r.curves.polylines) {
    if (line.closed) continue;
    EXPECT_TRUE(on_lattice_edge(r.curves.vertices[line.vertices.front()]));
    EXPECT_TRUE(on_lattice_edge(r.curves.vertices[line.vertices.back()]));
  }
}

TEST(MarchingSquares, UndefinedCornersLeaveTheCurveOpen) {
  // The unit circle with f undefined right of x = 0.5: one open arc, whose
  // ends lie within a square of the undefined region.
  const double h = 0.05;
  auto f = [](const Vec2& p) -> std::optional<double> {
    if (p.x() > 0.5) return std::nullopt;
    return p.norm() - 1.0;
  };
  const MarchingSquaresResult r = marching_squares(f, circle_seeds(Vec2::Zero(), 1.0, 40), with_cell(h));
  ASSERT_EQ(r.curves.polylines.size(), 1U);
  const Polyline& line = r.curves.polylines[0];
  EXPECT_FALSE(line.closed);
  EXPECT_GT(r.undefined_squares, 0U);
  expect_well_formed(r);
  for (const Vec2& v : r.curves.vertices) {
    EXPECT_LE(v.x(), 0.5);
    EXPECT_LE(std::abs(v.norm() - 1.0), circle_vertex_tolerance(1.0, h));
  }
  for (const std::uint32_t end : {line.vertices.front(), line.vertices.back()})
    EXPECT_GT(r.curves.vertices[end].x(), 0.5 - 2.0 * h);
  // The arc (x <= 0.5) runs counter-clockwise: from its upper end round
  // the left to its lower end.
  EXPECT_GT(r.curves.vertices[line.vertices.front()].y(), 0.0);
  EXPECT_LT(r.curves.vertices[line.vertices.back()].y(), 0.0);
}

TEST(MarchingSquares, SeamTestDropsJumpsButKeepsTrueCrossings) {
  // f is a true distance (slope 1) below y = 0 and jumps from -1 to +1
  // across the line x = 0.23 above it: a seam, as between the ends of a gap.
  auto f = [](const Vec2& p) -> std::optional<double> {
    if (p.y() < 0.0) return p.x() - 0.23;
    return p.x() < 0.23 ? -1.0 : 1.0;
  };
  const std::vector<Vec2> seeds{Vec2(0.23, -0.5), Vec2(0.23, 0.5)};
  const MarchingSquaresResult without = marching_squares(f, seeds, with_cell(0.1));
  MarchingSquaresOptions options = with_cell(0.1);
  options.max_slope = 2.0;
  const MarchingSquaresResult with = marching_squares(f, seeds, options);
  EXPECT_EQ(without.seam_squares, 0U);
  EXPECT_GT(with.seam_squares, 0U);
  double highest_without = -1e9, highest_with = -1e9;
  for (const Vec2& v : without.curves.vertices) highest_without = std::max(highest_without, v.y());
  for (const Vec2& v : with.curves.vertices) highest_with = std::max(highest_with, v.y());
  EXPECT_GT(highest_without, 0.5);  // the seam is drawn as a curve...
  EXPECT_LT(highest_with, 0.1);     // ...unless the test drops it
  ASSERT_FALSE(with.curves.polylines.empty());
  for (const Vec2& v : with.curves.vertices) EXPECT_NEAR(v.x(), 0.23, 1e-9);
}

TEST(MarchingSquares, KeepsCornersAndSquaresWhenAsked) {
  auto f = [](const Vec2& p) -> std::optional<double> {
    if (p.x() > 0.8) return std::nullopt;
    return p.norm() - 1.0;
  };
  const std::vector<Vec2> seeds = circle_seeds(Vec2::Zero(), 1.0, 24);
  MarchingSquaresOptions options = with_cell(0.1);
  options.keep_corners = true;
  const MarchingSquaresResult r = marching_squares(f, seeds, options);
  EXPECT_EQ(r.corners.size(), r.evaluated_corners);
  EXPECT_EQ(r.squares.size(), r.visited_squares);
  std::size_t undefined = 0;
  for (const SquareCorner& c : r.corners) {
    const Vec2 p = r.origin + 0.1 * Vec2(c.index[0], c.index[1]);
    const std::optional<double> expected = f(p);
    EXPECT_EQ(c.defined, expected.has_value());
    if (expected) {
      EXPECT_DOUBLE_EQ(c.value, *expected);
    }
    undefined += c.defined ? 0 : 1;
  }
  EXPECT_EQ(undefined, r.undefined_corners);
  EXPECT_GT(undefined, 0U);
}

TEST(MarchingSquares, RefusesBadCellsAndOverlongWalks) {
  auto f = [](const Vec2& p) -> std::optional<double> { return p.norm() - 1.0; };
  const std::vector<Vec2> seeds = circle_seeds(Vec2::Zero(), 1.0, 8);
  for (const double cell :
       {0.0, -1.0, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()})
    EXPECT_THROW((void)marching_squares(f, seeds, with_cell(cell)), InvalidInputError) << cell;
  EXPECT_THROW(
      (void)marching_squares(f, seeds, {.cell = 0.001, .max_slope = 0.0, .max_squares = 100, .keep_corners = false}),
      ResourceLimitError);
  EXPECT_THROW((void)marching_squares(f, seeds, with_cell(1e-12)), ResourceLimitError);
  EXPECT_TRUE(marching_squares(f, {}, with_cell(0.1)).curves.polylines.empty());
}

}  // namespace
}  // namespace recon
