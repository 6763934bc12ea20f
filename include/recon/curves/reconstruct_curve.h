#pragma once
// Hoppe's algorithm in two dimensions: curves from unorganized points in
// the plane, phases I to IV in one call, keeping every phase's result (the
// playground in web/playground draws them all).
//
// Phases I-III are the 3D code instantiated for D = 2 (tangent lines by
// k-neighbourhood PCA on the kd-tree, orientation along the Riemannian
// graph's minimum spanning tree, the signed distance with its undefined
// rule); phase IV is marching squares. Collinear points are a legitimate
// curve here (a straight line), unlike in 3D.
//
// Marching squares starts its walk from the squares holding a sample or a
// tangent-line origin (f vanishes at each origin: few samples around a
// tight bend put the lines a square or more inside the samples).
//
// Per-point results (planes, normals) are indexed like the input points.
// Unlike reconstruct(), the points are not renumbered in spatial order nor
// moved near the origin: 2D inputs are small (drawings, clicks, sections)
// and the phases work on differences of doubles, which keep their precision.
//
// Cost: O(n k log n) for phases I-II over n points at k, then phase IV's s squares with a nearest-line query each
// (O(s log n)); the complete orientation graph, if chosen, is O(n^2).

#include "recon/alternatives/orientation_graphs.h"
#include "recon/phase1_planes/tangent_planes.h"
#include "recon/phase2_orientation/orientation.h"
#include "recon/phase3_distance/signed_distance.h"
#include "recon/phase4_contour/marching_squares.h"

#include <optional>
#include <span>
#include <vector>

namespace recon {

/// Default neighbourhood size for curves. A curve's k-neighbourhood is a
/// stretch about k spacings long (a surface's covers a disc of radius about
/// sqrt(k / pi) spacings), so curves need a smaller k than surfaces: 8
/// spans about 4 spacings on either side, enough to average moderate noise
/// while following curvature down to radii of a few spacings.
inline constexpr int curve_default_k = 8;

/// Phase IV's seam test: a sign change steeper than this is a seam, not the
/// curve (see marching_squares.h). A distance has slope 1 at most; the
/// margin allows for the small jumps between neighbouring tangent lines of
/// noisy data, which agree in sign.
inline constexpr double curve_max_slope = 2.0;

struct CurveReconstructionOptions {
  TangentPlaneOptions planes{
      .k = curve_default_k, .adapt_k = true, .rho = std::nullopt, .tree = {}, .cloud = std::nullopt};  ///< phase I
  OrientationOptions orientation{};                                                                    ///< phase II
  OrientationGraph graph = OrientationGraph::riemannian;  ///< the graph phase II walks (orientation_graphs.h)
  SignedDistanceOptions distance{};                       ///< phase III: delta
  std::optional<double> cell;                             ///< phase IV square side; default rho / 2
  std::optional<int> resolution;                          ///< or: squares along the longest side of the bounding box
  double max_slope = curve_max_slope;                     ///< phase IV's seam test (marching_squares.h); 0: off
  std::size_t max_squares = MarchingSquaresOptions{}.max_squares;  ///< memory guard of the walk
  bool keep_corners = false;                                       ///< keep the evaluated corners and visited squares
};

struct CurveReconstruction {
  TangentPlanes<2> planes;      ///< phase I (indexed like the input)
  OrientedNormals<2> oriented;  ///< phase II: normals, Riemannian graph, spanning tree
  KdTree<2> origin_tree;        ///< over the plane origins: phase III's nearest-line queries
  double delta = 0.0;           ///< phase III's noise level
  bool delta_given = false;
  MarchingSquaresResult contour;  ///< phase IV: the polylines and the lattice statistics
  double seconds_distance_setup = 0.0;
};

/// The square side `options` asks for: the given cell, the longest
/// side of the points' bounding box over the resolution, or rho / 2. (With
/// rho / 2, measured on circles of 100 to 1000 samples, the lattice's own
/// error h^2 / (8 r) stays a tenth of the distance from the curve to the
/// true one, which the tangent lines set; squares are cheap in 2D.)
/// Cost: O(1); O(n) with a resolution (the bounding box).
/// Throws: InvalidInputError when both cell and resolution are given, or the one given is not positive
/// (a cell not finite either).
/// Pre: rho > 0 when neither is given; points not empty with a resolution.
[[nodiscard]] double curve_lattice_cell(std::span<const Vec2> points, double rho,
                                        const CurveReconstructionOptions& options);

/// Phases I to IV on `points`, every phase's result kept (see above).
/// Cost: O(n k log n + s log n) (see above).
/// Throws: what the phases throw: InvalidInputError for unusable data or
/// parameters (fewer than k + 1 distinct points, all points identical,
/// non-finite coordinates, a bad rho, delta, cell or max_slope), ResourceLimitError for
/// a lattice too large or a walk past max_squares; what an interruption check throws.
/// Pre: none.
[[nodiscard]] CurveReconstruction reconstruct_curve(std::span<const Vec2> points,
                                                    const CurveReconstructionOptions& options = {});

}  // namespace recon
