// Phase V, step 3 (refinement.h): the mean sag of each vertex's smooth
// edges, by which the vertex moves out so that the mesh crosses the
// surface instead of lying under it.
#include "phase5_refine/refinement_steps.h"

#include <cmath>

namespace recon::refinement_steps {

// Step 3: the mean sag of each vertex's smooth edges, |e|^2 kappa / 12 with
// kappa = (n_b - n_a) . e / |e|^2 (both normals on one side), signed along
// the vertex's own normal: positive where the surface bulges that way.
std::vector<double> mean_sag(const Mesh& contoured, const Projected& pr, double cos_crease) {
  const std::size_t n = contoured.vertices.size();
  std::vector<double> sum(n, 0.0);
  std::vector<std::uint32_t> edges(n, 0);
  auto add = [&](std::uint32_t a, std::uint32_t b) {
    const double c = pr.normal[a].dot(pr.normal[b]);
    if (std::abs(c) < cos_crease) return;
    const Vec3 nb = c < 0.0 ? Vec3(-pr.normal[b]) : pr.normal[b];
    sum[a] += (nb - pr.normal[a]).dot(pr.point[b] - pr.point[a]) / 12.0;
    ++edges[a];
  };
  for (const auto& t : contoured.triangles)
    for (std::size_t e = 0; e < 3; ++e) {
      add(t[e], t[(e + 1) % 3]);
      add(t[(e + 1) % 3], t[e]);
    }
  for (std::size_t v = 0; v < n; ++v) sum[v] = edges[v] > 0 && pr.partner[v] == none ? sum[v] / edges[v] : 0.0;
  return sum;
}

}  // namespace recon::refinement_steps
