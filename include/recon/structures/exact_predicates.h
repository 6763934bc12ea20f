#pragma once
// Exact orientation predicates on double coordinates: the sign of a
// determinant, always right, where the determinant computed in floating point
// can have the wrong sign (nearly coplanar or collinear points). The mesh
// check (mesh_embedding.h) decides every "do these triangles meet" with them.
//
// The textbook idea (Shewchuk 1997, "Adaptive precision floating-point
// arithmetic and fast robust geometric predicates"):
//   1. Filter. Compute the determinant in doubles, and a bound on its
//      rounding error proven from the formula (a small multiple of the
//      machine epsilon times the sum of the absolute values of its terms, the
//      "permanent"). A determinant larger than the bound has the right sign:
//      almost every call stops here, at the cost of the plain formula.
//   2. Exact. Otherwise compute the determinant exactly as a floating-point
//      expansion: a sum of doubles of increasing magnitude that do not
//      overlap, whose sign is that of its largest (last) component. A sum
//      a + b is exactly x + y with x = fl(a + b) (Knuth's two-sum), and a
//      product a * b is exactly x + y with x = fl(a * b) and y = fma(a, b, -x);
//      a coordinate difference is then a two-term expansion, products and sums
//      of expansions are expansions, and nothing is rounded.
// What changes here: Shewchuk's adaptive middle stages (reusing the filter's
// tail terms) are left out; the exact stage runs in full when the filter
// fails, which is rare (a few calls in a million on a mesh) and costs a few
// microseconds.
//
// Range: exact while no intermediate product overflows or underflows, which
// holds when every coordinate is 0 or of magnitude in [2^-290, 2^290] (a
// coordinate difference is then a multiple of 2^-342, a product of three a
// multiple of 2^-1026 > 2^-1074, and the sums stay under 2^906).
// coordinates_in_exact_range() tells; outside it the sign may be wrong.

#include "recon/core/point_cloud.h"

namespace recon {

/// The sign of the orientation of d with respect to the plane through a, b,
/// c: +1 when d lies below it (a, b, c counter-clockwise seen from above, the
/// side their normal (b - a) x (c - a) points to), -1 above, 0 when the four
/// are coplanar; exactly the sign of det[a - d; b - d; c - d].
/// Cost: O(1): about 30 flops when the filter decides, a few hundred more when not.
/// Throws: nothing.
/// Pre: coordinates_in_exact_range for the four points (else the sign may be wrong).
[[nodiscard]] int orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

/// The sign of the orientation of the 2D points (ax, ay), (bx, by), (cx, cy):
/// +1 counter-clockwise, -1 clockwise, 0 collinear; exactly the sign of
/// (ax - cx)(by - cy) - (ay - cy)(bx - cx).
/// Cost: O(1): about 10 flops when the filter decides.
/// Throws: nothing.
/// Pre: the six numbers in the exact range (see above).
[[nodiscard]] int orient2d(double ax, double ay, double bx, double by, double cx, double cy);

/// orient2d of a, b, c projected onto the coordinate plane without `axis`
/// (0: onto (y, z), 1: onto (z, x), 2: onto (x, y); the cyclic order keeps
/// the sign that of the normal's `axis` component).
/// Cost, Throws, Pre: as orient2d.
[[nodiscard]] int orient2d_dropping(const Vec3& a, const Vec3& b, const Vec3& c, int axis);

/// True when each coordinate of p is 0 or of magnitude in [2^-290, 2^290]
/// (finite), where the predicates above are exact.
/// Cost: O(1). Throws: nothing. Pre: none.
[[nodiscard]] bool coordinates_in_exact_range(const Vec3& p);

namespace exact_detail {
/// The exact stages alone, without the filter (for the tests: the filter must
/// never decide what the exact stage would not).
[[nodiscard]] int orient3d_exact(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);
[[nodiscard]] int orient2d_exact(double ax, double ay, double bx, double by, double cx, double cy);
}  // namespace exact_detail

}  // namespace recon
