#pragma once
// Uniform grid (spatial hash): exact k nearest neighbours by searching cells
// in rings around the query, the structure Hoppe's own 1992 program used.
//
// The textbook algorithm
//   Build: cut space into cubes (squares in 2D) of edge h, starting at the
//     bounding box's min corner; put every point in the cell it falls in.
//   Query q, k:
//     1. start at q's cell: ring 0;
//     2. compute the distances to the points of every cell of the next ring
//        (the cells whose largest coordinate difference from q's cell is r),
//        keeping the k nearest found so far; a cell whose box lies farther
//        than the k-th of them holds none of the answer and is skipped;
//     3. stop when k are found and the k-th lies nearer than any cell not
//        yet searched (the nearest face of the searched block of rings);
//        otherwise r + 1 and step 2.
//   A point beyond the searched block is at least as far as that face, so
//   the answer is exact.
//
// Storage: a hash of the occupied cells. The points are sorted by cell and
// stored cell after cell (CSR), and an open-addressing hash table maps a
// cell's integer coordinates to its range of positions [begin, end) (the
// offsets live in the table's slots: a search reads one slot for a cell,
// not a slot and then an offset array). A dense array over the bounding box
// would hold every cell of the box, and the box of a surface is mostly
// empty: at the default cell size it has on the order of n^(3/2) cells for n
// points on a surface, the occupied ones only about n / 7. The hash keeps
// memory O(n) whatever the shape and the cell size (under 40 bytes a point
// in 3D at the default size: the copied points, their indices, and two to
// four 16-byte hash slots per occupied cell).
//
// Contract (the kd-tree's, kdtree.h, so that tables compare entry for entry)
// - Distances are SQUARED Euclidean distances, computed as
//   (p - q).squaredNorm() like the kd-tree's: bit-identical to its own.
// - Indices are positions in the span given to the constructor.
// - A query that is one of the points IS its own neighbour (distance 0).
// - Results are ordered by (squared distance, index), ties going to the
//   smaller index: one correct answer, the one brute force gives.
//   Duplicate points are fine.
// - The grid copies the points (in cell order); the span need not outlive it.
// - A built grid is immutable; const queries are safe from many threads.
// - Counting (counts != nullptr): adds to counts->distance_evaluations one
//   per point of every cell whose points a query scans (the squared
//   distances computed); the cell-to-query bounds that skip cells are not
//   counted, as the kd-tree's slab bounds are not.
//
// The default cell size (default_cell_size): a surface sample of n points
// spread across a box of diagonal L covers an area on the order of L^2 (a
// torus 1 and 0.35 in radius: 13.8 against L^2 = 15.1), so cells of edge
// h = L * sqrt(m / n) hold about m points each where the surface crosses
// them. A closed curve (2D) is about twice as long as its box's diagonal (a
// circle: pi / sqrt 2 = 2.2 times), so there h = 2 L * m / n.
// m = target_points_per_cell = 8 (about 7 a cell on a torus): k-NN for
// k = 15..20 then stops after ring 1, the 27 cells around q's, in 99 % of
// the queries; smaller cells need ring 2 and are slower, larger ones only
// compute more distances (measured, see uniform_grid.cpp). A volume cloud
// gets fewer points a cell and searches a ring or two more: still exact,
// only slower. Points that all coincide get h = 1 (one cell).
//
// Guards
// - Cell coordinates are packed into a 64-bit key, 63 / D bits an axis, so
//   the box may be at most max_cells_across (2^21 in 3D, 2^31 in 2D) cells
//   wide along any axis: a smaller cell size is refused. It is also where a
//   dense grid would need absurd memory (2^63 cells); the hash itself needs
//   O(n) at any size. The default cell size always passes (sqrt(n / 8)
//   cells across at most in 3D, n / 16 in 2D).
// - A cell size too small for the data's spacing does not make searches
//   blow up: once the block of rings to search holds more cells than the grid
//   has occupied ones, the query visits the occupied cells directly (the
//   grid's worst case is then brute force over its cells).
// - Cell sizes above 4 * max_coordinate all make the same one-cell grid and
//   are taken as 4 * max_coordinate, so that squared distances in cells
//   cannot overflow.

#include "recon/core/operation_counts.h"
#include "recon/core/point_cloud.h"
#include "recon/structures/kdtree.h"

#include <cstdint>
#include <span>
#include <vector>

namespace recon {

template <int D>
class UniformGrid {
 public:
  using Point = Vec<D>;
  /// Integer coordinates of a cell: cell c spans [origin + c h, origin + (c + 1) h) along each axis.
  using Cell = Eigen::Matrix<std::int64_t, D, 1>;

  static constexpr int bits_per_axis = 63 / D;
  static constexpr std::int64_t max_cells_across = std::int64_t{1} << bits_per_axis;
  static constexpr double target_points_per_cell = 8.0;  ///< m of the default cell size (see above)

  /// Builds the grid with cells of default_cell_size(points).
  /// Cost: O(n) (a hash per point); here O(n log n), a sort by cell for the CSR order.
  /// Throws: InvalidInputError for more than 2^32 - 2 points or coordinates not finite or beyond +-max_coordinate.
  /// Pre: none.
  explicit UniformGrid(std::span<const Point> points);
  /// Builds the grid with cells of edge `cell_size`.
  /// Cost: as above.
  /// Throws: InvalidInputError as above, and for a cell size that is not finite, not positive, or so small that
  /// the points span more than max_cells_across cells along an axis (the guard above).
  /// Pre: none.
  UniformGrid(std::span<const Point> points, double cell_size);

  /// L * sqrt(m / n) in 3D, 2 L * m / n in 2D (L the bounding box's diagonal,
  /// m = target_points_per_cell); 1 when L is 0 or there are no points.
  /// Cost: O(n).
  /// Throws: InvalidInputError for coordinates not finite or beyond +-max_coordinate.
  /// Pre: none.
  [[nodiscard]] static double default_cell_size(std::span<const Point> points);

  [[nodiscard]] std::size_t size() const { return points_.size(); }
  /// The cell size in use: the one asked for, or 4 * max_coordinate if it was larger.
  [[nodiscard]] double cell_size() const { return cell_size_; }
  /// The corner of cell (0, ..., 0): the points' bounding box's min corner.
  [[nodiscard]] const Point& origin() const { return origin_; }
  /// Cells along each axis of the points' bounding box.
  [[nodiscard]] const Cell& cells_across() const { return cells_across_; }
  /// Cells holding at least one point.
  [[nodiscard]] std::size_t occupied_cells() const { return occupied_cells_; }

  /// The k nearest points to q, in (distance, index) order.
  /// Cost: O(C + p k) for the C cells searched and the p points in them, a point that enters the k best being
  /// inserted in order (most queries at the default size: 27 cells of about 8 points); at worst O(n k).
  /// Throws: InvalidInputError for k < 1 or k > size() (it does not answer with fewer as KdTree::knn does), or a
  /// coordinate of q that is not finite or beyond +-max_coordinate.
  /// Pre: none.
  [[nodiscard]] std::vector<Neighbor> knn(const Point& q, int k, OperationCounts* counts = nullptr) const;

  /// The k nearest neighbours of every point (itself included), as
  /// KdTree::all_knn returns them: row i lists point i's k nearest. Computed
  /// in parallel, visiting the points cell by cell; the table does not
  /// depend on the thread count.
  /// Cost: n queries as knn's.
  /// Throws: InvalidInputError for k < 1 or k > size().
  /// Pre: none.
  [[nodiscard]] KnnTable all_knn(int k, OperationCounts* counts = nullptr) const;

 private:
  // An occupied cell: its packed coordinates (key_of), or empty_slot, and
  // the positions of its points.
  struct Slot {
    std::uint64_t key;
    std::uint32_t begin, end;
  };
  static constexpr std::uint64_t empty_slot = ~std::uint64_t{0};  // no packed key has the top bit

  class Query;  // one search's state and steps (uniform_grid.cpp)

  // The construction's steps.
  void measure_in_cells(const Box<D>& box);
  std::vector<Slot> store_by_cell(std::span<const Point> points);
  void fill_table(const std::vector<Slot>& cells);

  [[nodiscard]] std::uint64_t key_of(const Cell& cell) const;
  [[nodiscard]] Cell cell_of_key(std::uint64_t key) const;
  /// The slot of an occupied cell; nullptr for an empty one.
  [[nodiscard]] const Slot* find(const Cell& cell) const;
  void check_k(int k) const;
  // The k = out.size() nearest to q into `out`; returns the distances computed.
  std::uint64_t search(const Point& q, std::span<Neighbor> out) const;

  Point origin_ = Point::Zero();
  double cell_size_ = 1.0;
  Cell cells_across_ = Cell::Ones();
  std::vector<Point> points_;         // in cell order
  std::vector<std::uint32_t> order_;  // position -> input index
  std::vector<Slot> table_;           // open addressing, a power of two long, at most half full
  int table_bits_ = 1;                // table_.size() == 2^table_bits_
  std::size_t occupied_cells_ = 0;
};

extern template class UniformGrid<2>;
extern template class UniformGrid<3>;

}  // namespace recon
