#include "recon/phase5_refine/vertex_normals.h"

#include "recon/core/errors.h"

#include <Eigen/Geometry>

#include <cmath>
#include <string>
#include <vector>

namespace recon {
namespace {

void check_mesh(const Mesh& mesh) {
  const std::size_t n = mesh.vertices.size();
  if (mesh.has_normals() && mesh.normals.size() != n)
    throw InvalidInputError("fill_face_normals: " + std::to_string(mesh.normals.size()) + " normals for " +
                            std::to_string(n) + " vertices");
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (const std::uint32_t v : mesh.triangles[t])
      if (v >= n)
        throw InvalidInputError("fill_face_normals: triangle " + std::to_string(t) + " uses vertex " +
                                std::to_string(v) + " of " + std::to_string(n));
}

// Per vertex, the sum of the cross products of its triangles (each twice
// the triangle's area along its normal), over the vertices in `wanted`.
std::vector<Vec3> area_weighted_sums(const Mesh& mesh, const std::vector<std::uint8_t>& wanted) {
  std::vector<Vec3> sum(mesh.vertices.size(), Vec3::Zero());
  for (const auto& t : mesh.triangles) {
    if (!wanted[t[0]] && !wanted[t[1]] && !wanted[t[2]]) continue;
    const Vec3& a = mesh.vertices[t[0]];
    const Vec3 cross = (mesh.vertices[t[1]] - a).cross(mesh.vertices[t[2]] - a);
    for (const std::uint32_t v : t)
      if (wanted[v]) sum[v] += cross;
  }
  return sum;
}

// v / |v| when |v| is a positive finite number; nothing otherwise.
bool normalise(const Vec3& v, Vec3& unit) {
  const double norm = v.norm();
  if (!std::isfinite(norm) || !(norm > 0.0)) return false;  // (isfinite first: no comparison with a NaN)
  unit = v / norm;
  return true;
}

// A vertex whose triangles have no area: the mean of the normals of the
// vertices it shares a triangle with (those that have one), else +z.
Vec3 neighbours_normal(const Mesh& mesh, const std::vector<std::vector<std::uint32_t>>& around, std::uint32_t v,
                       const std::vector<std::uint8_t>& defined) {
  Vec3 sum = Vec3::Zero();
  for (const std::uint32_t t : around[v])
    for (const std::uint32_t w : mesh.triangles[t])
      if (w != v && defined[w]) sum += mesh.normals[w];
  Vec3 unit = Vec3::UnitZ();
  normalise(sum, unit);
  return unit;
}

}  // namespace

FaceNormalFill fill_face_normals(Mesh& mesh) {
  check_mesh(mesh);
  const std::size_t n = mesh.vertices.size();
  if (!mesh.has_normals()) mesh.normals.assign(n, Vec3::Zero());
  std::vector<std::uint8_t> wanted(n, 0);
  for (std::size_t v = 0; v < n; ++v) wanted[v] = mesh.normals[v] == Vec3::Zero() ? 1 : 0;
  const std::vector<Vec3> sum = area_weighted_sums(mesh, wanted);
  FaceNormalFill fill;
  std::vector<std::uint32_t> undefined;
  for (std::uint32_t v = 0; v < n; ++v) {
    if (!wanted[v]) continue;
    if (normalise(sum[v], mesh.normals[v])) {
      ++fill.filled;
    } else {
      undefined.push_back(v);
    }
  }
  fill.undefined = undefined.size();
  if (undefined.empty()) return fill;
  // The rare vertices whose triangles all have zero area.
  std::vector<std::uint8_t> defined(n, 1);
  for (const std::uint32_t v : undefined) defined[v] = 0;
  std::vector<std::vector<std::uint32_t>> around(n);
  for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t)
    for (const std::uint32_t v : mesh.triangles[t])
      if (!defined[v]) around[v].push_back(t);
  for (const std::uint32_t v : undefined) mesh.normals[v] = neighbours_normal(mesh, around, v, defined);
  return fill;
}

}  // namespace recon
