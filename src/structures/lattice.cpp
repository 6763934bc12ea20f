#include "recon/structures/lattice.h"

#include "recon/core/errors.h"

#include <cmath>
#include <cstdio>
#include <string>

namespace recon {

void check_lattice_cell(double cell) {
  if (!std::isfinite(cell) || !(cell > 0.0))  // isfinite first: see fp_traps.h
    throw InvalidInputError("the lattice cell size must be a positive length");
}

template <int D>
Lattice<D> make_lattice(std::span<const Vec<D>> seeds, double cell) {
  Box<D> box;
  for (const Vec<D>& p : seeds) box.extend(p);
  return make_lattice<D>(box, cell);
}

namespace {
// Cells along axis a of the lattice over `box`, margins included (a double:
// it may be far beyond any integer type).
template <int D>
double cells_along(const Box<D>& box, double cell, int a) {
  const double margin = lattice_margin * cell;
  return std::ceil((box.max[a] - box.min[a] + 2.0 * margin) / cell);
}
}  // namespace

template <int D>
bool lattice_fits(const Box<D>& box, double cell) {
  check_lattice_cell(cell);
  for (int a = 0; a < D; ++a)
    if (!(cells_along<D>(box, cell, a) <= Lattice<D>::max_cells_per_axis)) return false;
  return true;
}

template <int D>
Lattice<D> make_lattice(const Box<D>& box, double cell) {
  check_lattice_cell(cell);
  Lattice<D> lattice;
  lattice.cell = cell;
  lattice.origin = box.min - Vec<D>::Constant(lattice_margin * cell);
  for (int a = 0; a < D; ++a) {
    const double cells = cells_along<D>(box, cell, a);
    if (!(cells <= Lattice<D>::max_cells_per_axis)) {
      char count[32];
      std::snprintf(count, sizeof count, "%.3g", cells);  // (never 300 digits)
      throw ResourceLimitError(std::string("the lattice would need ") + count + (D == 3 ? " cubes" : " squares") +
                               " along axis " + "xyz"[a] + " (at most " +
                               std::to_string(Lattice<D>::max_cells_per_axis) + "): use a larger --cell" +
                               (D == 3 ? " or a smaller --resolution" : ""));
    }
    lattice.size[static_cast<std::size_t>(a)] = static_cast<std::int32_t>(cells);
  }
  return lattice;
}

template Lattice<2> make_lattice<2>(std::span<const Vec<2>>, double);
template Lattice<3> make_lattice<3>(std::span<const Vec<3>>, double);
template Lattice<2> make_lattice<2>(const Box<2>&, double);
template Lattice<3> make_lattice<3>(const Box<3>&, double);
template bool lattice_fits<2>(const Box<2>&, double);
template bool lattice_fits<3>(const Box<3>&, double);

}  // namespace recon
