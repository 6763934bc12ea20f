#pragma once
// Phase IV in two dimensions: the zero set of the signed distance f becomes
// polylines by marching squares over a lattice (lattice.h), visiting only
// the squares near the curve (the 2D twin of marching_cubes.h).
//
// The textbook algorithm: for every square of a lattice over the bounding
// box, evaluate f at its 4 corners, and draw a segment between the sides
// where f changes sign (two segments in the two saddle cases); chain the
// segments into polylines.
//
// Lattice: squares of side `cell`, aligned on the seeds' bounding box with
// the same margin as the cubes (lattice_margin). The walk starts from the
// squares that contain a seed (a sample) and moves to a neighbouring square
// only across a side whose two corners do not have the same sign, or where
// f = 0 at a corner: the curve goes on there. Corner values are computed
// once and kept in a hash table, so time and memory grow with the length of
// the curve, not the area of the box.
//
// Per square (corners c0 = (0,0), c1 = (1,0), c2 = (1,1), c3 = (0,1), sides
// s_j from c_j to c_{j+1}, counter-clockwise):
// - a corner where f is undefined (phase III): the square yields nothing and
//   the walk does not go on through it, so the curve stays open there;
// - a corner is inside where f < 0; f = 0 counts as outside (as in 3D);
// - optionally (max_slope > 0), a side where f changes sign by more than
//   max_slope times the side's length makes the square yield nothing, as an
//   undefined corner does. A distance changes no faster than the distance
//   travelled (slope 1), so such a jump is no crossing of the curve but a
//   seam: the place where the nearest tangent line switches between two
//   lines that disagree (the two ends of a gap in the data, or the two
//   sides of a feature thinner than the sampling), where Hoppe's f jumps
//   from one sign to the other;
// - each side whose corners differ gets one vertex, at the linear
//   interpolation of the two values (kept at least 1/1000 of the side from
//   either corner), shared with the square on the other side: the polylines
//   are indexed, and two squares' segments meet exactly;
// - the two saddle configurations (c0 and c2 inside, c1 and c3 outside, or
//   the reverse) are decided by the bilinear interpolant's value at its
//   saddle point, (v0 v2 - v1 v3) / (v0 + v2 - v1 - v3) (the asymptotic
//   decider, Nielson and Hamann 1991): below 0 the inside corners are
//   joined across the square, otherwise they are cut apart. The decision
//   reads only the square's own four values, so it is the same whichever way
//   the walk arrives, and no side ever gets two vertices.
// Segments run with the inside on their left; chained head to tail at their
// shared vertices they form the polylines, closed when the chain comes back
// to its start, open when it ends at an undefined square or the lattice's
// edge.
//
// Cost: textbook O(N^2) evaluations of f for a lattice of N^2 squares; here
// O(s) for the s squares visited (about the curve's length / cell).

#include "recon/core/point_cloud.h"
#include "recon/structures/lattice.h"
#include "recon/structures/polyline.h"

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <vector>

namespace recon {

struct MarchingSquaresOptions {
  double cell = 0.0;                     ///< square side (a length); must be > 0
  double max_slope = 0.0;                ///< seam test (see above); 0: none
  std::size_t max_squares = 50'000'000;  ///< refuse walks that would visit more (memory guard)
  bool keep_corners = false;             ///< keep the evaluated corners and the visited squares in the result
};

using SquareCorner = Lattice<2>::Corner;

struct MarchingSquaresResult {
  PolylineSet curves;
  double cell = 0.0;
  Vec2 origin = Vec2::Zero();          ///< position of lattice corner (0, 0)
  std::array<std::int32_t, 2> size{};  ///< squares along each axis
  std::size_t seed_squares = 0;        ///< squares containing a seed
  std::size_t visited_squares = 0;     ///< squares whose corners were looked at
  std::size_t undefined_squares = 0;   ///< visited squares with an undefined corner
  std::size_t seam_squares = 0;        ///< visited squares refused by the seam test
  std::size_t saddle_squares = 0;      ///< visited squares decided by the saddle value
  std::size_t evaluated_corners = 0;
  std::size_t undefined_corners = 0;
  std::vector<SquareCorner> corners;                 ///< every evaluated corner (if keep_corners)
  std::vector<std::array<std::int32_t, 2>> squares;  ///< lower corner of every visited square (if keep_corners)
  double seconds = 0.0;                              ///< the whole walk, evaluations of f included
  double seconds_field = 0.0;                        ///< of which evaluating f (phase III's share)
};

/// The function contoured: its value at a point, or nullopt where undefined.
using ScalarField2 = std::function<std::optional<double>(const Vec2&)>;

/// The polylines of f = 0, walked from the squares that contain `seeds`
/// (normally the input points), in the seeds' coordinates. No seeds: no curves.
/// Cost: O(N^2) for the whole N^2 lattice; here O(s) evaluations of f and expected O(1) table work per square visited.
/// Throws: InvalidInputError when the cell is not a positive, finite length or max_slope is negative or not finite;
/// ResourceLimitError when an axis needs more than Lattice<2>::max_cells_per_axis (2^30) squares or the walk
/// passes max_squares; whatever f throws.
/// Pre: finite seeds.
[[nodiscard]] MarchingSquaresResult marching_squares(const ScalarField2& f, std::span<const Vec2> seeds,
                                                     const MarchingSquaresOptions& options);

}  // namespace recon
