#include "recon/phase5_refine/vertex_colors.h"

#include "recon/core/errors.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

namespace recon {
namespace {

constexpr int max_k = 64;

// The inverse-distance blend of one vertex's neighbours (nearest first).
Color blend(std::span<const Neighbor> nearest, std::span<const Color> colors) {
  const double floor2 = std::max(1e-6 * nearest.back().distance2, std::numeric_limits<double>::min());
  std::array<double, 3> sum{};
  double weights = 0.0;
  for (const Neighbor& n : nearest) {
    const double w = 1.0 / (n.distance2 + floor2);
    const Color& c = colors[n.index];
    for (std::size_t k = 0; k < 3; ++k) sum[k] += w * c[k];
    weights += w;
  }
  Color out{};
  for (std::size_t k = 0; k < 3; ++k)
    out[k] = static_cast<std::uint8_t>(std::lround(std::clamp(sum[k] / weights, 0.0, 255.0)));
  return out;
}

}  // namespace

std::vector<Color> vertex_colors(std::span<const Vec3> vertices, const KdTree<3>& samples,
                                 std::span<const Color> colors, const VertexColorOptions& options) {
  if (colors.size() != samples.size())
    throw InvalidInputError("vertex colours: " + std::to_string(colors.size()) + " colours for " +
                            std::to_string(samples.size()) + " samples");
  if (options.k < 1 || options.k > max_k)
    throw InvalidInputError("vertex colours: k must be from 1 to " + std::to_string(max_k) + ", not " +
                            std::to_string(options.k));
  std::vector<Color> out(vertices.size());
  if (vertices.empty()) return out;
  if (samples.empty()) throw InvalidInputError("vertex colours: there are no samples to take colours from");

  const std::size_t k = std::min(static_cast<std::size_t>(options.k), samples.size());
  const auto count = static_cast<std::int64_t>(vertices.size());
  // Vertices come in the mesh's order, which follows the lattice walk: a
  // static split gives each thread a region of the surface.
#pragma omp parallel for schedule(static)
  for (std::int64_t s = 0; s < count; ++s) {
    const auto v = static_cast<std::size_t>(s);
    std::array<Neighbor, max_k> nearest;
    const std::size_t found = samples.knn(vertices[v], std::span<Neighbor>(nearest.data(), k));
    out[v] = blend(std::span<const Neighbor>(nearest.data(), found), colors);
  }
  return out;
}

}  // namespace recon
