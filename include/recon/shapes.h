#pragma once
// Point samples of shapes whose surface is known exactly: the inputs of the
// tests, the benchmarks and `recon generate`. Each sample comes with the true
// outward normals, and each shape can measure the distance from any point to
// its true surface, so results can be checked against the truth.
//
// Sampling is uniform by area (a Poisson sample: random, with the clumps and
// gaps of random data), except the terrain's, which is grid-like as a
// scanner's; all are reproducible from `seed`.

#include "recon/point_cloud.h"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace recon {

class Shape {
 public:
  virtual ~Shape() = default;
  /// n points uniform by area, with their true outward normals.
  [[nodiscard]] virtual PointCloud sample(std::size_t n, std::uint64_t seed) const = 0;
  /// Unsigned distance from p to the true surface.
  [[nodiscard]] virtual double distance(const Vec3& p) const = 0;
  [[nodiscard]] virtual double area() const = 0;
  /// Euler characteristic of the surface (2 - 2 genus per closed piece).
  [[nodiscard]] virtual int euler_characteristic() const = 0;
  [[nodiscard]] virtual int components() const { return 1; }
};

[[nodiscard]] std::unique_ptr<Shape> make_sphere(double radius = 1.0, Vec3 centre = Vec3::Zero());
/// Ring of radius `major` around the z axis, tube radius `minor`.
[[nodiscard]] std::unique_ptr<Shape> make_torus(double major = 1.0, double minor = 0.35);
/// Semi-axes a, b, c along x, y, z.
[[nodiscard]] std::unique_ptr<Shape> make_ellipsoid(double a = 1.0, double b = 0.7, double c = 0.45);
/// Axis-aligned box centred at the origin with the given side lengths.
[[nodiscard]] std::unique_ptr<Shape> make_box(Vec3 sides = Vec3(1.0, 0.8, 0.6));
/// Sphere and torus side by side, `gap` apart at their closest.
[[nodiscard]] std::unique_ptr<Shape> make_sphere_and_torus(double gap = 0.5);

/// A scan-like open surface: the wavy height field
/// z = 0.15 sin 2x cos 3y + 0.05 sin(5x + 4y) over [-1, 1]^2, sampled on a
/// grid with 15 % jitter (rows of ceil(sqrt n) points; the last row may be
/// partial) rather than uniformly at random. One boundary, Euler
/// characteristic 1.
[[nodiscard]] std::unique_ptr<Shape> make_terrain();

/// By name: "sphere", "torus", "ellipsoid", "box", "two" (sphere + torus),
/// "terrain".
/// Throws InvalidInputError for another name.
[[nodiscard]] std::unique_ptr<Shape> make_shape(const std::string& name);

}  // namespace recon
