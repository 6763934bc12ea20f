#include "recon/phase1_planes/pca.h"

#include <Eigen/Geometry>  // cross

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

namespace recon {

namespace {

// One Jacobi rotation in the (p, q) plane, which zeroes a_pq:
// A <- J^T A J, V <- V J.
template <int D>
void rotate(Mat<D>& a, Mat<D>& v, int p, int q) {
  const double apq = a(p, q);
  // Rotation angle theta with tan(2 theta) = 2 a_pq / (a_qq - a_pp);
  // t = tan(theta) taken as the smaller root for stability. When a_pq is
  // negligible against d = a_qq - a_pp, theta is so large that its square
  // may overflow, and t = 1 / (2 theta) = a_pq / d to double precision (as
  // in Numerical Recipes' jacobi).
  const double d = a(q, q) - a(p, p);
  double t = 0.0;
  if (std::abs(d) + 100.0 * std::abs(apq) == std::abs(d)) {
    t = apq / d;  // d is not 0 here: a_pq is not
  } else {
    const double theta = d / (2.0 * apq);
    t = (theta >= 0.0 ? 1.0 : -1.0) / (std::abs(theta) + std::sqrt(theta * theta + 1.0));
  }
  const double c = 1.0 / std::sqrt(t * t + 1.0);
  const double s = t * c;
  const double tau = s / (1.0 + c);  // c = 1 - s tau: updates as small corrections
  // a_pq becomes 0, the diagonal moves by t a_pq, and only the entries in
  // rows/columns p and q change.
  a(p, p) -= t * apq;
  a(q, q) += t * apq;
  a(p, q) = a(q, p) = 0.0;
  for (int r = 0; r < D; ++r) {
    if (r == p || r == q) continue;
    const double g = a(r, p), h = a(r, q);
    a(r, p) = a(p, r) = g - s * (h + g * tau);
    a(r, q) = a(q, r) = h + s * (g - h * tau);
  }
  for (int r = 0; r < D; ++r) {
    const double g = v(r, p), h = v(r, q);
    v(r, p) = g - s * (h + g * tau);
    v(r, q) = h + s * (g - h * tau);
  }
}

// The sum of squares of the entries above the diagonal.
template <int D>
double off_diagonal(const Mat<D>& a) {
  double off = 0.0;
  for (int p = 0; p < D; ++p)
    for (int q = p + 1; q < D; ++q) off += a(p, q) * a(p, q);
  return off;
}

// Selection sort of at most 3 values, ascending, carrying the vectors along.
template <int D>
void sort_ascending(SymmetricEigen<D>& e) {
  for (int i = 0; i < D; ++i) {
    int m = i;
    for (int j = i + 1; j < D; ++j)
      if (e.values[j] < e.values[m]) m = j;
    if (m != i) {
      std::swap(e.values[i], e.values[m]);
      e.vectors.col(i).swap(e.vectors.col(m));
    }
  }
}

}  // namespace

template <int D>
SymmetricEigen<D> symmetric_eigen(const Mat<D>& input) {
  Mat<D> a = input.template selfadjointView<Eigen::Upper>();
  Mat<D> v = Mat<D>::Identity();
  const double scale = a.cwiseAbs().maxCoeff();
  if (scale > 0.0) {
    for (int sweep = 0; sweep < 50 && off_diagonal<D>(a) > 1e-36 * scale * scale; ++sweep)
      for (int p = 0; p < D; ++p)
        for (int q = p + 1; q < D; ++q)
          if (a(p, q) != 0.0) rotate<D>(a, v, p, q);
  }
  SymmetricEigen<D> result;
  result.values = a.diagonal();
  result.vectors = v;
  sort_ascending(result);
  return result;
}

namespace {

// The plane of a 3x3 covariance in closed form: the eigenvalues from the
// trigonometric solution of the characteristic cubic, the normal as the
// longest cross product of two rows of A - lambda_0 I (each row is
// orthogonal to the normal). About three times faster than the rotations.
// lambda_0 carries an absolute error of about eps * lambda_2, and so the
// normal one of about eps * lambda_2 / (lambda_1 - lambda_0): the closed form
// is taken only where lambda_1 - lambda_0 > 1e-4 lambda_2 (the normal then
// within 1e-12 of Jacobi's), which every neighbourhood of a surface
// satisfies; lines, points and round blobs go to the rotations.
bool closed_form_plane(const Mat<3>& a, Vec3& values, Vec3& normal) {
  const double a00 = a(0, 0), a01 = a(0, 1), a02 = a(0, 2), a11 = a(1, 1), a12 = a(1, 2), a22 = a(2, 2);
  const double q = (a00 + a11 + a22) / 3.0;
  const double b00 = a00 - q, b11 = a11 - q, b22 = a22 - q;
  const double p2 = (b00 * b00 + b11 * b11 + b22 * b22 + 2.0 * (a01 * a01 + a02 * a02 + a12 * a12)) / 6.0;
  if (!(p2 > 0.0) || !std::isfinite(p2)) return false;
  const double p = std::sqrt(p2);
  // det(B) / (2 p^3), B = A - q I: the cosine of three times the angle.
  const double det = b00 * (b11 * b22 - a12 * a12) - a01 * (a01 * b22 - a12 * a02) + a02 * (a01 * a12 - b11 * a02);
  const double phi = std::acos(std::clamp(det / (2.0 * p2 * p), -1.0, 1.0)) / 3.0;
  const double l2 = q + 2.0 * p * std::cos(phi);
  const double l0 = q + 2.0 * p * std::cos(phi + 2.0 * std::numbers::pi / 3.0);
  const double l1 = 3.0 * q - l0 - l2;
  if (!(l1 - l0 > 1e-4 * l2)) return false;
  const Vec3 m0(a00 - l0, a01, a02), m1(a01, a11 - l0, a12), m2(a02, a12, a22 - l0);
  Vec3 best = m0.cross(m1);
  for (const Vec3& c : {m0.cross(m2), m1.cross(m2)})
    if (c.squaredNorm() > best.squaredNorm()) best = c;
  const double length2 = best.squaredNorm();
  if (!(length2 > 0.0) || !std::isfinite(length2)) return false;
  values = Vec3(l0, l1, l2);
  normal = best / std::sqrt(length2);
  return true;
}

}  // namespace

template <int D>
PlaneFit<D> fit_plane(std::span<const Vec<D>> points, std::span<const std::uint32_t> indices) {
  const std::size_t count = indices.empty() ? points.size() : indices.size();
  auto at = [&](std::size_t j) -> const Vec<D>& { return indices.empty() ? points[j] : points[indices[j]]; };
  Vec<D> centroid = Vec<D>::Zero();
  for (std::size_t j = 0; j < count; ++j) centroid += at(j);
  centroid /= static_cast<double>(count);
  Mat<D> cov = Mat<D>::Zero();
  for (std::size_t j = 0; j < count; ++j) {
    const Vec<D> d = at(j) - centroid;
    for (int r = 0; r < D; ++r)  // upper triangle only: symmetric_eigen reads no more
      for (int c = r; c < D; ++c) cov(r, c) += d[r] * d[c];
  }
  cov /= static_cast<double>(count);
  if constexpr (D == 3) {
    Vec3 values, normal;
    if (closed_form_plane(cov, values, normal)) return {centroid, normal, values.cwiseMax(0.0)};
  }
  const SymmetricEigen<D> eig = symmetric_eigen<D>(cov);
  return {centroid, eig.vectors.col(0).normalized(), eig.values.cwiseMax(0.0)};
}

template SymmetricEigen<2> symmetric_eigen<2>(const Mat<2>&);
template SymmetricEigen<3> symmetric_eigen<3>(const Mat<3>&);
template PlaneFit<2> fit_plane<2>(std::span<const Vec<2>>, std::span<const std::uint32_t>);
template PlaneFit<3> fit_plane<3>(std::span<const Vec<3>>, std::span<const std::uint32_t>);

}  // namespace recon
