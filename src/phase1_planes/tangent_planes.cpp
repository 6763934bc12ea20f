#include "recon/phase1_planes/tangent_planes.h"

#include "recon/core/detail/mix64.h"
#include "recon/core/detail/parallel_for.h"
#include "recon/core/errors.h"
#include "recon/core/interruption.h"
#include "recon/core/progress.h"
#include "recon/core/timer.h"
#include "recon/phase1_planes/pca.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
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
// any size. Measured on the noise probes (about 2000 samples spread by a
// hash of their position) at 2k neighbours.
template <int D>
double probe_median(std::span<const Vec<D>> points, const TangentPlanes<D>& planes, int wider_k) {
  std::vector<double> residual;
  for (const Vec<D>& p : points)
    if (is_noise_probe<D>(p, points.size())) residual.push_back(probe_residual<D>(planes, points, p, wider_k));
  return probes_median(std::move(residual));
}

// Throws unless the options and the point count make a neighbourhood.
template <int D>
void check_request(std::size_t n, const TangentPlaneOptions& options) {
  const int k = options.k;
  if (k < D || k > max_k)
    throw InvalidInputError("k = " + std::to_string(k) + " is out of range: a neighbourhood needs at least " +
                            std::to_string(D) + " points and at most " + std::to_string(max_k));
  if (options.rho && !(*options.rho > 0.0 && std::isfinite(*options.rho)))
    throw InvalidInputError("rho must be a positive length");
  if (n < static_cast<std::size_t>(k) + 1)
    throw InvalidInputError("only " + std::to_string(n) + " point" + (n == 1 ? "" : "s") +
                            "; k = " + std::to_string(k) + " needs at least " + std::to_string(k + 1) +
                            (n > static_cast<std::size_t>(D) + 1 ? " (lower --k)" : ": too few to fit a surface"));
}

// What fitting one neighbourhood found, for the phase's counts.
struct FitFlags {
  bool distinct;    // x_i is no exact copy of an earlier point
  bool degenerate;  // no unique normal
};

// The plane through point i's neighbourhood `found` (k entries), kept in
// `result`, and the distance from x_i to its nearest distinct sample.
template <int D>
FitFlags fit_neighbourhood(TangentPlanes<D>& result, std::span<const Vec<D>> points, std::size_t i,
                           std::span<const Neighbor> found, float& nn_distance) {
  const std::size_t kk = found.size();
  std::uint32_t* row = result.neighbors.indices.data() + i * kk;
  for (std::size_t j = 0; j < kk; ++j) row[j] = found[j].index;
  // A row's first entry is the smallest index among exact copies of the
  // query (ties go to the smaller index), so x_i is a first occurrence
  // exactly when it heads its own row.
  const bool distinct = row[0] == i;
  const PlaneFit<D> fit = fit_plane<D>(points, std::span<const std::uint32_t>(row, kk));
  result.origins[i] = fit.centroid;
  result.normals[i] = fit.normal;
  result.eigenvalues[i] = fit.eigenvalues.template cast<float>();
  // No unique normal when the two smallest spreads are both negligible
  // against the largest (the neighbourhood is a line or a point).
  const bool degenerate = fit.eigenvalues[1] <= 1e-12 * fit.eigenvalues[D - 1];
  result.radius[i] = static_cast<float>(std::sqrt(found[kk - 1].distance2));
  for (std::size_t j = 0; j < kk; ++j)
    if (found[j].distance2 > 0.0) {
      nn_distance = static_cast<float>(std::sqrt(found[j].distance2));
      break;
    }
  return {distinct, degenerate};
}

// One pass per point: its k nearest neighbours, then the plane through
// them. Points are visited in the tree's leaf order, so consecutive queries
// touch the same nodes and the same neighbourhoods. Returns each point's
// distance to its nearest distinct sample (0 when it has none).
template <int D>
std::vector<float> fit_planes(TangentPlanes<D>& result, std::span<const Vec<D>> points) {
  const std::size_t n = points.size();
  const auto kk = static_cast<std::size_t>(result.k);
  result.neighbors.k = result.k;
  result.neighbors.indices.resize(n * kk);
  result.origins.resize(n);
  result.normals.resize(n);
  result.eigenvalues.resize(n);
  result.radius.resize(n);
  std::vector<float> nn_distance(n, 0.0f);
  std::size_t degenerate = 0, distinct = 0;
  const auto count = static_cast<std::int64_t>(n);
  const std::span<const std::uint32_t> leaf_order = result.point_tree.order();
  const std::span<const Vec<D>> tree_points = result.point_tree.points();
  ProgressCounter* const progress = progress_counter();
#pragma omp parallel reduction(+ : degenerate, distinct)
  {
    std::array<Neighbor, max_k> found;  // k <= max_k: no allocation per point
    // The previous query of this thread: its k neighbours are within its
    // k-th distance plus the step of this one, which bounds the search.
    std::int64_t previous = -2;
    Vec<D> previous_point = Vec<D>::Zero();
    double previous_radius = 0.0;
#pragma omp for schedule(dynamic, 1024)
    for (std::int64_t t = 0; t < count; ++t) {
      const auto i = static_cast<std::size_t>(leaf_order[static_cast<std::size_t>(t)]);
      const std::span<Neighbor> row_found(found.data(), kk);
      const Vec<D>& q = tree_points[static_cast<std::size_t>(t)];
      // A copy of the previous query has its answer already in `found` (a
      // mass of copies of one point, stored together, costs one query).
      if (previous != t - 1 || q != previous_point) {
        double within2 = std::numeric_limits<double>::infinity();
        if (previous == t - 1) {
          const double reach = (previous_radius + (q - previous_point).norm()) * (1.0 + 1e-9);
          within2 = reach * reach;
        }
        result.point_tree.knn(q, row_found, within2);
      }
      previous = t;
      previous_point = q;
      previous_radius = std::sqrt(found[kk - 1].distance2);
      const FitFlags flags = fit_neighbourhood<D>(result, points, i, row_found, nn_distance[i]);
      if (flags.distinct) ++distinct;
      if (flags.degenerate) ++degenerate;
      if (progress != nullptr && (t & 4095) == 4095) progress->advance(4096);
    }
  }
  result.distinct_points = distinct;
  result.degenerate = degenerate;
  return nn_distance;
}

// Throws when too few points are distinct, or no neighbourhood has a plane.
template <int D>
void check_fits(const TangentPlanes<D>& result) {
  const std::size_t n = result.origins.size(), distinct = result.distinct_points;
  const int k = result.k;
  if (distinct < static_cast<std::size_t>(k) + 1) {
    std::string message = "only " + std::to_string(distinct) + " distinct point" + (distinct == 1 ? "" : "s") +
                          " (of " + std::to_string(n) + "); k = " + std::to_string(k) + " needs at least " +
                          std::to_string(k + 1);
    message += distinct > static_cast<std::size_t>(D) + 1 ? " (lower --k)" : ": too few to fit a surface";
    throw InvalidInputError(message);
  }
  if (result.degenerate == n)
    throw InvalidInputError(D == 3 ? "all points lie on one line (or coincide): no surface to reconstruct"
                                   : "all points coincide: no curve to reconstruct");
}

// The noise: the median RMS distance of the neighbourhoods to their planes.
template <int D>
double noise_median(const TangentPlanes<D>& result) {
  const std::size_t n = result.eigenvalues.size();
  std::vector<double> residual(n);
  for (std::size_t i = 0; i < n; ++i) residual[i] = std::sqrt(static_cast<double>(result.eigenvalues[i][0]));
  return median(std::move(residual));
}

// A given rho replaces every rho_i and gap_i.
template <int D>
void use_given_rho(TangentPlanes<D>& result, double rho) {
  result.noise = noise_median(result);
  result.rho_given = true;
  result.rho = result.gap = rho;
  std::fill(result.local_rho.begin(), result.local_rho.end(), static_cast<float>(rho));
  std::fill(result.local_gap.begin(), result.local_gap.end(), static_cast<float>(rho));
}

// gap_i, and how irregular the spacing is: the coefficient of variation of
// each nearest-neighbour distance over the mean of its neighbourhood's (so
// a density that varies smoothly does not count). Random samples give
// about 0.5, scanners' grids 0.05 to 0.15.
// (Summed in fixed point: the sum depends neither on the thread count nor
// on the order of the terms; see SpacingSums.)
template <int D>
double local_gaps_and_irregularity(TangentPlanes<D>& result, const std::vector<float>& nn_distance, bool keep_parts) {
  const std::size_t n = nn_distance.size();
  const auto kk = static_cast<std::size_t>(result.k);
  std::vector<float> relative(n, 1.0f);
  detail::parallel_for(n, [&](std::size_t i) {
    float widest = 0.0f;
    double sum = 0.0;
    for (std::uint32_t j : result.neighbors.row(i)) {
      widest = std::max(widest, nn_distance[j]);
      sum += static_cast<double>(nn_distance[j]);
    }
    result.local_gap[i] = widest;
    if (sum > 0.0)
      relative[i] = static_cast<float>(static_cast<double>(nn_distance[i]) * static_cast<double>(kk) / sum);
  });
  SpacingSums sums;
  for (const float r : relative) sums.add(r);
  if (keep_parts) result.relative_spacing = std::move(relative);
  return sums.irregularity();
}

// rho_i, the radius within which every surface point has a sample: 1.5
// gap_i for a regular grid (its holes are at most ~0.7 spacing wide, with
// room for scan lines farther apart than the points along them), the whole
// neighbourhood radius for random samples, in between by the irregularity.
template <int D>
void local_rhos(TangentPlanes<D>& result) {
  detail::parallel_for(result.radius.size(), [&](std::size_t i) {
    result.local_rho[i] = local_rho_of(result.local_gap[i], result.radius[i], result.irregularity);
  });
}

// The median over the neighbourhoods that have a spacing: when most of the
// cloud is copies of a few points, theirs (0) would otherwise be the median.
double median_of_measured(const std::vector<float>& values) {
  std::vector<double> measured;
  measured.reserve(values.size());
  for (const float v : values)
    if (v > 0.0f) measured.push_back(static_cast<double>(v));
  return measured.empty() ? 0.0 : median(std::move(measured));
}

// gap_i, rho_i, and the cloud's medians of them and of the noise (or the
// whole cloud's, when given: the irregularity decides rho_i).
template <int D>
void measure_spacing(TangentPlanes<D>& result, const std::vector<float>& nn_distance,
                     const std::optional<CloudSpacing>& cloud, bool keep_parts) {
  result.irregularity = local_gaps_and_irregularity(result, nn_distance, keep_parts);
  if (keep_parts) result.raw_gap = result.local_gap;
  if (cloud) result.irregularity = cloud->irregularity;
  local_rhos(result);
  if (cloud) {
    result.rho = cloud->rho;
    result.gap = cloud->gap;
    result.noise = cloud->noise;
  } else {
    // (The three medians of the cloud, side by side.)
#pragma omp parallel sections
    {
#pragma omp section
      result.rho = median_of_measured(result.local_rho);
#pragma omp section
      result.gap = median_of_measured(result.local_gap);
#pragma omp section
      result.noise = noise_median(result);
    }
  }
  // A neighbourhood made only of copies of one point has no spacing to
  // measure and no plane: its gap is taken as the typical one (phase II
  // compares edges with it), and its rho_i stays 0, so that its plane, whose
  // normal is arbitrary, draws no surface (a scanner's "no return" written
  // as 0 0 0 thousands of times must not become a blob at the origin).
  for (float& gap : result.local_gap)
    if (gap == 0.0f) gap = static_cast<float>(result.gap);
}

// Isolated samples (see the header): a neighbourhood reaching more than
// isolation_factor times as far as those of the lower quarter of its
// neighbours'. Their rho_i = 0 leaves f undefined around them, so their
// planes draw no surface.
template <int D>
void mark_isolated(TangentPlanes<D>& result) {
  const auto count = static_cast<std::int64_t>(result.radius.size());
  std::size_t isolated = 0;
#pragma omp parallel reduction(+ : isolated)
  {
    std::vector<float> others;
#pragma omp for schedule(static)
    for (std::int64_t s = 0; s < count; ++s) {
      const auto i = static_cast<std::size_t>(s);
      if (result.radius[i] == 0.0f) {  // copies of one point only: no plane (see above), given rho or not
        result.local_rho[i] = 0.0f;
        continue;
      }
      const double limit = static_cast<double>(result.radius[i]) / isolation_factor;
      // Cheap first: no neighbour's radius under the limit, no quarter of them.
      bool any_below = false;
      for (std::uint32_t j : result.neighbors.row(i)) {
        const auto r_j = static_cast<double>(result.radius[j]);
        any_below = any_below || (j != i && r_j > 0.0 && r_j < limit);
      }
      if (!any_below) continue;
      others.clear();
      for (std::uint32_t j : result.neighbors.row(i))  // copies of one point have no radius to compare
        if (j != i && result.radius[j] > 0.0f) others.push_back(result.radius[j]);
      const auto quarter = others.begin() + static_cast<std::ptrdiff_t>(others.size() / 4);
      std::nth_element(others.begin(), quarter, others.end());
      if (static_cast<double>(*quarter) < limit) {
        result.local_rho[i] = 0.0f;
        ++isolated;
      }
    }
  }
  result.isolated = isolated;
}

// The k to run the phase again with when the noise is large against the
// neighbourhoods (see the header), or 0 when once is enough.
template <int D>
int adapted_k(std::span<const Vec<D>> points, const TangentPlanes<D>& result, const TangentPlaneOptions& options) {
  return raised_k(options, result.noise, result.rho, result.distinct_points, points.size(),
                  [&] { return probe_median<D>(points, result, 2 * options.k); });
}

// The phase over a built tree; `given` holds the points by index, or is
// empty when the tree is numbered by leaf order and its own copy serves.
template <int D>
TangentPlanes<D> planes_over(KdTree<D> tree, std::span<const Vec<D>> given, const TangentPlaneOptions& options,
                             double seconds_tree) {
  const std::span<const Vec<D>> points = given.empty() ? tree.points() : given;
  check_request<D>(points.size(), options);
  TangentPlanes<D> result;
  result.k = options.k;
  Timer timer;
  result.point_tree = std::move(tree);  // (moving keeps its buffers: `points` stays valid)
  result.seconds_tree = seconds_tree;

  const std::vector<float> nn_distance = fit_planes<D>(result, points);
  result.seconds_knn_pca = timer.lap();
  interruption_point();
  check_fits(result);
  result.local_rho.resize(points.size());
  result.local_gap.resize(points.size());
  if (options.rho)
    use_given_rho(result, *options.rho);
  else
    measure_spacing(result, nn_distance, options.cloud, options.keep_spacing_parts);
  mark_isolated(result);
  result.seconds_spacing = timer.lap();
  result.k_requested = options.k;

  if (const int raised_k = adapted_k<D>(points, result, options); raised_k > 0) {
    TangentPlaneOptions raised = options;
    raised.adapt_k = false;
    raised.k = raised_k;
    if (ProgressCounter* progress = progress_counter()) progress->expect(points.size());
    TangentPlanes<D> again = planes_over<D>(std::move(result.point_tree), given, raised, 0.0);
    again.k_requested = options.k;
    again.seconds_tree += result.seconds_tree;
    again.seconds_knn_pca += result.seconds_knn_pca;
    again.seconds_spacing += result.seconds_spacing;
    return again;
  }
  return result;
}

}  // namespace

void SpacingSums::add(float relative) {
  constexpr double scale = 1099511627776.0;      // 2^40
  const auto r = static_cast<double>(relative);  // (at most k: a neighbourhood's mean includes x_i's own)
  sum += static_cast<Wide>(std::llround(r * scale));
  sum2 += static_cast<Wide>(std::llround(r * r * scale));
  ++count;
}

void SpacingSums::add(const SpacingSums& other) {
  count += other.count;
  sum += other.sum;
  sum2 += other.sum2;
}

double SpacingSums::irregularity() const {
  if (count == 0 || sum == 0) return 0.0;
  constexpr double scale = 1099511627776.0;
  const auto n = static_cast<double>(count);
  const double mean = static_cast<double>(sum) / scale / n;
  const double variance = std::max(0.0, static_cast<double>(sum2) / scale / n - mean * mean);
  return std::sqrt(variance) / mean;
}

float local_rho_of(float gap, float radius, double irregularity) {
  const double w = std::clamp((irregularity - 0.15) / 0.3, 0.0, 1.0);
  const auto r = static_cast<double>(radius);
  const double regular = std::min(1.5 * static_cast<double>(gap), r);
  return static_cast<float>(regular + w * (r - regular));
}

template <int D>
bool is_noise_probe(const Vec<D>& p, std::size_t n) {
  constexpr double probes = 2000.0;
  if (static_cast<double>(n) <= probes) return true;
  std::uint64_t h = 0x9e3779b97f4a7c15ULL;
  for (int a = 0; a < D; ++a) {
    std::uint64_t bits = 0;  // (memcpy: Emscripten's libc++ has no std::bit_cast)
    const double x = p[a];
    std::memcpy(&bits, &x, sizeof bits);
    h = detail::mix64(h ^ bits);
  }
  return static_cast<double>(h) < probes / static_cast<double>(n) * 18446744073709551616.0;
}

double probes_median(std::vector<double> residuals) {
  return residuals.empty() ? std::numeric_limits<double>::infinity() : median(std::move(residuals));
}

int raised_k(const TangentPlaneOptions& options, double noise, double rho, std::size_t distinct, std::size_t n,
             const std::function<double()>& probe_median) {
  constexpr double noise_limit = 0.1;  // noise / rho above which k is raised
  constexpr int max_adapted_k = 64;
  const int k = options.k;
  if (!options.adapt_k || options.rho || !(noise > noise_limit * rho) || k >= max_adapted_k ||
      static_cast<std::size_t>(2 * k) > n || !(probe_median() < 1.4 * noise))
    return 0;
  const double wanted = std::ceil(k * noise / (noise_limit * rho));
  const int raised = static_cast<int>(std::min<double>(max_adapted_k, wanted));
  return static_cast<std::size_t>(raised) + 1 <= distinct ? raised : 0;
}

template <int D>
double probe_residual(const TangentPlanes<D>& planes, std::span<const Vec<D>> points, const Vec<D>& p, int wider_k) {
  std::vector<Neighbor> neighbours(static_cast<std::size_t>(wider_k));
  planes.point_tree.knn(p, std::span<Neighbor>(neighbours));
  std::vector<std::uint32_t> indices(neighbours.size());
  for (std::size_t j = 0; j < neighbours.size(); ++j) indices[j] = neighbours[j].index;
  return std::sqrt(fit_plane<D>(points, indices).eigenvalues[0]);
}

template bool is_noise_probe<2>(const Vec<2>&, std::size_t);
template bool is_noise_probe<3>(const Vec<3>&, std::size_t);
template double probe_residual<2>(const TangentPlanes<2>&, std::span<const Vec<2>>, const Vec<2>&, int);
template double probe_residual<3>(const TangentPlanes<3>&, std::span<const Vec<3>>, const Vec<3>&, int);

template <int D>
TangentPlanes<D> estimate_tangent_planes(std::span<const Vec<D>> points, const TangentPlaneOptions& options) {
  Timer timer;
  KdTree<D> tree(points, options.tree);  // refuses non-finite coordinates
  return planes_over<D>(std::move(tree), points, options, timer.lap());
}

template <int D>
TangentPlanes<D> estimate_tangent_planes(KdTree<D>&& tree, const TangentPlaneOptions& options) {
  if (!tree.numbered_by_leaf_order())
    throw InvalidInputError("estimate_tangent_planes: the tree must be numbered by leaf order first");
  return planes_over<D>(std::move(tree), {}, options, 0.0);
}

template <int D>
std::vector<Vec<D>> samples_of(const TangentPlanes<D>& planes) {
  std::vector<Vec<D>> x(planes.origins.size());
  const auto tree_points = planes.point_tree.points();
  const auto tree_order = planes.point_tree.order();
  for (std::size_t t = 0; t < x.size(); ++t) x[tree_order[t]] = tree_points[t];
  return x;
}

template std::vector<Vec<2>> samples_of<2>(const TangentPlanes<2>&);
template std::vector<Vec<3>> samples_of<3>(const TangentPlanes<3>&);
template TangentPlanes<2> estimate_tangent_planes<2>(std::span<const Vec<2>>, const TangentPlaneOptions&);
template TangentPlanes<3> estimate_tangent_planes<3>(std::span<const Vec<3>>, const TangentPlaneOptions&);
template TangentPlanes<2> estimate_tangent_planes<2>(KdTree<2>&&, const TangentPlaneOptions&);
template TangentPlanes<3> estimate_tangent_planes<3>(KdTree<3>&&, const TangentPlaneOptions&);

}  // namespace recon
