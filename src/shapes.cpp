#include "recon/shapes.h"

#include "recon/errors.h"

#include <algorithm>
#include <cmath>
#include <numbers>
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

class Sphere final : public Shape {
 public:
  Sphere(double r, Vec3 c) : r_(r), c_(std::move(c)) {}
  PointCloud sample(std::size_t n, std::uint64_t seed) const override {
    Rng rng(seed);
    PointCloud cloud;
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3 u = unit_vector(rng);
      cloud.positions.push_back(c_ + r_ * u);
      cloud.normals.push_back(u);
    }
    return cloud;
  }
  double distance(const Vec3& p) const override { return std::abs((p - c_).norm() - r_); }
  double area() const override { return 4.0 * std::numbers::pi * r_ * r_; }
  int euler_characteristic() const override { return 2; }

 private:
  double r_;
  Vec3 c_;
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
  static double height(double x, double y) { return 0.15 * std::sin(2.0 * x) * std::cos(3.0 * y) + 0.05 * std::sin(5.0 * x + 4.0 * y); }
  static double dx(double x, double y) { return 0.3 * std::cos(2.0 * x) * std::cos(3.0 * y) + 0.25 * std::cos(5.0 * x + 4.0 * y); }
  static double dy(double x, double y) { return -0.45 * std::sin(2.0 * x) * std::sin(3.0 * y) + 0.2 * std::cos(5.0 * x + 4.0 * y); }
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

std::unique_ptr<Shape> make_shape(const std::string& name) {
  if (name == "sphere") return make_sphere();
  if (name == "torus") return make_torus();
  if (name == "ellipsoid") return make_ellipsoid();
  if (name == "box") return make_box();
  if (name == "two") return make_sphere_and_torus();
  if (name == "terrain") return make_terrain();
  throw InvalidInputError("unknown shape '" + name + "' (known: sphere, torus, ellipsoid, box, two, terrain)");
}

}  // namespace recon
