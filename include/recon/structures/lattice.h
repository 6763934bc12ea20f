#pragma once
// The lattice of phase IV, in D = 2 (marching squares) or 3 (marching cubes)
// dimensions: cells (squares or cubes) of side `cell`, their corners at
//
//   position(i) = origin + i * cell,   i a vector of D integers,
//
// laid over the seeds' bounding box with `lattice_margin` cells to spare on
// every side. Cell i is the one whose lowest corner is corner i; it holds
// the points p with floor((p - origin) / cell) = i. The lattice is never
// stored: the walks visit only the cells near the surface, and keep their
// corners in hash tables keyed by key(i) (see lattice_table.h).
//
// A corner index packs into one 64-bit key, 64 / D bits per axis (21 in 3D,
// 32 in 2D); max_cells_per_axis keeps every corner of the lattice within
// those bits (and within int32 in 2D).

#include "recon/core/point_cloud.h"

#include <array>
#include <cmath>
#include <cstdint>
#include <span>

namespace recon {

/// Lattice corner 0 sits this many cells below the seeds' bounding box on
/// each axis: room for the surface to close beyond the outermost samples,
/// and a fractional part that keeps lattice planes off round coordinates
/// (flat data at z = 0 would otherwise put corners exactly on the surface).
inline constexpr double lattice_margin = 3.381966;

template <int D>
struct Lattice {
  static_assert(D == 2 || D == 3, "a lattice of squares or of cubes");
  using Index = std::array<std::int32_t, static_cast<std::size_t>(D)>;

  /// Bits of a key per axis, and the most cells along an axis.
  static constexpr int key_bits = 64 / D;
  static constexpr std::int32_t max_cells_per_axis = D == 3 ? (std::int32_t{1} << key_bits) - 2 : std::int32_t{1} << 30;

  /// One evaluated corner, for inspection and the visual feedback
  /// (LatticeCorner in 3D, SquareCorner in 2D).
  struct Corner {
    Index index{};       ///< lattice coordinates
    double value = 0.0;  ///< f, when defined
    bool defined = false;
  };

  Vec<D> origin = Vec<D>::Zero();  ///< position of corner (0, ..., 0)
  double cell = 0.0;               ///< side of a cell (a length)
  Index size{};                    ///< cells along each axis (corners: size + 1)

  [[nodiscard]] Vec<D> position(const Index& corner) const {
    Vec<D> p;
    for (int a = 0; a < D; ++a) p[a] = origin[a] + corner[static_cast<std::size_t>(a)] * cell;
    return p;
  }
  /// The cell holding p (possibly outside the lattice).
  [[nodiscard]] Index cell_of(const Vec<D>& p) const {
    Index i;
    for (int a = 0; a < D; ++a)
      i[static_cast<std::size_t>(a)] = static_cast<std::int32_t>(std::floor((p[a] - origin[a]) / cell));
    return i;
  }
  /// Whether cell i is one of the lattice's.
  [[nodiscard]] bool contains(const Index& i) const {
    for (std::size_t a = 0; a < axes; ++a)
      if (i[a] < 0 || i[a] >= size[a]) return false;
    return true;
  }

  /// The key of corner (or cell) i, whose coordinates are 0 .. size: axis a
  /// in bits [a * key_bits, (a + 1) * key_bits).
  [[nodiscard]] static std::uint64_t key(const Index& i) {
    std::uint64_t k = 0;
    for (std::size_t a = 0; a < axes; ++a) k |= std::uint64_t{static_cast<std::uint32_t>(i[a])} << (a * shift);
    return k;
  }
  [[nodiscard]] static Index index(std::uint64_t key) {
    constexpr std::uint64_t mask = (std::uint64_t{1} << shift) - 1;
    Index i;
    for (std::size_t a = 0; a < axes; ++a) i[a] = static_cast<std::int32_t>((key >> (a * shift)) & mask);
    return i;
  }

 private:
  static constexpr std::size_t axes = D, shift = key_bits;
};

/// The lattice the walks lay over `seeds` at cell side `cell`.
/// Cost: O(n) for the bounding box of n seeds.
/// Throws: InvalidInputError for a cell that is not a positive, finite length; ResourceLimitError when an
/// axis would need more than max_cells_per_axis cells.
/// Pre: seeds not empty, with finite coordinates.
template <int D>
[[nodiscard]] Lattice<D> make_lattice(std::span<const Vec<D>> seeds, double cell);
/// The same over the seeds' bounding box, known beforehand.
/// Cost: O(D).
/// Throws: as above.
/// Pre: box not empty, finite.
template <int D>
[[nodiscard]] Lattice<D> make_lattice(const Box<D>& box, double cell);

/// Whether make_lattice(box, cell) would fit: false where it would throw
/// ResourceLimitError. (reconstruct() asks before laying one lattice over a
/// cloud of far-apart clusters.)
/// Cost: O(D), D divisions.
/// Throws: InvalidInputError for a cell that is not a positive, finite length.
/// Pre: box not empty, finite.
template <int D>
[[nodiscard]] bool lattice_fits(const Box<D>& box, double cell);

/// Checks that `cell` can be a lattice's cell side.
/// Cost: O(1).
/// Throws: InvalidInputError unless `cell` is a positive, finite length.
/// Pre: none.
void check_lattice_cell(double cell);

}  // namespace recon
