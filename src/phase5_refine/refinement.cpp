#include "recon/phase5_refine/refinement.h"
#include "phase5_refine/refinement_steps.h"

#include "recon/core/errors.h"
#include "recon/core/interruption.h"
#include "recon/core/timer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

namespace recon {
namespace refinement_steps {

void compact(Builder& b, const std::vector<std::uint8_t>& keep_triangle) {
  compact_mesh(b.mesh, b.source, keep_triangle, [&b](std::uint32_t to, std::uint32_t from) {
    b.displacement[to] = b.displacement[from];
    b.planes[to] = b.planes[from];
    b.stem[to] = b.stem[from];
  });
  b.displacement.resize(b.mesh.vertices.size());
  b.planes.resize(b.mesh.vertices.size());
  b.stem.resize(b.mesh.vertices.size());
}

namespace {

// The fitted normal of each vertex (RefinementOptions::fitted_normals):
// a projected vertex's own plane alone, moved onto its quadric, has one;
// a vertex on two planes (a crease vertex, or one brought back onto a
// crease) or none (a corner) has (0, 0, 0). pr.normal is oriented as phase
// II oriented the plane, the side f is positive on, which the contoured
// triangles face.
std::vector<Vec3> fitted_normals(const Builder& b, const Projected& pr) {
  std::vector<Vec3> normals(b.mesh.vertices.size(), Vec3::Zero());
  for (std::size_t v = 0; v < normals.size(); ++v) {
    const auto& on = b.planes[v];
    if (on[0] != none && on[1] == none && pr.trusted[on[0]]) normals[v] = pr.normal[on[0]];
  }
  return normals;
}

void check_input(const RefinementInput& in) {
  const std::size_t n = in.origins.size();
  if (in.normals.size() != n || in.curvature.size() != n || (!in.piece.empty() && in.piece.size() != n) ||
      in.oriented.size() != n || in.distance == nullptr)
    throw InvalidInputError(
        "refine_mesh: the origins, normals (both), curvatures and pieces must all describe the same " +
        std::to_string(n) + " planes, and f is needed");
  if (n == 0) throw InvalidInputError("refine_mesh: no planes to refine against");
  if (in.blend > 1 && (in.origin_tree == nullptr || in.origin_tree->size() != n))
    throw InvalidInputError("refine_mesh: blending needs the tree over the origins");
}

}  // namespace

}  // namespace refinement_steps

using namespace refinement_steps;

RefinedPatch refine_patch(const Mesh& contoured, const RefinementInput& input, const RefinementOptions& options) {
  check_input(input);
  const double cos_crease = std::cos(options.crease_angle_degrees * std::numbers::pi / 180.0);
  Projected pr = project_vertices(contoured, input, options.max_move);
  interruption_point();
  const std::size_t brought_back = bring_back(pr, contoured, input, cos_crease, options.max_move);
  Builder b;
  b.mesh.vertices = pr.point;
  b.displacement.resize(pr.point.size());
  b.planes.resize(pr.point.size());
  b.stem.resize(pr.point.size());
  for (std::uint32_t v = 0; v < pr.point.size(); ++v) {
    b.planes[v] = {v, pr.partner[v]};
    b.stem[v] = {v, none};
  }
  if (options.chord_balance != 0.0) {
    const std::vector<double> sag = mean_sag(contoured, pr, cos_crease);
    for (std::size_t v = 0; v < sag.size(); ++v) b.mesh.vertices[v] += options.chord_balance * sag[v] * pr.normal[v];
  }
  for (std::size_t v = 0; v < pr.point.size(); ++v)
    b.displacement[v] = static_cast<float>((b.mesh.vertices[v] - contoured.vertices[v]).norm());
  interruption_point();
  sharpen(b, pr, contoured, input, cos_crease);
  interruption_point();
  const std::vector<std::uint8_t> put_back =
      options.keep_embedding ? untangle(b, contoured) : std::vector<std::uint8_t>(b.mesh.vertices.size(), 0);
  interruption_point();
  if (options.fitted_normals) {
    b.mesh.normals = fitted_normals(b, pr);
    for (std::size_t v = 0; v < put_back.size(); ++v)
      if (put_back[v]) b.mesh.normals[v] = Vec3::Zero();  // off its quadric now: vertex_normals.h fills it
  }
  RefinedPatch patch;
  patch.put_back =
      static_cast<std::size_t>(std::count_if(put_back.begin(), put_back.end(), [](std::uint8_t l) { return l > 0; }));
  patch.covered = covered_vertices(b, pr);
  patch.far = far_vertices(b, pr, input);
  patch.piece.resize(b.mesh.vertices.size());
  for (std::size_t v = 0; v < patch.piece.size(); ++v) {
    const std::uint32_t projected = b.planes[v][0];  // none for a corner; a crease vertex votes with its first end
    patch.piece[v] = projected == none ? none : input.piece.empty() ? 0 : input.piece[pr.plane[projected]];
  }
  patch.crease_vertices = b.creases;
  patch.brought_back = brought_back;
  patch.corner_vertices = b.corners;
  patch.unmoved = pr.unmoved;
  patch.mesh = std::move(b.mesh);
  patch.displacement = std::move(b.displacement);
  patch.stem = std::move(b.stem);
  patch.source = std::move(b.source);
  return patch;
}

void RefinedPatch::keep(const std::vector<std::uint8_t>& keep_triangle) {
  compact_mesh(mesh, source, keep_triangle, [this](std::uint32_t to, std::uint32_t from) {
    displacement[to] = displacement[from];
    stem[to] = stem[from];
    covered[to] = covered[from];
    far[to] = far[from];
    piece[to] = piece[from];
  });
  const std::size_t n = mesh.vertices.size();
  displacement.resize(n);
  stem.resize(n);
  covered.resize(n);
  far.resize(n);
  piece.resize(n);
}

// Steps 1 to 3 (refine_patch), then step 4 over the whole mesh.
Refinement refine_mesh(const Mesh& contoured, const RefinementInput& input, const RefinementOptions& options) {
  Timer timer;
  RefinedPatch patch = refine_patch(contoured, input, options);
  Refinement result;
  result.trimmed = trim_boundaries(patch);
  result.stray_triangles = drop_strays(patch);
  result.crease_vertices = patch.crease_vertices;
  result.brought_back = patch.brought_back;
  result.corner_vertices = patch.corner_vertices;
  result.unmoved = patch.unmoved;
  result.put_back = patch.put_back;
  if (!options.keep_fragments) {
    const Fragments f = find_fragments(patch.mesh, patch.piece, options.fragment_fraction);
    result.fragments = f.dropped;
    result.fragment_triangles = f.dropped_triangles;
    if (f.dropped > 0) patch.keep(f.keep_triangle);
  }
  result.mesh = std::move(patch.mesh);
  result.displacement = std::move(patch.displacement);
  result.seconds = timer.lap();
  return result;
}

}  // namespace recon
