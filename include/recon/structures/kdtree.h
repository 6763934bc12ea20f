#pragma once
// kd-tree: exact nearest-neighbour search in D dimensions (D = 2 or 3).
//
// Contract
// - Distances passed in and returned are SQUARED Euclidean distances.
// - Indices are positions in the span given to the constructor.
// - A query point that is itself in the tree IS its own neighbour (distance
//   0): `knn(points[i], k)` returns i first (or an exact duplicate of i with
//   a smaller index). Callers that want "other" points ask for k + 1.
// - Results are ordered by (squared distance, index), and ties are broken by
//   the smaller index, so every query has exactly one correct answer: the
//   same one brute force gives. Duplicate points are fine.
// - The tree copies the points (in leaf order, for cache locality); the
//   caller's span need not outlive it.
// - A built tree is immutable; const queries are safe from many threads.
//
// Construction is balanced: each inner node splits its points at the median
// of the axis along which they spread most, so the depth is about
// log2(n / leaf_size). Leaves hold up to `leaf_size` points (see bench/ for the
// measurement behind the default).
//
// The textbook search descends to the query's side of each split first,
// then visits the other side only if the splitting plane is nearer than the
// k-th best distance so far. The version here compares the distance to the
// other child's slab, kept incrementally per axis (Arya and Mount), skips
// subtrees a visitor rules out (labels, ties), and builds the subtrees in
// parallel, knowing every node's position in advance from the sizes alone.

#include "recon/core/operation_counts.h"
#include "recon/core/point_cloud.h"

#include <cstdint>
#include <limits>
#include <span>
#include <vector>

namespace recon {

/// One neighbour found by a query.
struct Neighbor {
  std::uint32_t index = 0;  ///< position in the points given to the tree
  double distance2 = 0.0;   ///< squared distance to the query

  friend bool operator<(const Neighbor& a, const Neighbor& b) {
    return a.distance2 < b.distance2 || (a.distance2 == b.distance2 && a.index < b.index);
  }
  friend bool operator==(const Neighbor&, const Neighbor&) = default;
};

/// The k nearest neighbours of every point of a tree, as one flat table:
/// row i (entries [i*k, (i+1)*k)) lists point i's neighbours, itself included,
/// in (distance, index) order.
struct KnnTable {
  int k = 0;
  std::vector<Neighbor> entries;  ///< n * k

  [[nodiscard]] std::size_t size() const { return k == 0 ? 0 : entries.size() / static_cast<std::size_t>(k); }
  [[nodiscard]] std::span<const Neighbor> row(std::size_t i) const {
    return {entries.data() + i * static_cast<std::size_t>(k), static_cast<std::size_t>(k)};
  }
};

/// Neighbour indices only, without distances (4 bytes an entry): row i
/// (entries [i*k, (i+1)*k)) lists k points for point i, nearest first.
/// Phase I keeps the neighbourhood of every point in this form.
struct NeighborLists {
  int k = 0;
  std::vector<std::uint32_t> indices;  ///< n * k

  [[nodiscard]] std::size_t size() const { return k == 0 ? 0 : indices.size() / static_cast<std::size_t>(k); }
  [[nodiscard]] std::span<const std::uint32_t> row(std::size_t i) const {
    return {indices.data() + i * static_cast<std::size_t>(k), static_cast<std::size_t>(k)};
  }
};

/// Checks that every coordinate is usable: finite and within +-max_coordinate.
/// Cost: O(n).
/// Throws: InvalidInputError when some are NaN, infinite or beyond +-max_coordinate (the message
/// says how many points have one and which comes first).
/// Pre: none.
template <int D>
void check_coordinates(std::span<const Vec<D>> points);

struct KdTreeOptions {
  int leaf_size = 16;  ///< most points in a leaf; 16 measured fastest (docs/benchmarks.md)
};

template <int D>
class KdTree {
 public:
  using Point = Vec<D>;
  static constexpr std::uint32_t no_child = std::numeric_limits<std::uint32_t>::max();

  /// A node covers the points at tree positions [begin, end). An inner node
  /// splits them on axis `axis`: the left child's points have coordinates
  /// <= left_max there, the right child's >= right_min (in a refitted tree
  /// the two ranges may overlap). boxes()[id] bounds
  /// node id's points exactly (drawn by the visual feedback); it is kept
  /// apart so that a search reads 40 bytes per node, not 88.
  struct Node {
    std::uint32_t begin = 0, end = 0;
    std::uint32_t left = no_child, right = no_child;
    std::uint8_t axis = 0;
    bool identical = false;       ///< every point of the node is a copy of one point; stored by increasing index
    std::uint32_t min_index = 0;  ///< the smallest index among the node's points (as searches report them)
    double left_max = 0.0, right_min = 0.0;
    [[nodiscard]] bool is_leaf() const { return left == no_child; }
  };

  KdTree() = default;
  /// Builds the tree over `points` (n of them).
  /// Cost: O(n log n), a linear median selection per level; subtrees over 65536 points are built in parallel.
  /// Throws: InvalidInputError for more than 2^32 - 1 points, a leaf size below 1, or coordinates that are
  /// not finite or beyond +-max_coordinate (the message counts them and names the first).
  /// Pre: none.
  explicit KdTree(std::span<const Point> points, KdTreeOptions options = {});
  /// The same over the points moved by -shift (points[i] - shift, computed
  /// as the tree copies them: the caller's array is neither copied first nor
  /// changed). reconstruct() builds its tree this way from a cloud it does
  /// not own.
  /// Cost: as above.
  /// Throws: as above (the coordinates are checked before the shift).
  /// Pre: none.
  KdTree(std::span<const Point> points, KdTreeOptions options, const Point& shift);

  [[nodiscard]] std::size_t size() const { return points_.size(); }
  [[nodiscard]] bool empty() const { return points_.empty(); }

  /// The k nearest points to q, in (distance, index) order; fewer when the
  /// tree holds fewer than k points (none for k <= 0).
  /// Cost: O(log n + k) expected for well-spread points (Friedman, Bentley, Finkel); O(n) at worst.
  /// Throws: nothing.
  /// Pre: q finite.
  [[nodiscard]] std::vector<Neighbor> knn(const Point& q, int k) const;
  /// Same, writing into `out` (capacity k = out.size()); returns how many
  /// were written. No allocation: this is the form for hot loops. Only
  /// points within squared distance `within2` are considered: when the
  /// caller knows k points lie that close (for the next point of a walk,
  /// the previous one's k-th distance plus the step), the answer is the same
  /// and the search prunes from the start.
  /// Cost: as knn above.
  /// Throws: nothing.
  /// Pre: q finite.
  std::size_t knn(const Point& q, std::span<Neighbor> out,
                  double within2 = std::numeric_limits<double>::infinity()) const;

  /// The nearest point to q; {no_child, infinity} when the tree is empty.
  /// Cost: O(log n) expected; O(n) at worst.
  /// Throws: nothing.
  /// Pre: q finite.
  [[nodiscard]] Neighbor nearest(const Point& q) const;

  /// Whether some point lies within distance sqrt(radius2) of q
  /// (inclusive); false for a negative or NaN radius2. Stops at the first
  /// one found: cheaper than asking for the nearest and comparing.
  /// Cost: O(log n) expected; O(n) at worst.
  /// Throws: nothing.
  /// Pre: q finite.
  [[nodiscard]] bool any_within(const Point& q, double radius2) const;

  /// Every point within distance sqrt(radius2) of q (inclusive), in
  /// (distance, index) order.
  /// Cost: O(log n + m log m) expected for m points found (the sort); O(n + m log m) at worst.
  /// Throws: nothing.
  /// Pre: q finite.
  [[nodiscard]] std::vector<Neighbor> radius(const Point& q, double radius2) const;

  /// The nearest point whose label differs from `own_label`, among points
  /// at squared distance <= max_distance2; index == no_child when none is.
  /// Subtrees whose points all carry `own_label` are skipped. Used by the
  /// Borůvka EMST to find each component's nearest outside point.
  /// Cost: O(log n) expected when the other labels are near; O(n) at worst.
  /// Throws: nothing.
  /// Pre: point_labels has one label per input point, node_labels is node_labels(point_labels) of this
  /// tree; q finite.
  [[nodiscard]] Neighbor nearest_with_other_label(const Point& q, std::int32_t own_label,
                                                  std::span<const std::int32_t> point_labels,
                                                  std::span<const std::int32_t> node_labels,
                                                  double max_distance2) const;
  /// Per node: the label all its points share, or -1 if they differ.
  /// Cost: O(n).
  /// Throws: nothing.
  /// Pre: point_labels has one non-negative label per input point.
  [[nodiscard]] std::vector<std::int32_t> node_labels(std::span<const std::int32_t> point_labels) const;

  /// The k nearest neighbours of every point in the tree (itself included),
  /// computed in parallel, visiting the points in leaf order for locality.
  /// Cost: O(n (log n + k)) expected, shared among the threads.
  /// Throws: InvalidInputError unless 1 <= k <= size().
  /// Pre: none.
  [[nodiscard]] KnnTable all_knn(int k) const;
  /// The same table, counted for the alternatives lab: adds to
  /// counts->distance_evaluations one for every point of every leaf the
  /// searches open (the squared distances to the query they compute; the
  /// slab bounds that prune subtrees are not counted). counts == nullptr is
  /// all_knn(k). The plain all_knn(k) counts nothing and is not slowed: the
  /// counting is compiled into a separate instance of the search.
  /// Cost, throws and preconditions as all_knn(k).
  [[nodiscard]] KnnTable all_knn(int k, OperationCounts* counts) const;

  /// Renumbers the points by tree position: point t of points() becomes
  /// point t, so that queries return tree positions and order() is the
  /// identity. Returns the former index of each point (the permutation from
  /// the new numbering to the old). The leaf order is a spatial order as good
  /// as a space-filling curve: reconstruct() adopts it for all its arrays.
  /// Cost: O(n).
  /// Throws: nothing.
  /// Pre: none.
  std::vector<std::uint32_t> renumber_by_leaf_order();
  /// True after renumber_by_leaf_order().
  [[nodiscard]] bool numbered_by_leaf_order() const { return leaf_numbered_; }

  /// The same tree over other points: point i of `points` takes the place
  /// of input point i (so the nodes hold the same indices), and the boxes
  /// and splits are recomputed from the new points. Searches are exact for
  /// any points; they are as fast as in a tree built afresh when each point
  /// lies near the one it replaces, as a tangent plane's origin lies near
  /// its sample.
  /// Cost: O(n), a small fraction of a build.
  /// Throws: InvalidInputError for a different count or unusable coordinates (see check_coordinates).
  /// Pre: none.
  [[nodiscard]] KdTree refit(std::span<const Point> points) const;

  /// Nodes in pre-order; nodes()[0] is the root.
  [[nodiscard]] const std::vector<Node>& nodes() const { return nodes_; }
  /// The exact bounding box of each node's points, indexed like nodes().
  [[nodiscard]] const std::vector<Box<D>>& boxes() const { return boxes_; }
  /// The points in tree (leaf) order: tree position t holds input point order()[t].
  [[nodiscard]] std::span<const Point> points() const { return points_; }
  /// Input index of the point at tree position t (leaf order).
  [[nodiscard]] std::span<const std::uint32_t> order() const { return order_; }
  [[nodiscard]] int depth() const { return depth_; }

 private:
  template <class Visitor>
  void search(const Point& q, Visitor& visitor) const;
  // all_knn's loop with a k-NN visitor that counts or does not; returns
  // the distances the searches computed (0 when not counted).
  template <class Visitor>
  std::uint64_t fill_knn_table(KnnTable& table) const;
  template <class Visitor>
  void descend(std::uint32_t id, const Point& q, double rd, Point& offsets, Visitor& visitor) const;

  std::vector<Point> points_;         // in tree (leaf) order
  std::vector<std::uint32_t> order_;  // tree position -> input index
  std::vector<Node> nodes_;
  std::vector<Box<D>> boxes_;
  KdTreeOptions options_;
  int depth_ = 0;
  bool leaf_numbered_ = false;
};

extern template class KdTree<2>;
extern template class KdTree<3>;

}  // namespace recon
