#include "recon/core/shapes.h"

#include "recon/core/errors.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <optional>
#include <random>
#include <sstream>

namespace recon {
namespace {

using Rng = std::mt19937_64;

double uniform(Rng& rng) { return std::uniform_real_distribution<double>(0.0, 1.0)(rng); }

Vec3 unit_vector(Rng& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  while (true) {
    const Vec3 v(g(rng), g(rng), g(rng));
    const double norm = v.norm();
    if (norm > 1e-9) return v / norm;
  }
}

// Running sums of patch areas: the last is the total area, and a uniform
// draw in [0, total) falls after the sums of the patches before the one
// it picks, so each patch is picked with probability area / total.
std::vector<double> running_sums(const std::vector<double>& areas) {
  std::vector<double> sums(areas.size());
  std::partial_sum(areas.begin(), areas.end(), sums.begin());
  return sums;
}

// A patch picked with probability proportional to its area (a patch of
// zero area is never picked).
std::size_t pick_patch(const std::vector<double>& sums, Rng& rng) {
  const double u = uniform(rng) * sums.back();
  const auto after = std::upper_bound(sums.begin(), sums.end(), u);
  return std::min(static_cast<std::size_t>(after - sums.begin()), sums.size() - 1);
}

// n points of a surface made of patches: each picks a patch by area and
// has `draw(patch, rng, cloud)` add one point of it, with its normal.
template <typename Draw>
PointCloud sample_by_area(std::size_t n, std::uint64_t seed, const std::vector<double>& areas, Draw&& draw) {
  Rng rng(seed);
  const std::vector<double> sums = running_sums(areas);
  PointCloud cloud;
  cloud.positions.reserve(n);
  cloud.normals.reserve(n);
  for (std::size_t i = 0; i < n; ++i) draw(pick_patch(sums, rng), rng, cloud);
  return cloud;
}

// A sphere; with `facing` -1 the wall of a spherical cavity, whose normals
// point into the cavity (out of the solid around it).
class Sphere final : public Shape {
 public:
  Sphere(double r, Vec3 c, double facing = 1.0) : r_(r), c_(std::move(c)), facing_(facing) {}
  PointCloud sample(std::size_t n, std::uint64_t seed) const override {
    Rng rng(seed);
    PointCloud cloud;
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3 u = unit_vector(rng);
      cloud.positions.push_back(c_ + r_ * u);
      cloud.normals.push_back(facing_ * u);
    }
    return cloud;
  }
  double distance(const Vec3& p) const override { return std::abs((p - c_).norm() - r_); }
  double area() const override { return 4.0 * std::numbers::pi * r_ * r_; }
  int euler_characteristic() const override { return 2; }

 private:
  double r_;
  Vec3 c_;
  double facing_;
};

class Torus final : public Shape {
 public:
  Torus(double major, double minor, Vec3 c) : R_(major), r_(minor), c_(std::move(c)) {}
  PointCloud sample(std::size_t n, std::uint64_t seed) const override {
    Rng rng(seed);
    PointCloud cloud;
    while (cloud.size() < n) {
      const double u = 2.0 * std::numbers::pi * uniform(rng);
      const double v = 2.0 * std::numbers::pi * uniform(rng);
      // Area element is proportional to R + r cos v: rejection keeps it uniform.
      if (uniform(rng) * (R_ + r_) > R_ + r_ * std::cos(v)) continue;
      const Vec3 normal(std::cos(v) * std::cos(u), std::cos(v) * std::sin(u), std::sin(v));
      const Vec3 ring(R_ * std::cos(u), R_ * std::sin(u), 0.0);
      cloud.positions.push_back(c_ + ring + r_ * normal);
      cloud.normals.push_back(normal);
    }
    return cloud;
  }
  double distance(const Vec3& p) const override {
    const Vec3 q = p - c_;
    const double radial = std::hypot(q.x(), q.y()) - R_;
    return std::abs(std::hypot(radial, q.z()) - r_);
  }
  double area() const override { return 4.0 * std::numbers::pi * std::numbers::pi * R_ * r_; }
  int euler_characteristic() const override { return 0; }

 private:
  double R_, r_;
  Vec3 c_;
};

class Ellipsoid final : public Shape {
 public:
  explicit Ellipsoid(Vec3 axes) : axes_(std::move(axes)) {}
  PointCloud sample(std::size_t n, std::uint64_t seed) const override {
    Rng rng(seed);
    PointCloud cloud;
    const double a = axes_.x(), b = axes_.y(), c = axes_.z();
    const double max_element = std::max({b * c, a * c, a * b});
    while (cloud.size() < n) {
      const Vec3 u = unit_vector(rng);
      // The map from the unit sphere stretches area by |(bc ux, ac uy, ab uz)|.
      const Vec3 stretch(b * c * u.x(), a * c * u.y(), a * b * u.z());
      if (uniform(rng) * max_element > stretch.norm()) continue;
      cloud.positions.push_back(axes_.cwiseProduct(u));
      cloud.normals.push_back(stretch.normalized());
    }
    return cloud;
  }
  // Closest point on the ellipsoid: x_i = p_i a_i^2 / (a_i^2 + t) with t the
  // root of sum (a_i p_i / (a_i^2 + t))^2 = 1, found by bisection (the sum
  // decreases in t on the interval where the closest point lies).
  double distance(const Vec3& p) const override {
    const Vec3 a2 = axes_.cwiseProduct(axes_);
    auto g = [&](double t) {
      double s = 0.0;
      for (int i = 0; i < 3; ++i) s += std::pow(axes_[i] * p[i] / (a2[i] + t), 2);
      return s - 1.0;
    };
    // For p near the surface (all the tests ask) the root lies in
    // (-min a_i^2, infinity), where the sum falls monotonically.
    const double amin = axes_.minCoeff();
    double lo = -amin * amin, hi = p.norm() * axes_.maxCoeff() + 1.0;
    for (int it = 0; it < 200; ++it) {
      const double mid = 0.5 * (lo + hi);
      (g(mid) > 0.0 ? lo : hi) = mid;
    }
    const double t = 0.5 * (lo + hi);
    Vec3 x;
    for (int i = 0; i < 3; ++i) x[i] = p[i] * a2[i] / (a2[i] + t);
    return (p - x).norm();
  }
  double area() const override {
    // Knud Thomsen's approximation (relative error below 1.1%).
    const double pw = 1.6075;
    const double a = std::pow(axes_.x(), pw), b = std::pow(axes_.y(), pw), c = std::pow(axes_.z(), pw);
    return 4.0 * std::numbers::pi * std::pow((a * b + a * c + b * c) / 3.0, 1.0 / pw);
  }
  int euler_characteristic() const override { return 2; }

 private:
  Vec3 axes_;
};

class Cuboid final : public Shape {
 public:
  explicit Cuboid(Vec3 sides) : half_(sides / 2.0) {}
  PointCloud sample(std::size_t n, std::uint64_t seed) const override {
    Rng rng(seed);
    PointCloud cloud;
    const Vec3 s = 2.0 * half_;
    const double areas[3] = {s.y() * s.z(), s.x() * s.z(), s.x() * s.y()};  // faces normal to x, y, z
    const double total = areas[0] + areas[1] + areas[2];
    for (std::size_t i = 0; i < n; ++i) {
      double pick = uniform(rng) * total;
      int axis = 0;
      while (axis < 2 && pick > areas[axis]) pick -= areas[axis++];
      const double sign = uniform(rng) < 0.5 ? -1.0 : 1.0;
      Vec3 p;
      for (int a = 0; a < 3; ++a) p[a] = (2.0 * uniform(rng) - 1.0) * half_[a];
      p[axis] = sign * half_[axis];
      Vec3 normal = Vec3::Zero();
      normal[axis] = sign;
      cloud.positions.push_back(p);
      cloud.normals.push_back(normal);
    }
    return cloud;
  }
  double distance(const Vec3& p) const override {
    const Vec3 q = p.cwiseAbs() - half_;
    const double outside = q.cwiseMax(0.0).norm();
    const double inside = std::min(q.maxCoeff(), 0.0);
    return std::abs(outside + inside);
  }
  double area() const override {
    const Vec3 s = 2.0 * half_;
    return 2.0 * (s.x() * s.y() + s.x() * s.z() + s.y() * s.z());
  }
  int euler_characteristic() const override { return 2; }

 private:
  Vec3 half_;
};

class Union final : public Shape {
 public:
  Union(std::unique_ptr<Shape> a, std::unique_ptr<Shape> b) : a_(std::move(a)), b_(std::move(b)) {}
  PointCloud sample(std::size_t n, std::uint64_t seed) const override {
    const auto na = static_cast<std::size_t>(std::llround(static_cast<double>(n) * a_->area() / area()));
    PointCloud cloud = a_->sample(na, seed);
    const PointCloud second = b_->sample(n - na, seed + 1);
    cloud.positions.insert(cloud.positions.end(), second.positions.begin(), second.positions.end());
    cloud.normals.insert(cloud.normals.end(), second.normals.begin(), second.normals.end());
    return cloud;
  }
  double distance(const Vec3& p) const override { return std::min(a_->distance(p), b_->distance(p)); }
  double area() const override { return a_->area() + b_->area(); }
  int euler_characteristic() const override { return a_->euler_characteristic() + b_->euler_characteristic(); }
  int components() const override { return a_->components() + b_->components(); }

 private:
  std::unique_ptr<Shape> a_, b_;
};

// The slab with three holes of make_machined_part(). Its surface is eleven
// patches: the six faces of the slab (top and bottom with three disks cut
// out) and three hole walls. Sampling picks a patch by its area, then a
// point uniformly on it (on the top and bottom by rejection: points that
// fall in a hole are drawn again). The distance is the smallest of the
// exact distances to the patches.
class MachinedPart final : public Shape {
 public:
  PointCloud sample(std::size_t n, std::uint64_t seed) const override {
    return sample_by_area(n, seed, patch_areas(), [this](std::size_t patch, Rng& rng, PointCloud& cloud) {
      if (patch < 6)
        sample_face(static_cast<int>(patch), rng, cloud);
      else
        sample_wall(patch - 6, rng, cloud);
    });
  }
  double distance(const Vec3& p) const override {
    double d = std::numeric_limits<double>::infinity();
    for (int face = 0; face < 6; ++face) d = std::min(d, face_distance(p, face));
    for (std::size_t hole = 0; hole < hole_x.size(); ++hole) d = std::min(d, wall_distance(p, hole));
    return d;
  }
  double area() const override {
    const std::vector<double> areas = patch_areas();
    return std::accumulate(areas.begin(), areas.end(), 0.0);
  }
  int euler_characteristic() const override { return -4; }  // genus 3

 private:
  static constexpr double hole_radius = 0.18;
  static constexpr std::array<double, 3> hole_x = {-0.6, 0.0, 0.6};  // hole axes, at y = 0
  const Vec3 half_ = Vec3(1.0, 0.5, 0.2);                            // half the slab's sides

  // Faces 0 to 5 are normal to axis face / 2, on its + side when face is
  // even; faces 4 and 5 (top and bottom) have the holes.
  static int face_axis(int face) { return face / 2; }
  static double face_sign(int face) { return face % 2 == 0 ? 1.0 : -1.0; }

  // Patches 0-5: the faces; 6-8: the hole walls.
  std::vector<double> patch_areas() const {
    const Vec3 side = 2.0 * half_;
    const double disks = 3.0 * std::numbers::pi * hole_radius * hole_radius;
    const double wall = 2.0 * std::numbers::pi * hole_radius * side.z();
    const double end = side.y() * side.z(), front = side.x() * side.z(), top = side.x() * side.y() - disks;
    return {end, end, front, front, top, top, wall, wall, wall};
  }

  // How far (x, y) lies inside a hole's disk: 0 when in no disk.
  static double depth_in_hole(double x, double y) {
    for (const double cx : hole_x) {
      const double r = std::hypot(x - cx, y);
      if (r < hole_radius) return hole_radius - r;
    }
    return 0.0;
  }

  void sample_face(int face, Rng& rng, PointCloud& cloud) const {
    const int axis = face_axis(face);
    Vec3 p;
    do {
      for (int a = 0; a < 3; ++a) p[a] = (2.0 * uniform(rng) - 1.0) * half_[a];
    } while (axis == 2 && depth_in_hole(p.x(), p.y()) > 0.0);
    p[axis] = face_sign(face) * half_[axis];
    Vec3 normal = Vec3::Zero();
    normal[axis] = face_sign(face);
    cloud.positions.push_back(p);
    cloud.normals.push_back(normal);
  }

  // A hole wall's outward normal points into the hole, towards its axis.
  void sample_wall(std::size_t hole, Rng& rng, PointCloud& cloud) const {
    const double phi = 2.0 * std::numbers::pi * uniform(rng);
    const double z = (2.0 * uniform(rng) - 1.0) * half_.z();
    const Vec3 radial(std::cos(phi), std::sin(phi), 0.0);
    cloud.positions.push_back(Vec3(hole_x[hole], 0.0, z) + hole_radius * radial);
    cloud.normals.push_back(-radial);
  }

  // A face is a region of its plane: sqrt(h^2 + d^2), h the height over the
  // plane and d the distance within the plane from p's projection to the
  // region: to the rectangle when outside it, to a hole's circle when
  // inside a hole (the holes never reach the rim), 0 otherwise.
  double face_distance(const Vec3& p, int face) const {
    const int axis = face_axis(face), u = (axis + 1) % 3, v = (axis + 2) % 3;
    const double h = p[axis] - face_sign(face) * half_[axis];
    const double du = std::max(std::abs(p[u]) - half_[u], 0.0);
    const double dv = std::max(std::abs(p[v]) - half_[v], 0.0);
    double d = std::hypot(du, dv);
    if (axis == 2 && d == 0.0) d = depth_in_hole(p.x(), p.y());
    return std::hypot(h, d);
  }

  // A finite cylinder wall (no caps): radially |rho - r|, and along the axis
  // the distance past its end.
  double wall_distance(const Vec3& p, std::size_t hole) const {
    const double rho = std::hypot(p.x() - hole_x[hole], p.y());
    return std::hypot(rho - hole_radius, std::max(std::abs(p.z()) - half_.z(), 0.0));
  }
};

// The points at distance r from a segment along x: a cylinder and two
// hemispherical caps, which together make a sphere's area.
class Capsule final : public Shape {
 public:
  Capsule(double half_length, double radius) : half_(half_length), r_(radius) {}
  PointCloud sample(std::size_t n, std::uint64_t seed) const override {
    Rng rng(seed);
    const double side = 2.0 * std::numbers::pi * r_ * 2.0 * half_;
    PointCloud cloud;
    for (std::size_t i = 0; i < n; ++i) {
      Vec3 axis_point = Vec3::Zero(), normal;
      if (uniform(rng) * area() < side) {
        const double phi = 2.0 * std::numbers::pi * uniform(rng);
        axis_point.x() = (2.0 * uniform(rng) - 1.0) * half_;
        normal = Vec3(0.0, std::cos(phi), std::sin(phi));
      } else {
        // A point of a whole sphere: its half facing +x goes on the right cap.
        normal = unit_vector(rng);
        axis_point.x() = normal.x() >= 0.0 ? half_ : -half_;
      }
      cloud.positions.push_back(axis_point + r_ * normal);
      cloud.normals.push_back(normal);
    }
    return cloud;
  }
  double distance(const Vec3& p) const override {
    const Vec3 nearest(std::clamp(p.x(), -half_, half_), 0.0, 0.0);
    return std::abs((p - nearest).norm() - r_);
  }
  double area() const override { return 2.0 * std::numbers::pi * r_ * 2.0 * half_ + 4.0 * std::numbers::pi * r_ * r_; }
  int euler_characteristic() const override { return 2; }

 private:
  double half_, r_;
};

// Distance in the plane from m to the segment ab.
double segment_distance(const Vec2& m, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double length2 = ab.squaredNorm();
  const double t = length2 > 0.0 ? std::clamp((m - a).dot(ab) / length2, 0.0, 1.0) : 0.0;
  return (a + t * ab - m).norm();
}

// Where along a frustum band, from radius r1 (t = 0) to r2 (t = 1), a share
// u of its area lies. The band's width at t is proportional to its radius
// r1 + t (r2 - r1), so the area up to t is r1 t + (r2 - r1) t^2 / 2 (of a
// total (r1 + r2) / 2); the root of that quadratic is written in the form
// that stays accurate when r1 is close to r2.
double band_parameter(double r1, double r2, double u) {
  const double share = u * 0.5 * (r1 + r2);
  const double denominator = r1 + std::sqrt(std::max(r1 * r1 + 2.0 * (r2 - r1) * share, 0.0));
  return denominator > 0.0 ? std::min(2.0 * share / denominator, 1.0) : 0.0;
}

// A closed solid of revolution around its own z axis, given by its profile:
// a polyline in the meridian half-plane (rho, z), rho >= 0, that starts and
// ends on the axis and runs from bottom to top with the solid on its left
// (a cone: (0, 0), (r, 0), (0, h)). Each profile segment sweeps a frustum
// band of area pi (r1 + r2) length, and its outward normal in the
// half-plane is the segment's direction turned clockwise. The solid is then
// rotated and moved into place.
//
// The distance is measured in the meridian half-plane through p: the
// nearest point of a surface of revolution lies in that half-plane, so the
// 2D distance from (rho, z) to the profile is the exact 3D distance.
class SolidOfRevolution final : public Shape {
 public:
  SolidOfRevolution(std::vector<Vec2> profile, const Eigen::Matrix3d& rotation, Vec3 origin)
      : profile_(std::move(profile)), rotation_(rotation), origin_(std::move(origin)) {}
  PointCloud sample(std::size_t n, std::uint64_t seed) const override {
    return sample_by_area(n, seed, band_areas(), [this](std::size_t s, Rng& rng, PointCloud& cloud) {
      const Vec2 a = profile_[s], b = profile_[s + 1];
      const Vec2 m = a + band_parameter(a.x(), b.x(), uniform(rng)) * (b - a);
      const Vec2 direction = (b - a).normalized();
      const Vec2 outward(direction.y(), -direction.x());
      const double phi = 2.0 * std::numbers::pi * uniform(rng);
      const double c = std::cos(phi), sn = std::sin(phi);
      cloud.positions.push_back(origin_ + rotation_ * Vec3(m.x() * c, m.x() * sn, m.y()));
      cloud.normals.push_back(rotation_ * Vec3(outward.x() * c, outward.x() * sn, outward.y()));
    });
  }
  double distance(const Vec3& p) const override {
    const Vec3 q = rotation_.transpose() * (p - origin_);
    const Vec2 m(std::hypot(q.x(), q.y()), q.z());
    double d = std::numeric_limits<double>::infinity();
    for (std::size_t s = 0; s + 1 < profile_.size(); ++s)
      d = std::min(d, segment_distance(m, profile_[s], profile_[s + 1]));
    return d;
  }
  double area() const override {
    const std::vector<double> areas = band_areas();
    return std::accumulate(areas.begin(), areas.end(), 0.0);
  }
  int euler_characteristic() const override { return 2; }

 private:
  std::vector<double> band_areas() const {
    std::vector<double> areas;
    for (std::size_t s = 0; s + 1 < profile_.size(); ++s) {
      const Vec2 a = profile_[s], b = profile_[s + 1];
      areas.push_back(std::numbers::pi * (a.x() + b.x()) * (b - a).norm());
    }
    return areas;
  }

  std::vector<Vec2> profile_;
  Eigen::Matrix3d rotation_;
  Vec3 origin_;
};

// Several shapes as one: Union of the first and the union of the rest.
std::unique_ptr<Shape> unite(std::vector<std::unique_ptr<Shape>> pieces) {
  std::unique_ptr<Shape> all = std::move(pieces.back());
  for (std::size_t i = pieces.size() - 1; i-- > 0;) all = std::make_unique<Union>(std::move(pieces[i]), std::move(all));
  return all;
}

// An upright cone or cylinder standing on z = 0 at (x, 0, 0).
std::unique_ptr<Shape> standing(std::vector<Vec2> profile, double x) {
  return std::make_unique<SolidOfRevolution>(std::move(profile), Eigen::Matrix3d::Identity(), Vec3(x, 0.0, 0.0));
}

// A wavy height field z = h(x, y) over a square, sampled on a jittered grid:
// what a range scanner looking down at a landscape records (regular
// spacing, an open surface with one boundary). nx = ceil(sqrt(n)) samples per
// row, spacing s = 2 / nx, rows filled in turn (the last may be partial).
class Terrain final : public Shape {
 public:
  PointCloud sample(std::size_t n, std::uint64_t seed) const override {
    Rng rng(seed);
    PointCloud cloud;
    cloud.positions.reserve(n);
    cloud.normals.reserve(n);
    const auto nx = static_cast<std::size_t>(std::ceil(std::sqrt(static_cast<double>(n))));
    const double s = 2.0 / static_cast<double>(nx);
    std::uniform_real_distribution<double> jitter(-0.15 * s, 0.15 * s);
    for (std::size_t i = 0; i < n; ++i) {
      const double x = -1.0 + (static_cast<double>(i % nx) + 0.5) * s + jitter(rng);
      const double y = -1.0 + (static_cast<double>(i / nx) + 0.5) * s + jitter(rng);
      cloud.positions.emplace_back(x, y, height(x, y));
      cloud.normals.push_back(normal(x, y));
    }
    return cloud;
  }
  // The nearest point of the surface over [-1, 1]^2, by projected
  // Gauss-Newton on (x, y) from p's own (x, y): the slopes are gentle.
  double distance(const Vec3& p) const override {
    double x = std::clamp(p.x(), -1.0, 1.0), y = std::clamp(p.y(), -1.0, 1.0);
    for (int iteration = 0; iteration < 20; ++iteration) {
      const Vec3 r = Vec3(x, y, height(x, y)) - p;
      const Vec3 tx(1.0, 0.0, dx(x, y)), ty(0.0, 1.0, dy(x, y));
      // Solve the 2 x 2 normal equations [a b; b c] step = -(tx.r, ty.r).
      const double a = tx.dot(tx), b = tx.dot(ty), c = ty.dot(ty), det = a * c - b * b;
      const double gx = -tx.dot(r), gy = -ty.dot(r);
      const double sx = (c * gx - b * gy) / det, sy = (a * gy - b * gx) / det;
      x = std::clamp(x + sx, -1.0, 1.0);
      y = std::clamp(y + sy, -1.0, 1.0);
      if (std::abs(sx) + std::abs(sy) < 1e-14) break;
    }
    return (Vec3(x, y, height(x, y)) - p).norm();
  }
  double area() const override {
    // Midpoint rule on a 512 x 512 grid (the integrand is smooth).
    constexpr int m = 512;
    const double h = 2.0 / m;
    double sum = 0.0;
    for (int i = 0; i < m; ++i)
      for (int j = 0; j < m; ++j) {
        const double x = -1.0 + (i + 0.5) * h, y = -1.0 + (j + 0.5) * h;
        sum += std::sqrt(1.0 + dx(x, y) * dx(x, y) + dy(x, y) * dy(x, y));
      }
    return sum * h * h;
  }
  int euler_characteristic() const override { return 1; }  // a disc

 private:
  static double height(double x, double y) {
    return 0.15 * std::sin(2.0 * x) * std::cos(3.0 * y) + 0.05 * std::sin(5.0 * x + 4.0 * y);
  }
  static double dx(double x, double y) {
    return 0.3 * std::cos(2.0 * x) * std::cos(3.0 * y) + 0.25 * std::cos(5.0 * x + 4.0 * y);
  }
  static double dy(double x, double y) {
    return -0.45 * std::sin(2.0 * x) * std::sin(3.0 * y) + 0.2 * std::cos(5.0 * x + 4.0 * y);
  }
  static Vec3 normal(double x, double y) { return Vec3(-dx(x, y), -dy(x, y), 1.0).normalized(); }
};

// A surface made of axis-aligned rectangles: the boundary of a union of
// boxes that touch along faces, cut into the rectangles that stay on the
// outside. Each rectangle lies in the plane x_axis = level, spans
// [lo, hi] in the two other axes (axis + 1, axis + 2, in that order) and
// faces the `sign` side of its plane. Sampling by area; the distance is
// the least of the exact distances to the rectangles.
struct AxisRectangle {
  int axis = 0;
  double sign = 1.0;
  double level = 0.0;
  Vec2 lo, hi;
  [[nodiscard]] double area() const { return (hi - lo).prod(); }
};

class Rectangles final : public Shape {
 public:
  Rectangles(std::vector<AxisRectangle> rectangles, int euler) : rectangles_(std::move(rectangles)), euler_(euler) {}
  PointCloud sample(std::size_t n, std::uint64_t seed) const override {
    return sample_by_area(n, seed, areas(), [this](std::size_t r, Rng& rng, PointCloud& cloud) {
      const AxisRectangle& rect = rectangles_[r];
      Vec3 p, normal = Vec3::Zero();
      p[rect.axis] = rect.level;
      for (int k = 0; k < 2; ++k) p[(rect.axis + 1 + k) % 3] = rect.lo[k] + uniform(rng) * (rect.hi[k] - rect.lo[k]);
      normal[rect.axis] = rect.sign;
      cloud.positions.push_back(p);
      cloud.normals.push_back(normal);
    });
  }
  double distance(const Vec3& p) const override {
    double d = std::numeric_limits<double>::infinity();
    for (const AxisRectangle& rect : rectangles_) {
      const double h = p[rect.axis] - rect.level;
      const double du = std::max({rect.lo[0] - p[(rect.axis + 1) % 3], p[(rect.axis + 1) % 3] - rect.hi[0], 0.0});
      const double dv = std::max({rect.lo[1] - p[(rect.axis + 2) % 3], p[(rect.axis + 2) % 3] - rect.hi[1], 0.0});
      d = std::min(d, std::sqrt(h * h + du * du + dv * dv));
    }
    return d;
  }
  double area() const override {
    const std::vector<double> a = areas();
    return std::accumulate(a.begin(), a.end(), 0.0);
  }
  int euler_characteristic() const override { return euler_; }

 private:
  std::vector<double> areas() const {
    std::vector<double> a;
    for (const AxisRectangle& rect : rectangles_) a.push_back(rect.area());
    return a;
  }
  std::vector<AxisRectangle> rectangles_;
  int euler_;
};

// The six faces of the box [lo, hi], less the one on `skip_axis`'s
// `skip_sign` side (none when skip_axis is -1).
void add_box_faces(const Vec3& lo, const Vec3& hi, int skip_axis, double skip_sign, std::vector<AxisRectangle>& out) {
  for (int axis = 0; axis < 3; ++axis)
    for (const double sign : {1.0, -1.0}) {
      if (axis == skip_axis && sign == skip_sign) continue;
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      out.push_back({axis, sign, sign > 0.0 ? hi[axis] : lo[axis], Vec2(lo[u], lo[v]), Vec2(hi[u], hi[v])});
    }
}

// A closed polygon in the (u, v) plane, counter-clockwise, extruded along w
// from 0 to `span`, closed by two flat caps, then turned by `rotation` and
// moved by `origin`.
// Each polygon edge sweeps a rectangular wall whose outward normal is the
// edge's direction turned clockwise. A cap is sampled by rejection from
// the polygon's bounding rectangle. The distance is exact: the least of
// the distances to the walls (2D distance to the edge, and how far past
// the ends along w) and to the caps (height over the cap, and 2D distance
// to the polygon where p's projection falls outside it).
class Prism final : public Shape {
 public:
  Prism(std::vector<Vec2> polygon, double span, const Eigen::Matrix3d& rotation, Vec3 origin)
      : polygon_(std::move(polygon)), span_(span), rotation_(rotation), origin_(std::move(origin)) {
    for (const Vec2& q : polygon_) {
      lo_ = lo_.cwiseMin(q);
      hi_ = hi_.cwiseMax(q);
    }
  }
  PointCloud sample(std::size_t n, std::uint64_t seed) const override {
    return sample_by_area(n, seed, patch_areas(), [this](std::size_t patch, Rng& rng, PointCloud& cloud) {
      const std::size_t edges = polygon_.size();
      Vec3 local, normal;
      if (patch < edges) {
        const Vec2 a = polygon_[patch], b = polygon_[(patch + 1) % edges];
        const Vec2 m = a + uniform(rng) * (b - a), d = (b - a).normalized();
        local = Vec3(m.x(), m.y(), uniform(rng) * span_);
        normal = Vec3(d.y(), -d.x(), 0.0);
      } else {
        Vec2 m;
        do m = lo_ + Vec2(uniform(rng), uniform(rng)).cwiseProduct(hi_ - lo_);
        while (!inside(m));
        const bool top = patch == edges + 1;
        local = Vec3(m.x(), m.y(), top ? span_ : 0.0);
        normal = Vec3(0.0, 0.0, top ? 1.0 : -1.0);
      }
      cloud.positions.push_back(origin_ + rotation_ * local);
      cloud.normals.push_back(rotation_ * normal);
    });
  }
  double distance(const Vec3& p) const override {
    const Vec3 q = rotation_.transpose() * (p - origin_);
    const Vec2 m(q.x(), q.y());
    double edge = std::numeric_limits<double>::infinity();
    for (std::size_t e = 0; e < polygon_.size(); ++e)
      edge = std::min(edge, segment_distance(m, polygon_[e], polygon_[(e + 1) % polygon_.size()]));
    const double past_ends = std::max({-q.z(), q.z() - span_, 0.0});
    const double walls = std::hypot(edge, past_ends);
    const double outside = inside(m) ? 0.0 : edge;
    const double caps = std::hypot(std::min(std::abs(q.z()), std::abs(q.z() - span_)), outside);
    return std::min(walls, caps);
  }
  double area() const override {
    const std::vector<double> a = patch_areas();
    return std::accumulate(a.begin(), a.end(), 0.0);
  }
  int euler_characteristic() const override { return 2; }

 private:
  // Patches: one wall per edge, then the bottom cap (w = 0) and the top.
  std::vector<double> patch_areas() const {
    std::vector<double> areas;
    double twice_area = 0.0;
    for (std::size_t e = 0; e < polygon_.size(); ++e) {
      const Vec2 a = polygon_[e], b = polygon_[(e + 1) % polygon_.size()];
      areas.push_back((b - a).norm() * span_);
      twice_area += a.x() * b.y() - b.x() * a.y();
    }
    areas.push_back(0.5 * twice_area);
    areas.push_back(0.5 * twice_area);
    return areas;
  }
  // Even-odd rule: a ray towards +u crosses the boundary an odd number of times.
  bool inside(const Vec2& m) const {
    bool odd = false;
    for (std::size_t e = 0, f = polygon_.size() - 1; e < polygon_.size(); f = e++) {
      const Vec2 &a = polygon_[e], &b = polygon_[f];
      if ((a.y() > m.y()) != (b.y() > m.y()) && m.x() < a.x() + (m.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y()))
        odd = !odd;
    }
    return odd;
  }

  std::vector<Vec2> polygon_;
  double span_;
  Eigen::Matrix3d rotation_;
  Vec3 origin_;
  Vec2 lo_ = Vec2::Constant(std::numeric_limits<double>::infinity());
  Vec2 hi_ = Vec2::Constant(-std::numeric_limits<double>::infinity());
};

// The symmetric NACA four-digit section of chord 1 and greatest thickness
// `thickness` (at 30 % of the chord), with the closed trailing edge (the
// last coefficient -0.1036 instead of -0.1015): its half-thickness falls
// to exactly 0 at x = 1. Cosine spacing puts more vertices near the round
// leading edge; counter-clockwise from the trailing edge over the top.
std::vector<Vec2> naca_section(double thickness, int vertices_per_side) {
  auto half = [thickness](double x) {
    return 5.0 * thickness *
           (0.2969 * std::sqrt(x) - 0.1260 * x - 0.3516 * x * x + 0.2843 * x * x * x - 0.1036 * x * x * x * x);
  };
  std::vector<Vec2> polygon;
  for (int i = 0; i < vertices_per_side; ++i) {  // top: x from 1 down to 0
    const double x = 0.5 * (1.0 + std::cos(std::numbers::pi * i / vertices_per_side));
    polygon.emplace_back(x, i == 0 ? 0.0 : half(x));
  }
  for (int i = vertices_per_side; i > 0; --i) {  // bottom: x from 0 up to (not including) 1
    const double x = 0.5 * (1.0 + std::cos(std::numbers::pi * i / vertices_per_side));
    polygon.emplace_back(x, -half(x));
  }
  return polygon;
}

}  // namespace

std::unique_ptr<Shape> make_terrain() { return std::make_unique<Terrain>(); }

std::unique_ptr<Shape> make_sphere(double radius, Vec3 centre) { return std::make_unique<Sphere>(radius, centre); }
std::unique_ptr<Shape> make_torus(double major, double minor) {
  return std::make_unique<Torus>(major, minor, Vec3::Zero());
}
std::unique_ptr<Shape> make_ellipsoid(double a, double b, double c) {
  return std::make_unique<Ellipsoid>(Vec3(a, b, c));
}
std::unique_ptr<Shape> make_box(Vec3 sides) { return std::make_unique<Cuboid>(sides); }
std::unique_ptr<Shape> make_sphere_and_torus(double gap) {
  // Torus (R = 1, r = 0.35) around the origin; sphere of radius 0.6 beside it.
  const double x = 1.0 + 0.35 + gap + 0.6;
  return std::make_unique<Union>(std::make_unique<Sphere>(0.6, Vec3(x, 0.0, 0.0)),
                                 std::make_unique<Torus>(1.0, 0.35, Vec3::Zero()));
}

std::unique_ptr<Shape> make_hollow_ball(double outer, double inner) {
  return std::make_unique<Union>(std::make_unique<Sphere>(outer, Vec3::Zero()),
                                 std::make_unique<Sphere>(inner, Vec3::Zero(), -1.0));
}
std::unique_ptr<Shape> make_nested_balls() {
  return std::make_unique<Union>(make_hollow_ball(), std::make_unique<Sphere>(0.3, Vec3::Zero()));
}

std::unique_ptr<Shape> make_plate(double thickness) { return std::make_unique<Cuboid>(Vec3(2.0, 1.0, thickness)); }

std::unique_ptr<Shape> make_club(double thickness) {
  // The blade [0, 1] x [-t/2, t/2] x [0, 0.3]; the handle, 0.1 x 0.1 in
  // section, stands on its top from x = 0.05 to 0.15 and rises to z = 1.5.
  const double t = thickness, w = 0.1, top = 0.3, x0 = 0.05, x1 = x0 + w;
  std::vector<AxisRectangle> rectangles;
  add_box_faces(Vec3(0.0, -t / 2, 0.0), Vec3(1.0, t / 2, top), 2, 1.0, rectangles);
  add_box_faces(Vec3(x0, -w / 2, top), Vec3(x1, w / 2, top + 1.2), 2, -1.0, rectangles);
  // The blade's top, less the handle's foot (the handle is the wider);
  // the handle's underside, less the blade (two strips hang over it).
  // The plane z = top is axis 2: its rectangles span (x, y).
  rectangles.push_back({2, 1.0, top, Vec2(0.0, -t / 2), Vec2(x0, t / 2)});
  rectangles.push_back({2, 1.0, top, Vec2(x1, -t / 2), Vec2(1.0, t / 2)});
  rectangles.push_back({2, -1.0, top, Vec2(x0, -w / 2), Vec2(x1, -t / 2)});
  rectangles.push_back({2, -1.0, top, Vec2(x0, t / 2), Vec2(x1, w / 2)});
  return std::make_unique<Rectangles>(std::move(rectangles), 2);
}

std::unique_ptr<Shape> make_airfoil(double thickness) {
  // The section in (x, z) (turned a quarter about x: the section's v
  // becomes z, the span runs along -y), centred on the origin.
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(std::numbers::pi / 2.0, Vec3::UnitX()).toRotationMatrix();
  std::vector<Vec2> polygon = naca_section(thickness, 100);
  for (Vec2& q : polygon) q.x() -= 0.5;
  return std::make_unique<Prism>(std::move(polygon), 1.5, turn, Vec3(0.0, 0.75, 0.0));
}

std::unique_ptr<Shape> make_cup(double thickness) {
  // Outer radius 0.5, height 0.8: outside bottom, outer wall, rim, inner
  // wall, floor, each a band of the profile.
  const double r = 0.5, h = 0.8, t = thickness;
  return std::make_unique<SolidOfRevolution>(
      std::vector<Vec2>{{0.0, 0.0}, {r, 0.0}, {r, h}, {r - t, h}, {r - t, t}, {0.0, t}}, Eigen::Matrix3d::Identity(),
      Vec3::Zero());
}

std::unique_ptr<Shape> make_cavity_cube(double thickness) {
  return std::make_unique<Union>(make_box(Vec3::Constant(1.0)),
                                 std::make_unique<Sphere>(0.5 - thickness, Vec3::Zero(), -1.0));
}

std::unique_ptr<Shape> make_two_cavities(double thickness) {
  return std::make_unique<Union>(make_hollow_ball(1.0, 1.0 - thickness), make_hollow_ball(0.55, 0.55 - thickness));
}

std::unique_ptr<Shape> make_machined_part() { return std::make_unique<MachinedPart>(); }
std::unique_ptr<Shape> make_handle() { return std::make_unique<Capsule>(1.0, 0.08); }

std::vector<std::unique_ptr<Shape>> make_conics_pieces() {
  auto cone = [](double r, double h) { return std::vector<Vec2>{{0.0, 0.0}, {r, 0.0}, {0.0, h}}; };
  auto cylinder = [](double r, double z0, double z1) {
    return std::vector<Vec2>{{0.0, z0}, {r, z0}, {r, z1}, {0.0, z1}};
  };
  const Eigen::Matrix3d tilt = Eigen::AngleAxisd(std::numbers::pi / 3.0, Vec3::UnitY()).toRotationMatrix();
  std::vector<std::unique_ptr<Shape>> pieces;
  pieces.push_back(standing(cone(0.12, 1.2), -1.7));
  pieces.push_back(standing(cone(0.35, 0.4), -0.8));
  pieces.push_back(standing(cylinder(0.2, 0.0, 0.5), 0.15));
  pieces.push_back(std::make_unique<SolidOfRevolution>(cylinder(0.15, -0.3, 0.3), tilt, Vec3(1.1, 0.0, 0.3)));
  pieces.push_back(make_sphere(0.25, Vec3(2.1, 0.0, 0.25)));
  return pieces;
}
std::unique_ptr<Shape> make_conics() { return unite(make_conics_pieces()); }

namespace {

// The thin solids' thickness: the default, or the one asked for if the
// shape has one and it lies within the shape's range.
struct ThicknessRange {
  const char* name;
  double fallback, low, high;  // default, and the open interval (low, high) it must lie in
};
constexpr std::array<ThicknessRange, 7> thickness_ranges = {{{"plate", 0.05, 0.0, 1.0},
                                                             {"club", 0.03, 0.0, 0.1},
                                                             {"airfoil", 0.12, 0.0, 0.5},
                                                             {"cup", 0.04, 0.0, 0.25},
                                                             {"cavity-cube", 0.1, 0.0, 0.5},
                                                             {"two-cavities", 0.1, 0.0, 0.3},
                                                             {"shell", 0.3, 0.0, 1.0}}};

std::string number(double x) {
  std::ostringstream out;
  out << x;
  return out.str();
}

std::optional<double> thickness_for(const std::string& name, std::optional<double> asked) {
  for (const ThicknessRange& range : thickness_ranges) {
    if (name != range.name) continue;
    if (!asked) return range.fallback;
    if (!(*asked > range.low && *asked < range.high))
      throw InvalidInputError("thickness " + number(*asked) + " out of range for '" + name +
                              "': it must lie strictly between " + number(range.low) + " and " + number(range.high));
    return asked;
  }
  if (asked)
    throw InvalidInputError("shape '" + name +
                            "' has no thickness (plate, club, airfoil, cup, cavity-cube, two-cavities and shell have)");
  return std::nullopt;
}

}  // namespace

std::unique_ptr<Shape> make_shape(const std::string& name, std::optional<double> thickness) {
  static const std::array<const char*, 17> known = {
      "sphere", "torus",  "ellipsoid", "box",  "two",     "terrain", "part",        "handle",      "conics",
      "shell",  "nested", "plate",     "club", "airfoil", "cup",     "cavity-cube", "two-cavities"};
  if (std::find(known.begin(), known.end(), name) == known.end())
    throw InvalidInputError("unknown shape '" + name +
                            "' (known: sphere, torus, ellipsoid, box, two, terrain, part, handle, conics, shell, "
                            "nested, plate, club, airfoil, cup, cavity-cube, two-cavities)");
  const std::optional<double> t = thickness_for(name, thickness);
  if (name == "sphere") return make_sphere();
  if (name == "torus") return make_torus();
  if (name == "ellipsoid") return make_ellipsoid();
  if (name == "box") return make_box();
  if (name == "two") return make_sphere_and_torus();
  if (name == "terrain") return make_terrain();
  if (name == "part") return make_machined_part();
  if (name == "handle") return make_handle();
  if (name == "conics") return make_conics();
  if (name == "nested") return make_nested_balls();
  if (name == "shell") return thickness ? make_hollow_ball(1.0, 1.0 - *t) : make_hollow_ball();
  if (name == "plate") return make_plate(*t);
  if (name == "club") return make_club(*t);
  if (name == "airfoil") return make_airfoil(*t);
  if (name == "cup") return make_cup(*t);
  if (name == "cavity-cube") return make_cavity_cube(*t);
  return make_two_cavities(*t);
}

void add_noise(PointCloud& cloud, double fraction, std::uint64_t seed) {
  const double sigma = fraction * bounding_box<3>(cloud.positions).diagonal();
  std::mt19937_64 rng(seed ^ 0x9e3779b97f4a7c15ULL);
  std::normal_distribution<double> gauss(0.0, sigma);
  for (auto& p : cloud.positions) p += Vec3(gauss(rng), gauss(rng), gauss(rng));
}

}  // namespace recon
