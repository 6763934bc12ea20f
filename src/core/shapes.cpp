#include "recon/core/shapes.h"

#include "recon/core/errors.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <random>

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

std::unique_ptr<Shape> make_shape(const std::string& name) {
  if (name == "sphere") return make_sphere();
  if (name == "torus") return make_torus();
  if (name == "ellipsoid") return make_ellipsoid();
  if (name == "box") return make_box();
  if (name == "two") return make_sphere_and_torus();
  if (name == "terrain") return make_terrain();
  if (name == "part") return make_machined_part();
  if (name == "handle") return make_handle();
  if (name == "conics") return make_conics();
  if (name == "shell") return make_hollow_ball();
  if (name == "nested") return make_nested_balls();
  throw InvalidInputError("unknown shape '" + name +
                          "' (known: sphere, torus, ellipsoid, box, two, terrain, part, handle, conics, shell, "
                          "nested)");
}

void add_noise(PointCloud& cloud, double fraction, std::uint64_t seed) {
  const double sigma = fraction * bounding_box<3>(cloud.positions).diagonal();
  std::mt19937_64 rng(seed ^ 0x9e3779b97f4a7c15ULL);
  std::normal_distribution<double> gauss(0.0, sigma);
  for (auto& p : cloud.positions) p += Vec3(gauss(rng), gauss(rng), gauss(rng));
}

}  // namespace recon
