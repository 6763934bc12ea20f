#pragma once
// Step 1 of a tiled run (tiles.h), when the cloud is larger than one
// phase I can measure: the cloud-wide measures taken exactly, over the
// tiles. Private to src/.
//
// The plain idea: phase I's cloud-wide measures (the medians behind rho,
// the gap and the noise, the irregularity of the spacing, k raised for
// noise, the medians of the refined fits) are each made of one value per
// sample. So run phase I on every tile, keep the values of the samples the
// tile owns (its core's), and take the measures over all of them: sums in
// fixed point, medians by rank with a selection over the values on disk
// (two passes over the files, 64 Ki counters, whatever the cloud's size).
// The measures then equal reconstruct()'s on the whole cloud
// (tangent_planes.h says how each measure allows this).
//
// The steps mirror phase I in memory (reconstruct.cpp, phase_1):
//   A. planes at k: the spacing's measures; k raised once for noise (A
//      again at the raised k);
//   B. (refined) the quadrics' own fits: their residuals' median, and how
//      many neighbourhoods were split into two sheets (a raised k is undone
//      when more than a quarter were: A and B again at the k asked for);
//   C. (refined) the quadrics taken, given B's medians: the median of their
//      residuals, the noise.
// Each step reads every tile's points once and runs phase I there.
//
// Cost: phase I two to five times over the tiles (the cloud and its
// halos), and 12 bytes a sample on disk.

#include "recon/tiles/tiles.h"

#include <cstdint>
#include <filesystem>
#include <optional>

namespace recon::tile_statistics {

/// The cloud-wide measures, as reconstruct() takes them over the whole cloud.
struct Measures {
  int k = 0;
  CloudSpacing spacing;  ///< (refined: its noise is the quadrics')
  std::optional<QuadricMedians> quadric_medians;
  /// 99.9th percentiles of the neighbourhood radius and of rho_i (for the halo).
  double radius_q = 0.0, rho_q = 0.0;
  std::uint64_t samples = 0;  ///< the samples measured (each tile's own)
  /// Samples whose neighbourhood may reach past their tile's points: 0
  /// when the plan's halo holds them all (as it should).
  std::uint64_t inexact = 0;
};

/// Phase I over the tiles of `plan`, binned in `dir`, with the options
/// asked for (`asked`: k, adapt_k, rho, the fits' options, cell or
/// resolution, max_memory); the tiles must hold every point of the cloud
/// in their cores. Throws what reading the tiles' files throws (ParseError,
/// IoError naming the file) and InvalidInputError for options phase I refuses.
[[nodiscard]] Measures measure_over_tiles(const TilePlan& plan, const std::filesystem::path& dir,
                                          const ReconstructionOptions& asked);

}  // namespace recon::tile_statistics
