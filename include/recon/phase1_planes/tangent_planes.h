#pragma once
// Phase I: a tangent plane for every point.
//
// For each x_i, its k-neighbourhood N(x_i) (x_i and its k - 1 nearest other
// points, found with our kd-tree) is fitted with a plane by PCA: the origin
// o_i is the centroid of N(x_i) and the normal n_i the eigenvector of the
// smallest eigenvalue of its covariance. Normals are unit but not yet
// oriented (phase II does that).
//
// The phase also measures the sampling, locally, so that later phases adapt
// to scans whose density varies across the surface:
// - gap_i, the widest spacing between neighbouring samples around x_i: the
//   largest, over x_i's neighbours x_j, of the distance from x_j to its
//   nearest distinct sample. Phase II uses it to tell a gap between two
//   objects from the spacing within one. With a given rho, gap_i = rho.
// - rho_i, the sampling density in Hoppe's sense (the data is rho-dense when
//   every point of the surface is within rho of a sample), which phase III
//   uses. How far the emptiest spot is from a sample depends on how regular
//   the sampling is: on a scanner's grid it is under a spacing, so rho_i =
//   1.5 gap_i; in a random (Poisson) sample, chance leaves holes several
//   spacings wide, and only the radius of the k-neighbourhood bounds them
//   (docs/benchmarks.md). The irregularity of the spacing (measured below)
//   moves rho_i between the two. `rho` is the median of the rho_i, the
//   figure reported; a value given by the user replaces every rho_i.
//
// Isolated samples. A stray point far from the rest (a scanner's outlier, a
// speck of dust, a handful of them) has a neighbourhood of distant samples:
// its plane is fitted across empty space, and its rho_i (about the size of
// its neighbourhood) is as large as the distance. Left alone, it would grow
// a sheet of surface that wide in phase III. A sample is isolated when its
// neighbourhood radius is more than isolation_factor times that of the
// lower quarter of its neighbours: they are surrounded by samples and it is
// not. Its rho_i is set to 0, which leaves f undefined around it (phase
// III), so its plane draws no surface; its neighbours are not affected.
// Within one surface, neighbourhood radii change smoothly: a spacing must
// grow about twentyfold from one side of a neighbourhood to the other to
// isolate a sample. A stray cluster of more than about 3k/4 samples is not
// isolated by this test (it would be a small object).
//
// Works in D = 2 (tangent lines of a curve) and D = 3.
//
// The textbook phase is one loop: for each point, a k-NN query and a PCA
// fit; then the spacing measures from the lists. The version here runs the
// loop in parallel over the kd-tree's leaf order (consecutive queries touch
// the same nodes), bounds each query by the previous one's k-th distance
// plus the step between them, and answers a run of exact copies with one
// query. The answers are those of the textbook loop.
//
// Cost: O(n log n + n k) expected for n points at k (the tree, then a query and an O(k) fit per
// point); here the same shared among the threads, twice when adapt_k raises k.

#include "recon/core/point_cloud.h"
#include "recon/structures/kdtree.h"

#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <vector>

namespace recon {

// Noise. sqrt(lambda_0) is the RMS distance of a neighbourhood to its
// plane; its median over the cloud, `noise`, measures the noise (plus the
// curvature a plane cannot follow). When the noise is large against the
// neighbourhood (noise > 0.1 rho), k neighbours cannot average it out and
// some normals come out tangent rather than normal; with adapt_k the phase
// then runs again with k raised in proportion (k * noise / (0.1 rho), at most
// 64), once. A user's explicit k should set adapt_k = false.
//
// Default k = 20, the top of the range Hoppe's program used (4 to 20): the
// plane fits average moderate noise, rho (for random samples the
// 20-neighbourhood radius) covers their random gaps, and at sharp edges
// and corners the tilted planes of neighbourhoods straddling a crease are
// few enough not to draw fins (measured on a box: docs/benchmarks.md).
// Smaller k follows thinner features.

/// Tangent planes whose normals are further apart than this meet at a
/// crease: phase I's fits (local_quadrics.h), phase III's choice of plane
/// (signed_distance.h) and phase V's creases (refinement.h) share it.
inline constexpr double crease_angle_degrees = 25.0;

/// A sample whose neighbourhood radius exceeds this many times that of the
/// lower quarter of its neighbours is isolated (see above).
inline constexpr double isolation_factor = 10.0;

/// The cloud-wide measures phase I takes over all the samples: the
/// irregularity of the spacing and the medians of rho_i, gap_i and the
/// noise. A tile of a larger cloud (tiles.h) is given the whole cloud's, so
/// that its rho_i and everything after are the whole cloud's too.
struct CloudSpacing {
  double irregularity = 0.0;
  double rho = 0.0;
  double gap = 0.0;
  double noise = 0.0;
};

// Measuring a cloud in parts. A tiled run (tiles.h) takes the cloud-wide
// measures over its tiles, each holding a part of the samples, and must
// find the values an in-memory run finds, exactly. So each measure is one
// that parts can add up to: the medians are taken by rank over all the
// parts' values; the irregularity from sums taken in fixed point (integer
// sums do not depend on the order of the terms, so neither on the parts
// nor on the thread count); and the samples whose wider neighbourhoods
// tell noise from curvature are chosen by a hash of their position, not
// by their place in a kd-tree.

/// The sums behind the irregularity: each relative spacing (a sample's
/// nearest-neighbour distance over its neighbourhood's mean) and its square,
/// in fixed point (2^-40).
struct SpacingSums {
  __extension__ typedef unsigned __int128 Wide;  // (a GCC and Clang extension)
  std::uint64_t count = 0;
  Wide sum = 0, sum2 = 0;
  /// Adds one relative spacing, or another part's sums.
  /// Cost: O(1).
  /// Throws: nothing.
  /// Pre: 0 <= relative <= k, as phase I's are (the fixed-point sums must not overflow).
  void add(float relative);
  void add(const SpacingSums& other);
  /// Standard deviation over mean of the relative spacings (0 for none).
  /// Cost: O(1).
  /// Throws: nothing.
  /// Pre: none.
  [[nodiscard]] double irregularity() const;
};

/// rho_i from gap_i, the neighbourhood radius and the cloud's irregularity
/// (see the header): between min(1.5 gap, radius) for a regular sampling and the radius for a random one.
/// Cost: O(1).
/// Throws: nothing.
/// Pre: none.
[[nodiscard]] float local_rho_of(float gap, float radius, double irregularity);

/// Whether the sample at p is one of the about 2000 samples of a cloud of
/// n that tell noise from curvature (all of them up to 2000), chosen by a hash of p.
/// Cost: O(D).
/// Throws: nothing.
/// Pre: none.
template <int D>
[[nodiscard]] bool is_noise_probe(const Vec<D>& p, std::size_t n);

struct TangentPlaneOptions;

/// The median of the noise probes' residuals (the upper one of an even
/// count; infinity for none, which raises no k).
/// Cost: O(m) for m residuals (a selection).
/// Throws: nothing.
/// Pre: no NaN residual.
[[nodiscard]] double probes_median(std::vector<double> residuals);

/// The k to run phase I again with, or 0 (see above): from the cloud's
/// noise and rho, its distinct samples (n of them in all), and the median
/// residual of the noise probes' neighbourhoods of 2k samples, asked for
/// only when the rest calls for a raise.
/// Cost: O(1), and at most one call of probe_median.
/// Throws: what probe_median throws; nothing else.
/// Pre: none.
[[nodiscard]] int raised_k(const TangentPlaneOptions& options, double noise, double rho, std::size_t distinct,
                           std::size_t n, const std::function<double()>& probe_median);

struct TangentPlaneOptions {
  int k = 20;                 ///< neighbourhood size, the point itself included
  bool adapt_k = true;        ///< raise k once for noisy data (see above)
  std::optional<double> rho;  ///< sampling density; estimated per point when absent
  KdTreeOptions tree{};       ///< kd-tree over the input points
  /// Given: the cloud-wide measures are taken from here instead of being
  /// measured over these points (the local values still are); with rho
  /// estimated only.
  std::optional<CloudSpacing> cloud;
  /// Keep each sample's part in the cloud-wide measures
  /// (TangentPlanes::relative_spacing and raw_gap), for a cloud measured in
  /// parts (see above).
  bool keep_spacing_parts = false;
};

// Storage. Positions, origins and normals are double: coordinates of
// geo-referenced scans need its 16 digits, and normals are compared by sign
// of dot products. The per-point measures (eigenvalues, rho_i, gap_i, the
// neighbourhood radius) are float: they are compared against each other and
// against lengths with tolerances far above float's 7 digits, and float
// halves their memory. The neighbourhoods are kept (4 bytes an entry) because
// phase II builds its graph from them.

template <int D>
struct TangentPlanes {
  using Values = Eigen::Matrix<float, D, 1>;
  std::vector<Vec<D>> origins;      ///< o_i, centroid of the neighbourhood of x_i
  std::vector<Vec<D>> normals;      ///< n_i, unit, unoriented
  std::vector<Values> eigenvalues;  ///< covariance eigenvalues, ascending
  std::vector<float> local_rho;     ///< rho_i (see above), or the given rho; 0 for an isolated sample
                                    ///< and for a neighbourhood of copies of one point (no plane)
  std::vector<float> local_gap;     ///< gap_i (see above), or the given rho
  std::vector<float> radius;        ///< distance from x_i to the farthest point of N(x_i)
  NeighborLists neighbors;          ///< N(x_i), nearest first (x_i, or an earlier exact copy, first)
  /// With keep_spacing_parts: x_i's nearest-neighbour distance over the
  /// mean of its neighbourhood's (the irregularity's part), and gap_i before
  /// a neighbourhood of copies takes the median gap (0 there).
  std::vector<float> relative_spacing, raw_gap;
  double rho = 0.0;           ///< median of local_rho, or the given rho
  double gap = 0.0;           ///< median of local_gap, or the given rho
  double irregularity = 0.0;  ///< spread of the spacing: ~0.5 random, ~0.1 scanner grids
  bool rho_given = false;
  int k = 0;                        ///< the k used
  int k_requested = 0;              ///< the k asked for (differs when adapt_k raised it)
  double noise = 0.0;               ///< median sqrt(lambda_0): RMS distance of neighbourhoods to their planes
  std::size_t distinct_points = 0;  ///< points that are not exact copies of an earlier one
  std::size_t degenerate = 0;       ///< neighbourhoods with no unique normal (collinear / coincident)
  std::size_t isolated = 0;         ///< isolated samples, whose planes draw no surface (see above)
  KdTree<D> point_tree;             ///< over the input points; phase III queries it
  double seconds_tree = 0.0;        ///< building point_tree
  double seconds_knn_pca = 0.0;     ///< the k-NN queries and plane fits (one pass)
  double seconds_spacing = 0.0;     ///< gap_i, rho_i, noise

  /// lambda_0 / (lambda_0 + ... ): 0 for a perfectly flat neighbourhood,
  /// 1/D for an isotropic blob.
  [[nodiscard]] CloudSpacing spacing() const { return {irregularity, rho, gap, noise}; }

  [[nodiscard]] double surface_variation(std::size_t i) const {
    const auto sum = static_cast<double>(eigenvalues[i].sum());
    return sum > 0.0 ? static_cast<double>(eigenvalues[i][0]) / sum : 0.0;
  }
};

/// Phase I over n points in D dimensions: a plane per point (TangentPlanes, indexed like `points`), the
/// local and cloud-wide sampling measures, and the kd-tree phase III queries.
/// Cost: O(n log n + n k) expected (see the header).
/// Throws: InvalidInputError when k < D or k > 256, the given rho is not a positive finite length, there
/// are fewer than k + 1 points or k + 1 distinct points, a coordinate is not finite or beyond
/// +-max_coordinate, there are more than 2^32 - 1 points, options.tree.leaf_size < 1, or every
/// neighbourhood is degenerate (all points on one line, or identical); what an interruption check throws.
/// Pre: none.
template <int D>
[[nodiscard]] TangentPlanes<D> estimate_tangent_planes(std::span<const Vec<D>> points,
                                                       const TangentPlaneOptions& options = {});

/// The same over a kd-tree already built and numbered by leaf order
/// (KdTree::renumber_by_leaf_order): its own copy of the points is THE point
/// set, point i being tree.points()[i]. No second copy of the points is made;
/// this is how reconstruct() works. options.tree is not used.
/// Cost: as above, less the tree's build.
/// Throws: InvalidInputError when the tree is not numbered by leaf order, and as above.
/// Pre: none.
template <int D>
[[nodiscard]] TangentPlanes<D> estimate_tangent_planes(KdTree<D>&& tree, const TangentPlaneOptions& options = {});

/// The RMS distance to their plane of the `wider_k` samples nearest p: a
/// noise probe's residual (see above).
/// Cost: O(log n + wider_k) expected (a query and a fit).
/// Throws: nothing.
/// Pre: `points` are the planes' samples, indexed like them (as samples_of gives, or the tree's own points
/// when numbered by leaf order); 1 <= wider_k <= n.
template <int D>
[[nodiscard]] double probe_residual(const TangentPlanes<D>& planes, std::span<const Vec<D>> points, const Vec<D>& p,
                                    int wider_k);

/// The samples x_i, indexed like the planes (the kd-tree keeps its copy of
/// them in its own order).
/// Cost: O(n).
/// Throws: nothing.
/// Pre: none.
template <int D>
[[nodiscard]] std::vector<Vec<D>> samples_of(const TangentPlanes<D>& planes);

}  // namespace recon
