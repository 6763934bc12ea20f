#include "recon/tangent_planes.h"

#include "recon/errors.h"
#include "recon/pca.h"
#include "recon/timer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

namespace recon {
namespace {

constexpr int max_k = 256;

double median(std::vector<double> values) {
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

// Tells noise from curvature. A plane fitted to a curved, noise-free patch
// of radius r misses it by about r^2 / R, so doubling the neighbourhood
// (r grows by sqrt 2) doubles the residual; noise gives the same residual at
// any size. Measured on up to 2000 evenly spread points at 2k neighbours.
template <int D>
bool residual_is_noise(std::span<const Vec<D>> points, const TangentPlanes<D>& planes, int wider_k) {
  const std::size_t n = points.size();
  if (static_cast<std::size_t>(wider_k) > n) return false;
  const std::size_t step = std::max<std::size_t>(1, n / 2000);
  std::vector<double> residual;
  std::vector<Neighbor> neighbours(static_cast<std::size_t>(wider_k));
  std::vector<std::uint32_t> indices(neighbours.size());
  for (std::size_t i = 0; i < n; i += step) {
    planes.point_tree.knn(points[i], std::span<Neighbor>(neighbours));
    for (std::size_t j = 0; j < neighbours.size(); ++j) indices[j] = neighbours[j].index;
    residual.push_back(std::sqrt(fit_plane<D>(points, indices).eigenvalues[0]));
  }
  return median(std::move(residual)) < 1.4 * planes.noise;
}

}  // namespace

template <int D>
TangentPlanes<D> estimate_tangent_planes(std::span<const Vec<D>> points, const TangentPlaneOptions& options) {
  const std::size_t n = points.size();
  const int k = options.k;
  if (k < D || k > max_k)
    throw InvalidInputError("k = " + std::to_string(k) + " is out of range: a neighbourhood needs at least " +
                            std::to_string(D) + " points and at most " + std::to_string(max_k));
  if (options.rho && !(*options.rho > 0.0 && std::isfinite(*options.rho)))
    throw InvalidInputError("rho must be a positive length");
  for (std::size_t i = 0; i < n; ++i)
    if (!points[i].allFinite())
      throw InvalidInputError("point " + std::to_string(i) + " has a non-finite coordinate");
  if (n < static_cast<std::size_t>(k) + 1)
    throw InvalidInputError("only " + std::to_string(n) + " point" + (n == 1 ? "" : "s") + "; k = " +
                            std::to_string(k) + " needs at least " + std::to_string(k + 1) +
                            (n > static_cast<std::size_t>(D) + 1 ? " (lower --k)" : ": too few to fit a surface"));

  TangentPlanes<D> result;
  result.k = k;
  Timer timer;
  result.point_tree = KdTree<D>(points, options.tree);
  const KnnTable knn = result.point_tree.all_knn(k);
  result.seconds_knn = timer.lap();

  // A row's first entry is the smallest index among exact copies of the
  // query (ties go to the smaller index), so x_i is a first occurrence
  // exactly when it heads its own row.
  for (std::size_t i = 0; i < n; ++i) result.distinct_points += knn.row(i)[0].index == i ? 1u : 0u;
  if (result.distinct_points < static_cast<std::size_t>(k) + 1) {
    const std::size_t distinct = result.distinct_points;
    std::string message = "only " + std::to_string(distinct) + " distinct point" + (distinct == 1 ? "" : "s") +
                          " (of " + std::to_string(n) + "); k = " + std::to_string(k) + " needs at least " +
                          std::to_string(k + 1);
    message += distinct > static_cast<std::size_t>(D) + 1 ? " (lower --k)" : ": too few to fit a surface";
    throw InvalidInputError(message);
  }

  result.origins.resize(n);
  result.normals.resize(n);
  result.eigenvalues.resize(n);
  std::vector<double> nn_distance(n, 0.0);
  std::size_t degenerate = 0;
  const auto count = static_cast<std::int64_t>(n);
#pragma omp parallel for schedule(dynamic, 4096) reduction(+ : degenerate)
  for (std::int64_t s = 0; s < count; ++s) {
    const auto i = static_cast<std::size_t>(s);
    const auto row = knn.row(i);
    std::array<std::uint32_t, max_k> indices;  // k <= max_k: no allocation per point
    for (std::size_t j = 0; j < row.size(); ++j) indices[j] = row[j].index;
    const PlaneFit<D> fit = fit_plane<D>(points, std::span<const std::uint32_t>(indices.data(), row.size()));
    result.origins[i] = fit.centroid;
    result.normals[i] = fit.normal;
    result.eigenvalues[i] = fit.eigenvalues;
    // No unique normal when the two smallest spreads are both negligible
    // against the largest (the neighbourhood is a line or a point).
    if (fit.eigenvalues[1] <= 1e-12 * fit.eigenvalues[D - 1]) ++degenerate;
    for (const Neighbor& nb : row)
      if (nb.distance2 > 0.0) {
        nn_distance[i] = std::sqrt(nb.distance2);
        break;
      }
  }
  result.degenerate = degenerate;
  if (degenerate == n)
    throw InvalidInputError(D == 3 ? "all points lie on one line (or coincide): no surface to reconstruct"
                                   : "all points coincide: no curve to reconstruct");

  result.local_rho.resize(n);
  result.local_gap.resize(n);
  if (options.rho) {
    result.rho_given = true;
    result.rho = result.gap = *options.rho;
    std::fill(result.local_rho.begin(), result.local_rho.end(), *options.rho);
    std::fill(result.local_gap.begin(), result.local_gap.end(), *options.rho);
  } else {
    // How irregular the spacing is: the coefficient of variation of each
    // nearest-neighbour distance over the mean of its neighbourhood's (so a
    // density that varies smoothly does not count). Random samples give
    // about 0.5, scanners' grids 0.05 to 0.15.
    std::vector<double> relative(n, 1.0);
#pragma omp parallel for schedule(static)
    for (std::int64_t s = 0; s < count; ++s) {
      const auto i = static_cast<std::size_t>(s);
      const auto row = knn.row(i);
      double widest = 0.0, sum = 0.0;
      for (const Neighbor& nb : row) {
        widest = std::max(widest, nn_distance[nb.index]);
        sum += nn_distance[nb.index];
      }
      result.local_gap[i] = widest;
      if (sum > 0.0) relative[i] = nn_distance[i] * static_cast<double>(row.size()) / sum;
    }
    double mean = 0.0, variance = 0.0;
    for (double r : relative) mean += r;
    mean /= static_cast<double>(n);
    for (double r : relative) variance += (r - mean) * (r - mean);
    result.irregularity = std::sqrt(variance / static_cast<double>(n)) / mean;
    // rho_i, the radius within which every surface point has a sample:
    // 1.5 gap_i for a regular grid (its holes are at most ~0.7 spacing wide,
    // with room for scan lines farther apart than the points along them),
    // the whole neighbourhood radius for random samples, in between by the
    // irregularity.
    const double w = std::clamp((result.irregularity - 0.15) / 0.3, 0.0, 1.0);
#pragma omp parallel for schedule(static)
    for (std::int64_t s = 0; s < count; ++s) {
      const auto i = static_cast<std::size_t>(s);
      const double radius = std::sqrt(knn.row(i).back().distance2);
      const double regular = std::min(1.5 * result.local_gap[i], radius);
      result.local_rho[i] = regular + w * (radius - regular);
    }
    result.rho = median(result.local_rho);
    result.gap = median(result.local_gap);
    // A neighbourhood made only of copies of one point has no spacing to
    // measure: give it the typical one.
    for (std::size_t i = 0; i < n; ++i) {
      if (result.local_rho[i] == 0.0) result.local_rho[i] = result.rho;
      if (result.local_gap[i] == 0.0) result.local_gap[i] = result.gap;
    }
  }
  {
    std::vector<double> residual(n);
    for (std::size_t i = 0; i < n; ++i) residual[i] = std::sqrt(result.eigenvalues[i][0]);
    result.noise = median(std::move(residual));
  }
  result.seconds_pca = timer.lap();
  result.k_requested = k;

  constexpr double noise_limit = 0.1;  // noise / rho above which k is raised
  constexpr int max_adapted_k = 64;
  if (options.adapt_k && !options.rho && result.noise > noise_limit * result.rho && k < max_adapted_k &&
      residual_is_noise(points, result, 2 * k)) {
    const double wanted = std::ceil(k * result.noise / (noise_limit * result.rho));
    TangentPlaneOptions raised = options;
    raised.adapt_k = false;
    raised.k = static_cast<int>(std::min<double>(max_adapted_k, wanted));
    if (static_cast<std::size_t>(raised.k) + 1 <= result.distinct_points) {
      TangentPlanes<D> again = estimate_tangent_planes<D>(points, raised);
      again.k_requested = k;
      again.seconds_knn += result.seconds_knn;
      again.seconds_pca += result.seconds_pca;
      return again;
    }
  }
  return result;
}

template TangentPlanes<2> estimate_tangent_planes<2>(std::span<const Vec<2>>, const TangentPlaneOptions&);
template TangentPlanes<3> estimate_tangent_planes<3>(std::span<const Vec<3>>, const TangentPlaneOptions&);

}  // namespace recon
