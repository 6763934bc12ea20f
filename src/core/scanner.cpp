// The range-scan simulator declared in shapes.h: a few views of a shape, a
// z-buffer per view over a dense sample of its true surface. See scan() there
// for the contract; the steps below follow its list.

#include "recon/core/errors.h"
#include "recon/core/shapes.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <vector>

namespace recon {
namespace {

using Rng = std::mt19937_64;

constexpr double view_distance = 2.5;           // eye to centre, in bounding radii
constexpr double min_incidence_cosine = 0.17;   // about 80 degrees: steeper hits return nothing
constexpr double depth_jump_footprints = 10.0;  // a neighbour this many footprints nearer: a mixed pixel
constexpr double dense_per_pixel = 6.0;         // dense samples per pixel at the nearest range
constexpr std::size_t probe_resolution = 64;    // pixels a side for measuring the coverage
constexpr std::size_t max_resolution = 4096;
constexpr std::size_t max_dense_points = 12000000;

// A pinhole camera at `eye` looking at the shape's centre, with a square
// image just covering the bounding sphere.
struct View {
  Vec3 eye;
  Eigen::Matrix3d to_camera;  // rows: right, up, forward
  double half_width = 0.0;    // of the image, in units of depth (tan of the half field of view)
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  // the misregistration, about the centre
  Vec3 translation = Vec3::Zero();
};

// Where the views stand: spread in azimuth around the vertical, at random
// elevations of 15 to 45 degrees above the centre (so the underside is
// never seen), each with its own small rigid error.
std::vector<View> place_views(const ScanOptions& options, const Vec3& centre, double radius, double diagonal) {
  Rng rng(options.seed ^ 0x5ca9f00dULL);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> g(0.0, 1.0);
  const double start = 2.0 * std::numbers::pi * u(rng);
  std::vector<View> views;
  for (std::size_t k = 0; k < options.views; ++k) {
    const double azimuth =
        start + 2.0 * std::numbers::pi * (static_cast<double>(k) + 0.3 * u(rng)) / static_cast<double>(options.views);
    const double elevation = (15.0 + 30.0 * u(rng)) * std::numbers::pi / 180.0;
    const Vec3 direction(std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth),
                         std::sin(elevation));
    View view;
    view.eye = centre + view_distance * radius * direction;
    const Vec3 forward = -direction;
    const Vec3 right = forward.cross(Vec3::UnitZ()).normalized();
    const Vec3 up = right.cross(forward);
    view.to_camera.row(0) = right.transpose();
    view.to_camera.row(1) = up.transpose();
    view.to_camera.row(2) = forward.transpose();
    view.half_width = 1.0 / std::sqrt(view_distance * view_distance - 1.0);
    // Drawn for every view, used or not, so a misregistration never moves the views themselves.
    Vec3 axis(g(rng), g(rng), g(rng)), shift(g(rng), g(rng), g(rng));
    if (options.misregistration > 0.0) {
      if (axis.norm() < 1e-9) axis = Vec3::UnitZ();
      if (shift.norm() < 1e-9) shift = Vec3::UnitX();
      view.rotation = Eigen::AngleAxisd(options.misregistration, axis.normalized()).toRotationMatrix();
      view.translation = options.misregistration * diagonal * shift.normalized();
    }
    views.push_back(view);
  }
  return views;
}

// One view's z-buffer: for each pixel, the dense sample nearest the eye
// among those that project into it and face the scanner steeply enough.
struct DepthImage {
  std::size_t width = 0;
  std::vector<double> depth;          // infinity where nothing was hit
  std::vector<std::uint32_t> sample;  // the dense sample seen there
  double pixel = 0.0;                 // pixel side, in units of depth
};

DepthImage render(const View& view, const PointCloud& dense, std::size_t width) {
  DepthImage image;
  image.width = width;
  image.pixel = 2.0 * view.half_width / static_cast<double>(width);
  image.depth.assign(width * width, std::numeric_limits<double>::infinity());
  image.sample.assign(width * width, 0);
  for (std::size_t i = 0; i < dense.size(); ++i) {
    const Vec3 ray = dense.positions[i] - view.eye;
    const double range = ray.norm();
    if (-dense.normals[i].dot(ray) < min_incidence_cosine * range) continue;  // back-facing or grazing
    const Vec3 q = view.to_camera * ray;
    const double col = (q.x() / q.z() + view.half_width) / image.pixel;
    const double row = (q.y() / q.z() + view.half_width) / image.pixel;
    if (!(col >= 0.0 && row >= 0.0 && col < static_cast<double>(width) && row < static_cast<double>(width))) continue;
    const std::size_t at = static_cast<std::size_t>(row) * width + static_cast<std::size_t>(col);
    if (q.z() < image.depth[at]) {
      image.depth[at] = q.z();
      image.sample[at] = static_cast<std::uint32_t>(i);
    }
  }
  return image;
}

// A hit much deeper than a neighbour's is a sample of a farther surface
// seen through a gap in the dense sample, or a pixel astride a depth edge
// (which real scanners also drop): either way, no return.
bool is_mixed_pixel(const DepthImage& image, std::size_t row, std::size_t col) {
  const double d = image.depth[row * image.width + col];
  const double jump = depth_jump_footprints * image.pixel * d;
  for (std::size_t r = row > 0 ? row - 1 : 0; r <= std::min(row + 1, image.width - 1); ++r)
    for (std::size_t c = col > 0 ? col - 1 : 0; c <= std::min(col + 1, image.width - 1); ++c)
      if (image.depth[r * image.width + c] < d - jump) return true;
  return false;
}

std::size_t covered_pixels(const DepthImage& image) {
  return static_cast<std::size_t>(
      std::count_if(image.depth.begin(), image.depth.end(), [](double d) { return std::isfinite(d); }));
}

// The returns of one view: each kept pixel's sample, moved along its ray
// by the range noise (its spread grows with the range, as a scanner's),
// then by the view's misregistration.
void add_returns(const View& view, const DepthImage& image, const PointCloud& dense, const Vec3& centre, double sigma,
                 Rng& rng, PointCloud& cloud) {
  std::normal_distribution<double> g(0.0, 1.0);
  const double mean_range = (view.eye - centre).norm();
  for (std::size_t row = 0; row < image.width; ++row)
    for (std::size_t col = 0; col < image.width; ++col) {
      const std::size_t at = row * image.width + col;
      if (!std::isfinite(image.depth[at]) || is_mixed_pixel(image, row, col)) continue;
      const Vec3& p = dense.positions[image.sample[at]];
      const Vec3 ray = p - view.eye;
      const double range = ray.norm();
      const Vec3 noisy = sigma > 0.0 ? Vec3(p + ray / range * (sigma * range / mean_range * g(rng))) : p;
      cloud.positions.push_back(centre + view.rotation * (noisy - centre) + view.translation);
      cloud.normals.push_back(view.rotation * dense.normals[image.sample[at]]);
    }
}

}  // namespace

PointCloud scan(const Shape& shape, const ScanOptions& options) {
  if (options.views == 0 || options.views > 64)
    throw InvalidInputError("a scan needs at least one view (--scan 1 to 64)");
  if (options.points == 0) throw InvalidInputError("a scan needs a positive number of points");
  if (!(options.noise >= 0.0 && options.noise < 1.0) ||
      !(options.misregistration >= 0.0 && options.misregistration < 1.0))
    throw InvalidInputError("scan noise and misregistration must lie in [0, 1)");
  // Step 1: the bounding sphere, from a first sample.
  const PointCloud probe = shape.sample(200000, options.seed ^ 0x0b5e55edULL);
  const Box<3> box = bounding_box<3>(probe.positions);
  const Vec3 centre = 0.5 * (box.min + box.max);
  const double diagonal = box.diagonal(), radius = 0.5 * diagonal;
  const std::vector<View> views = place_views(options, centre, radius, diagonal);
  // Step 2: the resolution that gives about `points` returns, from the
  // share of a coarse image each view covers.
  std::size_t probe_hits = 0;
  for (const View& view : views) probe_hits += covered_pixels(render(view, probe, probe_resolution));
  const double per_pixel = static_cast<double>(std::max<std::size_t>(probe_hits, 1)) /
                           static_cast<double>(probe_resolution * probe_resolution);
  const auto width = std::clamp<std::size_t>(
      static_cast<std::size_t>(std::ceil(std::sqrt(static_cast<double>(options.points) / per_pixel))), 8,
      max_resolution);
  // Step 3: a dense sample with a few samples in every pixel's footprint at
  // the nearest range, so that a pixel's first hit is on the nearest surface.
  const double footprint = (view_distance - 1.0) * radius * 2.0 * views.front().half_width / static_cast<double>(width);
  const auto dense_count = std::min<std::size_t>(
      static_cast<std::size_t>(std::ceil(dense_per_pixel * shape.area() / (footprint * footprint))), max_dense_points);
  const PointCloud dense = shape.sample(std::max<std::size_t>(dense_count, options.points), options.seed);
  // Step 4: each view's z-buffer, its returns with noise and misregistration.
  Rng rng(options.seed ^ 0x7a11c0deULL);
  PointCloud cloud;
  for (const View& view : views)
    add_returns(view, render(view, dense, width), dense, centre, options.noise * diagonal, rng, cloud);
  return cloud;
}

}  // namespace recon
