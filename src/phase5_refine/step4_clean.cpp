// Phase V, step 4 (refinement.h): open boundaries cut back to the data,
// triangles beyond f's reach dropped, fragments found.
#include "phase5_refine/refinement_steps.h"

#include <algorithm>

namespace recon::refinement_steps {

// Step 4a: an open boundary is cut back to the data. f is defined up to
// about 1.5 rho + delta past the last samples (signed_distance.h), so the
// contoured surface runs on past an open edge of the data; triangles whose
// three vertices lie farther from their plane's sample than the local
// spacing there are peeled off, starting from the boundary and moving
// inwards only (a closed surface has no boundary and loses nothing, and no
// hole is made inside the surface).
// Whether each vertex lies within the spacing of its plane's sample (or of
// one of its two planes' samples, on a crease).
std::vector<std::uint8_t> covered_vertices(const Builder& b, const Projected& pr) {
  std::vector<std::uint8_t> covered(b.mesh.vertices.size(), 1);
  for (std::size_t v = 0; v < covered.size(); ++v) {
    const auto& on = b.planes[v];
    if (on[0] != none) covered[v] = pr.covered[on[0]] || (on[1] != none && pr.covered[on[1]]);
  }
  return covered;
}

std::size_t trim_boundaries(RefinedPatch& patch) {
  Peeling peeling(patch.mesh, patch.covered);
  const std::size_t peeled = peeling.peel();
  if (peeled > 0) patch.keep(peeling.kept());
  return peeled;
}

// Step 4, triangles beyond f's reach. f is defined only within about
// 1.5 rho_i + delta of a sample, and a mesh on the surface lies within a
// cell of it; where sheets lie closer than a cell the lattice cannot
// follow them, and the zero set drawn between the planes of both can run
// off into empty space (a fin). A triangle whose three vertices are all
// farther than in.reach * rho_i + delta from every sample is dropped.
// (Vertices that near their plane's own origin are not searched.)
std::vector<std::uint8_t> far_vertices(const Builder& b, const Projected& pr, const RefinementInput& in) {
  const std::size_t n = b.mesh.vertices.size();
  std::vector<std::uint8_t> far(n, 0);
  if (in.sample_tree == nullptr) return far;
  const auto count = static_cast<std::int64_t>(n);
#pragma omp parallel for schedule(dynamic, 4096)
  for (std::int64_t s = 0; s < count; ++s) {
    const auto v = static_cast<std::size_t>(s);
    const std::uint32_t own = b.planes[v][0];
    if (own == none) continue;  // a corner: where its planes meet
    const std::uint32_t plane = pr.plane[own];
    const double reach = in.reach * static_cast<double>(in.local_rho[plane]) + in.delta;
    const Vec3& p = b.mesh.vertices[v];
    if ((p - in.origins[plane]).squaredNorm() <= reach * reach) continue;
    far[v] = in.sample_tree->any_within(p, reach * reach) ? 0 : 1;
  }
  return far;
}

std::size_t drop_strays(RefinedPatch& patch) {
  std::vector<std::uint8_t> keep(patch.mesh.triangles.size(), 1);
  std::size_t dropped = 0;
  for (std::size_t t = 0; t < keep.size(); ++t) {
    const auto& tri = patch.mesh.triangles[t];
    if (patch.far[tri[0]] && patch.far[tri[1]] && patch.far[tri[2]]) {
      keep[t] = 0;
      ++dropped;
    }
  }
  if (dropped > 0) patch.keep(keep);
  return dropped;
}

namespace {

std::uint32_t find_root(std::vector<std::uint32_t>& parent, std::uint32_t v) {
  while (parent[v] != v) v = parent[v] = parent[parent[v]];
  return v;
}

}  // namespace

Fragments find_fragments(const Mesh& mesh, const std::vector<std::uint32_t>& piece_of_vertex, double fraction) {
  const std::size_t n = mesh.vertices.size();
  std::vector<std::uint32_t> parent(n);
  for (std::uint32_t v = 0; v < n; ++v) parent[v] = v;
  for (const auto& t : mesh.triangles)
    for (std::size_t e = 1; e < 3; ++e) {
      const std::uint32_t a = find_root(parent, t[0]), b = find_root(parent, t[e]);
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  Fragments f;
  f.keep_triangle.assign(mesh.triangles.size(), 1);
  std::size_t roots = 0;
  for (std::uint32_t v = 0; v < n && roots < 2; ++v) roots += parent[v] == v ? 1u : 0u;
  if (roots < 2) return f;  // one component (or none): nothing to compare
  // Per component (by root): triangles, and votes for its piece.
  std::unordered_map<std::uint32_t, std::size_t> triangles;
  std::unordered_map<std::uint32_t, std::unordered_map<std::uint32_t, std::size_t>> votes;
  for (const auto& t : mesh.triangles) ++triangles[find_root(parent, t[0])];
  for (std::uint32_t v = 0; v < n; ++v)
    if (piece_of_vertex[v] != none) ++votes[find_root(parent, v)][piece_of_vertex[v]];
  std::unordered_map<std::uint32_t, std::uint32_t> piece_of;
  std::unordered_map<std::uint32_t, std::size_t> largest;  // per piece
  for (const auto& [root, count] : triangles) {
    std::uint32_t piece = 0;
    std::size_t best = 0;
    for (const auto& [p, c] : votes[root])
      if (c > best || (c == best && p < piece)) {
        best = c;
        piece = p;
      }
    piece_of[root] = piece;
    largest[piece] = std::max(largest[piece], count);
  }
  for (const auto& [root, count] : triangles)
    if (static_cast<double>(count) < fraction * static_cast<double>(largest[piece_of[root]])) {
      ++f.dropped;
      f.dropped_triangles += count;
    }
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const std::uint32_t root = find_root(parent, mesh.triangles[t][0]);
    if (static_cast<double>(triangles[root]) < fraction * static_cast<double>(largest[piece_of[root]]))
      f.keep_triangle[t] = 0;
  }
  return f;
}

}  // namespace recon::refinement_steps
