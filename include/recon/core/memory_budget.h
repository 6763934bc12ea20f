#pragma once
// The memory budget of a run: what each stage will hold, estimated before
// it allocates, and the refusal when that exceeds the limit.
//
// The estimates come from peaks measured on this implementation (docs/
// benchmarks.md), rounded up; the colours' 3 bytes a point and a mesh vertex
// are under 1 % of them and left out. The limit is the caller's (--max-memory,
// ReconstructionOptions::max_memory) or default_memory_limit(): half the
// physical memory (resource_usage.h).
//
// Stages:
//   - phases I-II: the neighbourhoods, the planes and the Riemannian graph,
//     per point and per neighbour (the second-order fits of the refined
//     method add their curvature, misfit and guide normals);
//   - the lattice walk (3D): what phases I-II leave held per point, plus
//     each visited cube;
//   - the lattice walk (2D): each visited square.

#include <cstddef>
#include <string_view>

namespace recon {

/// Bytes phases I and II hold at their peak for `points` points at k, with
/// or without the refined method's second-order fits.
[[nodiscard]] double estimated_bytes_planes_and_graph(std::size_t points, int k, bool second_order_fits = false);
/// Bytes held during the 3D lattice walk: what phases I-II leave plus the cubes.
[[nodiscard]] double estimated_bytes_lattice(std::size_t points, double cubes);

/// The peak of a whole 3D reconstruction of `points` points at k, told
/// before phase I has measured the sampling: the larger of phases I-II and
/// the walk, with 3 cubes visited a point (a surface sampled about as
/// finely as the cell; measured 2 to 3). Tiled runs (tiles.h) size their
/// tiles with it, and `recon reconstruct` decides with it to work in tiles.
[[nodiscard]] double estimated_bytes_reconstruction(std::size_t points, int k, bool second_order_fits);

/// The most cubes a 3D walk over `points` points may visit within `limit`
/// bytes (marching_cubes' max_cubes): a walk estimated wrongly cannot run
/// on until memory is exhausted.
[[nodiscard]] std::size_t max_cubes_within(std::size_t limit, std::size_t points);
/// The same for the squares of a 2D walk (marching_squares' max_squares).
[[nodiscard]] std::size_t max_squares_within(std::size_t limit);

/// `limit` when set (non-zero), default_memory_limit() otherwise.
[[nodiscard]] std::size_t memory_limit_or_default(std::size_t limit);

/// Throws ResourceLimitError "WHAT would need about X GB, more than the Y GB
/// allowed (--max-memory...): REMEDY, or raise --max-memory" when bytes > limit.
void check_memory(double bytes, std::size_t limit, std::string_view what, std::string_view remedy);
/// check_memory for phases I-II of `points` points at k.
void check_memory_planes_and_graph(std::size_t points, int k, std::size_t limit, bool second_order_fits = false);

/// A tiled run measures the cloud (rho, delta, k: tiles.h) on a sample
/// drawn within a quarter of its memory limit, as whole patches of the
/// cloud. Throws ResourceLimitError "the memory limit is too small for the
/// cloud-wide statistics ..." naming the limit, the points it allows
/// (`allowed`), the points drawn and the k + 1 phase I needs, when fewer
/// than k + 1 were drawn from a cloud of more (`cloud_points`); a cloud of
/// k points or fewer is refused by phase I itself, which says to lower k.
void check_statistics_sample(std::size_t drawn, std::size_t allowed, std::size_t cloud_points, int k,
                             std::size_t limit);

}  // namespace recon
