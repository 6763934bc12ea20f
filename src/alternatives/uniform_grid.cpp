#include "recon/alternatives/uniform_grid.h"

#include "recon/core/errors.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <utility>

namespace recon {
namespace {

constexpr double infinity = std::numeric_limits<double>::infinity();

// A query farther than this many cells from the origin is placed at this
// distance instead: far beyond any grid (2^31 cells at most), and the
// division that finds its cell cannot overflow.
constexpr double farthest_cell = 0x1p62;

// Fibonacci hashing (Knuth): multiply by 2^64 / golden ratio and keep the
// top bits, which depend on every bit of the key.
std::size_t hash_slot(std::uint64_t key, int table_bits) {
  return static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ULL) >> (64 - table_bits));
}

// The distance, in cells, from coordinate `low` up to coordinate `high`
// along one axis, shortened by a hair. The hair covers rounding: a point's
// cell and the query's position in cells are computed, not exact, and a
// point lying on a cell face may tie the k-th distance, so a bound must
// never exceed the true distance. 1e-12 relative is thousands of times the
// few ulps at stake, and costs a search at most a rare extra ring.
double gap_in_cells(double low, double high) {
  return std::max(0.0, high - low - 1e-12 * (1.0 + std::abs(low) + std::abs(high)));
}

// The k best candidates seen so far, in (distance, index) order in a
// caller's buffer: a better candidate is inserted where it belongs and the
// worst drops off the end. For the small k of surface reconstruction this
// beats a heap (as in the kd-tree): most candidates lose to the k-th at
// once, and the few that win move a few entries.
struct KBest {
  std::span<Neighbor> out;
  std::size_t count = 0;

  [[nodiscard]] bool full() const { return count == out.size(); }
  /// The k-th distance so far; infinity until k are found.
  [[nodiscard]] double worst2() const { return full() ? out.back().distance2 : infinity; }
  void offer(const Neighbor& candidate) {
    if (full()) {
      if (!(candidate < out.back())) return;
    } else {
      ++count;
    }
    std::size_t i = count - 1;
    for (; i > 0 && candidate < out[i - 1]; --i) out[i] = out[i - 1];
    out[i] = candidate;
  }
};

}  // namespace

// ---------------------------------------------------------------------------
// Build

// The choice of m = target_points_per_cell, measured: all_knn over a torus
// sample of 1M points, one thread, seconds and distances a point (the
// kd-tree: 1.59 s and 76 for k = 15, 2.11 s and 91 for k = 20):
//   m                   1      2      4      8     16
//   points a cell     1.6    2.3    3.8    7.0   13.3
//   k = 15, s        5.77   3.58   2.43   2.22   2.10
//           dist.      29     33     45     72     94
//   k = 20, s        7.26   4.27   2.94   2.50   2.48
//           dist.      36     42     51     81    117
// Small cells cost cell visits (ring 2 is 98 cells), large ones distances;
// m = 8 is within 6 % of the fastest and computes fewer distances than the kd-tree.
template <int D>
double UniformGrid<D>::default_cell_size(std::span<const Point> points) {
  check_coordinates<D>(points);  // before measuring the box
  const double diagonal = bounding_box<D>(points).diagonal();
  if (points.empty() || !(diagonal > 0.0)) return 1.0;
  const double per_point = target_points_per_cell / static_cast<double>(points.size());
  return D == 3 ? diagonal * std::sqrt(per_point) : 2.0 * diagonal * per_point;
}

template <int D>
UniformGrid<D>::UniformGrid(std::span<const Point> points) : UniformGrid(points, default_cell_size(points)) {}

template <int D>
UniformGrid<D>::UniformGrid(std::span<const Point> points, double cell_size) {
  if (!std::isfinite(cell_size) || !(cell_size > 0.0)) {  // isfinite first: no FP exception on NaN
    std::ostringstream message;
    message << "uniform grid: the cell size must be positive and finite, not " << cell_size;
    throw InvalidInputError(message.str());
  }
  if (points.size() >= std::numeric_limits<std::uint32_t>::max())
    throw InvalidInputError("uniform grid: " + std::to_string(points.size()) +
                            " points is more than the 2^32 - 2 supported");
  check_coordinates<D>(points);
  cell_size_ = std::min(cell_size, 4.0 * max_coordinate);
  if (points.empty()) return;
  measure_in_cells(bounding_box<D>(points));
  const std::vector<Slot> cells = store_by_cell(points);
  occupied_cells_ = cells.size();
  fill_table(cells);
}

// The box, measured in cells; refused when a coordinate would not fit its
// bits of the key.
template <int D>
void UniformGrid<D>::measure_in_cells(const Box<D>& box) {
  origin_ = box.min;
  for (int a = 0; a < D; ++a) {
    const double extent = box.max[a] - origin_[a];
    const auto most = static_cast<double>(max_cells_across);
    if (!(extent < most * cell_size_)) {  // extent / cell_size_ might overflow
      std::ostringstream message;
      message << "uniform grid: a cell size of " << cell_size_ << " makes the points more than " << max_cells_across
              << " cells wide along axis " << a << "; choose a cell size of at least " << 2.0 * extent / most
              << " (or leave it to the default)";
      throw InvalidInputError(message.str());
    }
    // Monotone rounding keeps every point's cell below this, as the box's
    // max corner's is.
    cells_across_[a] = static_cast<std::int64_t>(std::floor(extent / cell_size_)) + 1;
  }
}

// Copies the points sorted by cell (then by index: the order is
// deterministic) and returns each occupied cell with its range of positions.
template <int D>
std::vector<typename UniformGrid<D>::Slot> UniformGrid<D>::store_by_cell(std::span<const Point> points) {
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(points.size());  // (cell, index)
  for (std::size_t i = 0; i < points.size(); ++i) {
    Cell cell;
    for (int a = 0; a < D; ++a)
      cell[a] = static_cast<std::int64_t>(std::floor((points[i][a] - origin_[a]) / cell_size_));
    keyed[i] = {key_of(cell), static_cast<std::uint32_t>(i)};
  }
  std::sort(keyed.begin(), keyed.end());

  points_.resize(points.size());
  order_.resize(points.size());
  std::vector<Slot> cells;
  for (std::size_t t = 0; t < keyed.size(); ++t) {
    const auto& [key, i] = keyed[t];
    if (t == 0 || key != cells.back().key) cells.push_back(Slot{key, static_cast<std::uint32_t>(t), 0});
    cells.back().end = static_cast<std::uint32_t>(t + 1);
    points_[t] = points[i];
    order_[t] = i;
  }
  return cells;
}

// The hash table: at most half full, so that a probe ends soon.
template <int D>
void UniformGrid<D>::fill_table(const std::vector<Slot>& cells) {
  while ((std::size_t{1} << table_bits_) < 2 * cells.size()) ++table_bits_;
  table_.assign(std::size_t{1} << table_bits_, Slot{empty_slot, 0, 0});
  const std::size_t mask = table_.size() - 1;
  for (const Slot& cell : cells) {
    std::size_t s = hash_slot(cell.key, table_bits_);
    while (table_[s].key != empty_slot) s = (s + 1) & mask;  // linear probing
    table_[s] = cell;
  }
}

// Cell coordinates, each in [0, max_cells_across), side by side in one integer.
template <int D>
std::uint64_t UniformGrid<D>::key_of(const Cell& cell) const {
  std::uint64_t key = 0;
  for (int a = D - 1; a >= 0; --a) key = (key << bits_per_axis) | static_cast<std::uint64_t>(cell[a]);
  return key;
}

template <int D>
typename UniformGrid<D>::Cell UniformGrid<D>::cell_of_key(std::uint64_t key) const {
  const std::uint64_t mask = (std::uint64_t{1} << bits_per_axis) - 1;
  Cell cell;
  for (int a = 0; a < D; ++a) {
    cell[a] = static_cast<std::int64_t>(key & mask);
    key >>= bits_per_axis;
  }
  return cell;
}

template <int D>
const typename UniformGrid<D>::Slot* UniformGrid<D>::find(const Cell& cell) const {
  if (table_.empty()) return nullptr;
  const std::uint64_t key = key_of(cell);
  const std::size_t mask = table_.size() - 1;
  for (std::size_t s = hash_slot(key, table_bits_);; s = (s + 1) & mask) {
    if (table_[s].key == key) return &table_[s];
    if (table_[s].key == empty_slot) return nullptr;
  }
}

// ---------------------------------------------------------------------------
// Search

// One k-NN query: the steps of the header's algorithm, and the fallback for
// cells far too small. Positions are measured in cells from the origin.
template <int D>
class UniformGrid<D>::Query {
 public:
  Query(const UniformGrid& grid, const Point& q, std::span<Neighbor> out) : grid_(grid), q_(q), best_{out, 0} {
    for (int a = 0; a < D; ++a) {
      const double offset = q[a] - grid.origin_[a];
      u_[a] = std::abs(offset) <= farthest_cell * grid.cell_size_ ? offset / grid.cell_size_
                                                                  : std::copysign(farthest_cell, offset);
      // Outside the box, q's cell is taken as the one just beyond its face:
      // rings grow from there, and the bounds use q's true position.
      home_[a] = std::clamp(static_cast<std::int64_t>(std::floor(u_[a])), std::int64_t{-1}, grid.cells_across_[a]);
    }
  }

  // Steps 1 to 3. Returns the distances computed.
  std::uint64_t run() {
    for (std::int64_t r = 0;; ++r) {
      if (r > 0 && block_cells(r) > grid_.occupied_cells()) {
        search_occupied_cells_beyond(r - 1);
        break;
      }
      search_ring(r);
      const double unsearched2 = distance2_to_unsearched(r);
      if (unsearched2 == infinity || best_.worst2() < unsearched2) break;
    }
    return evaluations_;
  }

 private:
  // Step 2 for ring r: every cell of the ring inside the grid, but for those
  // whose box is farther than the k-th distance found so far.
  void search_ring(std::int64_t r) {
    if (r == 0) {
      if (inside_grid(home_)) search_cell_if_near(home_);
      return;
    }
    // Each cell of the ring once: it lies on the faces home[a] +- r of the
    // block for some axes a; it is visited with the first of them, so the
    // axes before a stay strictly inside the block.
    for (int a = 0; a < D; ++a) {
      for (const std::int64_t side : {-r, r}) {
        Cell low, high;
        bool empty = false;
        for (int b = 0; b < D; ++b) {
          const std::int64_t reach = b == a ? 0 : b < a ? r - 1 : r;
          const std::int64_t centre = b == a ? home_[b] + side : home_[b];
          low[b] = std::max<std::int64_t>(centre - reach, 0);
          high[b] = std::min(centre + reach, grid_.cells_across_[b] - 1);
          empty = empty || low[b] > high[b];
        }
        if (!empty) for_each_cell(low, high);
      }
    }
  }

  // Every cell of the block [low, high], row by row.
  void for_each_cell(const Cell& low, const Cell& high) {
    Cell cell = low;
    while (true) {
      search_cell_if_near(cell);
      int b = 0;  // the odometer's next digit: axes at their high wrap to their low
      while (b < D && cell[b] == high[b]) {
        cell[b] = low[b];
        ++b;
      }
      if (b == D) return;
      ++cell[b];
    }
  }

  // Step 3's bound: the squared distance from q to the nearest cell outside
  // the block of rings 0..r, i.e. to the nearest face of the block that has
  // grid cells beyond it; infinity when the block covers the grid.
  [[nodiscard]] double distance2_to_unsearched(std::int64_t r) const {
    double gap = infinity;
    for (int a = 0; a < D; ++a) {
      if (home_[a] - r > 0) gap = std::min(gap, gap_in_cells(static_cast<double>(home_[a] - r), u_[a]));
      if (home_[a] + r + 1 < grid_.cells_across_[a])
        gap = std::min(gap, gap_in_cells(u_[a], static_cast<double>(home_[a] + r + 1)));
    }
    return gap == infinity ? infinity : gap * gap * grid_.cell_size_ * grid_.cell_size_;
  }

  // A lower bound on the squared distance from q to any point of `cell`.
  [[nodiscard]] double distance2_to_cell(const Cell& cell) const {
    double sum = 0.0;
    for (int a = 0; a < D; ++a) {
      const auto low = static_cast<double>(cell[a]);
      double gap = 0.0;
      if (u_[a] < low) gap = gap_in_cells(u_[a], low);
      if (u_[a] > low + 1.0) gap = gap_in_cells(low + 1.0, u_[a]);
      sum += gap * gap;
    }
    return sum * grid_.cell_size_ * grid_.cell_size_;
  }

  void search_cell_if_near(const Cell& cell) {
    if (best_.full() && distance2_to_cell(cell) > best_.worst2()) return;  // equal may hold a tie: searched
    if (const Slot* slot = grid_.find(cell)) search_cell(*slot);
  }

  void search_cell(const Slot& slot) {
    for (std::uint32_t t = slot.begin; t < slot.end; ++t)
      best_.offer(Neighbor{grid_.order_[t], (grid_.points_[t] - q_).squaredNorm()});
    evaluations_ += slot.end - slot.begin;
  }

  // Cells of the block of rings 0..r inside the grid.
  [[nodiscard]] std::uint64_t block_cells(std::int64_t r) const {
    std::uint64_t cells = 1;  // at most 2^63: the grid's cells fit a 63-bit key
    for (int a = 0; a < D; ++a) {
      const std::int64_t low = std::max<std::int64_t>(home_[a] - r, 0);
      const std::int64_t high = std::min(home_[a] + r, grid_.cells_across_[a] - 1);
      cells *= low > high ? 0 : static_cast<std::uint64_t>(high - low + 1);
    }
    return cells;
  }

  // The fallback, when rings hold more cells than the grid has points' cells
  // (a cell size far below the spacing): visit the occupied cells outside
  // the rings 0..r already searched directly, skipping those too far.
  void search_occupied_cells_beyond(std::int64_t r) {
    for (const Slot& slot : grid_.table_) {
      if (slot.key == empty_slot) continue;
      const Cell cell = grid_.cell_of_key(slot.key);
      if ((cell - home_).cwiseAbs().maxCoeff() <= r) continue;  // in rings 0..r
      if (!best_.full() || distance2_to_cell(cell) <= best_.worst2()) search_cell(slot);
    }
  }

  [[nodiscard]] bool inside_grid(const Cell& cell) const {
    return (cell.array() >= 0).all() && (cell.array() < grid_.cells_across_.array()).all();
  }

  const UniformGrid& grid_;
  const Point& q_;
  KBest best_;
  Point u_;    // q in cells from the origin (within +-farthest_cell)
  Cell home_;  // q's cell, or the one just beyond the grid's face when q is outside
  std::uint64_t evaluations_ = 0;
};

template <int D>
std::uint64_t UniformGrid<D>::search(const Point& q, std::span<Neighbor> out) const {
  return Query(*this, q, out).run();
}

template <int D>
void UniformGrid<D>::check_k(int k) const {
  if (k < 1 || static_cast<std::size_t>(k) > size())
    throw InvalidInputError("uniform grid: k = " + std::to_string(k) + " neighbours asked of a grid of " +
                            std::to_string(size()) + " points");
}

template <int D>
std::vector<Neighbor> UniformGrid<D>::knn(const Point& q, int k, OperationCounts* counts) const {
  check_k(k);
  for (int a = 0; a < D; ++a) {
    if (std::isfinite(q[a]) && std::abs(q[a]) <= max_coordinate) continue;  // isfinite first: no FP exception on NaN
    std::ostringstream message;
    message << "uniform grid: the query has a coordinate that is not finite or beyond +-" << max_coordinate;
    throw InvalidInputError(message.str());
  }
  std::vector<Neighbor> nearest(static_cast<std::size_t>(k));
  const std::uint64_t evaluations = search(q, nearest);
  if (counts != nullptr) counts->distance_evaluations += evaluations;
  return nearest;
}

template <int D>
KnnTable UniformGrid<D>::all_knn(int k, OperationCounts* counts) const {
  check_k(k);
  const auto kk = static_cast<std::size_t>(k);
  KnnTable table;
  table.k = k;
  table.entries.resize(size() * kk);
  const auto n = static_cast<std::int64_t>(size());
  std::uint64_t evaluations = 0;
#pragma omp parallel for schedule(dynamic, 1024) reduction(+ : evaluations)
  for (std::int64_t s = 0; s < n; ++s) {
    const auto t = static_cast<std::size_t>(s);
    const auto i = static_cast<std::size_t>(order_[t]);
    evaluations += search(points_[t], std::span<Neighbor>(table.entries.data() + i * kk, kk));
  }
  if (counts != nullptr) counts->distance_evaluations += evaluations;
  return table;
}

template class UniformGrid<2>;
template class UniformGrid<3>;

}  // namespace recon
