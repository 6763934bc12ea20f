#pragma once
// Point samples of shapes whose surface is known exactly: the inputs of the
// tests, the benchmarks and `recon generate`. Each sample comes with the true
// outward normals, and each shape can measure the distance from any point to
// its true surface, so results can be checked against the truth.
//
// Sampling is uniform by area (a Poisson sample: random, with the clumps and
// gaps of random data), except the terrain's, which is grid-like as a
// scanner's; all are reproducible from `seed`.

#include "recon/core/point_cloud.h"

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace recon {

class Shape {
 public:
  virtual ~Shape() = default;
  /// n points uniform by area, with their true outward normals; the same for the same seed.
  /// Cost: O(n) expected (rejection sampling where a patch is not a rectangle).
  /// Throws: nothing.
  /// Pre: none.
  [[nodiscard]] virtual PointCloud sample(std::size_t n, std::uint64_t seed) const = 0;
  /// Unsigned distance from p to the true surface.
  /// Cost: O(1) (a closed form, or at most a fixed number of Newton steps).
  /// Throws: nothing.
  /// Pre: p finite.
  [[nodiscard]] virtual double distance(const Vec3& p) const = 0;
  [[nodiscard]] virtual double area() const = 0;
  /// Euler characteristic of the surface (2 - 2 genus per closed piece).
  [[nodiscard]] virtual int euler_characteristic() const = 0;
  [[nodiscard]] virtual int components() const { return 1; }
};

/// The factories below (make_sphere to make_conics_pieces) make the shapes described.
/// Cost: O(1) each.
/// Throws: nothing.
/// Pre: positive sizes (not checked).
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
/// characteristic 1. Its distance() follows the surface from p's own
/// (x, y): exact near the surface (within 0.3 of it, where the tests ask),
/// it may come out too large farther away.
[[nodiscard]] std::unique_ptr<Shape> make_terrain();

/// A machined part, the kind of solid a CAD model describes: the slab
/// [-1, 1] x [-0.5, 0.5] x [-0.2, 0.2] with three vertical round holes of
/// radius 0.18 drilled through it, their axes at x = -0.6, 0, 0.6 (y = 0).
/// Every hole stays 0.32 from the slab's rim and 0.24 from its neighbour.
/// The surface has 11 patches: top and bottom (rectangles minus three
/// disks), four side faces, three hole walls (their normals point towards
/// the hole's axis, out of the solid). It has sharp creases (the edges of
/// the slab, the rims of the holes) and corners, which smooth shapes lack.
/// Genus 3: Euler characteristic 2 - 2 * 3 = -4, one component.
[[nodiscard]] std::unique_ptr<Shape> make_machined_part();

/// A long thin capsule: the points at distance 0.08 from the segment from
/// (-1, 0, 0) to (1, 0, 0) (a cylinder closed by two hemispheres). Genus 0.
/// Thin features are where a reconstruction's neighbourhoods reach across
/// to the far side.
[[nodiscard]] std::unique_ptr<Shape> make_handle();

/// The course's data set: five separate closed solids in one cloud (about
/// 16,000 points when `recon generate` writes it), standing on z = 0 in a
/// row along x, at least 0.3 apart:
///   0. a tall narrow cone, apex up (base radius 0.12, height 1.2), at x = -1.7;
///   1. a short wide cone, apex up (base radius 0.35, height 0.4), at x = -0.8;
///   2. an upright cylinder (radius 0.2, height 0.5, flat cap on top), at x = 0.15;
///   3. a cylinder lying tilted (radius 0.15, length 0.6, its axis 60 degrees
///      from vertical in the x-z plane), centred at (1.1, 0, 0.3);
///   4. a sphere of radius 0.25 centred at (2.1, 0, 0.25).
/// Each cone is closed by its base disk, each cylinder by two caps.
/// Why the course used it: orienting normals (phase II) starts at the
/// highest point of each piece, where the outward normal is known to point
/// up, so every separate piece needs its own start, and the highest point
/// is not always on a smooth cap: the tall narrow cone's highest point is
/// its apex (a tip with no tangent plane), the tilted cylinder's is on the
/// rim between a cap and its side (a crease). An orientation that handles
/// those starts gets no piece inside out.
/// Five components, Euler characteristic 5 * 2 = 10.
[[nodiscard]] std::unique_ptr<Shape> make_conics();
/// The five pieces of make_conics(), in the order listed there (to tell
/// which piece a point of its sample belongs to: the nearest).
[[nodiscard]] std::vector<std::unique_ptr<Shape>> make_conics_pieces();

/// A hollow ball: the sphere of radius `outer` around the origin and, inside
/// it, the wall of a spherical cavity of radius `inner`, whose true normals
/// point into the cavity (out of the material). Two components, Euler
/// characteristic 4; the two walls are sampled by area (the inner gets
/// (inner / outer)^2 of the outer's share).
[[nodiscard]] std::unique_ptr<Shape> make_hollow_ball(double outer = 1.0, double inner = 0.7);
/// make_hollow_ball() with a solid ball of radius 0.3 in its cavity (normals
/// outward again: material inside the cavity). Three components, Euler
/// characteristic 6.
[[nodiscard]] std::unique_ptr<Shape> make_nested_balls();

/// Adds Gaussian noise to every position: each coordinate gets an
/// independent offset of standard deviation `fraction` times the diagonal
/// of the cloud's bounding box (the scale `recon generate --noise` and the
/// evaluation scripts use). Reproducible from `seed`; normals are kept.
/// Cost: O(n).
/// Throws: nothing.
/// Pre: fraction > 0 and at least two distinct positions (std::normal_distribution needs a positive spread).
void add_noise(PointCloud& cloud, double fraction, std::uint64_t seed);

/// How scan() looks at a shape (the options of `recon generate --scan`).
struct ScanOptions {
  std::size_t views = 4;         ///< viewpoints around the shape, 1 to 64
  std::size_t points = 100000;   ///< about how many points all the views return together
  double noise = 0.0;            ///< range noise: std. deviation along the ray, a fraction of the diagonal
  double misregistration = 0.0;  ///< each view's rigid error: radians of rotation, and that fraction of the diagonal
  std::uint64_t seed = 1;
};

/// What a range scanner standing at a few places around the shape records:
/// holes where no view sees the surface, noise along the rays, more points
/// near the scanner, views that do not quite line up.
///   - The views stand 2.5 bounding radii from the centre of the shape's
///     bounding box, spread evenly in azimuth around the z axis (with a
///     random start and jitter), 15 to 45 degrees above the centre: the
///     underside and every self-shadowed region get no points (real holes).
///   - Each view is a pinhole camera whose square image just covers the
///     bounding sphere; a pixel returns the first surface point along its
///     ray. The first hit is found by a z-buffer over a dense sample of the
///     true surface (about six samples per pixel footprint at the nearest
///     range) rather than by casting rays, because every Shape can sample
///     itself but only some can tell inside from outside.
///   - A pixel returns nothing where the surface is seen at more than about
///     80 degrees from its normal (or from behind), or where a neighbouring
///     pixel is nearer by more than ten pixel footprints (a pixel astride a
///     depth edge, which scanners also drop).
///   - The image resolution is set so all views together return about
///     `points` points (a first coarse rendering measures the coverage).
///     The density on the surface falls with the square of the range and
///     with the slant, as a scanner's does.
///   - Each return moves along its ray by a Gaussian of standard deviation
///     noise x diagonal x (its range / the view's distance to the centre);
///     then the view's misregistration moves all its returns: a rotation
///     by `misregistration` radians about a random axis through the centre
///     and a shift of misregistration x diagonal in a random direction.
///   - The normals are the true outward normals of the points hit, turned
///     with their view's misregistration (not by the noise).
/// The same options give the same cloud. Points come view by view.
/// Cost: O(dense sample + views x pixels); the dense sample is capped at
/// 12 million points, the image at 4096 pixels a side.
/// Throws: InvalidInputError for no views, no points, or noise or
/// misregistration outside [0, 1).
/// Pre: shape's sample() is uniform by area (its density sets the dense sample's).
[[nodiscard]] PointCloud scan(const Shape& shape, const ScanOptions& options);

/// The thin solids: closed solids with two sheets close together, where a
/// reconstruction's neighbourhoods span both. `thickness` is in the same
/// units as the shape (absolute, not in multiples of a sample spacing:
/// the caller knows its point count and works out rho).
/// The box [-1, 1] x [-0.5, 0.5] x [-t/2, t/2]. Genus 0.
[[nodiscard]] std::unique_ptr<Shape> make_plate(double thickness = 0.05);
/// A golf club: a thin blade [0, 1] x [-t/2, t/2] x [0, 0.3] and a handle of
/// 0.1 x 0.1 section standing on its top (x from 0.05 to 0.15) up to z = 1.5.
/// Every face is axis-aligned; where the handle meets the blade the creases
/// are concave. One closed surface, genus 0.
/// Pre: 0 < thickness < 0.1 (the handle is the wider).
[[nodiscard]] std::unique_ptr<Shape> make_club(double thickness = 0.03);
/// A wing: the symmetric NACA four-digit section of chord 1 (x from -0.5
/// to 0.5), greatest thickness `thickness` at 30 % of the chord, with the
/// closed trailing edge (it thins to nothing at x = 0.5), as a polygon of
/// 200 vertices; extruded along y from -0.75 to 0.75 and closed by two flat
/// end caps. Convex. Genus 0.
[[nodiscard]] std::unique_ptr<Shape> make_airfoil(double thickness = 0.12);
/// A cup of outer radius 0.5 and height 0.8 standing on z = 0, with walls
/// and floor `thickness` thick: one solid of revolution whose outer and
/// inner walls meet at a flat rim (genus 0; a concave crease where the
/// inner wall meets the floor). Pre: 0 < thickness < 0.25.
[[nodiscard]] std::unique_ptr<Shape> make_cup(double thickness = 0.04);
/// The unit cube around the origin with a spherical cavity of radius
/// 0.5 - thickness at its centre (the wall is `thickness` at its thinnest,
/// at the faces' centres); the cavity's wall faces into it. Two
/// components, Euler characteristic 4.
[[nodiscard]] std::unique_ptr<Shape> make_cavity_cube(double thickness = 0.1);
/// Two nested cavities: a hollow ball (radii 1 and 1 - t) whose cavity
/// holds a second hollow ball (radii 0.55 and 0.55 - t), so the pieces'
/// sides alternate out, in, out, in with their depth. Four components,
/// Euler characteristic 8. Pre: 0 < thickness < 0.3.
[[nodiscard]] std::unique_ptr<Shape> make_two_cavities(double thickness = 0.1);

/// A shape by name, at its default sizes: "sphere", "torus", "ellipsoid", "box", "two" (sphere + torus),
/// "terrain", "part" (make_machined_part), "handle", "conics", "shell" (make_hollow_ball, outer radius 1,
/// the cavity's radius 1 - thickness), "nested" (make_nested_balls), and the thin solids "plate", "club",
/// "airfoil", "cup", "cavity-cube", "two-cavities" (make_plate to make_two_cavities) with the given
/// thickness, or their default one (shell: 0.3) without.
/// Cost: O(1).
/// Throws: InvalidInputError for another name, a thickness for a shape that has none, or a thickness
/// outside the shape's range (for each, the open interval from 0 to the bound its factory states;
/// plate below 1, airfoil below 0.5, shell below 1, cavity-cube below 0.5).
/// Pre: none.
[[nodiscard]] std::unique_ptr<Shape> make_shape(const std::string& name,
                                                std::optional<double> thickness = std::nullopt);

}  // namespace recon
