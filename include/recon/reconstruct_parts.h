#pragma once
// The parts reconstruct() (reconstruct.h) is made of, for callers that run
// some of them on their own: a tiled run (tiles/tiles.h) runs phase I over
// the whole cloud and the later phases tile by tile, each tile with the
// options, the lattice cell, f and phase V's input that reconstruct() would
// give it; the 2D curves (curves/reconstruct_curve.h) choose the cell and
// build phase I's tree the same way; estimate_normals() runs phase I
// (reconstruct_phase_1) and phase II (orientation_options) as it does.
// A user who wants a mesh needs reconstruct.h only.

#include "recon/reconstruct.h"

#include <functional>
#include <optional>
#include <span>
#include <string>

namespace recon {

/// The refusal of a contour with no triangle, in memory and in tiles: an
/// empty mesh is never the answer to a cloud that passed phases I-III, and
/// writing one would hide the cause.
/// Cost: O(1).
/// Throws: always InvalidInputError "no surface found: FIGURES", and when
/// the cell is not smaller than half the cloud's longest side, why and the
/// cell to use (`smaller_cell`: which option gives it).
/// Pre: none.
[[noreturn]] void refuse_no_surface(const std::string& figures, double cell, double longest_side,
                                    const std::string& smaller_cell);

/// Phase III's f as reconstruct() built it for `r`: the same planes, delta
/// and plane choice.
/// Cost: O(1) (f references r's planes and tree).
/// Throws: nothing.
/// Pre: r has passed phase II (its normals oriented) and outlives f.
[[nodiscard]] SignedDistance<3> signed_distance_of(const Reconstruction& r);

/// Phase V's input as reconstruct() gave it for `r` (refined; f from
/// signed_distance_of).
/// Cost: O(1) (it references r and f).
/// Throws: nothing.
/// Pre: r from the refined method, through phase II; r and f outlive the input.
[[nodiscard]] RefinementInput refinement_input_of(const Reconstruction& r, const SignedDistance<3>& f);
/// The same from its parts (each tile of tiles.h has its own): phase I's
/// planes, their normals as phase II oriented them, the second-order fits'
/// curvature, each plane's piece of data (empty: one), f over the planes and
/// the tree over their origins (blending, on noisy data).
/// Cost: O(1) (it references them).
/// Throws: nothing.
/// Pre: the spans one entry per plane (piece: one or none); all outlive the input.
[[nodiscard]] RefinementInput refinement_input(const TangentPlanes<3>& planes, std::span<const Vec3> oriented,
                                               std::span<const Curvature> curvature,
                                               std::span<const std::uint32_t> piece, const SignedDistance<3>& f,
                                               const KdTree<3>& origin_tree);
/// Phase V's options as reconstruct() runs it at cube side `cell`: a
/// max_move of 0 becomes the cell. Cost: O(1). Throws: nothing. Pre: cell > 0.
[[nodiscard]] RefinementOptions refinement_options(const RefinementOptions& given, double cell);

/// The translation reconstruct() applies before working: the centre of the
/// bounding box when the cloud lies farther from the origin than its own
/// diagonal, zero otherwise (results of data near the origin are then
/// expressed in the input's own coordinates).
/// Cost: O(n) for n points.
/// Throws: nothing.
/// Pre: finite coordinates (working_tree checks them first).
[[nodiscard]] Vec3 working_offset(std::span<const Vec3> points);
/// The same from the points' bounding box. Cost: O(1).
[[nodiscard]] Vec3 working_offset(const Box<3>& box);

/// Phase I's kd-tree as reconstruct() and estimate_normals() start from it:
/// over the points moved by working_offset (subtracted as the tree copies
/// them), renumbered by leaf order; order[j] is the input index of point j.
struct WorkingTree {
  Vec3 offset = Vec3::Zero();
  std::vector<std::uint32_t> order;
  KdTree<3> tree;
};
/// Builds it.
/// Cost: O(n log n) for n points (the tree's build).
/// Throws: InvalidInputError for coordinates that are not finite or beyond
/// +-max_coordinate (check_coordinates), before anything else, and what
/// the tree's build throws (structures/kdtree.h).
/// Pre: none.
[[nodiscard]] WorkingTree working_tree(std::span<const Vec3> points, const KdTreeOptions& options);
/// The same moved by a given offset (a tile of a larger cloud takes the
/// whole cloud's, tiles.h). Cost, Throws: as above.
[[nodiscard]] WorkingTree working_tree(std::span<const Vec3> points, const KdTreeOptions& options, const Vec3& offset);

/// Phase II's options in a run of `options` once phase I gave `r`: the
/// refined method decides each component's side at its best extreme and
/// walks with the fits' guide normals and misfits.
/// Cost: O(1) (the fits' arrays are shared, not copied). Throws: nothing.
/// Pre: r from reconstruct_phase_1 with `options`; r outlives the options.
[[nodiscard]] OrientationOptions orientation_options(const Reconstruction& r, const ReconstructionOptions& options);
/// Phase III's options in a run of method `method`: the refined method
/// weighs 8 planes where creases are near (signed_distance.h).
/// Cost: O(1). Throws: nothing. Pre: none.
[[nodiscard]] SignedDistanceOptions signed_distance_options(Method method, const SignedDistanceOptions& given,
                                                            const std::optional<LocalQuadrics>& quadrics);

/// A lattice cell a run asks for: `cell` when given; the longest side of
/// the data's bounding box (computed only then) over `resolution` when that
/// is given; `fallback` otherwise. (Shared by the 3D and 2D runs.)
/// Cost: O(1), and longest_side's when resolution is given.
/// Throws: InvalidInputError when both are given or the one given is not positive.
/// Pre: none.
[[nodiscard]] double chosen_cell(std::optional<double> cell, std::optional<int> resolution,
                                 const std::function<double()>& longest_side, double fallback);

/// The cube side that `options` asks for, given the points and the phase I
/// result: the given cell or resolution, else rho (hoppe92) or rho / sqrt 2 (refined).
/// Cost: O(1), O(n) for a resolution (the bounding box).
/// Throws: what chosen_cell throws.
/// Pre: planes from phase I over `points`.
[[nodiscard]] double lattice_cell(std::span<const Vec3> points, const TangentPlanes<3>& planes,
                                  const ReconstructionOptions& options);
/// The same from the data's longest side (computed only when needed) and
/// the cloud's rho (a tiled run's plan, which holds no points). Cost, Throws: as above.
[[nodiscard]] double lattice_cell(const std::function<double()>& longest_side, double rho,
                                  const ReconstructionOptions& options);

}  // namespace recon
