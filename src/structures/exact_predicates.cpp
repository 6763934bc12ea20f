#include "recon/structures/exact_predicates.h"

#include <array>
#include <cmath>
#include <cstddef>

// This file is compiled with -ffp-contract=off (src/structures/CMakeLists.txt):
// the error-free transformations below need every + and * rounded on its own,
// never fused by the compiler into one multiply-add.

namespace recon {
namespace {

constexpr double epsilon = 0x1p-53;  // half an ulp of 1: the unit roundoff
// Shewchuk's proven bounds on the rounding error of the plain formulas,
// relative to their permanents (the sums of the absolute values of the terms).
constexpr double orient2d_bound = (3.0 + 16.0 * epsilon) * epsilon;
constexpr double orient3d_bound = (7.0 + 56.0 * epsilon) * epsilon;

// a + b = sum + error exactly (Knuth's two-sum: no condition on |a|, |b|).
struct Pair {
  double sum, error;
};
Pair two_sum(double a, double b) {
  const double x = a + b;
  const double b_virtual = x - a;
  const double a_virtual = x - b_virtual;
  return {x, (a - a_virtual) + (b - b_virtual)};
}
// a + b exactly when |a| >= |b| (Dekker's fast two-sum).
Pair fast_two_sum(double a, double b) {
  const double x = a + b;
  return {x, b - (x - a)};
}
// a * b = product + error exactly: the fused multiply-add rounds only once.
Pair two_product(double a, double b) {
  const double x = a * b;
  return {x, std::fma(a, b, -x)};
}

// Floating-point expansions: the exact sum of their components, which do
// not overlap and increase in magnitude, zeros left out; each function writes
// its result into `out` (room enough, as the comments count) and returns the
// number of components. The sign of an expansion is that of its last.

// e + f (Shewchuk's fast expansion sum, zeros eliminated): the components of
// both merged by magnitude, then added up from the smallest with two-sums.
// Needs round-to-nearest-even, the default. At most m + n components.
int sum(const double* e, int m, const double* f, int n, double* out) {
  std::array<double, 256> g;
  int i = 0, j = 0, k = 0;
  while (i < m || j < n)
    g[static_cast<std::size_t>(k++)] = (j >= n || (i < m && std::fabs(e[i]) < std::fabs(f[j]))) ? e[i++] : f[j++];
  int size = 0;
  if (k == 0) return 0;
  double q = g[0];
  for (int g_index = 1; g_index < k; ++g_index) {
    const Pair s = g_index == 1 ? fast_two_sum(g[1], g[0]) : two_sum(q, g[static_cast<std::size_t>(g_index)]);
    if (s.error != 0.0) out[size++] = s.error;
    q = s.sum;
  }
  if (q != 0.0 || size == 0) out[size++] = q;
  return size;
}

// e * b (Shewchuk's scale-expansion, zeros eliminated). At most 2m components.
int scale(const double* e, int m, double b, double* out) {
  if (m == 0) return 0;
  int size = 0;
  const Pair p = two_product(e[0], b);
  if (p.error != 0.0) out[size++] = p.error;
  double q = p.sum;
  for (int i = 1; i < m; ++i) {
    const Pair t = two_product(e[i], b);
    const Pair s = two_sum(q, t.error);
    if (s.error != 0.0) out[size++] = s.error;
    const Pair f = fast_two_sum(t.sum, s.sum);
    if (f.error != 0.0) out[size++] = f.error;
    q = f.sum;
  }
  if (q != 0.0 || size == 0) out[size++] = q;
  return size;
}

// e * f for f of at most two components (a coordinate difference). At most 4m.
int times_pair(const double* e, int m, const double* f, int n, double* out) {
  std::array<double, 128> low, high;
  if (n == 1) return scale(e, m, f[0], out);
  const int a = scale(e, m, f[0], low.data()), b = scale(e, m, f[1], high.data());
  return sum(low.data(), a, high.data(), b, out);
}

int sign_of(const double* e, int m) { return m == 0 || e[m - 1] == 0.0 ? 0 : e[m - 1] > 0.0 ? 1 : -1; }

// a - b exactly, as one or two components.
struct Difference {
  std::array<double, 2> c;
  int size;
};
Difference difference(double a, double b) {
  const Pair p = two_sum(a, -b);
  if (p.error == 0.0) return {{p.sum, 0.0}, 1};
  return {{p.error, p.sum}, 2};
}

// u1 * v2 - u2 * v1 exactly (at most 16 components).
int minor2(const Difference& u1, const Difference& u2, const Difference& v1, const Difference& v2, double* out) {
  std::array<double, 8> left, right;
  const int a = times_pair(u1.c.data(), u1.size, v2.c.data(), v2.size, left.data());
  const int b = times_pair(u2.c.data(), u2.size, v1.c.data(), v1.size, right.data());
  for (int i = 0; i < b; ++i) right[static_cast<std::size_t>(i)] = -right[static_cast<std::size_t>(i)];
  return sum(left.data(), a, right.data(), b, out);
}

}  // namespace

namespace exact_detail {

int orient2d_exact(double ax, double ay, double bx, double by, double cx, double cy) {
  std::array<double, 16> det;
  const int n = minor2(difference(ax, cx), difference(ay, cy), difference(bx, cx), difference(by, cy), det.data());
  return sign_of(det.data(), n);
}

int orient3d_exact(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  std::array<std::array<Difference, 3>, 3> m;  // rows a - d, b - d, c - d
  const std::array<const Vec3*, 3> rows = {&a, &b, &c};
  for (std::size_t r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k) m[r][static_cast<std::size_t>(k)] = difference((*rows[r])[k], d[k]);
  // Expansion by the first column: each term its entry times its 2x2 minor
  // (16 components at most, times a difference: 64), then the three added.
  std::array<double, 16> minor;
  std::array<std::array<double, 64>, 3> term;
  std::array<int, 3> size{};
  const std::array<std::array<std::size_t, 2>, 3> others = {{{1, 2}, {2, 0}, {0, 1}}};
  for (std::size_t r = 0; r < 3; ++r) {
    const auto& p = m[others[r][0]];
    const auto& q = m[others[r][1]];
    const int n = minor2(p[1], p[2], q[1], q[2], minor.data());
    size[r] = times_pair(minor.data(), n, m[r][0].c.data(), m[r][0].size, term[r].data());
  }
  std::array<double, 128> two;
  std::array<double, 192> all;
  const int n2 = sum(term[0].data(), size[0], term[1].data(), size[1], two.data());
  const int n3 = sum(two.data(), n2, term[2].data(), size[2], all.data());
  return sign_of(all.data(), n3);
}

}  // namespace exact_detail

int orient2d(double ax, double ay, double bx, double by, double cx, double cy) {
  const double left = (ax - cx) * (by - cy);
  const double right = (ay - cy) * (bx - cx);
  const double det = left - right;
  const double permanent = std::fabs(left) + std::fabs(right);
  // (In the exact range a product rounds to 0 only when it is 0: a zero
  // permanent is a zero determinant.)
  if (permanent == 0.0) return 0;
  const double bound = orient2d_bound * permanent;
  if (det > bound) return 1;
  if (-det > bound) return -1;
  return exact_detail::orient2d_exact(ax, ay, bx, by, cx, cy);
}

int orient2d_dropping(const Vec3& a, const Vec3& b, const Vec3& c, int axis) {
  const int u = (axis + 1) % 3, v = (axis + 2) % 3;
  return orient2d(a[u], a[v], b[u], b[v], c[u], c[v]);
}

int orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const double adx = a.x() - d.x(), ady = a.y() - d.y(), adz = a.z() - d.z();
  const double bdx = b.x() - d.x(), bdy = b.y() - d.y(), bdz = b.z() - d.z();
  const double cdx = c.x() - d.x(), cdy = c.y() - d.y(), cdz = c.z() - d.z();
  const double bc1 = bdy * cdz, bc2 = bdz * cdy;
  const double ca1 = cdy * adz, ca2 = cdz * ady;
  const double ab1 = ady * bdz, ab2 = adz * bdy;
  const double det = adx * (bc1 - bc2) + bdx * (ca1 - ca2) + cdx * (ab1 - ab2);
  const double permanent = (std::fabs(bc1) + std::fabs(bc2)) * std::fabs(adx) +
                           (std::fabs(ca1) + std::fabs(ca2)) * std::fabs(bdx) +
                           (std::fabs(ab1) + std::fabs(ab2)) * std::fabs(cdx);
  if (permanent == 0.0) return 0;  // (as in orient2d)
  const double bound = orient3d_bound * permanent;
  if (det > bound) return 1;
  if (-det > bound) return -1;
  return exact_detail::orient3d_exact(a, b, c, d);
}

bool coordinates_in_exact_range(const Vec3& p) {
  for (int k = 0; k < 3; ++k) {
    if (!std::isfinite(p[k])) return false;  // (first: an ordered comparison with NaN raises FE_INVALID)
    const double x = std::fabs(p[k]);
    if (x != 0.0 && (x < 0x1p-290 || x > 0x1p290)) return false;
  }
  return true;
}

}  // namespace recon
