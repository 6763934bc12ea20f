#pragma once
// Principal component analysis of a small point set: the least-squares
// plane (line in 2D) through it, the heart of phase I.
//
// The covariance of the points about their centroid is a symmetric D x D
// matrix; its eigenvector of the SMALLEST eigenvalue is the direction in which
// the points spread least, the normal of the best-fitting plane. The
// eigenvalues are variances along the principal directions: lambda_0 is the
// mean squared distance of the points to the plane, and lambda_0 / (sum of
// all) measures how far from planar the neighbourhood is (0 = flat).

#include "recon/core/point_cloud.h"

#include <Eigen/Core>

#include <cstdint>
#include <span>

namespace recon {

template <int D>
using Mat = Eigen::Matrix<double, D, D>;

/// Eigen-decomposition of a symmetric matrix.
template <int D>
struct SymmetricEigen {
  Vec<D> values;   ///< ascending
  Mat<D> vectors;  ///< column c is the unit eigenvector of values[c]
};

/// The eigenvalues (ascending) and unit eigenvectors of a symmetric matrix,
/// by cyclic Jacobi rotations: each rotation zeroes one off-diagonal entry;
/// sweeps repeat until the off-diagonal part is negligible (a handful for
/// D <= 3). Accurate to machine precision for small and nearly repeated
/// eigenvalues, where closed-form cubic solutions lose digits. Only the upper
/// triangle of `a` is read.
/// Cost: O(D^3) a sweep, at most 50 sweeps.
/// Throws: nothing.
/// Pre: finite entries.
template <int D>
[[nodiscard]] SymmetricEigen<D> symmetric_eigen(const Mat<D>& a);

template <int D>
struct PlaneFit {
  Vec<D> centroid;
  Vec<D> normal;       ///< unit; sign arbitrary
  Vec<D> eigenvalues;  ///< of the covariance (divided by the count), ascending
};

/// Fits a plane to points[indices[...]] (all points when indices is empty):
/// centroid, then the covariance about it in a second pass (double precision,
/// no cancellation from large coordinates).
/// In 3D, where the smallest eigenvalue stands apart (lambda_1 - lambda_0 >
/// 1e-4 lambda_2, every neighbourhood of a surface), the eigenvalues come
/// from the closed-form cubic and the normal from cross products, three
/// times faster than the rotations and within 1e-12 of them; elsewhere
/// (lines, points, round blobs) symmetric_eigen decides.
/// Cost: O(m D^2) for m points, and O(D^3) for the eigenvectors.
/// Throws: nothing.
/// Pre: at least one point; every index below points.size(); finite coordinates.
template <int D>
[[nodiscard]] PlaneFit<D> fit_plane(std::span<const Vec<D>> points, std::span<const std::uint32_t> indices = {});

}  // namespace recon
