#include "recon/phase2_orientation/emst.h"

#include "recon/core/detail/parallel_for.h"
#include "recon/core/parallel.h"  // AtomicRef
#include "recon/core/progress.h"

#include <atomic>
#include <cmath>
#include <limits>
#include <numeric>
#include <span>
#include <stdexcept>
#include <vector>

namespace recon {
namespace {

using detail::parallel_for;

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

// Borůvka's rounds over the kd-tree (see emst.h; the textbook Borůvka over
// a given graph is alternatives/boruvka.h), one step per member function.
// A component is named by its root, a point of it; label_[i] is the root of
// point i's component. The arrays are made once and serve every round.
template <int D>
class KdTreeBoruvka {
 public:
  KdTreeBoruvka(const KdTree<D>& tree, std::span<const Vec<D>> points, const EmstHints& hints);

  [[nodiscard]] std::size_t component_count() const { return roots_.size(); }
  void scan_lists();
  void query_tree();
  void hook_components();
  void add_round_edges();
  void jump_to_roots();
  void merge_components();
  [[nodiscard]] std::vector<Edge> take_edges() { return std::move(edges_); }

 private:
  void reduce(std::span<const std::uint32_t> which);
  template <class Body>
  void for_roots(Body&& body);
  [[nodiscard]] bool may_ask(std::uint32_t i);

  const KdTree<D>& tree_;
  std::span<const Vec<D>> points_;
  const EmstHints& hints_;
  std::size_t n_;
  bool hinted_;
  std::vector<std::int32_t> label_;
  std::vector<Candidate> per_point_;
  // Per component (indexed by its root): the point whose candidate is the
  // best found so far, and that candidate's squared length.
  std::vector<std::uint32_t> best_point_;
  std::vector<double> bound_;
  // The current components by root, ascending, and the points whose list
  // still reaches outside their component (only they are scanned in step
  // 1). Both shrink every round, so the rounds after the first cost what
  // their components and active points do, not what n does.
  std::vector<std::uint32_t> roots_;
  std::vector<std::uint32_t> active_;
  // Per active point, where its list may first leave its component: the
  // entries before it are in the component for good.
  std::vector<std::uint16_t> cursor_;
  std::vector<std::uint32_t> queried_;  // points whose candidate came from a tree query this round
  // Per root of the round: the component its best edge leads to, then the
  // root of the component it is part of after the round.
  std::vector<std::uint32_t> hook_, merged_into_;
  std::vector<std::uint32_t> place_;  // per root of the round, as roots_ lists them
  std::vector<Edge> edges_;
};

template <int D>
KdTreeBoruvka<D>::KdTreeBoruvka(const KdTree<D>& tree, std::span<const Vec<D>> points, const EmstHints& hints)
    : tree_(tree),
      points_(points),
      hints_(hints),
      n_(points.size()),
      hinted_(hints.lists != nullptr && hints.lists->size() == n_ && hints.certain_radius2.size() == n_ &&
              hints.lists->k <= UINT16_MAX),
      label_(n_),
      per_point_(n_),
      best_point_(n_),
      bound_(n_),
      roots_(n_),
      hook_(n_),
      merged_into_(n_),
      place_(n_) {
  edges_.reserve(n_ - 1);
  for (std::uint32_t i = 0; i < n_; ++i) roots_[i] = i;
  if (hinted_) {
    active_ = roots_;
    cursor_.assign(n_, 0);
  }
  for (std::uint32_t i = 0; i < n_; ++i) label_[i] = static_cast<std::int32_t>(i);
}

// The component's best candidate so far, from points' candidates in any
// order and from many threads at once: best_point_ only ever moves to a
// point with a smaller candidate, and the least candidate of a component
// is unique (the order is strict and two points of one component cannot
// find the same edge), so the outcome does not depend on the order.
template <int D>
void KdTreeBoruvka<D>::reduce(std::span<const std::uint32_t> which) {
  parallel_for(which.size(), [&](std::size_t s) {
    const std::uint32_t i = which[s];
    if (!per_point_[i].valid()) return;
    AtomicRef<std::uint32_t> best(best_point_[static_cast<std::size_t>(label_[i])]);
    std::uint32_t current = best.load(std::memory_order_relaxed);
    while ((current == none || per_point_[i] < per_point_[current]) &&
           !best.compare_exchange_weak(current, i, std::memory_order_relaxed)) {
    }
  });
}

template <int D>
template <class Body>
void KdTreeBoruvka<D>::for_roots(Body&& body) {
  parallel_for(roots_.size(), [&](std::size_t s) { body(roots_[s]); });
}

// 1. What the lists give for free: the first entry of another component is
//    the point's nearest outside point. A point whose whole list is in its
//    own component stays so (components only merge): it leaves the active
//    points for good. Likewise the entries before a point's cursor: each
//    round reads on from where the last one stopped. Then each component's
//    best so far, which bounds the queries of step 2.
template <int D>
void KdTreeBoruvka<D>::scan_lists() {
  parallel_for(active_.size(), [&](std::size_t s) {
    const std::uint32_t i = active_[s];
    per_point_[i] = Candidate{};
    const auto row = hints_.lists->row(i);
    for (std::size_t e = cursor_[i]; e < row.size(); ++e) {
      const std::uint32_t j = row[e];
      if (label_[j] == label_[i]) continue;
      per_point_[i] = Candidate::make((points_[j] - points_[i]).squaredNorm(), i, j);
      cursor_[i] = static_cast<std::uint16_t>(e);
      break;
    }
  });
  for_roots([&](std::uint32_t r) { best_point_[r] = none; });
  reduce(active_);
  for_roots([&](std::uint32_t r) {
    bound_[r] = best_point_[r] == none ? std::numeric_limits<double>::infinity() : per_point_[best_point_[r]].d2;
  });
}

// Whether point i must query the tree: its list did not settle it, and it
// could still beat its component's best.
template <int D>
bool KdTreeBoruvka<D>::may_ask(std::uint32_t i) {
  if (!hinted_) return true;
  const double limit = AtomicRef<double>(bound_[static_cast<std::size_t>(label_[i])]).load(std::memory_order_relaxed);
  // An exact copy of an earlier point (its list starts with that point)
  // shares its component from the first round on and would ask the very
  // same question: only the first of the copies asks it.
  return !per_point_[i].valid() && hints_.certain_radius2[i] <= limit && hints_.lists->row(i)[0] == i;
}

// 2. Tree queries where a point could still beat its component's best:
//    bounded by that best, which the queries lower as they go (only the
//    work depends on the order, not the answer: the reduction keeps the
//    least candidate under the strict order).
template <int D>
void KdTreeBoruvka<D>::query_tree() {
  queried_.clear();
  const auto count = static_cast<std::int64_t>(n_);
  // (Most rounds of a dense cloud ask nothing: the labels of the tree's
  // nodes are worked out only for a round that asks.)
  bool asks = false;
#pragma omp parallel for schedule(static) reduction(|| : asks)
  for (std::int64_t s = 0; s < count; ++s) asks = asks || may_ask(static_cast<std::uint32_t>(s));
  const std::vector<std::int32_t> node_label = asks ? tree_.node_labels(label_) : std::vector<std::int32_t>{};
#pragma omp parallel if (asks)
  {
    std::vector<std::uint32_t> mine;
#pragma omp for schedule(dynamic, 1024) nowait
    for (std::int64_t s = 0; s < (asks ? count : 0); ++s) {
      const auto i = static_cast<std::uint32_t>(s);
      if (!may_ask(i)) continue;
      double& best = bound_[static_cast<std::size_t>(label_[i])];
      const double limit = AtomicRef<double>(best).load(std::memory_order_relaxed);
      const Neighbor nb = tree_.nearest_with_other_label(points_[i], label_[i], label_, node_label, limit);
      if (nb.index == KdTree<D>::no_child) continue;
      per_point_[i] = Candidate::make(nb.distance2, i, nb.index);
      mine.push_back(i);
      lower(best, nb.distance2);
    }
#pragma omp critical(recon_emst_queried)
    queried_.insert(queried_.end(), mine.begin(), mine.end());
  }
  reduce(queried_);
}

// 3. Every component hooks onto the component its best edge leads to. The
//    edges are all in the tree, and form a forest over the components but
//    for one thing: two components that chose each other chose the same
//    edge (the least between them), and the smaller root keeps it and stays
//    a root. place_ marks the roots that keep an edge: all but the roots
//    without one and the larger root of each pair.
template <int D>
void KdTreeBoruvka<D>::hook_components() {
  for_roots([&](std::uint32_t r) {
    const std::uint32_t p = best_point_[r];
    if (p == none) {  // no outside point (not expected while two components remain)
      hook_[r] = r;
      return;
    }
    const Candidate& c = per_point_[p];
    const auto lo = static_cast<std::uint32_t>(label_[c.lo]), hi = static_cast<std::uint32_t>(label_[c.hi]);
    hook_[r] = lo == r ? hi : lo;
  });
  parallel_for(roots_.size(), [&](std::size_t s) {
    const std::uint32_t r = roots_[s];
    const std::uint32_t h = hook_[r];
    const bool pair = h != r && hook_[h] == r;  // r and h chose each other
    place_[s] = h == r || (pair && h < r) ? 0 : 1;
    merged_into_[r] = pair && r < h ? r : h;
  });
}

// The round's edges join the tree, in root order: a prefix sum over the
// roots gives each kept edge its place, so they are written in parallel.
template <int D>
void KdTreeBoruvka<D>::add_round_edges() {
  const std::size_t root_count = roots_.size();
  const auto end = place_.begin() + static_cast<std::ptrdiff_t>(root_count);
  std::inclusive_scan(place_.begin(), end, place_.begin());  // kept up to and including s
  const std::size_t first = edges_.size();
  edges_.resize(first + place_[root_count - 1]);
  parallel_for(root_count, [&](std::size_t t) {
    const std::uint32_t before = t == 0 ? 0 : place_[t - 1];
    if (place_[t] == before) return;
    const Candidate& c = per_point_[best_point_[roots_[t]]];
    edges_[first + before] = {c.lo, c.hi, std::sqrt(c.d2)};
  });
}

// 4. Each root follows the hooks to the root of its tree, by pointer
//    jumping: every pass halves the distance left, and each pass is
//    parallel. (After t passes each root points 2^t hooks up its tree or
//    to its root, so 33 passes reach every root; a 34th would mean a
//    cycle, which the strict order of the edges rules out.)
template <int D>
void KdTreeBoruvka<D>::jump_to_roots() {
  const auto root_count = static_cast<std::int64_t>(roots_.size());
  int passes = 0;
  for (bool moved = true; moved;) {
    if (++passes > 33) throw std::logic_error("Borůvka: the components' hooks form a cycle");
    moved = false;
    // hook_ <- merged_into_, then merged_into_ <- its own target's target:
    // two arrays, so that no pass reads what it writes.
    for_roots([&](std::uint32_t r) { hook_[r] = merged_into_[r]; });
#pragma omp parallel for schedule(static) reduction(|| : moved)
    for (std::int64_t s = 0; s < root_count; ++s) {
      const std::uint32_t r = roots_[static_cast<std::size_t>(s)];
      const std::uint32_t next = hook_[hook_[r]];
      moved = moved || next != hook_[r];
      merged_into_[r] = next;
    }
  }
}

// 5. The points take the label of their new component's root; the roots
//    and the active points shrink.
template <int D>
void KdTreeBoruvka<D>::merge_components() {
  for (const std::uint32_t i : queried_) per_point_[i] = Candidate{};  // not an active point's: cleared here
  std::erase_if(roots_, [&](std::uint32_t r) { return merged_into_[r] != r; });
  parallel_for(n_, [&](std::size_t s) {
    std::int32_t& l = label_[s];
    l = static_cast<std::int32_t>(merged_into_[static_cast<std::size_t>(l)]);
  });
  // Points whose list lay inside their component this round stay inside.
  std::erase_if(active_, [&](std::uint32_t i) { return !per_point_[i].valid(); });
}

}  // namespace

template <int D>
std::vector<Edge> euclidean_minimum_spanning_tree(const KdTree<D>& tree, std::span<const Vec<D>> points,
                                                  const EmstHints& hints) {
  if (points.size() < 2) return {};
  KdTreeBoruvka<D> boruvka(tree, points, hints);
  ProgressCounter* const progress = progress_counter();  // counts the merges
  while (boruvka.component_count() > 1) {
    const std::size_t before = boruvka.component_count();
    boruvka.scan_lists();       // each point's nearest outside point, where its list knows it
    boruvka.query_tree();       // ... and where it does not
    boruvka.hook_components();  // each component takes its shortest outside edge
    boruvka.add_round_edges();
    boruvka.jump_to_roots();  // the components those edges join
    boruvka.merge_components();
    if (progress != nullptr) progress->advance(before - boruvka.component_count());
  }
  return boruvka.take_edges();
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
