#include "recon/structures/kdtree.h"

#include "recon/core/detail/parallel_for.h"
#include "recon/core/errors.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

namespace recon {
namespace {

constexpr double infinity = std::numeric_limits<double>::infinity();
constexpr double bound_slack = 1.0 + 1e-12;

bool before(double d2_a, std::uint32_t i_a, double d2_b, std::uint32_t i_b) {
  return d2_a < d2_b || (d2_a == d2_b && i_a < i_b);
}

// The k best candidates seen so far, kept sorted in a caller-provided buffer.
// For the small k of surface reconstruction, insertion into a sorted array
// beats a heap.
struct KnnCollector {
  std::span<Neighbor> out;
  std::size_t count = 0;
  double limit = infinity;  // nothing farther is wanted (a known upper bound on the k-th distance)

  [[nodiscard]] double bound() const { return count < out.size() ? limit : out.back().distance2; }
  void offer(std::uint32_t index, double d2) {
    if (count == out.size()) {
      if (!before(d2, index, out.back().distance2, out.back().index)) return;
    } else {
      if (d2 > limit) return;
      ++count;
    }
    std::size_t i = count - 1;
    while (i > 0 && before(d2, index, out[i - 1].distance2, out[i - 1].index)) {
      out[i] = out[i - 1];
      --i;
    }
    out[i] = Neighbor{index, d2};
  }
};

// The k-NN search's visitor (see KdTree::descend): it offers every point
// within the bound to the collector, under its input index.
struct KnnVisitor {
  KnnCollector collector;
  const std::uint32_t* order;
  [[nodiscard]] double bound() const { return collector.bound(); }
  [[nodiscard]] static bool skip(std::uint32_t) { return false; }
  void visit(std::uint32_t t, double d2) { collector.offer(order[t], d2); }
  [[nodiscard]] static std::uint64_t distance_evaluations() { return 0; }
};

// The same search, counting the squared distances it computes (the lab's
// figure). A separate type, so that the plain search compiles without the
// count (descend asks for count_distances at compile time).
struct CountingKnnVisitor : KnnVisitor {
  std::uint64_t evaluations = 0;
  void count_distances(std::uint32_t m) { evaluations += m; }
  [[nodiscard]] std::uint64_t distance_evaluations() const { return evaluations; }
};

// The build works on (point, input index) pairs so that the median
// selection moves contiguous data rather than chasing indices.
template <int D>
using Item = std::pair<Vec<D>, std::uint32_t>;

// The points moved by -shift, each with its input index.
template <int D>
std::vector<Item<D>> shifted_items(std::span<const Vec<D>> points, const Vec<D>& shift) {
  std::vector<Item<D>> items(points.size());
  if (shift == Vec<D>::Zero()) {
    for (std::size_t i = 0; i < points.size(); ++i) items[i] = {points[i], static_cast<std::uint32_t>(i)};
  } else {
    for (std::size_t i = 0; i < points.size(); ++i) items[i] = {points[i] - shift, static_cast<std::uint32_t>(i)};
  }
  return items;
}

// The shape of the tree depends only on the sizes (each node splits its
// points into halves of sizes m / 2 and m - m / 2), so every subtree's node
// count is known in advance: node ids are pre-order positions computed,
// not appended, and the subtrees can be built in parallel.
struct TreeShape {
  std::uint32_t leaf;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> memo;  // size -> nodes, for every size in the tree
  // Fills the memo: the recursion meets every size the tree has (at most
  // two per level).
  std::uint32_t count(std::uint32_t size) {
    if (size <= leaf) return 1;
    for (const auto& [s, c] : memo)
      if (s == size) return c;
    const std::uint32_t c = 1 + count(size / 2) + count(size - size / 2);
    memo.emplace_back(size, c);
    return c;
  }
  [[nodiscard]] std::uint32_t nodes(std::uint32_t size) const {
    if (size <= leaf) return 1;
    for (const auto& [s, c] : memo)
      if (s == size) return c;
    return 0;  // not reached: count() saw every size
  }
  [[nodiscard]] int depth(std::uint32_t size) const { return size <= leaf ? 0 : 1 + depth(size - size / 2); }
};

// Builds node `id` over items [begin, end), then its subtrees: the two
// halves at the median of the axis along which the points spread most.
// Subtrees of more than 65536 points are OpenMP tasks.
template <int D>
struct Builder {
  using Node = typename KdTree<D>::Node;
  std::vector<Node>& nodes;
  std::vector<Box<D>>& boxes;
  std::vector<Item<D>>& items;
  const TreeShape& shape;

  void build(std::uint32_t id, std::uint32_t begin, std::uint32_t end) {
    Node node;
    node.begin = begin;
    node.end = end;
    Box<D> box;
    for (auto t = begin; t < end; ++t) box.extend(items[t].first);
    boxes[id] = box;
    node.identical = box.min == box.max;
    // Copies of one point, in index order (any order is a valid tree, as
    // they coincide): a search then finds the smallest indices among them
    // at the front (see descend).
    if (node.identical && !std::is_sorted(items.begin() + begin, items.begin() + end,
                                          [](const auto& a, const auto& b) { return a.second < b.second; }))
      std::sort(items.begin() + begin, items.begin() + end,
                [](const auto& a, const auto& b) { return a.second < b.second; });
    if (end - begin > shape.leaf) {
      const Vec<D> extent = box.extent();
      std::uint8_t axis = 0;
      for (std::uint8_t a = 1; a < D; ++a)
        if (extent[a] > extent[axis]) axis = a;
      const std::uint32_t mid = begin + (end - begin) / 2;
      if (!node.identical)
        std::nth_element(items.begin() + begin, items.begin() + mid, items.begin() + end,
                         [axis](const auto& a, const auto& b) { return a.first[axis] < b.first[axis]; });
      node.axis = axis;
      node.left = id + 1;
      node.right = id + 1 + shape.nodes(mid - begin);
      if (end - begin > 65536) {
#pragma omp task default(shared) firstprivate(node, begin, mid)
        build(node.left, begin, mid);
#pragma omp task default(shared) firstprivate(node, mid, end)
        build(node.right, mid, end);
#pragma omp taskwait
      } else {
        build(node.left, begin, mid);
        build(node.right, mid, end);
      }
      node.left_max = boxes[node.left].max[axis];
      node.right_min = boxes[node.right].min[axis];
      node.min_index = std::min(nodes[node.left].min_index, nodes[node.right].min_index);
    } else {
      node.min_index = KdTree<D>::no_child;
      for (auto t = begin; t < end; ++t) node.min_index = std::min(node.min_index, items[t].second);
    }
    nodes[id] = node;
  }
};

// A table of n rows of k for all_knn to fill, after checking 1 <= k <= n.
KnnTable empty_knn_table(int k, std::size_t n) {
  if (k < 1 || static_cast<std::size_t>(k) > n)
    throw InvalidInputError("k = " + std::to_string(k) + " neighbours asked of a tree of " + std::to_string(n) +
                            " points");
  KnnTable table;
  table.k = k;
  table.entries.resize(n * static_cast<std::size_t>(k));
  return table;
}

}  // namespace

template <int D>
void check_coordinates(std::span<const Vec<D>> points) {
  // Count every unusable point, so the message says how many as well as where.
  std::size_t bad = 0;
  std::size_t first = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    bool usable = true;
    for (int c = 0; c < D; ++c)  // isfinite first: no floating-point exception on NaN
      usable = usable && std::isfinite(points[i][c]) && std::abs(points[i][c]) <= max_coordinate;
    if (!usable && bad++ == 0) first = i;
  }
  if (bad == 0) return;
  std::ostringstream message;
  message << bad << (bad == 1 ? " point has" : " points have") << " a coordinate that is not finite or beyond +-"
          << max_coordinate << "; the first is point " << first;
  throw InvalidInputError(message.str());
}

template <int D>
KdTree<D>::KdTree(std::span<const Point> points, KdTreeOptions options) : KdTree(points, options, Point::Zero()) {}

template <int D>
KdTree<D>::KdTree(std::span<const Point> points, KdTreeOptions options, const Point& shift) : options_(options) {
  if (options.leaf_size < 1) throw InvalidInputError("kd-tree leaf size must be at least 1");
  if (points.size() >= no_child)
    throw InvalidInputError("kd-tree: " + std::to_string(points.size()) +
                            " points is more than the 2^32 - 1 supported");
  check_coordinates<D>(points);
  if (points.empty()) return;

  std::vector<Item<D>> items = shifted_items<D>(points, shift);
  TreeShape shape{static_cast<std::uint32_t>(options_.leaf_size), {}};
  const auto n = static_cast<std::uint32_t>(points.size());
  nodes_.resize(shape.count(n));
  boxes_.resize(nodes_.size());
  depth_ = shape.depth(n);
  Builder<D> builder{nodes_, boxes_, items, shape};
#pragma omp parallel
#pragma omp single
  builder.build(0, 0, n);

  points_.resize(items.size());
  order_.resize(items.size());
  for (std::size_t t = 0; t < items.size(); ++t) {
    points_[t] = items[t].first;
    order_[t] = items[t].second;
  }
}

// Depth-first search with the incremental lower bound of Arya and Mount:
// `offsets` holds, per axis, the squared distance from q to the slab of the
// current node, and `rd` their sum, a lower bound on the distance from q to
// any point below the node. A Visitor provides bound() (prune subtrees
// farther than that), skip(node) and visit(tree position, d2); a counting
// visitor also count_distances(m), told of the m distances a leaf computes.
// (The recursion is the hottest code of phases I and II: it starts on a
// cache line of its own, where it runs about 2 % faster than where a build
// happens to place it at 16 bytes past one; docs/benchmarks.md.)
template <int D>
template <class Visitor>
[[gnu::aligned(64)]] void KdTree<D>::descend(std::uint32_t id, const Point& q, double rd, Point& offsets,
                                             Visitor& visitor) const {
  if (visitor.skip(id)) return;
  const Node& node = nodes_[id];
  // Copies of one point: one distance for all, and a visitor that knows
  // which of them can matter takes only those (nearest_with_other_label:
  // the EMST's searches near a mass of identical points, a scanner's "no
  // return" written as 0 0 0 again and again, stay logarithmic instead of
  // visiting every copy). k-NN does without: phase I asks once per run of
  // copies, and the check would cost every other search.
  if constexpr (requires { visitor.visit_identical(id, node, 0.0); }) {
    if (node.identical) {
      const double d2 = (points_[node.begin] - q).squaredNorm();
      if (d2 <= visitor.bound() && visitor.visit_identical(id, node, d2)) return;
    }
  }
  if (node.is_leaf()) {
    if constexpr (requires { visitor.count_distances(std::uint32_t{}); })
      visitor.count_distances(node.end - node.begin);
    for (auto t = node.begin; t < node.end; ++t) {
      const double d2 = (points_[t] - q).squaredNorm();
      if (d2 <= visitor.bound()) visitor.visit(t, d2);
    }
    return;
  }
  const int a = node.axis;
  const double to_left = q[a] - node.left_max;    // > 0: q beyond the left child's points
  const double to_right = q[a] - node.right_min;  // < 0: q before the right child's points
  std::uint32_t near_child = node.left, far_child = node.right;
  // The far child's slab is 0 away when q lies inside it: only possible
  // where the children's ranges overlap (a refitted tree).
  double cut = to_right < 0.0 ? to_right * to_right : 0.0;
  // On the split itself, left first: in a leaf-numbered tree it holds the
  // smaller indices, which win ties (see the pruning below).
  if (to_left + to_right > 0) {
    std::swap(near_child, far_child);
    cut = to_left > 0.0 ? to_left * to_left : 0.0;
  }
  descend(near_child, q, rd, offsets, visitor);
  const double old = offsets[a];
  const double rd_far = rd - old + cut;
  // The incremental sum can round a hair above the distance the leaf will
  // compute exactly; the slack keeps ties (which decide the answer) inside.
  bool visit_far = rd_far <= visitor.bound() * bound_slack;
  if constexpr (requires { visitor.tie_index(); }) {
    // Only copies of q are still wanted (the bound is 0) and ties go to the
    // smaller index: a subtree whose indices are all larger holds none. A
    // mass of copies spread over many subtrees is then searched in
    // logarithmic time, not by visiting every copy.
    // (A bound of 0 admits only rd_far == 0, tested first: it is cheap and
    // almost never true.)
    if (rd_far == 0.0 && visitor.bound() == 0.0 && nodes_[far_child].min_index > visitor.tie_index()) visit_far = false;
  }
  if (visit_far) {
    offsets[a] = cut;
    descend(far_child, q, rd_far, offsets, visitor);
    offsets[a] = old;
  }
}

template <int D>
template <class Visitor>
void KdTree<D>::search(const Point& q, Visitor& visitor) const {
  if (nodes_.empty()) return;
  const Box<D>& box = boxes_[0];
  Point offsets;
  double rd = 0.0;
  for (int a = 0; a < D; ++a) {
    double d = 0.0;
    if (q[a] < box.min[a]) d = box.min[a] - q[a];
    if (q[a] > box.max[a]) d = q[a] - box.max[a];
    offsets[a] = d * d;
    rd += offsets[a];
  }
  descend(0, q, rd, offsets, visitor);
}

template <int D>
std::size_t KdTree<D>::knn(const Point& q, std::span<Neighbor> out, double within2) const {
  KnnVisitor visitor{KnnCollector{out, 0, within2}, order_.data()};
  if (out.empty()) return 0;
  search(q, visitor);
  return visitor.collector.count;
}

template <int D>
std::vector<Neighbor> KdTree<D>::knn(const Point& q, int k) const {
  std::vector<Neighbor> out(static_cast<std::size_t>(std::max(k, 0)));
  out.resize(knn(q, std::span<Neighbor>(out)));
  return out;
}

template <int D>
Neighbor KdTree<D>::nearest(const Point& q) const {
  Neighbor best{no_child, infinity};
  knn(q, std::span<Neighbor>(&best, 1));
  return best;
}

template <int D>
bool KdTree<D>::any_within(const Point& q, double radius2) const {
  struct Visitor {
    double r2;
    // Once a point is found the bound drops below every distance, and the
    // search unwinds without looking at anything more.
    [[nodiscard]] double bound() const { return r2; }
    [[nodiscard]] static bool skip(std::uint32_t) { return false; }
    void visit(std::uint32_t, double) { r2 = -1.0; }
  } visitor{radius2};
  if (!(radius2 >= 0.0)) return false;
  search(q, visitor);
  return visitor.r2 < 0.0;
}

template <int D>
std::vector<Neighbor> KdTree<D>::radius(const Point& q, double radius2) const {
  struct Visitor {
    double r2;
    const std::uint32_t* order;
    std::vector<Neighbor> found;
    [[nodiscard]] double bound() const { return r2; }
    [[nodiscard]] static bool skip(std::uint32_t) { return false; }
    void visit(std::uint32_t t, double d2) { found.push_back({order[t], d2}); }
  } visitor{radius2, order_.data(), {}};
  search(q, visitor);
  std::sort(visitor.found.begin(), visitor.found.end());
  return std::move(visitor.found);
}

template <int D>
Neighbor KdTree<D>::nearest_with_other_label(const Point& q, std::int32_t own_label,
                                             std::span<const std::int32_t> point_labels,
                                             std::span<const std::int32_t> node_labels, double max_distance2) const {
  struct Visitor {
    std::int32_t own;
    const std::int32_t* point_labels;
    const std::int32_t* node_labels;
    const std::uint32_t* order;
    Neighbor best;
    [[nodiscard]] double bound() const { return best.distance2; }
    [[nodiscard]] bool skip(std::uint32_t id) const { return node_labels[id] == own; }
    [[nodiscard]] std::uint32_t tie_index() const { return best.index; }
    void visit(std::uint32_t t, double d2) {
      const std::uint32_t i = order[t];
      if (point_labels[i] != own && before(d2, i, best.distance2, best.index)) best = {i, d2};
    }
    // Copies of one point under one other label: the first (smallest index) wins.
    bool visit_identical(std::uint32_t id, const Node& node, double d2) {
      if (node_labels[id] < 0) return false;  // own labels are skipped
      const std::uint32_t i = order[node.begin];
      if (before(d2, i, best.distance2, best.index)) best = {i, d2};
      return true;
    }
  } visitor{own_label, point_labels.data(), node_labels.data(), order_.data(), Neighbor{no_child, max_distance2}};
  search(q, visitor);
  return visitor.best;
}

template <int D>
std::vector<std::int32_t> KdTree<D>::node_labels(std::span<const std::int32_t> point_labels) const {
  std::vector<std::int32_t> labels(nodes_.size());
  // Children come after their parent in pre-order: fill from the back.
  for (std::size_t id = nodes_.size(); id-- > 0;) {
    const Node& node = nodes_[id];
    if (node.is_leaf()) {
      std::int32_t label = point_labels[order_[node.begin]];
      for (auto t = node.begin + 1; t < node.end && label >= 0; ++t)
        if (point_labels[order_[t]] != label) label = -1;
      labels[id] = label;
    } else {
      labels[id] = labels[node.left] == labels[node.right] ? labels[node.left] : -1;
    }
  }
  return labels;
}

template <int D>
KdTree<D> KdTree<D>::refit(std::span<const Point> points) const {
  if (points.size() != size())
    throw InvalidInputError("kd-tree refit: " + std::to_string(points.size()) + " points for a tree of " +
                            std::to_string(size()));
  check_coordinates<D>(points);
  KdTree tree;
  tree.options_ = options_;
  tree.depth_ = depth_;
  tree.leaf_numbered_ = leaf_numbered_;
  tree.order_ = order_;
  tree.nodes_ = nodes_;
  tree.boxes_.resize(nodes_.size());
  tree.points_.resize(points.size());
  detail::parallel_for(points.size(), [&](std::size_t t) { tree.points_[t] = points[order_[t]]; });
  // Leaves first (in parallel), then each inner node from its children:
  // children follow their parent in pre-order, so a backward pass finds them done.
  detail::parallel_for_dynamic(nodes_.size(), 256, [&](std::size_t id) {
    Node& node = tree.nodes_[id];
    if (!node.is_leaf()) return;
    Box<D> box;
    for (auto t = node.begin; t < node.end; ++t) box.extend(tree.points_[t]);
    tree.boxes_[id] = box;
    // Copies of one point must be stored by increasing index (see Node).
    node.identical = box.min == box.max && std::is_sorted(order_.begin() + node.begin, order_.begin() + node.end);
  });
  for (std::size_t id = nodes_.size(); id-- > 0;) {
    Node& node = tree.nodes_[id];
    if (node.is_leaf()) continue;
    const Box<D>& left = tree.boxes_[node.left];
    const Box<D>& right = tree.boxes_[node.right];
    Box<D> box;
    box.min = left.min.cwiseMin(right.min);
    box.max = left.max.cwiseMax(right.max);
    tree.boxes_[id] = box;
    node.left_max = left.max[node.axis];
    node.right_min = right.min[node.axis];
    const std::uint32_t mid = tree.nodes_[node.left].end;
    node.identical = box.min == box.max && tree.nodes_[node.left].identical && tree.nodes_[node.right].identical &&
                     order_[mid - 1] < order_[mid];
  }
  return tree;
}

template <int D>
std::vector<std::uint32_t> KdTree<D>::renumber_by_leaf_order() {
  std::vector<std::uint32_t> former = order_;
  for (std::size_t t = 0; t < order_.size(); ++t) order_[t] = static_cast<std::uint32_t>(t);
  for (Node& node : nodes_) node.min_index = node.begin;
  leaf_numbered_ = true;
  return former;
}

template <int D>
template <class Visitor>
std::uint64_t KdTree<D>::fill_knn_table(KnnTable& table) const {
  const auto kk = static_cast<std::size_t>(table.k);
  return detail::parallel_count(size(), 4096, [&](std::size_t t) {
    const auto i = static_cast<std::size_t>(order_[t]);
    const std::span<Neighbor> row(table.entries.data() + i * kk, kk);
    Visitor visitor{KnnVisitor{KnnCollector{row, 0, infinity}, order_.data()}};
    search(points_[t], visitor);
    return visitor.distance_evaluations();
  });
}

template <int D>
KnnTable KdTree<D>::all_knn(int k) const {
  KnnTable table = empty_knn_table(k, size());
  (void)fill_knn_table<KnnVisitor>(table);
  return table;
}

template <int D>
KnnTable KdTree<D>::all_knn(int k, OperationCounts* counts) const {
  if (counts == nullptr) return all_knn(k);
  KnnTable table = empty_knn_table(k, size());
  counts->distance_evaluations += fill_knn_table<CountingKnnVisitor>(table);
  return table;
}

static_assert(sizeof(KdTree<3>::Node) == 40, "a node fills 40 bytes; `identical` and min_index live in the padding");

template class KdTree<2>;
template class KdTree<3>;
template void check_coordinates<2>(std::span<const Vec<2>>);
template void check_coordinates<3>(std::span<const Vec<3>>);

}  // namespace recon
