#pragma once
// Phase I, second order: a quadric per neighbourhood, so that each tangent
// plane touches the surface instead of cutting under it. (The default
// method; `hoppe92` keeps the planes of tangent_planes.h.)
//
// The textbook idea. Phase I fits a plane through the centroid of x_i's k
// neighbours. On a curved surface the centroid lies inside, by about
// r^2 / (4 R) for a neighbourhood of radius r on a radius of curvature R, and
// every surface drawn from those planes is shrunk by that much. Fit instead
// a height function of second order over the plane,
//
//   w = a u^2 + b u v + c v^2 + d u + e v + g     (u, v along the plane, w along n_i),
//
// by least squares over the same k points, and move x_i onto it: the foot
// point s_i and the normal there replace (o_i, n_i). The quadric's second
// derivatives at s_i (the surface's curvature there) are kept, for phase V
// (refinement.h), which projects mesh vertices onto these quadrics.
//
// Two places where one neighbourhood describes the wrong surface:
// - Creases. A neighbourhood straddling a sharp edge fits neither face (its
//   fit residual is large) and its plane cuts the edge off. Where one of x_i's
//   neighbours x_j fits its own neighbourhood at least twice as well and x_i
//   lies on that quadric, x_i takes x_j's quadric: near an edge, the samples
//   a little further into the same face have neighbourhoods on that face
//   alone. Phase III's nearest-plane rule then meets the faces at the edge.
//   Only poor fits look: those beyond four times the median residual. On a
//   sparse CAD part (a few thousand samples) nearly every neighbourhood
//   reaches an edge, the median is itself a crease's residual, and no fit
//   looked poor: every edge came out rounded off. So a fit also looks when
//   its residual passes the larger of 16 times the lower quartile (the
//   faces' own residual, noise included: on noisy or smooth data that bound
//   lies beyond the median's) and 1/200 of the median radius (which a
//   noise-free smooth face never reaches).
// - Two sheets closer than a neighbourhood (a thin plate, a fold, an arm
//   against a body). The neighbourhood's heights over its plane then fall in
//   two groups with an empty band between them; the plane through the
//   centroid lies in the empty band and would draw a fin there. The fit is
//   redone on the group x_i belongs to, so each origin lies on its own sheet
//   (phase II then carries the orientation across the gap reversed:
//   orientation.h).
//
// Cost: O(n k) beyond phase I, one more least-squares fit (6 x 6) per neighbourhood, in parallel;
// and 12 bytes a sample kept (the curvature, the residual).

#include "recon/phase1_planes/tangent_planes.h"

#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

namespace recon {

/// The cloud-wide medians the fits compare against: of the fits' residuals
/// (poor fits look for a better one) and their lower quartile, of the
/// neighbourhood radii (strays), and of the residuals of the fits taken
/// (the noise). A tile of a larger cloud (tiles.h) is given the whole cloud's.
struct QuadricMedians {
  double fit_residual = 0.0;
  double radius = 0.0;
  double noise = 0.0;
  double fit_residual_quartile = 0.0;
};

struct LocalQuadricOptions {
  double crease_ratio = 0.5;  ///< borrow a neighbour's fit when its residual is below this fraction of one's own
  /// A fit looks for a better one beyond four times the median residual,
  /// and also beyond the larger of this many times the residuals' lower
  /// quartile ...
  double crease_quartile = 16.0;
  double smooth_residual = 0.005;  ///< ... and this fraction of the median radius (see Creases above)
  double sheet_gap = 0.5;          ///< two sheets: an empty band of heights over this fraction of their whole range
  int min_sheet_points = 4;        ///< ... with at least this many samples on either side
  /// ... unless the other side is a parallel sheet nearer than this: sheets
  /// closer than the lattice can follow are fitted as one surface between
  /// them. 0: always split (reconstruct() replaces 0 by 1.5 lattice cells).
  double min_sheet_separation = 0.0;
  double sheet_residual = 0.1;  ///< or a fit residual over this fraction of the radius: tested for two sheets
  /// A fit whose residual exceeds this fraction of the neighbourhood radius
  /// describes no surface: phase I's plane is kept, which passes through no
  /// sample and so draws nothing.
  double surface_residual = 0.2;
  /// So does a neighbourhood this many times wider than the median one
  /// (strays scattered far from the data reach each other across empty space).
  double stray_radius = 20.0;
  /// Given: these medians instead of those of these samples (see above).
  std::optional<QuadricMedians> cloud;
  /// Keep each sample's part in the medians (LocalQuadrics::fit_residual
  /// and was_split), for a cloud measured in parts (tangent_planes.h).
  bool keep_parts = false;
};

/// The second fundamental form at s_i, as the height of the surface above
/// its tangent plane: h(t) = P a^2 + Q a b + R b^2 for a tangent vector
/// t = a t1 + b t2, where (t1, t2) = tangent_basis(normal) and `normal` is
/// the unoriented normal stored with it.
struct Curvature {
  float p = 0.0f, q = 0.0f, r = 0.0f;
};

/// The values of LocalQuadricOptions::min_sheet_separation that give the
/// same fits: those s with below < s <= up_to. Each pair of parallel sheets
/// the fits measured lies either nearer than the separation used (kept as
/// one surface) or not (split); a separation between the nearest such gaps
/// on either side decides every pair alike. (The web page uses it: a new
/// lattice cell, of which the separation is 1.5, keeps phases I-II when it
/// falls in the range.)
struct SeparationRange {
  double below = -std::numeric_limits<double>::infinity();
  double up_to = std::numeric_limits<double>::infinity();
  /// Whether separation s gives the same fits.
  /// Cost: O(1).
  /// Throws: nothing.
  /// Pre: none.
  [[nodiscard]] bool holds(double s) const { return below < s && s <= up_to; }
};

struct LocalQuadrics {
  std::vector<Vec3> origins;  ///< s_i: x_i moved onto its quadric (replaces the centroid)
  std::vector<Vec3> normals;  ///< unit normal at s_i, on the same side as phase I's n_i
  /// Phase I's PCA normals in single precision, phase II's guide
  /// (orientation.h; filled and released by reconstruct()).
  std::vector<Eigen::Vector3f> guide;
  std::vector<Curvature> curvature;  ///< at s_i, in tangent_basis(normals[i])
  std::vector<float> residual;       ///< RMS distance of the fitted samples to their quadric
  /// 1 where a neighbour's normal is more than crease_angle_degrees
  /// (signed_distance.h) away from this sample's: the band along creases,
  /// where phase III weighs several planes.
  std::vector<std::uint8_t> near_crease;
  double noise = 0.0;      ///< median residual of the fits taken: the noise, without the curvature a plane misses
  QuadricMedians medians;  ///< the medians used (noise among them)
  /// With keep_parts: per sample, its own fit's residual (before any is
  /// borrowed; medians.fit_residual is the median of the finite ones), and
  /// 1 where its neighbourhood was split into two sheets.
  std::vector<float> fit_residual;
  std::vector<std::uint8_t> was_split;
  std::size_t borrowed = 0;   ///< samples that took a neighbour's quadric (near creases)
  std::size_t split = 0;      ///< neighbourhoods split into two sheets
  std::size_t flat = 0;       ///< fits that fell back to a plane (samples too few, collinear, or no surface)
  SeparationRange same_fits;  ///< the sheet separations that give these fits
  double seconds = 0.0;
};

/// An orthonormal basis (t1, t2) of the plane normal to the unit vector n,
/// a fixed function of n (not continuous where n.z changes sign).
/// Cost: O(1).
/// Throws: nothing.
/// Pre: n is a unit vector.
[[nodiscard]] std::array<Vec3, 2> tangent_basis(const Vec3& n);

/// A quadric per neighbourhood of phase I's n samples at k, with the foot points, normals and curvatures
/// it gives (see the header). Neighbourhoods of copies of one point keep their plane (curvature 0).
/// Cost: O(n k), a 6 x 6 least-squares fit per neighbourhood; here also O(k log k) per neighbourhood tested
/// for two sheets and O(k^2) per poor fit looking among its neighbours' neighbours for a better one.
/// Throws: InvalidInputError unless the planes come from estimate_tangent_planes over a tree numbered by
/// leaf order (as reconstruct() builds it), their neighbour lists not yet released.
/// Pre: none.
[[nodiscard]] LocalQuadrics fit_local_quadrics(const TangentPlanes<3>& planes, const LocalQuadricOptions& options = {});

/// The refined method's phase I: the quadrics' origins and normals take
/// the planes' places (moved out of `quadrics`), phase I's PCA normals
/// become `quadrics.guide` (they guide phase II, orientation.h), and the
/// noise (phase III's delta is twice it) becomes what the quadrics miss:
/// the curvature a plane cannot follow, or a second sheet, is no noise.
/// Cost: O(n).
/// Throws: nothing.
/// Pre: quadrics was fitted to `planes` by fit_local_quadrics, and not adopted before.
void adopt_second_order(TangentPlanes<3>& planes, LocalQuadrics& quadrics);

/// A point of a fitted surface and the unit normal there.
struct SurfacePoint {
  Vec3 point;
  Vec3 normal;  ///< on the side of the plane's normal
};

/// p moved onto the quadric through `origin` with unit `normal` and
/// `curvature` (as LocalQuadrics holds them), along the quadric's normal:
/// the nearest point of the quadric for p within about 1 / |curvature|.
/// Cost: O(1) (three fixed-point steps).
/// Throws: nothing.
/// Pre: `normal` is a unit vector.
[[nodiscard]] SurfacePoint project_onto_quadric(const Vec3& origin, const Vec3& normal, const Curvature& curvature,
                                                const Vec3& p);

}  // namespace recon
