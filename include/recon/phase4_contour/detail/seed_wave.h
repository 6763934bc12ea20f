#pragma once
// Machinery of reconstruct()'s pipelining, not part of phase IV's contract
// (marching_cubes.h): the walk's first wave, built and evaluated ahead of the
// walk, beside phase II.
//
// The first wave depends on the seeds and the cell only: the lattice, the
// cubes that hold a seed (in the order the walk takes them, seed by seed)
// and the corners of those cubes, each once, in the order the walk meets
// them (a cube's corners in marching-cubes order). It can be built, and f
// evaluated at its corners, before f's signs are settled: reconstruct() does
// both beside phase II, and the walk then starts from it with the values
// instead of from the seeds.

#include "recon/phase4_contour/marching_cubes.h"
#include "recon/structures/lattice.h"

#include <array>
#include <cstdint>
#include <memory>
#include <span>

namespace recon {

class SeedWave {
 public:
  /// Throws as marching_cubes() does for the cell and the lattice size, and
  /// InvalidInputError when there are no seeds.
  SeedWave(std::span<const Vec3> seeds, double cell);
  /// The same on a region's lattice (MarchingCubesOptions::region): only
  /// the seeds in its walk box count (there may be none).
  SeedWave(std::span<const Vec3> seeds, double cell, const LatticeRegion& region);
  SeedWave(SeedWave&&) noexcept;
  SeedWave& operator=(SeedWave&&) noexcept;
  ~SeedWave();

  /// (A wave moved from, as into marching_cubes(), is empty: no cubes, no
  /// corners, and lattice() must not be called.)
  [[nodiscard]] const Lattice<3>& lattice() const;
  [[nodiscard]] std::size_t cube_count() const;
  [[nodiscard]] std::size_t corner_count() const;
  /// Corner i of the wave, in the order above. Corner indices past
  /// corner_count() throw InvalidInputError here and below.
  [[nodiscard]] std::array<std::int32_t, 3> corner(std::size_t i) const;
  /// Gives f's value at corner i (NaN: undefined). The walk takes it instead
  /// of calling f there: it must be what f gives, or the mesh is that of
  /// another function. Safe from several threads at once for distinct i.
  void set_value(std::size_t i, double value);
  /// The value given at corner i; NaN when none was (or f is undefined there).
  [[nodiscard]] double value(std::size_t i) const;

  struct Walk;  // the walk's state: the lattice, its corner table and the first wave's cubes

 private:
  void add_seeds(std::span<const Vec3> seeds, const LatticeRegion* region);
  std::unique_ptr<Walk> walk_;
  friend struct SeedWaveAccess;
};

/// The walk of marching_cubes() from a first wave built beforehand (at
/// options.cell): f is not called at the corners whose value was given
/// (SeedWave::set_value). Throws InvalidInputError when the wave was built at
/// another cell or was moved away already.
[[nodiscard]] MarchingCubesResult marching_cubes(const ScalarField& f, SeedWave wave,
                                                 const MarchingCubesOptions& options);

}  // namespace recon
