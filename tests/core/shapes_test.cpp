// Tests of the known shapes (shapes.h), every one by name. The oracles:
// - a sample point lies on the surface: its distance() is 0;
// - a normal is perpendicular to the surface (stepping e along it moves
//   e away) and points out: by the divergence theorem, the flux of the
//   field p through the closed surface, (1/3) sum (p . n) area / N over a
//   uniform sample, is the enclosed volume, known in closed form (a patch
//   with flipped normals changes it by twice its share);
// - area(): the closed form where there is one, and for every shape the
//   volume of the thin shell {q : distance(q) < t} measured by Monte
//   Carlo, which is 2 t area up to terms in t^2 (Steiner's formula);
// - uniform sampling: the share of the samples in a ball matches the
//   share of the shell there;
// - distance(): a brute-force minimum over a million samples, which can
//   only exceed the true distance, and by no more than the sample spacing.

#include "recon/core/shapes.h"
#include "recon/core/errors.h"
#include "recon/reconstruct.h"
#include "recon/structures/mesh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <random>
#include <string>
#include <vector>

namespace recon {
namespace {

constexpr double pi = std::numbers::pi;

// What is known in closed form about each shape (the sizes are the
// defaults of make_shape's shapes, as shapes.h documents them).
struct Truth {
  std::string name;
  int euler_characteristic = 2;
  int components = 1;
  std::optional<double> area;    // absent where shapes.cpp approximates it
  std::optional<double> volume;  // absent for the open terrain
  bool concave_creases = false;  // a step along a normal near one comes closer to the facing patch
};

double sphere_area(double r) { return 4.0 * pi * r * r; }
double sphere_volume(double r) { return 4.0 / 3.0 * pi * r * r * r; }
double cone_area(double r, double h) { return pi * r * r + pi * r * std::hypot(r, h); }
double cone_volume(double r, double h) { return pi * r * r * h / 3.0; }
double cylinder_area(double r, double h) { return 2.0 * pi * r * r + 2.0 * pi * r * h; }
double cylinder_volume(double r, double h) { return pi * r * r * h; }
double box_area(double a, double b, double c) { return 2.0 * (a * b + a * c + b * c); }
double ball_shell_volume(double outer, double inner) { return sphere_volume(outer) - sphere_volume(inner); }

// The thin solids at their default thicknesses (shapes.h): plate 0.05,
// club 0.03, airfoil 0.12 (the NACA section's area is 0.68085 t c), cup
// 0.04, cavity-cube 0.1, two-cavities 0.1.
std::vector<Truth> thin_truths() {
  const double t = 0.03, foot = 0.1 * t;  // the club: the handle's foot on the blade hides foot twice
  const double club_area = box_area(1.0, t, 0.3) + box_area(0.1, 0.1, 1.2) - 2.0 * foot;
  const double r = 0.5, h = 0.8, c = 0.04, ri = r - c;  // the cup
  const double cup_area =
      pi * r * r + 2.0 * pi * r * h + pi * (r * r - ri * ri) + 2.0 * pi * ri * (h - c) + pi * ri * ri;
  const double cup_volume = pi * r * r * h - pi * ri * ri * (h - c);
  return {
      {"plate", 2, 1, box_area(2.0, 1.0, 0.05), 2.0 * 1.0 * 0.05},
      {"club", 2, 1, club_area, 1.0 * t * 0.3 + 0.1 * 0.1 * 1.2, true},
      {"airfoil", 2, 1, std::nullopt, 0.68085 * 0.12 * 1.5},
      {"cup", 2, 1, cup_area, cup_volume, true},
      {"cavity-cube", 4, 2, 6.0 + sphere_area(0.4), 1.0 - sphere_volume(0.4)},
      {"two-cavities", 8, 4, sphere_area(1.0) + sphere_area(0.9) + sphere_area(0.55) + sphere_area(0.45),
       ball_shell_volume(1.0, 0.9) + ball_shell_volume(0.55, 0.45)},
  };
}

std::vector<Truth> all_truths() {
  const double torus_area = 4.0 * pi * pi * 0.35, torus_volume = 2.0 * pi * pi * 0.35 * 0.35;
  const double r = 0.18, hole_disk = pi * r * r;  // the part: a 2 x 1 x 0.4 slab, three holes
  const double part_area = 2.0 * (2.0 - 3.0 * hole_disk) + 2.0 * 0.4 + 2.0 * 0.8 + 3.0 * 2.0 * pi * r * 0.4;
  const double part_volume = 0.4 * (2.0 - 3.0 * hole_disk);
  const double handle_area = 2.0 * pi * 0.08 * 2.0 + sphere_area(0.08);
  const double handle_volume = pi * 0.08 * 0.08 * 2.0 + sphere_volume(0.08);
  const double conics_area = cone_area(0.12, 1.2) + cone_area(0.35, 0.4) + cylinder_area(0.2, 0.5) +
                             cylinder_area(0.15, 0.6) + sphere_area(0.25);
  const double conics_volume = cone_volume(0.12, 1.2) + cone_volume(0.35, 0.4) + cylinder_volume(0.2, 0.5) +
                               cylinder_volume(0.15, 0.6) + sphere_volume(0.25);
  return {
      {"sphere", 2, 1, sphere_area(1.0), sphere_volume(1.0)},
      {"torus", 0, 1, torus_area, torus_volume},
      {"ellipsoid", 2, 1, std::nullopt, 4.0 / 3.0 * pi * 1.0 * 0.7 * 0.45},
      {"box", 2, 1, 2.0 * (0.8 + 0.6 + 0.48), 0.48},
      {"two", 2, 2, sphere_area(0.6) + torus_area, sphere_volume(0.6) + torus_volume},
      {"terrain", 1, 1, std::nullopt, std::nullopt},
      {"part", -4, 1, part_area, part_volume},
      {"handle", 2, 1, handle_area, handle_volume},
      {"conics", 10, 5, conics_area, conics_volume},
      {"shell", 4, 2, sphere_area(1.0) + sphere_area(0.7), sphere_volume(1.0) - sphere_volume(0.7)},
      {"nested", 6, 3, sphere_area(1.0) + sphere_area(0.7) + sphere_area(0.3),
       sphere_volume(1.0) - sphere_volume(0.7) + sphere_volume(0.3)},
  };
}

std::vector<Truth> every_truth() {
  std::vector<Truth> truths = all_truths();
  for (Truth& t : thin_truths()) truths.push_back(std::move(t));
  return truths;
}

Truth truth_of(const std::string& name) {
  for (const Truth& t : every_truth())
    if (t.name == name) return t;
  ADD_FAILURE() << "no truth for " << name;
  return {};
}

// Monte Carlo points of the shell {q : distance(q) < t}, drawn uniformly in
// the sample's bounding box grown by t, and the box's volume per draw.
struct Shell {
  std::vector<Vec3> points;
  double volume_per_draw = 0.0;
  [[nodiscard]] double volume() const { return volume_per_draw * static_cast<double>(points.size()); }
};

Shell thin_shell(const Shape& shape, double t, std::size_t draws, std::uint64_t seed) {
  const PointCloud cloud = shape.sample(20000, seed);
  Box<3> box = bounding_box<3>(cloud.positions);
  box.min.array() -= 2.0 * t;
  box.max.array() += 2.0 * t;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Shell shell;
  shell.volume_per_draw = box.extent().prod() / static_cast<double>(draws);
  for (std::size_t i = 0; i < draws; ++i) {
    const Vec3 q = box.min + Vec3(u(rng), u(rng), u(rng)).cwiseProduct(box.extent());
    if (shape.distance(q) < t) shell.points.push_back(q);
  }
  return shell;
}

// (1/3) the flux of p - c through a closed surface of the given area, from a
// uniform sample of it: the enclosed volume when the normals point out. The
// flux is the same for any c; the samples' centroid keeps the estimate's
// variance low.
double enclosed_volume(const PointCloud& cloud, double area) {
  Vec3 c = Vec3::Zero();
  for (const Vec3& p : cloud.positions) c += p;
  c /= static_cast<double>(cloud.size());
  double flux = 0.0;
  for (std::size_t i = 0; i < cloud.size(); ++i) flux += (cloud.positions[i] - c).dot(cloud.normals[i]);
  return flux * area / static_cast<double>(cloud.size()) / 3.0;
}

double diagonal_of(const PointCloud& cloud) { return bounding_box<3>(cloud.positions).diagonal(); }

class ShapeTest : public ::testing::TestWithParam<std::string> {};

TEST_P(ShapeTest, SamplesLieOnTheSurfaceWithUnitNormals) {
  const auto shape = make_shape(GetParam());
  const PointCloud cloud = shape->sample(20000, 3);
  ASSERT_EQ(cloud.size(), 20000u);
  ASSERT_EQ(cloud.normals.size(), 20000u);
  const double tolerance = 1e-9 * diagonal_of(cloud);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    ASSERT_LT(shape->distance(cloud.positions[i]), tolerance) << "sample " << i;
    ASSERT_NEAR(cloud.normals[i].norm(), 1.0, 1e-12) << "sample " << i;
  }
}

// A step of e along a normal moves e away from the surface only when the
// normal is perpendicular to it (a tilted one comes closer). At a convex
// crease this holds too; within about e of a concave one (the club's
// handle on its blade, the cup's floor) the facing patch comes closer, so
// there the step may come out shorter, never longer, on a few samples.
TEST_P(ShapeTest, NormalsArePerpendicularToTheSurface) {
  const Truth truth = truth_of(GetParam());
  const auto shape = make_shape(GetParam());
  const PointCloud cloud = shape->sample(20000, 4);
  const double e = 1e-3;
  std::size_t shorter = 0;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const double d = shape->distance(cloud.positions[i] + e * cloud.normals[i]);
    if (truth.concave_creases && d < e - 1e-8) {
      ++shorter;
      continue;
    }
    ASSERT_NEAR(d, e, 1e-8) << "sample " << i;
  }
  EXPECT_LT(shorter, cloud.size() / 100);
}

// The flux of p through the surface is 3 times the volume inside when the
// normals point out, and less when some point in.
TEST_P(ShapeTest, NormalsPointOutOfTheSolid) {
  const Truth truth = truth_of(GetParam());
  const auto shape = make_shape(GetParam());
  const PointCloud cloud = shape->sample(1000000, 5);
  if (!truth.volume) {  // the open terrain: facing up, where a scanner looks from
    for (const Vec3& n : cloud.normals) ASSERT_GT(n.z(), 0.0);
    return;
  }
  EXPECT_NEAR(enclosed_volume(cloud, shape->area()), *truth.volume, 0.025 * *truth.volume);
}

TEST_P(ShapeTest, AreaMatchesClosedFormAndThinShell) {
  const Truth truth = truth_of(GetParam());
  const auto shape = make_shape(GetParam());
  if (truth.area) {
    EXPECT_NEAR(shape->area(), *truth.area, 1e-12 * *truth.area);
  }
  // At convex creases the shell's outer wedges and inner overlaps nearly
  // cancel (a part in a thousand here); the terrain's open rim adds half
  // a disk of radius t per unit of length (about 1.5 %).
  const double t = 0.01;
  const Shell shell = thin_shell(*shape, t, 600000, 6);
  ASSERT_GT(shell.points.size(), 5000u);  // a statistical error of 1.5 % at most
  EXPECT_NEAR(shell.volume() / (2.0 * t), shape->area(), 0.04 * shape->area());
}

// The terrain is left out: it is sampled on a grid in (x, y), not by area.
TEST_P(ShapeTest, SamplesAreUniformByArea) {
  if (GetParam() == "terrain") GTEST_SKIP() << "the terrain's sampling is grid-like, uniform in x and y";
  const auto shape = make_shape(GetParam());
  const PointCloud cloud = shape->sample(100000, 7);
  const Shell shell = thin_shell(*shape, 0.01, 600000, 8);
  const double radius = 0.3 * diagonal_of(cloud);
  for (const std::size_t centre : {0u, 1u, 2u, 3u}) {
    const Vec3 c = cloud.positions[centre];
    auto share = [&](const std::vector<Vec3>& points) {
      const auto inside =
          std::count_if(points.begin(), points.end(), [&](const Vec3& p) { return (p - c).norm() < radius; });
      return static_cast<double>(inside) / static_cast<double>(points.size());
    };
    EXPECT_NEAR(share(cloud.positions), share(shell.points), 0.03) << "ball around sample " << centre;
  }
}

TEST_P(ShapeTest, DistanceAgreesWithBruteForceOverADenseSample) {
  const auto shape = make_shape(GetParam());
  const PointCloud dense = shape->sample(1000000, 9);
  const double diagonal = diagonal_of(dense);
  const double spacing = 4.0 * std::sqrt(shape->area() / static_cast<double>(dense.size()));
  std::mt19937_64 rng(10);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  // The terrain's distance is exact near the surface only (shapes.h).
  const bool far_queries = GetParam() != "terrain";
  for (int query = 0; query < 60; ++query) {
    // Half the queries near the surface (where mistakes show), half anywhere near the shape.
    const bool near = query % 2 == 0 || !far_queries;
    const Vec3 base = near ? dense.positions[rng() % dense.size()] : Vec3::Zero();
    const double reach = near ? 0.1 * diagonal : 0.6 * diagonal;
    const Vec3 q = base + reach * Vec3(u(rng), u(rng), u(rng));
    double brute = std::numeric_limits<double>::infinity();
    for (const Vec3& p : dense.positions) brute = std::min(brute, (p - q).squaredNorm());
    brute = std::sqrt(brute);
    const double d = shape->distance(q);
    EXPECT_GE(brute, d - 1e-9 * diagonal) << "query " << q.transpose();
    EXPECT_LE(brute, d + spacing) << "query " << q.transpose();
  }
}

TEST_P(ShapeTest, SameSeedSameSampleOtherSeedOtherSample) {
  const auto shape = make_shape(GetParam());
  const PointCloud a = shape->sample(2000, 11), b = shape->sample(2000, 11), c = shape->sample(2000, 12);
  EXPECT_EQ(a.positions, b.positions);
  EXPECT_EQ(a.normals, b.normals);
  EXPECT_NE(a.positions, c.positions);
}

TEST_P(ShapeTest, TopologyIsAsDocumented) {
  const Truth truth = truth_of(GetParam());
  const auto shape = make_shape(GetParam());
  EXPECT_EQ(shape->euler_characteristic(), truth.euler_characteristic);
  EXPECT_EQ(shape->components(), truth.components);
}

INSTANTIATE_TEST_SUITE_P(Shapes, ShapeTest,
                         ::testing::Values("sphere", "torus", "ellipsoid", "box", "two", "terrain", "part", "handle",
                                           "conics", "shell", "nested", "plate", "club", "airfoil", "cup",
                                           "cavity-cube", "two-cavities"),
                         [](const ::testing::TestParamInfo<std::string>& shape) {
                           std::string name = shape.param;  // a test name has no '-'
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });

TEST(ShapeNames, UnknownNameIsRefusedWithTheKnownOnes) {
  try {
    (void)make_shape("cube");
    FAIL() << "no error";
  } catch (const std::exception& e) {
    for (const char* name : {"part", "handle", "conics", "terrain"})
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
  }
}

// ---------------------------------------------------------------- thin solids

// The thickness asked for is the wall's: a point halfway through a wall
// lies t/2 from both its sheets. Checked down to ρ/2 at 40,000 points
// (ρ about 0.01 on the plate) and at a few multiples of it.
TEST(ThinSolids, AWallsMiddleLiesHalfTheThicknessFromTheSurface) {
  struct Wall {
    std::string shape;
    Vec3 (*middle)(double t);
    double tolerance;  // relative to t: the airfoil is a polygon, thinner than its curve between vertices
  };
  const std::vector<Wall> walls = {
      {"plate", [](double) { return Vec3(0.3, 0.2, 0.0); }, 1e-12},
      {"club", [](double) { return Vec3(0.5, 0.0, 0.15); }, 1e-12},
      {"airfoil", [](double) { return Vec3(-0.2, 0.0, 0.0); }, 2e-3},  // thickest at 30 % of the chord
      {"cup", [](double t) { return Vec3(0.5 - t / 2, 0.0, 0.4); }, 1e-12},
      {"cup", [](double t) { return Vec3(0.0, 0.1, t / 2); }, 1e-12},
      {"cavity-cube", [](double t) { return Vec3(0.0, 0.5 - t / 2, 0.0); }, 1e-12},
      {"two-cavities", [](double t) { return Vec3(1.0 - t / 2, 0.0, 0.0); }, 1e-12},
      {"two-cavities", [](double t) { return Vec3(0.0, 0.0, 0.55 - t / 2); }, 1e-12},
      {"shell", [](double t) { return Vec3(0.0, 1.0 - t / 2, 0.0); }, 1e-12},
  };
  for (const Wall& wall : walls)
    for (const double t : {0.005, 0.0075, 0.01, 0.02, 0.05}) {
      const auto shape = make_shape(wall.shape, t);
      EXPECT_NEAR(shape->distance(wall.middle(t)), t / 2, wall.tolerance * t) << wall.shape << " at " << t;
    }
}

// Thin walls change the volume, not the topology: the flux of p through
// the sample is the solid's volume at every thickness (a sheet facing the
// wrong way would count its side's volume with the wrong sign).
TEST(ThinSolids, NormalsPointOutAtEveryThickness) {
  for (const double t : {0.005, 0.02}) {
    const double ri = 0.5 - t;
    const std::vector<std::pair<std::string, double>> volumes = {
        {"plate", 2.0 * t},
        {"club", 1.0 * t * 0.3 + 0.1 * 0.1 * 1.2},
        {"cup", pi * 0.25 * 0.8 - pi * ri * ri * (0.8 - t)},
        {"cavity-cube", 1.0 - sphere_volume(0.5 - t)},
        {"two-cavities", ball_shell_volume(1.0, 1.0 - t) + ball_shell_volume(0.55, 0.55 - t)},
    };
    for (const auto& [name, volume] : volumes) {
      const auto shape = make_shape(name, t);
      EXPECT_NEAR(enclosed_volume(shape->sample(400000, 21), shape->area()), volume, 0.05 * volume)
          << name << " at " << t;
    }
  }
}

// Whether q lies in the material of each thin solid of thickness t (as
// shapes.h describes them); the airfoil, convex, is left to the flux.
bool in_box(const Vec3& q, const Vec3& lo, const Vec3& hi) {
  return (q.array() > lo.array()).all() && (q.array() < hi.array()).all();
}
bool in_material(const std::string& shape, double t, const Vec3& q) {
  const double r = q.norm();
  if (shape == "plate") return in_box(q, Vec3(-1.0, -0.5, -t / 2), Vec3(1.0, 0.5, t / 2));
  if (shape == "club")
    return in_box(q, Vec3(0.0, -t / 2, 0.0), Vec3(1.0, t / 2, 0.3)) ||
           in_box(q, Vec3(0.05, -0.05, 0.3), Vec3(0.15, 0.05, 1.5));
  if (shape == "cup") {
    const double rho = std::hypot(q.x(), q.y());
    return q.z() > 0.0 && q.z() < 0.8 && rho < 0.5 && !(rho < 0.5 - t && q.z() > t);
  }
  if (shape == "cavity-cube") return in_box(q, Vec3::Constant(-0.5), Vec3::Constant(0.5)) && r > 0.5 - t;
  return (r < 1.0 && r > 1.0 - t) || (r < 0.55 && r > 0.55 - t);  // two-cavities
}

// Every sample's normal leaves the material: a step of e along it lands
// outside, a step back inside. The flux would miss a small patch turned
// the wrong way (the club's overhangs under the handle are 1.7 % of its
// area, 2 % of its volume); this does not.
TEST(ThinSolids, EveryNormalPointsOutOfTheMaterial) {
  const double e = 1e-4;
  for (const double t : {0.005, 0.02})
    for (const std::string name : {"plate", "club", "cup", "cavity-cube", "two-cavities"}) {
      const PointCloud cloud = make_shape(name, t)->sample(50000, 22);
      for (std::size_t i = 0; i < cloud.size(); ++i) {
        const Vec3 &p = cloud.positions[i], &n = cloud.normals[i];
        ASSERT_FALSE(in_material(name, t, p + e * n)) << name << " at " << t << ", sample " << i;
        ASSERT_TRUE(in_material(name, t, p - e * n)) << name << " at " << t << ", sample " << i;
      }
    }
}

TEST(ThinSolids, AThicknessOutOfRangeOrForAnotherShapeIsRefused) {
  const std::vector<std::pair<std::string, double>> refused = {
      {"plate", 0.0},        {"plate", -0.1},  {"club", 0.1},  {"cup", 0.25},  {"cavity-cube", 0.5},
      {"two-cavities", 0.3}, {"airfoil", 0.5}, {"shell", 1.0}, {"torus", 0.1}, {"part", 0.1}};
  for (const auto& [name, t] : refused) EXPECT_THROW((void)make_shape(name, t), InvalidInputError) << name << " " << t;
  EXPECT_NO_THROW((void)make_shape("club", 0.099));
}

// ---------------------------------------------------------------- part

// Which of the part's eleven patches a sample is on, from its normal: the
// six faces (+x, -x, +y, -y, +z, -z, normals along an axis) are 0-5, the
// hole walls (horizontal normals in every direction) 6-8, by x.
std::size_t part_patch(const Vec3& p, const Vec3& n) {
  for (int axis = 0; axis < 3; ++axis) {
    if (n[axis] == 1.0) return static_cast<std::size_t>(2 * axis);
    if (n[axis] == -1.0) return static_cast<std::size_t>(2 * axis + 1);
  }
  return p.x() < -0.3 ? 6 : p.x() < 0.3 ? 7 : 8;
}

TEST(ShapePart, EachPatchGetsItsShareOfTheSamples) {
  const auto part = make_machined_part();
  const double r = 0.18, top = 2.0 - 3.0 * pi * r * r, wall = 2.0 * pi * r * 0.4;
  const std::vector<double> areas = {0.4, 0.4, 0.8, 0.8, top, top, wall, wall, wall};
  const std::size_t n = 200000;
  const PointCloud cloud = part->sample(n, 13);
  std::vector<double> count(areas.size(), 0.0);
  for (std::size_t i = 0; i < n; ++i) count[part_patch(cloud.positions[i], cloud.normals[i])] += 1.0;
  for (std::size_t k = 0; k < areas.size(); ++k) {
    const double share = areas[k] / part->area();
    const double sigma = std::sqrt(share * (1.0 - share) / static_cast<double>(n));
    EXPECT_NEAR(count[k] / static_cast<double>(n), share, 5.0 * sigma) << "patch " << k;
  }
}

TEST(ShapePart, NoSampleFallsInAHoleAndWallsFaceTheirAxis) {
  const PointCloud cloud = make_machined_part()->sample(50000, 14);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Vec3& p = cloud.positions[i];
    for (const double cx : {-0.6, 0.0, 0.6}) {
      const double rho = std::hypot(p.x() - cx, p.y());
      ASSERT_GE(rho, 0.18 - 1e-12) << "sample " << i << " is inside the hole at x = " << cx;
      if (rho < 0.18 + 1e-9) {  // on this hole's wall: the normal points to its axis
        ASSERT_NEAR(cloud.normals[i].dot(Vec3(cx - p.x(), -p.y(), 0.0) / rho), 1.0, 1e-9);
      }
    }
  }
}

TEST(ShapePart, DistanceAtPointsWorkedOutByHand) {
  const auto part = make_machined_part();
  EXPECT_NEAR(part->distance(Vec3(0.0, 0.0, 0.0)), 0.18, 1e-15);                           // on a hole's axis
  EXPECT_NEAR(part->distance(Vec3(0.3, 0.0, 0.0)), 0.12, 1e-15);                           // between two holes
  EXPECT_NEAR(part->distance(Vec3(0.6, 0.0, 0.5)), std::hypot(0.3, 0.18), 1e-15);          // above a hole: its rim
  EXPECT_NEAR(part->distance(Vec3(0.6, 0.05, 0.1)), 0.13, 1e-15);                          // in a hole, off axis
  EXPECT_NEAR(part->distance(Vec3(0.9, 0.4, 0.15)), 0.05, 1e-15);                          // inside, near a corner
  EXPECT_NEAR(part->distance(Vec3(1.3, 0.9, 0.6)), std::sqrt(0.09 + 0.16 + 0.16), 1e-15);  // off a corner
  EXPECT_NEAR(part->distance(Vec3(-0.3, 0.2, 0.25)), 0.05, 1e-15);                         // above the top face
}

// ---------------------------------------------------------------- handle

TEST(ShapeHandle, SideAndCapsGetTheirShares) {
  const auto handle = make_handle();
  const std::size_t n = 200000;
  const PointCloud cloud = handle->sample(n, 15);
  double caps = 0.0;
  for (const Vec3& p : cloud.positions) caps += std::abs(p.x()) > 1.0 ? 1.0 : 0.0;
  const double share = 4.0 * pi * 0.08 * 0.08 / handle->area();
  const double sigma = std::sqrt(share * (1.0 - share) / static_cast<double>(n));
  EXPECT_NEAR(caps / static_cast<double>(n), share, 5.0 * sigma);
  EXPECT_NEAR(handle->distance(Vec3(0.3, 0.0, 0.0)), 0.08, 1e-15);
  EXPECT_NEAR(handle->distance(Vec3(1.5, 0.0, 0.0)), 0.42, 1e-15);
  EXPECT_NEAR(handle->distance(Vec3(-0.5, 0.3, 0.4)), 0.42, 1e-15);
}

// ---------------------------------------------------------------- conics

// The piece of make_conics() a point is nearest to.
std::size_t nearest_piece(const std::vector<std::unique_ptr<Shape>>& pieces, const Vec3& p) {
  std::size_t best = 0;
  for (std::size_t i = 1; i < pieces.size(); ++i)
    if (pieces[i]->distance(p) < pieces[best]->distance(p)) best = i;
  return best;
}

TEST(ShapeConics, PiecesGetTheirSharesAndEncloseTheirVolumes) {
  const auto conics = make_conics();
  const auto pieces = make_conics_pieces();
  ASSERT_EQ(pieces.size(), 5u);
  const std::vector<double> volumes = {cone_volume(0.12, 1.2), cone_volume(0.35, 0.4), cylinder_volume(0.2, 0.5),
                                       cylinder_volume(0.15, 0.6), sphere_volume(0.25)};
  const std::size_t n = 400000;
  const PointCloud cloud = conics->sample(n, 16);
  std::vector<PointCloud> split(pieces.size());
  for (std::size_t i = 0; i < n; ++i) {
    PointCloud& piece = split[nearest_piece(pieces, cloud.positions[i])];
    piece.positions.push_back(cloud.positions[i]);
    piece.normals.push_back(cloud.normals[i]);
  }
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    const double share = pieces[k]->area() / conics->area();
    EXPECT_NEAR(static_cast<double>(split[k].size()) / static_cast<double>(n), share, 1e-4) << "piece " << k;
    EXPECT_NEAR(enclosed_volume(split[k], pieces[k]->area()), volumes[k], 0.02 * volumes[k]) << "piece " << k;
  }
}

TEST(ShapeConics, PiecesAreApartAndTopsAreWhereTheHeaderSays) {
  const auto pieces = make_conics_pieces();
  std::vector<PointCloud> samples;
  for (const auto& piece : pieces) samples.push_back(piece->sample(1500, 17));
  for (std::size_t a = 0; a < samples.size(); ++a)
    for (std::size_t b = a + 1; b < samples.size(); ++b)
      for (const Vec3& p : samples[a].positions) ASSERT_GT(pieces[b]->distance(p), 0.3) << a << " and " << b;
  // The tall narrow cone's apex, (-1.7, 0, 1.2), is its highest point.
  EXPECT_NEAR(pieces[0]->distance(Vec3(-1.7, 0.0, 1.2)), 0.0, 1e-15);
  // The tilted cylinder's highest point is on the rim of its upper cap: the
  // axis (sin 60, 0, cos 60) from (1.1, 0, 0.3), 0.3 up it, then 0.15 along
  // the cap towards +z.
  const double s = std::sin(pi / 3.0), c = std::cos(pi / 3.0);
  const Vec3 rim = Vec3(1.1, 0.0, 0.3) + 0.3 * Vec3(s, 0.0, c) + 0.15 * Vec3(-c, 0.0, s);
  EXPECT_NEAR(pieces[3]->distance(rim), 0.0, 1e-12);
  for (const Vec3& p : samples[3].positions) EXPECT_LE(p.z(), rim.z() + 1e-12);
  for (const Vec3& p : samples[0].positions) EXPECT_LE(p.z(), 1.2 + 1e-12);
}

// ---------------------------------------------------------------- reconstruction

// The part's genus, as recon's default reconstruction recovers it from 20,000
// samples: one closed surface with three handles.
TEST(ShapeReconstruct, PartIsOneClosedSurfaceOfGenusThree) {
  const auto part = make_machined_part();
  PointCloud cloud = part->sample(20000, 18);
  cloud.normals.clear();
  const Reconstruction r = reconstruct(cloud);
  const MeshTopology t = analyze_topology(r.mesh());
  EXPECT_TRUE(t.watertight()) << t.boundary_edges << " boundary, " << t.non_manifold_edges << " non-manifold, "
                              << t.inconsistent_edges << " inconsistently oriented edges";
  EXPECT_EQ(t.components, 1u);
  EXPECT_EQ(t.euler_characteristic, -4);
  EXPECT_GT(t.signed_volume, 0.0);
}

// The course's data set at its own size. Each piece is found as its own
// phase II component, and none comes out inside out: not those whose top
// is a tip (the tall cone), a rim (the tilted cylinder), a flat cap or a
// smooth pole, and not the wide cone, whose rim is a crease sharper than a
// right angle (its faces meet at 49 degrees: the walk alone turned its base
// inside out, orientation.h). Their normals agree with the true ones, and
// the cylinders and the sphere are closed meshes with positive volume. (The
// wide cone's 49-degree rim is thinner than a cell near its edge: at seed
// 19 its mesh keeps a hole of 4 edges there.) The tall cone's top is thinner
// than a neighbourhood (radius under 0.048 in its top two fifths, sample
// spacing about 0.02): there a neighbourhood wraps round the whole cone and
// its normal is a guess (39 of 305 wrong at seed 19, which also leaves the
// spike's mesh open); below it, every normal faces out.
struct ConicsRun {
  Reconstruction r;
  PointCloud truth;
  std::vector<double> agree, total;  // per piece
  double cone_below_tip_wrong = 0.0;
};

ConicsRun run_conics(std::uint64_t seed) {
  const auto pieces = make_conics_pieces();
  ConicsRun run;
  run.truth = make_conics()->sample(16000, seed);
  PointCloud cloud = run.truth;
  cloud.normals.clear();
  ReconstructionOptions options;
  options.keep_graph = true;
  run.r = reconstruct(cloud, options);
  run.agree.assign(pieces.size(), 0.0);
  run.total.assign(pieces.size(), 0.0);
  const auto normals = run.r.normals();
  for (std::size_t j = 0; j < run.r.order.size(); ++j) {
    const std::size_t i = run.r.order[j];
    const std::size_t k = nearest_piece(pieces, run.truth.positions[i]);
    const bool right = normals[j].dot(run.truth.normals[i]) > 0.0;
    run.total[k] += 1.0;
    run.agree[k] += right ? 1.0 : 0.0;
    if (k == 0 && run.truth.positions[i].z() < 0.6 * 1.2 && !right) run.cone_below_tip_wrong += 1.0;
  }
  return run;
}

TEST(ShapeReconstruct, ConicsPiecesAreFoundAndNoneIsInsideOut) {
  for (const std::uint64_t seed : {1u, 19u}) {
    const ConicsRun run = run_conics(seed);
    ASSERT_TRUE(run.r.oriented.has_value());
    EXPECT_EQ(run.r.oriented->component_count(), 5u) << seed;
    EXPECT_EQ(run.cone_below_tip_wrong, 0.0) << seed;
    EXPECT_GT(run.agree[0] / run.total[0], 0.97) << seed << ": the tall cone";
    EXPECT_GT(run.agree[1] / run.total[1], 0.99) << seed << ": the wide cone";
    EXPECT_EQ(run.r.oriented->crease_patches_turned, 1u) << seed << ": the wide cone's base";
    for (const std::size_t k : {2u, 3u, 4u}) EXPECT_GT(run.agree[k] / run.total[k], 0.999) << seed << ": piece " << k;
    // The mesh components of the cylinders and the sphere: closed, facing out.
    const MeshTopology t = analyze_topology(run.r.mesh());
    std::size_t closed_outward = 0;
    for (const auto& c : t.component_list)
      closed_outward += c.boundary_edges == 0 && c.euler_characteristic == 2 && c.signed_volume > 0.0 ? 1u : 0u;
    EXPECT_GE(closed_outward, 3u) << seed;
  }
}

// add_noise: the offsets have the asked standard deviation (a fraction of
// the bounding-box diagonal) and no bias, on every axis; the same seed gives
// the same cloud, another seed another; normals stay.
TEST(ShapeNoise, GaussianAtTheAskedScaleAndReproducible) {
  const PointCloud clean = make_torus()->sample(40000, 3);
  const double diagonal = bounding_box<3>(clean.positions).diagonal();
  PointCloud noisy = clean;
  add_noise(noisy, 0.01, 5);
  Vec3 sum = Vec3::Zero(), sum2 = Vec3::Zero();
  for (std::size_t i = 0; i < clean.size(); ++i) {
    const Vec3 d = noisy.positions[i] - clean.positions[i];
    sum += d;
    sum2 += d.cwiseProduct(d);
  }
  const auto n = static_cast<double>(clean.size());
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(std::sqrt(sum2[a] / n), 0.01 * diagonal, 0.02 * 0.01 * diagonal) << "axis " << a;
    EXPECT_LT(std::abs(sum[a] / n), 0.02 * 0.01 * diagonal) << "axis " << a;
  }
  EXPECT_EQ(noisy.normals, clean.normals);
  PointCloud again = clean, other = clean;
  add_noise(again, 0.01, 5);
  add_noise(other, 0.01, 6);
  EXPECT_EQ(again.positions, noisy.positions);
  EXPECT_NE(other.positions, noisy.positions);
}

}  // namespace
}  // namespace recon
