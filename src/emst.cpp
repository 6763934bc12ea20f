#include "recon/emst.h"

#include <cmath>
#include <limits>

namespace recon {
namespace {

constexpr std::uint32_t none = UINT32_MAX;

// A candidate edge, ordered by (squared length, smaller end, larger end).
struct Candidate {
  double d2 = std::numeric_limits<double>::infinity();
  std::uint32_t lo = none, hi = none;

  static Candidate make(double d2, std::uint32_t a, std::uint32_t b) {
    return a < b ? Candidate{d2, a, b} : Candidate{d2, b, a};
  }
  [[nodiscard]] bool valid() const { return lo != none; }
  friend bool operator<(const Candidate& x, const Candidate& y) {
    if (x.d2 != y.d2) return x.d2 < y.d2;
    if (x.lo != y.lo) return x.lo < y.lo;
    return x.hi < y.hi;
  }
};

}  // namespace

template <int D>
std::vector<Edge> euclidean_minimum_spanning_tree(const KdTree<D>& tree, std::span<const Vec<D>> points,
                                                  const KnnTable* knn) {
  const std::size_t n = points.size();
  std::vector<Edge> edges;
  if (n < 2) return edges;
  edges.reserve(n - 1);
  UnionFind sets(n);
  std::vector<std::int32_t> label(n);
  std::vector<Candidate> per_point(n);
  std::vector<Candidate> per_component(n);
  std::vector<std::uint8_t> needs_query(n);
  const auto count = static_cast<std::int64_t>(n);

  while (sets.set_count() > 1) {
    for (std::uint32_t i = 0; i < n; ++i) label[i] = static_cast<std::int32_t>(sets.find(i));
    const std::vector<std::int32_t> node_label = tree.node_labels(label);

    // 1. Answers the k-NN lists give for free.
#pragma omp parallel for schedule(static)
    for (std::int64_t s = 0; s < count; ++s) {
      const auto i = static_cast<std::uint32_t>(s);
      per_point[i] = Candidate{};
      needs_query[i] = 1;
      if (knn == nullptr) continue;
      for (const Neighbor& nb : knn->row(i)) {
        if (label[nb.index] != label[i]) {
          per_point[i] = Candidate::make(nb.distance2, i, nb.index);
          needs_query[i] = 0;
          break;
        }
      }
    }
    auto reduce = [&] {
      for (std::uint32_t i = 0; i < n; ++i) {
        Candidate& best = per_component[static_cast<std::size_t>(label[i])];
        if (per_point[i] < best) best = per_point[i];
      }
    };
    std::fill(per_component.begin(), per_component.end(), Candidate{});
    reduce();

    // 2. Tree queries where the list did not settle it and could still beat
    //    the component's best so far.
#pragma omp parallel for schedule(dynamic, 1024)
    for (std::int64_t s = 0; s < count; ++s) {
      const auto i = static_cast<std::uint32_t>(s);
      if (!needs_query[i]) continue;
      const Candidate& bound = per_component[static_cast<std::size_t>(label[i])];
      if (knn != nullptr && knn->row(i).back().distance2 > bound.d2) continue;
      const Neighbor nb = tree.nearest_with_other_label(points[i], label[i], label, node_label, bound.d2);
      if (nb.index != KdTree<D>::no_child) per_point[i] = Candidate::make(nb.distance2, i, nb.index);
    }
    reduce();

    for (std::uint32_t c = 0; c < n; ++c) {
      const Candidate& best = per_component[c];
      if (best.valid() && sets.unite(best.lo, best.hi)) edges.push_back({best.lo, best.hi, std::sqrt(best.d2)});
    }
  }
  return edges;
}

template std::vector<Edge> euclidean_minimum_spanning_tree<2>(const KdTree<2>&, std::span<const Vec<2>>,
                                                              const KnnTable*);
template std::vector<Edge> euclidean_minimum_spanning_tree<3>(const KdTree<3>&, std::span<const Vec<3>>,
                                                              const KnnTable*);

}  // namespace recon
