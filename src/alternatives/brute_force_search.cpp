#include "recon/alternatives/brute_force_search.h"

#include "recon/core/errors.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <string>

namespace recon {
namespace {

template <int D>
void check_points_and_k(std::span<const Vec<D>> points, int k) {
  if (points.size() >= std::numeric_limits<std::uint32_t>::max())
    throw InvalidInputError("brute-force search: " + std::to_string(points.size()) +
                            " points is more than the 2^32 - 2 supported");
  if (k < 1 || static_cast<std::size_t>(k) > points.size())
    throw InvalidInputError("brute-force search: k = " + std::to_string(k) + " neighbours asked of " +
                            std::to_string(points.size()) + " points");
  check_coordinates<D>(points);
}

template <int D>
void check_query(const Vec<D>& q) {
  for (int c = 0; c < D; ++c) {
    if (std::isfinite(q[c]) && std::abs(q[c]) <= max_coordinate) continue;  // isfinite first: no FP exception on NaN
    std::ostringstream message;
    message << "brute-force search: the query has a coordinate that is not finite or beyond +-" << max_coordinate;
    throw InvalidInputError(message.str());
  }
}

// Steps 1 and 2 for one query. `all` is scratch space for n entries; the k
// nearest go to `out` (k = out.size()). Returns the distances computed.
template <int D>
std::uint64_t k_nearest(std::span<const Vec<D>> points, const Vec<D>& q, std::span<Neighbor> all,
                        std::span<Neighbor> out) {
  for (std::size_t i = 0; i < points.size(); ++i)
    all[i] = Neighbor{static_cast<std::uint32_t>(i), (points[i] - q).squaredNorm()};
  const auto k = static_cast<std::ptrdiff_t>(out.size());
  std::partial_sort(all.begin(), all.begin() + k, all.end());  // Neighbor's < is (distance, index)
  std::copy_n(all.begin(), k, out.begin());
  return points.size();
}

}  // namespace

template <int D>
std::vector<Neighbor> brute_force_knn(std::span<const Vec<D>> points, const Vec<D>& q, int k, OperationCounts* counts) {
  check_points_and_k<D>(points, k);
  check_query<D>(q);
  std::vector<Neighbor> all(points.size());
  std::vector<Neighbor> nearest(static_cast<std::size_t>(k));
  const std::uint64_t evaluations = k_nearest<D>(points, q, all, nearest);
  if (counts != nullptr) counts->distance_evaluations += evaluations;
  return nearest;
}

template <int D>
KnnTable brute_force_all_knn(std::span<const Vec<D>> points, int k, OperationCounts* counts) {
  check_points_and_k<D>(points, k);
  const std::size_t n = points.size();
  const auto kk = static_cast<std::size_t>(k);
  KnnTable table;
  table.k = k;
  table.entries.resize(n * kk);
  const std::span<Neighbor> entries(table.entries);
  const auto count = static_cast<std::int64_t>(n);
  std::uint64_t evaluations = 0;
#pragma omp parallel reduction(+ : evaluations)
  {
    std::vector<Neighbor> all(n);  // each thread's scratch row
#pragma omp for schedule(dynamic, 64)
    for (std::int64_t s = 0; s < count; ++s) {
      const auto i = static_cast<std::size_t>(s);
      evaluations += k_nearest<D>(points, points[i], all, entries.subspan(i * kk, kk));
    }
  }
  if (counts != nullptr) counts->distance_evaluations += evaluations;
  return table;
}

template std::vector<Neighbor> brute_force_knn<2>(std::span<const Vec2>, const Vec2&, int, OperationCounts*);
template std::vector<Neighbor> brute_force_knn<3>(std::span<const Vec3>, const Vec3&, int, OperationCounts*);
template KnnTable brute_force_all_knn<2>(std::span<const Vec2>, int, OperationCounts*);
template KnnTable brute_force_all_knn<3>(std::span<const Vec3>, int, OperationCounts*);

}  // namespace recon
