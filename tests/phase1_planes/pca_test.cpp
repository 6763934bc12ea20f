#include "recon/phase1_planes/pca.h"

#include <gtest/gtest.h>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <random>

namespace recon {
namespace {

TEST(Pca, RecoversTheNormalOfRandomPlanes) {
  std::mt19937 rng(3);
  std::normal_distribution<double> g(0.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    const Vec3 normal = Vec3(g(rng), g(rng), g(rng)).normalized();
    const Vec3 u = normal.unitOrthogonal();
    const Vec3 v = normal.cross(u);
    // Far from the origin, to show the two-pass covariance keeps precision.
    const Vec3 offset = Vec3(g(rng), g(rng), g(rng)) * 1000.0;
    std::vector<Vec3> pts;
    for (int i = 0; i < 15; ++i) pts.push_back(offset + g(rng) * u + 0.1 * g(rng) * v);
    const PlaneFit<3> fit = fit_plane<3>(pts);
    EXPECT_NEAR(std::abs(fit.normal.dot(normal)), 1.0, 1e-9);
    EXPECT_NEAR(fit.eigenvalues[0], 0.0, 1e-9);
    EXPECT_GT(fit.eigenvalues[1], 0.0);
  }
}

template <int D>
void check_against_eigen(std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  for (int trial = 0; trial < 500; ++trial) {
    Mat<D> a;
    for (int r = 0; r < D; ++r)
      for (int c = 0; c < D; ++c) a(r, c) = g(rng);
    a = (a * a.transpose()).eval();
    if (trial % 5 == 0) a(0, 1) = a(1, 0) = 0.0;       // already partly diagonal
    if (trial % 7 == 0) a = Mat<D>::Identity() * 2.0;  // repeated eigenvalue
    if (trial % 13 == 0) a(0, 1) = a(1, 0) = 1e-300;   // negligible: theta^2 would overflow
    if (trial % 11 == 0) a *= 1e-12;                   // tiny scale
    const SymmetricEigen<D> ours = symmetric_eigen<D>(a);
    const Eigen::SelfAdjointEigenSolver<Mat<D>> theirs(a);
    const double scale = std::max(1e-300, a.norm());
    for (int c = 0; c < D; ++c) {
      EXPECT_NEAR(ours.values[c], theirs.eigenvalues()[c], 1e-12 * scale);
      // Each vector is an eigenvector of its value, unit length.
      const Vec<D> x = ours.vectors.col(c);
      EXPECT_NEAR(x.norm(), 1.0, 1e-12);
      EXPECT_LE((a * x - ours.values[c] * x).norm(), 1e-11 * scale);
    }
    EXPECT_LE((ours.vectors.transpose() * ours.vectors - Mat<D>::Identity()).norm(), 1e-12);
  }
}

TEST(Pca, SymmetricEigenAgreesWithEigen3x3) { check_against_eigen<3>(5); }
TEST(Pca, SymmetricEigenAgreesWithEigen2x2) { check_against_eigen<2>(6); }

// fit_plane takes a closed form where the plane is well defined and the
// Jacobi rotations elsewhere: either way its normal and eigenvalues are
// those of symmetric_eigen on the same covariance. Neighbourhoods of every
// kind: flat, noisy, curved, thin strips, lines, round blobs, copies, tiny
// and far from the origin.
TEST(Pca, PlaneFitAgreesWithTheRotationsOnEveryKindOfNeighbourhood) {
  std::mt19937 rng(8);
  std::normal_distribution<double> g(0.0, 1.0);
  int closed_form_cases = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const Vec3 n = Vec3(g(rng), g(rng), g(rng)).normalized();
    const Vec3 u = n.unitOrthogonal(), v = n.cross(u);
    const int kind = trial % 6;
    const double spread_v = kind == 3 ? 1e-3 : kind == 4 ? 1e-9 : 1.0;                    // strips, lines
    const double spread_n = kind == 0 ? 0.0 : kind == 1 ? 1e-3 : kind == 5 ? 1.0 : 0.05;  // flat .. round
    const double scale = trial % 7 == 0 ? 1e-6 : 1.0;
    const Vec3 offset = trial % 5 == 0 ? Vec3(3e5, -2e5, 1e5) : Vec3::Zero();
    std::vector<Vec3> pts;
    for (int i = 0; i < 20; ++i) {
      const double a = g(rng), b = g(rng);
      const double bend = kind == 2 ? 0.2 * a * a : 0.0;  // a curved patch
      pts.push_back(offset + scale * (a * u + spread_v * b * v + (spread_n * g(rng) + bend) * n));
    }
    if (trial % 50 == 0) pts.assign(20, pts[0]);  // copies of one point
    const PlaneFit<3> fit = fit_plane<3>(pts);
    // The covariance as fit_plane forms it, solved by the rotations.
    Mat<3> cov = Mat<3>::Zero();
    for (const Vec3& p : pts) {
      const Vec3 d = p - fit.centroid;
      cov += d * d.transpose();
    }
    cov /= static_cast<double>(pts.size());
    const SymmetricEigen<3> eig = symmetric_eigen<3>(cov);
    const double top = std::max(eig.values[2], 1e-300);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(fit.eigenvalues[c], std::max(0.0, eig.values[c]), 1e-12 * top) << trial;
    EXPECT_NEAR(fit.normal.norm(), 1.0, 1e-12);
    if (eig.values[1] - eig.values[0] > 1e-4 * eig.values[2]) {  // a plane: one normal, up to sign
      ++closed_form_cases;
      EXPECT_GT(std::abs(fit.normal.dot(eig.vectors.col(0))), 1.0 - 1e-12) << trial;
    } else {  // no unique normal: still an eigenvector of the smallest value
      EXPECT_LE((cov * fit.normal - fit.eigenvalues[0] * fit.normal).norm(), 1e-10 * top) << trial;
    }
  }
  EXPECT_GT(closed_form_cases, 1500);
}

TEST(Pca, LineIn2DHasTheRightNormal) {
  std::vector<Vec2> pts;
  for (int i = 0; i < 10; ++i) pts.emplace_back(i * 0.3, 1.0 + i * 0.3);  // along (1, 1)
  const PlaneFit<2> fit = fit_plane<2>(pts);
  EXPECT_NEAR(std::abs(fit.normal.dot(Vec2(1, -1).normalized())), 1.0, 1e-12);
}

}  // namespace
}  // namespace recon
