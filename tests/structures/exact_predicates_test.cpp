#include "recon/structures/exact_predicates.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#ifdef RECON_HAVE_GMP
#include <gmpxx.h>
#endif

// The oracles: exact integer arithmetic in __int128, on inputs chosen so that
// it cannot overflow. In 2D, every coordinate a multiple of 2^-53 under 32 in
// magnitude (so scaled by 2^53 an integer under 2^58; the determinant's
// products stay under 2^120), which covers every double in [1/2, 32) and
// perturbations by one ulp there. In 3D, integer coordinates under 2^40
// (products of three differences under 2^123), and the same scaled by 2^250
// and 2^-290 (a power of two leaves the sign as it was). Where GMP is found
// (it comes with CGAL), rationals check 3D on doubles at full precision too.

namespace recon {
namespace {

__extension__ typedef __int128 Int;  // (a GCC and Clang extension)

int sign_of(Int x) { return x > 0 ? 1 : x < 0 ? -1 : 0; }

Int scaled(double x) { return static_cast<Int>(std::ldexp(x, 53)); }  // exact for multiples of 2^-53 under 2^10

int orient2d_oracle(double ax, double ay, double bx, double by, double cx, double cy) {
  const Int acx = scaled(ax) - scaled(cx), acy = scaled(ay) - scaled(cy);
  const Int bcx = scaled(bx) - scaled(cx), bcy = scaled(by) - scaled(cy);
  return sign_of(acx * bcy - acy * bcx);
}

using IntPoint = std::array<std::int64_t, 3>;

int orient3d_oracle(const IntPoint& a, const IntPoint& b, const IntPoint& c, const IntPoint& d) {
  Int m[3][3];
  const IntPoint* rows[3] = {&a, &b, &c};
  for (std::size_t r = 0; r < 3; ++r)
    for (std::size_t k = 0; k < 3; ++k) m[r][k] = Int{(*rows[r])[k]} - Int{d[k]};
  const Int det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                  m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  return sign_of(det);
}

Vec3 to_vec(const IntPoint& p, int exponent) {
  return {std::ldexp(static_cast<double>(p[0]), exponent), std::ldexp(static_cast<double>(p[1]), exponent),
          std::ldexp(static_cast<double>(p[2]), exponent)};
}

// The plain formula, rounded: what the predicates must do better than.
double naive2d(double ax, double ay, double bx, double by, double cx, double cy) {
  return (ax - cx) * (by - cy) - (ay - cy) * (bx - cx);
}

TEST(ExactPredicates, Orient2dAgreesOnRandomPoints) {
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<std::int64_t> m(-(std::int64_t{1} << 57), std::int64_t{1} << 57);
  auto x = [&] { return std::ldexp(static_cast<double>(m(rng) >> 4 << 4), -53); };  // (a double: 53 bits)
  for (int i = 0; i < 20000; ++i) {
    const double ax = x(), ay = x(), bx = x(), by = x(), cx = x(), cy = x();
    ASSERT_EQ(orient2d(ax, ay, bx, by, cx, cy), orient2d_oracle(ax, ay, bx, by, cx, cy)) << i;
  }
}

// Kettner et al.'s classroom example: p near (1/2, 1/2) on a grid of ulps,
// and the line through (12, 12) and (24, 24); the rounded formula gets the
// side of many of them wrong.
TEST(ExactPredicates, Orient2dNearCollinearByUlps) {
  const double u = std::ldexp(1.0, -53);
  int naive_wrong = 0;
  for (int i = 0; i < 64; ++i)
    for (int j = 0; j < 64; ++j) {
      const double px = 0.5 + i * u, py = 0.5 + j * u;
      const int exact = orient2d_oracle(px, py, 12.0, 12.0, 24.0, 24.0);
      ASSERT_EQ(orient2d(px, py, 12.0, 12.0, 24.0, 24.0), exact) << i << " " << j;
      ASSERT_EQ(exact_detail::orient2d_exact(px, py, 12.0, 12.0, 24.0, 24.0), exact) << i << " " << j;
      const double n = naive2d(px, py, 12.0, 12.0, 24.0, 24.0);
      if ((n > 0) - (n < 0) != exact) ++naive_wrong;
    }
  EXPECT_GT(naive_wrong, 100);  // the cases are hard ones
}

// Four points: three random, the fourth on their plane (an integer
// combination), then moved by -1, 0 or +1 along one axis.
struct Quad {
  IntPoint a, b, c, d;
};
Quad near_coplanar(std::mt19937_64& rng) {
  std::uniform_int_distribution<std::int64_t> big(-(std::int64_t{1} << 33), std::int64_t{1} << 33);
  std::uniform_int_distribution<std::int64_t> small(-6, 6), nudge(-1, 1), axis(0, 2);
  Quad q;
  for (auto* p : {&q.a, &q.b, &q.c})
    for (auto& x : *p) x = big(rng);
  const std::int64_t s = small(rng), t = small(rng);
  for (std::size_t k = 0; k < 3; ++k) q.d[k] = q.a[k] + s * (q.b[k] - q.a[k]) + t * (q.c[k] - q.a[k]);
  q.d[static_cast<std::size_t>(axis(rng))] += nudge(rng);
  return q;
}

TEST(ExactPredicates, Orient3dAgreesOnNearCoplanarIntegers) {
  std::mt19937_64 rng(11);
  int zero = 0;
  for (int i = 0; i < 20000; ++i) {
    const Quad q = near_coplanar(rng);
    const int exact = orient3d_oracle(q.a, q.b, q.c, q.d);
    zero += exact == 0;
    for (const int exponent : {0, 250, -290}) {  // as they are, huge, tiny
      const Vec3 a = to_vec(q.a, exponent), b = to_vec(q.b, exponent), c = to_vec(q.c, exponent),
                 d = to_vec(q.d, exponent);
      ASSERT_TRUE(coordinates_in_exact_range(a) && coordinates_in_exact_range(d));
      ASSERT_EQ(orient3d(a, b, c, d), exact) << i << " at 2^" << exponent;
      ASSERT_EQ(orient3d(b, c, a, d), exact) << i;   // an even permutation keeps the sign
      ASSERT_EQ(orient3d(b, a, c, d), -exact) << i;  // an odd one flips it
    }
    ASSERT_EQ(exact_detail::orient3d_exact(to_vec(q.a, 0), to_vec(q.b, 0), to_vec(q.c, 0), to_vec(q.d, 0)), exact);
  }
  EXPECT_GT(zero, 2000);  // exactly coplanar cases are among them
}

TEST(ExactPredicates, Orient3dAgreesOnRandomIntegers) {
  std::mt19937_64 rng(13);
  std::uniform_int_distribution<std::int64_t> x(-(std::int64_t{1} << 39), std::int64_t{1} << 39);
  for (int i = 0; i < 20000; ++i) {
    IntPoint p[4];
    for (auto& point : p)
      for (auto& c : point) c = x(rng);
    ASSERT_EQ(orient3d(to_vec(p[0], 0), to_vec(p[1], 0), to_vec(p[2], 0), to_vec(p[3], 0)),
              orient3d_oracle(p[0], p[1], p[2], p[3]));
  }
}

TEST(ExactPredicates, SignConventionAndRange) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  EXPECT_EQ(orient3d(a, b, c, Vec3(0, 0, -1)), 1);  // below a counter-clockwise triangle
  EXPECT_EQ(orient3d(a, b, c, Vec3(0, 0, 1)), -1);
  EXPECT_EQ(orient3d(a, b, c, Vec3(5, -7, 0)), 0);
  EXPECT_EQ(orient2d(0, 0, 1, 0, 0, 1), 1);
  EXPECT_EQ(orient2d_dropping(a, b, c, 2), 1);  // the normal's z is positive
  EXPECT_FALSE(coordinates_in_exact_range(Vec3(0, std::ldexp(1.0, 300), 0)));
  EXPECT_FALSE(coordinates_in_exact_range(Vec3(std::ldexp(1.0, -300), 0, 0)));
  EXPECT_FALSE(coordinates_in_exact_range(Vec3(NAN, 0, 0)));
  EXPECT_TRUE(coordinates_in_exact_range(Vec3(0, -1e80, 1e-80)));
}

#ifdef RECON_HAVE_GMP
int orient3d_rational(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  mpq_class m[3][3];
  const Vec3* rows[3] = {&a, &b, &c};
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k) m[r][k] = mpq_class((*rows[r])[k]) - mpq_class(d[k]);
  const mpq_class det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                        m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                        m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  return sgn(det);
}

// Points on the plane z = 0.3 x + 0.7 y (rounded), then moved by a few ulps.
TEST(ExactPredicates, Orient3dAgreesWithRationalsOnUlpPerturbedPlanes) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_int_distribution<int> steps(-2, 2);
  auto on_plane = [&](double scale) {
    const double x = u(rng) * scale, y = u(rng) * scale;
    return Vec3(x, y, 0.3 * x + 0.7 * y);
  };
  auto nudge = [&](Vec3 p) {
    for (int k = 0; k < 3; ++k)
      for (int s = steps(rng); s != 0; s += s > 0 ? -1 : 1) p[k] = std::nextafter(p[k], s > 0 ? INFINITY : -INFINITY);
    return p;
  };
  for (int i = 0; i < 5000; ++i)
    for (const double scale : {1.0, 1e60, 1e-60}) {
      const Vec3 a = on_plane(scale), b = on_plane(scale), c = on_plane(scale), d = nudge(on_plane(scale));
      const int exact = orient3d_rational(a, b, c, d);
      ASSERT_EQ(orient3d(a, b, c, d), exact) << i << " " << scale;
      ASSERT_EQ(exact_detail::orient3d_exact(a, b, c, d), exact) << i << " " << scale;
    }
}
#endif

}  // namespace
}  // namespace recon
