#include "recon/emst.h"

#include "recon/parallel.h"  // AtomicRef

#include <atomic>
#include <cmath>
#include <limits>
#include <numeric>
#include <span>
#include <stdexcept>
#include <vector>

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

// Lowers `bound` to `value` if smaller; safe from many threads.
void lower(double& bound, double value) {
  AtomicRef<double> shared(bound);
  double current = shared.load(std::memory_order_relaxed);
  while (value < current && !shared.compare_exchange_weak(current, value, std::memory_order_relaxed)) {
  }
}

}  // namespace

template <int D>
std::vector<Edge> euclidean_minimum_spanning_tree(const KdTree<D>& tree, std::span<const Vec<D>> points,
                                                  const EmstHints& hints) {
  const std::size_t n = points.size();
  std::vector<Edge> edges;
  if (n < 2) return edges;
  edges.reserve(n - 1);
  const bool hinted = hints.lists != nullptr && hints.lists->size() == n && hints.certain_radius2.size() == n &&
                      hints.lists->k <= UINT16_MAX;
  std::vector<std::int32_t> label(n);
  std::vector<Candidate> per_point(n);
  // Per component (indexed by its root): the point whose candidate is the
  // best found so far, and that candidate's squared length.
  std::vector<std::uint32_t> best_point(n);
  std::vector<double> bound(n);
  const auto count = static_cast<std::int64_t>(n);
  // The current components by root, ascending, and the points whose list
  // still reaches outside their component (only they are scanned in step
  // 1). Both shrink every round, so the rounds after the first cost what
  // their components and active points do, not what n does.
  std::vector<std::uint32_t> roots(n);
  for (std::uint32_t i = 0; i < n; ++i) roots[i] = i;
  std::vector<std::uint32_t> active;
  // Per active point, where its list may first leave its component: the
  // entries before it are in the component for good.
  std::vector<std::uint16_t> cursor;
  if (hinted) {
    active = roots;
    cursor.assign(n, 0);
  }
  std::vector<std::uint32_t> queried;  // points whose candidate came from a tree query this round

  for (std::uint32_t i = 0; i < n; ++i) label[i] = static_cast<std::int32_t>(i);
  // Per root of the round: the component its best edge leads to, then the
  // root of the component it is part of after the round.
  std::vector<std::uint32_t> hook(n), merged_into(n);
  std::vector<std::uint32_t> place(n);  // per root of the round, as roots lists them

  // The component's best candidate so far, from points' candidates in any
  // order and from many threads at once: best_point only ever moves to a
  // point with a smaller candidate, and the least candidate of a component
  // is unique (the order is strict and two points of one component cannot
  // find the same edge), so the outcome does not depend on the order.
  auto reduce = [&](std::span<const std::uint32_t> which) {
    const auto m = static_cast<std::int64_t>(which.size());
#pragma omp parallel for schedule(static)
    for (std::int64_t s = 0; s < m; ++s) {
      const std::uint32_t i = which[static_cast<std::size_t>(s)];
      if (!per_point[i].valid()) continue;
      AtomicRef<std::uint32_t> best(best_point[static_cast<std::size_t>(label[i])]);
      std::uint32_t current = best.load(std::memory_order_relaxed);
      while ((current == none || per_point[i] < per_point[current]) &&
             !best.compare_exchange_weak(current, i, std::memory_order_relaxed)) {
      }
    }
  };
  // Parallel loops over the current roots.
  auto for_roots = [&](auto&& body) {
    const auto m = static_cast<std::int64_t>(roots.size());
#pragma omp parallel for schedule(static)
    for (std::int64_t s = 0; s < m; ++s) body(roots[static_cast<std::size_t>(s)]);
  };

  while (roots.size() > 1) {
    // 1. What the lists give for free: the first entry of another component
    //    is the point's nearest outside point. A point whose whole list is
    //    in its own component stays so (components only merge): it leaves
    //    the active points for good. Likewise the entries before a point's
    //    cursor: each round reads on from where the last one stopped.
    const auto active_count = static_cast<std::int64_t>(active.size());
#pragma omp parallel for schedule(static)
    for (std::int64_t s = 0; s < active_count; ++s) {
      const std::uint32_t i = active[static_cast<std::size_t>(s)];
      per_point[i] = Candidate{};
      const auto row = hints.lists->row(i);
      for (std::size_t e = cursor[i]; e < row.size(); ++e) {
        const std::uint32_t j = row[e];
        if (label[j] == label[i]) continue;
        per_point[i] = Candidate::make((points[j] - points[i]).squaredNorm(), i, j);
        cursor[i] = static_cast<std::uint16_t>(e);
        break;
      }
    }
    for_roots([&](std::uint32_t r) { best_point[r] = none; });
    reduce(active);
    for_roots([&](std::uint32_t r) {
      bound[r] = best_point[r] == none ? std::numeric_limits<double>::infinity() : per_point[best_point[r]].d2;
    });

    // 2. Tree queries where a point could still beat its component's best:
    //    bounded by that best, which the queries lower as they go (only the
    //    work depends on the order, not the answer: the reduction below
    //    keeps the least candidate under the strict order).
    queried.clear();
    auto may_ask = [&](std::uint32_t i) {
      if (!hinted) return true;
      const double limit = AtomicRef<double>(bound[static_cast<std::size_t>(label[i])]).load(std::memory_order_relaxed);
      // An exact copy of an earlier point (its list starts with that point)
      // shares its component from the first round on and would ask the very
      // same question: only the first of the copies asks it. Thousands of
      // copies of one point, each query a few hundred nodes, took seconds.
      return !per_point[i].valid() && hints.certain_radius2[i] <= limit && hints.lists->row(i)[0] == i;
    };
    // (Most rounds of a dense cloud ask nothing: the labels of the tree's
    // nodes are worked out only for a round that asks.)
    bool asks = false;
#pragma omp parallel for schedule(static) reduction(|| : asks)
    for (std::int64_t s = 0; s < count; ++s) asks = asks || may_ask(static_cast<std::uint32_t>(s));
    const std::vector<std::int32_t> node_label = asks ? tree.node_labels(label) : std::vector<std::int32_t>{};
#pragma omp parallel if (asks)
    {
      std::vector<std::uint32_t> mine;
#pragma omp for schedule(dynamic, 1024) nowait
      for (std::int64_t s = 0; s < (asks ? count : 0); ++s) {
        const auto i = static_cast<std::uint32_t>(s);
        if (!may_ask(i)) continue;
        double& best = bound[static_cast<std::size_t>(label[i])];
        const double limit = AtomicRef<double>(best).load(std::memory_order_relaxed);
        const Neighbor nb = tree.nearest_with_other_label(points[i], label[i], label, node_label, limit);
        if (nb.index == KdTree<D>::no_child) continue;
        per_point[i] = Candidate::make(nb.distance2, i, nb.index);
        mine.push_back(i);
        lower(best, nb.distance2);
      }
#pragma omp critical(recon_emst_queried)
      queried.insert(queried.end(), mine.begin(), mine.end());
    }
    reduce(queried);

    // 3. Every component hooks onto the component its best edge leads to.
    //    The edges are all in the tree, and form a forest over the
    //    components but for one thing: two components that chose each
    //    other chose the same edge (the least between them), and the
    //    smaller root keeps it and stays a root. Then each root follows the
    //    hooks to the root of its tree, by pointer jumping: every pass
    //    halves the distance left, and each pass is parallel.
    for_roots([&](std::uint32_t r) {
      const std::uint32_t p = best_point[r];
      if (p == none) {  // no outside point (not expected while two components remain)
        hook[r] = r;
        return;
      }
      const Candidate& c = per_point[p];
      const auto lo = static_cast<std::uint32_t>(label[c.lo]), hi = static_cast<std::uint32_t>(label[c.hi]);
      hook[r] = lo == r ? hi : lo;
    });
    // The round's edges, in root order: a root keeps its edge unless it has
    // none or is the larger root of a pair. A prefix sum over the roots
    // gives each kept edge its place, so they are written in parallel.
    const auto root_count = static_cast<std::int64_t>(roots.size());
#pragma omp parallel for schedule(static)
    for (std::int64_t s = 0; s < root_count; ++s) {
      const std::uint32_t r = roots[static_cast<std::size_t>(s)];
      const std::uint32_t h = hook[r];
      const bool pair = h != r && hook[h] == r;  // r and h chose each other
      place[static_cast<std::size_t>(s)] = h == r || (pair && h < r) ? 0 : 1;
      merged_into[r] = pair && r < h ? r : h;
    }
    std::inclusive_scan(place.begin(), place.begin() + root_count, place.begin());  // kept up to and including s
    const std::size_t first = edges.size();
    edges.resize(first + place[static_cast<std::size_t>(root_count - 1)]);
#pragma omp parallel for schedule(static)
    for (std::int64_t s = 0; s < root_count; ++s) {
      const auto t = static_cast<std::size_t>(s);
      const std::uint32_t before = t == 0 ? 0 : place[t - 1];
      if (place[t] == before) continue;
      const Candidate& c = per_point[best_point[roots[t]]];
      edges[first + before] = {c.lo, c.hi, std::sqrt(c.d2)};
    }
    int passes = 0;
    // (After t passes each root points 2^t hooks up its tree or to its
    // root, so 33 passes reach every root; a 34th would mean a cycle,
    // which the strict order of the edges rules out.)
    for (bool moved = true; moved;) {
      if (++passes > 33) throw std::logic_error("Borůvka: the components' hooks form a cycle");
      moved = false;
      // hook <- merged_into, then merged_into <- its own target's target:
      // two arrays, so that no pass reads what it writes.
      for_roots([&](std::uint32_t r) { hook[r] = merged_into[r]; });
#pragma omp parallel for schedule(static) reduction(|| : moved)
      for (std::int64_t s = 0; s < root_count; ++s) {
        const std::uint32_t r = roots[static_cast<std::size_t>(s)];
        const std::uint32_t next = hook[hook[r]];
        moved = moved || next != hook[r];
        merged_into[r] = next;
      }
    }
    for (const std::uint32_t i : queried) per_point[i] = Candidate{};  // not an active point's: cleared here
    std::erase_if(roots, [&](std::uint32_t r) { return merged_into[r] != r; });
#pragma omp parallel for schedule(static)
    for (std::int64_t s = 0; s < count; ++s) {
      std::int32_t& l = label[static_cast<std::size_t>(s)];
      l = static_cast<std::int32_t>(merged_into[static_cast<std::size_t>(l)]);
    }
    // Points whose list lay inside their component this round stay inside.
    std::erase_if(active, [&](std::uint32_t i) { return !per_point[i].valid(); });
  }
  return edges;
}

template <int D>
std::vector<Edge> euclidean_minimum_spanning_tree(const KdTree<D>& tree, std::span<const Vec<D>> points,
                                                  const KnnTable& knn) {
  NeighborLists lists;
  lists.k = knn.k;
  lists.indices.reserve(knn.entries.size());
  for (const Neighbor& nb : knn.entries) lists.indices.push_back(nb.index);
  std::vector<double> radius2(knn.size());
  for (std::size_t i = 0; i < radius2.size(); ++i) radius2[i] = knn.row(i).back().distance2;
  return euclidean_minimum_spanning_tree<D>(tree, points, EmstHints{&lists, radius2});
}

template std::vector<Edge> euclidean_minimum_spanning_tree<2>(const KdTree<2>&, std::span<const Vec<2>>,
                                                              const EmstHints&);
template std::vector<Edge> euclidean_minimum_spanning_tree<3>(const KdTree<3>&, std::span<const Vec<3>>,
                                                              const EmstHints&);
template std::vector<Edge> euclidean_minimum_spanning_tree<2>(const KdTree<2>&, std::span<const Vec<2>>,
                                                              const KnnTable&);
template std::vector<Edge> euclidean_minimum_spanning_tree<3>(const KdTree<3>&, std::span<const Vec<3>>,
                                                              const KnnTable&);

}  // namespace recon
