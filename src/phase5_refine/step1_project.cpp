// Phase V, step 1 (refinement.h): every vertex onto the quadric of the
// plane f takes there, blended over the nearest planes on noisy data.
#include "phase5_refine/refinement_steps.h"

#include "recon/core/progress.h"

#include <algorithm>
#include <cmath>

namespace recon::refinement_steps {

namespace {

// On noisy data each quadric carries its neighbourhood's noise: the point
// is projected onto the quadrics of the `blend` origins nearest to it that
// face the same way as plane i (not across a crease), and the results are
// averaged with weights falling off with the distance to each origin (a
// Gaussian of the farthest one's distance): a moving least-squares surface.
SurfacePoint blended_projection(const RefinementInput& in, std::uint32_t i, const Vec3& p) {
  constexpr std::size_t most = 32;
  std::array<Neighbor, most> found;
  const std::size_t count = in.origin_tree->knn(
      p, std::span<Neighbor>(found.data(), std::min<std::size_t>(most, static_cast<std::size_t>(in.blend))));
  const double h2 = std::max(found[count - 1].distance2, 1e-300);
  Vec3 point = Vec3::Zero(), normal = Vec3::Zero();
  double total = 0.0;
  for (std::size_t c = 0; c < count; ++c) {
    const std::uint32_t j = found[c].index;
    if (std::abs(in.normals[j].dot(in.normals[i])) < 0.9063077870366499) continue;  // across a crease
    const SurfacePoint q = project_onto_quadric(in.origins[j], in.normals[j], in.curvature[j], p);
    const double w = std::exp(-found[c].distance2 / h2);
    point += w * q.point;
    normal += w * (q.normal.dot(in.normals[i]) < 0.0 ? Vec3(-q.normal) : q.normal);
    total += w;
  }
  if (!(total > 0.0)) return project_onto_quadric(in.origins[i], in.normals[i], in.curvature[i], p);
  return {point / total, normal.normalized()};
}

}  // namespace

// Step 1: every vertex onto the quadric of the plane f takes there (so the
// faces meeting at a crease split the space as f does). A vertex that would
// move further than max_move stays put.
Projected project_vertices(const Mesh& mesh, const RefinementInput& in, double max_move) {
  const std::size_t n = mesh.vertices.size();
  Projected out;
  out.point.resize(n);
  out.normal.resize(n);
  out.plane.resize(n);
  out.partner.assign(n, none);
  out.covered.assign(n, 1);
  out.trusted.assign(n, 1);
  std::size_t unmoved = 0;
  const auto count = static_cast<std::int64_t>(n);
  ProgressCounter* const progress = progress_counter();
#pragma omp parallel reduction(+ : unmoved)
  {
    // The walk emits neighbouring vertices one after another: the previous
    // vertex's plane bounds the search for the next (the answer is the same).
    std::uint32_t hint = SignedDistance<3>::no_hint;
#pragma omp for schedule(dynamic, 1024)
    for (std::int64_t s = 0; s < count; ++s) {
      const auto v = static_cast<std::size_t>(s);
      if (progress != nullptr && (s & 4095) == 4095) progress->advance(4096);
      const Vec3& p = mesh.vertices[v];
      const std::uint32_t i = in.distance->plane_for(p, hint);
      hint = i;
      const SurfacePoint q = in.blend > 1 ? blended_projection(in, i, p)
                                          : project_onto_quadric(in.origins[i], in.normals[i], in.curvature[i], p);
      const bool trusted = max_move <= 0.0 || (q.point - p).norm() <= max_move;
      out.point[v] = trusted ? q.point : p;
      out.normal[v] = in.oriented[i].dot(in.normals[i]) < 0.0 ? Vec3(-q.normal) : q.normal;
      out.plane[v] = i;
      out.trusted[v] = trusted ? 1 : 0;
      if (!in.spacing.empty())
        out.covered[v] = (p - in.origins[i]).norm() <= static_cast<double>(in.spacing[i]) ? 1 : 0;
      unmoved += trusted ? 0 : 1;
    }
  }
  out.unmoved = unmoved;
  return out;
}

// The normal curvature of plane i's quadric along the direction d (any
// length; its part in the tangent plane counts).
double curvature_along(const RefinementInput& in, std::uint32_t i, const Vec3& d) {
  const auto t = tangent_basis(in.normals[i]);
  const double a = d.dot(t[0]), b = d.dot(t[1]);
  const double length2 = a * a + b * b;
  if (!(length2 > 0.0)) return 0.0;
  const Curvature& c = in.curvature[i];
  const auto cp = static_cast<double>(c.p), cq = static_cast<double>(c.q), cr = static_cast<double>(c.r);
  return 2.0 * (cp * a * a + cq * a * b + cr * b * b) / length2;
}

}  // namespace recon::refinement_steps
