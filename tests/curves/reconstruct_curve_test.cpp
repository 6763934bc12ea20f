// Curves from points in the plane, end to end (phases I to IV in 2D),
// against the true curves the points were sampled from.
//
// Samples are stratified along the curve (one random point in each of n
// equal parameter intervals, seeded): the data is then rho-dense, the
// condition under which Hoppe's method promises a faithful curve. Purely
// random samples leave gaps several spacings wide, which the method
// rightly leaves open.
//
// The distance bound. A vertex of the result lies on the zero set of f,
// which, near the data, is made of pieces of the tangent lines (each line
// within the region where its origin is the nearest), joined by marching
// squares' linear interpolation. A tangent line is fitted to a
// neighbourhood of radius R on a curve of radius of curvature at least
// r_min: the arc it fits lies within its sagitta R^2 / (2 r_min) of any
// chord, and the least-squares line lies between the arc's extremes, so
// the line is within R^2 / (2 r_min) of the curve over the neighbourhood.
// Interpolating f linearly over a square side of length h adds h^2 / (8
// r_min) (f's second derivative is at most 1 / r_min) and the clamp
// keeping vertices off the corners 1e-3 h. So
//   bound = R_max^2 / (2 r_min) + h^2 / (8 r_min) + 1e-3 h,
// R_max the largest neighbourhood radius phase I found.

#include "recon/curves/reconstruct_curve.h"

#include "recon/core/errors.h"
#include "test_data.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace recon {
namespace {

using Curve = std::function<Vec2(double)>;  // t in [0, 1) -> point

std::vector<Vec2> stratified(const Curve& curve, int n, std::uint64_t seed, double from = 0.0, double to = 1.0) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Vec2> points;
  for (int i = 0; i < n; ++i) points.push_back(curve(from + (to - from) * (i + unit(random)) / n));
  return points;
}

Curve circle(const Vec2& centre, double radius) {
  return [=](double t) {
    const double a = 2.0 * std::numbers::pi * t;
    return Vec2(centre + radius * Vec2(std::cos(a), std::sin(a)));
  };
}

double largest_radius(const CurveReconstruction& r) {
  return static_cast<double>(*std::max_element(r.planes.radius.begin(), r.planes.radius.end()));
}

double distance_bound(const CurveReconstruction& r, double r_min) {
  const double big_r = largest_radius(r), h = r.contour.cell;
  return big_r * big_r / (2.0 * r_min) + h * h / (8.0 * r_min) + 1e-3 * h;
}

// Distance from p to the ellipse x^2/a^2 + y^2/b^2 = 1: a dense scan of the
// parameter, then golden-section search around the best sample.
double distance_to_ellipse(const Vec2& p, double a, double b) {
  auto d = [&](double t) { return (p - Vec2(a * std::cos(t), b * std::sin(t))).norm(); };
  constexpr int samples = 2048;
  const double step = 2.0 * std::numbers::pi / samples;
  double best_t = 0.0;
  for (int i = 1; i < samples; ++i)
    if (d(i * step) < d(best_t)) best_t = i * step;
  double lo = best_t - step, hi = best_t + step;
  const double g = (std::sqrt(5.0) - 1.0) / 2.0;
  for (int i = 0; i < 100; ++i) {
    const double m1 = hi - g * (hi - lo), m2 = lo + g * (hi - lo);
    if (d(m1) < d(m2))
      hi = m2;
    else
      lo = m1;
  }
  return d(0.5 * (lo + hi));
}

// Distance from p to the segment ab.
double distance_to_segment(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double t = ab.squaredNorm() > 0.0 ? std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

// Distance from p to the nearest point of the result's curves.
double distance_to_curves(const Vec2& p, const PolylineSet& curves) {
  double best = std::numeric_limits<double>::infinity();
  for (const Polyline& line : curves.polylines) {
    const std::size_t n = line.vertices.size();
    for (std::size_t j = 0; j + (line.closed ? 0 : 1) < n; ++j)
      best = std::min(
          best, distance_to_segment(p, curves.vertices[line.vertices[j]], curves.vertices[line.vertices[(j + 1) % n]]));
  }
  return best;
}

TEST(ReconstructCurve, CircleIsOneClosedCurveNearTheCircle) {
  for (const std::uint64_t seed : {1u, 2u, 3u}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const std::vector<Vec2> points = stratified(circle(Vec2::Zero(), 1.0), 200, seed);
    const CurveReconstruction r = reconstruct_curve(points);
    const PolylineSet& curves = r.contour.curves;
    ASSERT_EQ(curves.polylines.size(), 1U);
    EXPECT_TRUE(curves.polylines[0].closed);
    const double bound = distance_bound(r, 1.0);
    double worst = 0.0;
    for (const Vec2& v : curves.vertices) worst = std::max(worst, std::abs(v.norm() - 1.0));
    EXPECT_LE(worst, bound);
    // Outward normals: the curve turns counter-clockwise around the disc.
    EXPECT_NEAR(signed_area(curves, curves.polylines[0]), std::numbers::pi, 2.0 * std::numbers::pi * bound);
    // And it is all there: every sample is close to it.
    for (const Vec2& p : points) EXPECT_LE(distance_to_curves(p, curves), bound + r.contour.cell);
    // Every phase's result is kept: a plane and an oriented unit normal
    // per point, the spanning tree, the lattice statistics.
    EXPECT_EQ(r.planes.origins.size(), points.size());
    ASSERT_EQ(r.oriented.normals.size(), points.size());
    for (std::size_t i = 0; i < points.size(); ++i) EXPECT_GT(r.oriented.normals[i].dot(points[i]), 0.5);
    EXPECT_EQ(r.oriented.tree.order.size(), points.size());
    EXPECT_GT(r.contour.visited_squares, 0U);
  }
}

TEST(ReconstructCurve, EllipseIsOneClosedCurveNearTheEllipse) {
  const double a = 2.0, b = 1.0;
  const Curve ellipse = [&](double t) {
    return Vec2(a * std::cos(2.0 * std::numbers::pi * t), b * std::sin(2.0 * std::numbers::pi * t));
  };
  const std::vector<Vec2> points = stratified(ellipse, 300, 4);
  const CurveReconstruction r = reconstruct_curve(points);
  const PolylineSet& curves = r.contour.curves;
  ASSERT_EQ(curves.polylines.size(), 1U);
  EXPECT_TRUE(curves.polylines[0].closed);
  const double bound = distance_bound(r, b * b / a);  // the smallest radius of curvature, at the ends of the long axis
  for (const Vec2& v : curves.vertices) EXPECT_LE(distance_to_ellipse(v, a, b), bound);
  EXPECT_GT(signed_area(curves, curves.polylines[0]), 0.0);
  EXPECT_NEAR(signed_area(curves, curves.polylines[0]), std::numbers::pi * a * b, 0.02 * std::numbers::pi * a * b);
}

TEST(ReconstructCurve, FigureEightOfTwoLoopsGivesTwoClosedCurves) {
  // Two unit loops one above the other, a quarter apart where they come
  // closest (about 5 sample spacings): neither may swallow the other, and
  // each must face out (orientation is not carried across the gap).
  const Vec2 low(0.0, 0.0), high(0.0, 2.25);
  std::vector<Vec2> points = stratified(circle(low, 1.0), 300, 5);
  for (const Vec2& p : stratified(circle(high, 1.0), 300, 6)) points.push_back(p);
  const CurveReconstruction r = reconstruct_curve(points);
  const PolylineSet& curves = r.contour.curves;
  ASSERT_EQ(curves.polylines.size(), 2U);
  const double bound = distance_bound(r, 1.0);
  for (const Polyline& line : curves.polylines) {
    EXPECT_TRUE(line.closed);
    EXPECT_NEAR(signed_area(curves, line), std::numbers::pi, 2.0 * std::numbers::pi * bound);
    // All of one loop's vertices are near one circle.
    const Vec2 centre = curves.vertices[line.vertices[0]].y() < 1.125 ? low : high;
    for (const std::uint32_t v : line.vertices) EXPECT_LE(std::abs((curves.vertices[v] - centre).norm() - 1.0), bound);
  }
}

TEST(ReconstructCurve, TwoSeparateCirclesGiveTwoClosedCurves) {
  const Vec2 c1(-1.0, 0.5), c2(2.5, -0.5);
  const double r1 = 1.0, r2 = 0.6;
  std::vector<Vec2> points = stratified(circle(c1, r1), 200, 7);
  for (const Vec2& p : stratified(circle(c2, r2), 120, 8)) points.push_back(p);
  const CurveReconstruction r = reconstruct_curve(points);
  const PolylineSet& curves = r.contour.curves;
  ASSERT_EQ(curves.polylines.size(), 2U);
  EXPECT_EQ(r.oriented.component_count(), 2U);
  const double bound = distance_bound(r, r2);
  std::vector<double> areas;
  for (const Polyline& line : curves.polylines) {
    EXPECT_TRUE(line.closed);
    areas.push_back(signed_area(curves, line));
    for (const std::uint32_t v : line.vertices) {
      const Vec2& p = curves.vertices[v];
      EXPECT_LE(std::min(std::abs((p - c1).norm() - r1), std::abs((p - c2).norm() - r2)), bound);
    }
  }
  std::sort(areas.begin(), areas.end());
  EXPECT_NEAR(areas[0], std::numbers::pi * r2 * r2, 0.03 * std::numbers::pi * r2 * r2);
  EXPECT_NEAR(areas[1], std::numbers::pi * r1 * r1, 0.03 * std::numbers::pi * r1 * r1);
}

// Phase II along each graph of orientation_graphs.h: the two circles stay
// apart along every graph but the complete one, whose tree joins them; the
// curves come out the same wherever the circles each get one orientation.
TEST(ReconstructCurve, TheGraphPhaseTwoWalksIsTheCallersChoice) {
  std::vector<Vec2> points = stratified(circle(Vec2(-1.0, 0.5), 1.0), 200, 7);
  for (const Vec2& p : stratified(circle(Vec2(2.5, -0.5), 0.6), 120, 8)) points.push_back(p);
  const CurveReconstruction reference = reconstruct_curve(points);
  for (const OrientationGraph graph : all_orientation_graphs) {
    CurveReconstructionOptions options;
    options.graph = graph;
    const CurveReconstruction r = reconstruct_curve(points, options);
    EXPECT_EQ(r.oriented.component_count(), graph == OrientationGraph::complete ? 1u : 2u) << name_of(graph);
    EXPECT_EQ(r.oriented.graph.graph.edge_count(), build_orientation_graph<2>(r.planes, graph).graph.edge_count())
        << name_of(graph);
    EXPECT_EQ(r.contour.curves.polylines.size(), 2u) << name_of(graph);
  }
  // The default is the Riemannian graph, as before this choice existed.
  EXPECT_EQ(reference.oriented.graph.graph.edge_count(),
            build_riemannian_graph<2>(reference.planes).graph.edge_count());
}

TEST(ReconstructCurve, OpenArcStaysOpen) {
  // Half a unit circle: the curve must stop near the ends of the data,
  // not close across the empty half.
  const std::vector<Vec2> points = stratified(circle(Vec2::Zero(), 1.0), 150, 9, 0.0, 0.5);
  const CurveReconstruction r = reconstruct_curve(points);
  const PolylineSet& curves = r.contour.curves;
  ASSERT_EQ(curves.polylines.size(), 1U);
  const Polyline& line = curves.polylines[0];
  EXPECT_FALSE(line.closed);
  // Along the arc, the distance bound holds. Beyond its ends, the curve
  // goes on along the end's tangent line as far as f is defined: no farther
  // than rho_i + delta from the last sample, plus a square where the walk
  // stops; that is its distance to the arc (to the arc's end point).
  const double bound = distance_bound(r, 1.0);
  const double rho_max = static_cast<double>(*std::max_element(r.planes.local_rho.begin(), r.planes.local_rho.end()));
  const double overshoot = rho_max + r.delta + 2.0 * r.contour.cell;
  for (const Vec2& v : curves.vertices) {
    if (v.y() >= 0.0) {
      EXPECT_LE(std::abs(v.norm() - 1.0), bound) << v.transpose();
    } else {
      EXPECT_LE(std::min((v - Vec2(1.0, 0.0)).norm(), (v - Vec2(-1.0, 0.0)).norm()), overshoot) << v.transpose();
    }
  }
  // So the curve is only a little longer than the arc (pi), nothing like
  // a closed circle's 2 pi, and covers it.
  EXPECT_GT(length(curves, line), std::numbers::pi - 2.0 * (1.0 / 150.0) * std::numbers::pi);
  EXPECT_LT(length(curves, line), std::numbers::pi + 2.0 * overshoot);
}

TEST(ReconstructCurve, FewPointsAroundATightBendAreStillFound) {
  // 20 points on a unit circle at k = 8: each neighbourhood spans 126
  // degrees, so the tangent lines pass well inside the samples, more than a
  // square from any of them. The walk also starts at the lines' origins.
  std::vector<Vec2> points;
  for (int i = 0; i < 20; ++i) {
    const double a = 2.0 * std::numbers::pi * (i + 0.3) / 20.0;
    points.emplace_back(std::cos(a), std::sin(a));
  }
  CurveReconstructionOptions options;
  options.planes.adapt_k = false;
  const CurveReconstruction r = reconstruct_curve(points, options);
  const PolylineSet& curves = r.contour.curves;
  ASSERT_EQ(curves.polylines.size(), 1U);
  EXPECT_TRUE(curves.polylines[0].closed);
  EXPECT_GT(signed_area(curves, curves.polylines[0]), 0.0);
  const double bound = distance_bound(r, 1.0);
  for (const Vec2& v : curves.vertices) EXPECT_LE(std::abs(v.norm() - 1.0), bound);
}

TEST(ReconstructCurve, CollinearPointsGiveAStraightOpenCurve) {
  // Collinear points are a degenerate surface in 3D but a fine curve in 2D.
  std::vector<Vec2> points;
  const Vec2 start(0.3, -0.2), direction = Vec2(3.0, 1.0).normalized();
  for (int i = 0; i < 40; ++i) points.push_back(start + 0.05 * i * direction);
  const CurveReconstruction r = reconstruct_curve(points);
  const PolylineSet& curves = r.contour.curves;
  ASSERT_EQ(curves.polylines.size(), 1U);
  EXPECT_FALSE(curves.polylines[0].closed);
  // Every tangent line is the line itself, so f is linear and exact.
  const Vec2 normal(-direction.y(), direction.x());
  for (const Vec2& v : curves.vertices) EXPECT_NEAR((v - start).dot(normal), 0.0, 1e-12);
  EXPECT_GT(length(curves, curves.polylines[0]), 0.05 * 39);
}

TEST(ReconstructCurve, RefusesTooFewOrIdenticalPoints) {
  const std::vector<Vec2> few = stratified(circle(Vec2::Zero(), 1.0), 6, 10);
  try {
    (void)reconstruct_curve(few);
    FAIL() << "6 points at k = 8 were accepted";
  } catch (const InvalidInputError& e) {
    EXPECT_NE(std::string(e.what()).find("lower --k"), std::string::npos) << e.what();
  }
  const std::vector<Vec2> same(30, Vec2(1.0, 2.0));
  try {
    (void)reconstruct_curve(same);
    FAIL() << "identical points were accepted";
  } catch (const InvalidInputError& e) {
    EXPECT_NE(std::string(e.what()).find("distinct"), std::string::npos) << e.what();
  }
  std::vector<Vec2> bad = stratified(circle(Vec2::Zero(), 1.0), 30, 11);
  bad[7].x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW((void)reconstruct_curve(bad), InvalidInputError);
  CurveReconstructionOptions both;
  both.cell = 0.1;
  both.resolution = 10;
  EXPECT_THROW((void)reconstruct_curve(stratified(circle(Vec2::Zero(), 1.0), 30, 12), both), InvalidInputError);
}

// Hoppe's curve1.pts: 126 samples of one open curve (records "p 0 y z",
// listed in order along it), whose two ends are about ten spacings apart
// and whose lower end curls into a tongue thinner than the sampling. There
// is no formula for the true curve; the polyline through the samples in
// file order stands for it.
TEST(ReconstructCurveRealData, HoppeCurve1IsOneOpenCurveAlongTheSamples) {
  const std::filesystem::path input = testing::shared_data("hoppe_curve1/curve1.pts");
  RECON_REQUIRE_DATA(input);
  std::ifstream in(input);
  std::vector<Vec2> points;
  for (std::string line; std::getline(in, line);) {
    std::istringstream fields(line);
    std::string record;
    double x = 0.0, y = 0.0, z = 0.0;
    if (fields >> record >> x >> y >> z && record == "p") points.emplace_back(y, z);
  }
  ASSERT_EQ(points.size(), 126U);
  const CurveReconstruction r = reconstruct_curve(points);
  const PolylineSet& curves = r.contour.curves;
  ASSERT_EQ(curves.polylines.size(), 1U);
  EXPECT_FALSE(curves.polylines[0].closed);
  // Hoppe's rule keeps f, and so the curve, within rho_i + delta of the
  // samples; a vertex is on a square side whose corners passed the rule,
  // so it may be a side further. Besides, the corner rule of phase III
  // (signed_distance.h) accepts 1.5 rho_i + delta + |f|, |f| being at most
  // the slope limit times a side at a vertex's corners.
  const double rho_max = static_cast<double>(*std::max_element(r.planes.local_rho.begin(), r.planes.local_rho.end()));
  const double h = r.contour.cell;
  const double bound = 1.5 * rho_max + r.delta + (1.0 + curve_max_slope) * h;
  double worst = 0.0;
  for (const Vec2& v : curves.vertices) {
    double nearest = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i + 1 < points.size(); ++i)
      nearest = std::min(nearest, distance_to_segment(v, points[i], points[i + 1]));
    worst = std::max(worst, nearest);
  }
  EXPECT_LE(worst, bound);
  // The curve follows the data: nine samples in ten (all but the thin
  // tongue) lie within rho of it.
  const auto near = std::count_if(points.begin(), points.end(),
                                  [&](const Vec2& p) { return distance_to_curves(p, curves) <= r.planes.rho; });
  EXPECT_GE(static_cast<double>(near), 0.9 * static_cast<double>(points.size()));
}

}  // namespace
}  // namespace recon
