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
/// Cost: O(1).
/// Throws: nothing.
/// Pre: k >= 0.
[[nodiscard]] double estimated_bytes_planes_and_graph(std::size_t points, int k, bool second_order_fits = false);
/// Bytes held during the 3D lattice walk: what phases I-II leave plus the cubes.
/// Cost: O(1).
/// Throws: nothing.
/// Pre: cubes >= 0.
[[nodiscard]] double estimated_bytes_lattice(std::size_t points, double cubes);

/// The peak of a whole 3D reconstruction of `points` points at k, told
/// before phase I has measured the sampling: the larger of phases I-II and
/// the walk, with 3 cubes visited a point (a surface sampled about as
/// finely as the cell; measured 2 to 3). Tiled runs (tiles.h) size their
/// tiles with it, and `recon reconstruct` decides with it to work in tiles.
/// Cost: O(1).
/// Throws: nothing.
/// Pre: k >= 0.
[[nodiscard]] double estimated_bytes_reconstruction(std::size_t points, int k, bool second_order_fits);

/// The most cubes a 3D walk over `points` points may visit within `limit`
/// bytes (marching_cubes' max_cubes): a walk estimated wrongly cannot run
/// on until memory is exhausted. 0 when the points alone exceed the limit.
/// Cost: O(1).
/// Throws: nothing.
/// Pre: none.
[[nodiscard]] std::size_t max_cubes_within(std::size_t limit, std::size_t points);
/// The same for the squares of a 2D walk (marching_squares' max_squares).
/// Cost: O(1).
/// Throws: nothing.
/// Pre: none.
[[nodiscard]] std::size_t max_squares_within(std::size_t limit);

/// `limit` when set (non-zero), default_memory_limit() otherwise.
/// Cost: O(1) (a sysconf call when `limit` is 0).
/// Throws: nothing.
/// Pre: none.
[[nodiscard]] std::size_t memory_limit_or_default(std::size_t limit);

/// Refuses `bytes` beyond `limit`, with the message "WHAT would need about X GB, more than
/// the Y GB allowed (--max-memory...): REMEDY, or raise --max-memory".
/// Cost: O(1).
/// Throws: ResourceLimitError when bytes > limit.
/// Pre: none.
void check_memory(double bytes, std::size_t limit, std::string_view what, std::string_view remedy);
/// check_memory for phases I-II of `points` points at k (remedy: lower --k or thin the cloud).
/// Cost: O(1).
/// Throws: ResourceLimitError when their estimate exceeds `limit`.
/// Pre: k >= 0.
void check_memory_planes_and_graph(std::size_t points, int k, std::size_t limit, bool second_order_fits = false);

/// A tiled run measures the cloud (rho, delta, k: tiles.h) on a sample
/// drawn within a quarter of its memory limit, as whole patches of the
/// cloud. This refuses a sample too small for phase I, with a message
/// ("the memory limit is too small for the cloud-wide statistics ...")
/// naming the limit, the points it allows (`allowed`), the points drawn and
/// the k + 1 phase I needs. A cloud of k points or fewer passes: phase I
/// itself refuses it and says to lower k.
/// Cost: O(1).
/// Throws: ResourceLimitError when drawn < k + 1 and drawn < cloud_points.
/// Pre: none.
void check_statistics_sample(std::size_t drawn, std::size_t allowed, std::size_t cloud_points, int k,
                             std::size_t limit);

}  // namespace recon
