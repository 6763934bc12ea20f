// Phase VI against Debian's meshoptimizer 0.18 (issue 30): at ten times
// fewer triangles, on phase V's meshes of the box, the fandisk-like part and
// an open hemisphere, what each keeps of the creases, corners and boundary,
// and the time on a mesh of about a million triangles.
//
//   recon_simplify_bench [--big N] [--ratio R]
//   recon_simplify_bench --mesh FILE [--ratio R] [--threads T]
//   (N points for the timing run, default 1000000, 0: skip; R the fraction
//   of the triangles kept, default 0.1; --mesh: only time phase VI on that
//   mesh, best of three, e.g. phase V's mesh of the 1M-point torus)
//
// Measures, all against phase V's mesh (the input of both):
//   corners   the box's 8 true corners: the farthest from a vertex of the result
//   creases   the midpoints of the input's sharp edges (dihedral over 60
//             degrees): mean and largest distance to the result
//   boundary  loops before / after, and the largest distance from an input
//             boundary vertex to the result's boundary edges
// meshoptimizer runs three ways: plain; meshopt_SimplifyLockBorder; and the
// mesh split along its creases (25 degrees: each side's vertices apart, so
// the creases become borders) with LockBorder, welded back afterwards.
#include "recon/core/parallel.h"
#include "recon/core/shapes.h"
#include "recon/core/timer.h"
#include "recon/io/mesh_io.h"
#include "recon/phase6_simplify/simplification.h"
#include "recon/reconstruct.h"
#include "recon/structures/mesh.h"
#include "recon/structures/union_find.h"

#include <meshoptimizer.h>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <numbers>
#include <random>
#include <string>
#include <vector>

using namespace recon;

namespace {

Vec3 normal_of(const Mesh& m, std::size_t f) {
  const auto& t = m.triangles[f];
  return (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]).normalized();
}

std::map<std::uint64_t, std::vector<std::uint32_t>> edge_faces(const Mesh& m) {
  std::map<std::uint64_t, std::vector<std::uint32_t>> faces;
  for (std::uint32_t f = 0; f < m.triangles.size(); ++f)
    for (std::size_t e = 0; e < 3; ++e) faces[edge_key(m.triangles[f][e], m.triangles[f][(e + 1) % 3])].push_back(f);
  return faces;
}

double distance_to(const Mesh& m, const Vec3& p) {
  double best = 1e300;
  for (const auto& t : m.triangles)
    best = std::min(best, point_triangle_distance(p, m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]));
  return best;
}

double segment_distance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / std::max(ab.squaredNorm(), 1e-300), 0.0, 1.0);
  return (p - (a + t * ab)).norm();
}

struct Row {
  std::string shape, method;
  std::size_t before = 0, after = 0;
  double corner = -1, crease_mean = 0, crease_max = 0, boundary = 0;
  std::size_t loops_before = 0, loops_after = 0;
  double seconds = 0;
};

void measure(const Mesh& in, const Mesh& out, bool box, Row& row) {
  row.before = in.triangles.size();
  row.after = out.triangles.size();
  if (box) {
    row.corner = 0;
    const Vec3 half(0.5, 0.4, 0.3);
    for (int s = 0; s < 8; ++s) {
      const Vec3 c((s & 1 ? 1 : -1) * half.x(), (s & 2 ? 1 : -1) * half.y(), (s & 4 ? 1 : -1) * half.z());
      double nearest = 1e300;
      for (const Vec3& v : out.vertices) nearest = std::min(nearest, (v - c).norm());
      row.corner = std::max(row.corner, nearest);
    }
  }
  std::size_t n = 0;
  for (const auto& [key, faces] : edge_faces(in)) {
    if (faces.size() != 2 || normal_of(in, faces[0]).dot(normal_of(in, faces[1])) > 0.5) continue;
    const Vec3 mid = 0.5 * (in.vertices[key >> 32] + in.vertices[key & 0xffffffffu]);
    const double d = distance_to(out, mid);
    row.crease_mean += d;
    row.crease_max = std::max(row.crease_max, d);
    ++n;
  }
  if (n > 0) row.crease_mean /= static_cast<double>(n);
  row.loops_before = analyze_topology(in).boundary_loops;
  row.loops_after = analyze_topology(out).boundary_loops;
  const auto rim = boundary_edges(out);
  for (const auto& e : boundary_edges(in)) {
    double nearest = 1e300;
    for (const auto& r : rim)
      nearest = std::min(nearest, segment_distance(in.vertices[e[0]], out.vertices[r[0]], out.vertices[r[1]]));
    if (!rim.empty()) row.boundary = std::max(row.boundary, nearest);
  }
}

// The result of meshopt_simplify as a mesh on the input's vertices.
Mesh from_indices(const Mesh& in, const std::vector<unsigned>& indices, const std::vector<std::uint32_t>& original) {
  Mesh m;
  std::vector<std::uint32_t> index(in.vertices.size(), UINT32_MAX);
  for (std::size_t i = 0; i + 2 < indices.size(); i += 3) {
    std::array<std::uint32_t, 3> t{};
    for (std::size_t k = 0; k < 3; ++k) {
      const std::uint32_t v = original.empty() ? indices[i + k] : original[indices[i + k]];
      if (index[v] == UINT32_MAX) {
        index[v] = static_cast<std::uint32_t>(m.vertices.size());
        m.vertices.push_back(in.vertices[v]);
      }
      t[k] = index[v];
    }
    m.triangles.push_back(t);
  }
  return m;
}

// The mesh split along its creases: the corners of the triangles around a
// vertex are joined across smooth edges only; each group is a vertex.
void split_along_creases(const Mesh& in, std::vector<float>& xyz, std::vector<unsigned>& indices,
                         std::vector<std::uint32_t>& original) {
  const auto faces = edge_faces(in);
  UnionFind corners(in.triangles.size() * 3);
  for (const auto& [key, list] : faces) {
    if (list.size() != 2 ||
        normal_of(in, list[0]).dot(normal_of(in, list[1])) < std::cos(25.0 * std::numbers::pi / 180))
      continue;
    for (const std::uint32_t v :
         {static_cast<std::uint32_t>(key >> 32), static_cast<std::uint32_t>(key & 0xffffffffu)}) {
      std::array<std::size_t, 2> c{};
      for (std::size_t s = 0; s < 2; ++s)
        for (std::size_t k = 0; k < 3; ++k)
          if (in.triangles[list[s]][k] == v) c[s] = 3 * list[s] + k;
      corners.unite(static_cast<std::uint32_t>(c[0]), static_cast<std::uint32_t>(c[1]));
    }
  }
  std::map<std::uint32_t, unsigned> vertex_of_group;
  for (std::size_t c = 0; c < 3 * in.triangles.size(); ++c) {
    const std::uint32_t root = corners.find(static_cast<std::uint32_t>(c));
    const auto [it, added] = vertex_of_group.emplace(root, static_cast<unsigned>(original.size()));
    if (added) {
      const std::uint32_t v = in.triangles[c / 3][c % 3];
      original.push_back(v);
      for (int a = 0; a < 3; ++a) xyz.push_back(static_cast<float>(in.vertices[v][a]));
    }
    indices.push_back(it->second);
  }
}

double ratio = 0.1;

Mesh meshopt(const Mesh& in, int way, double& seconds) {
  std::vector<float> xyz;
  std::vector<unsigned> indices;
  std::vector<std::uint32_t> original;
  if (way == 2) {
    split_along_creases(in, xyz, indices, original);
  } else {
    for (const Vec3& v : in.vertices)
      for (int a = 0; a < 3; ++a) xyz.push_back(static_cast<float>(v[a]));
    for (const auto& t : in.triangles) indices.insert(indices.end(), t.begin(), t.end());
  }
  std::vector<unsigned> out(indices.size());
  Timer timer;
  const std::size_t n =
      meshopt_simplify(out.data(), indices.data(), indices.size(), xyz.data(), xyz.size() / 3, 3 * sizeof(float),
                       3 * static_cast<std::size_t>(ratio * static_cast<double>(indices.size() / 3)), 1.0f,
                       way == 0 ? 0u : unsigned{meshopt_SimplifyLockBorder}, nullptr);
  seconds = timer.elapsed();
  out.resize(n);
  return from_indices(in, out, original);
}

Mesh phase_5_mesh(const PointCloud& cloud) {
  ReconstructionOptions options;
  return reconstruct(cloud, options).mesh();
}

PointCloud hemisphere(std::size_t n) {
  std::mt19937_64 random(7);
  std::normal_distribution<double> normal;
  PointCloud cloud;
  while (cloud.positions.size() < n) {
    Vec3 v(normal(random), normal(random), normal(random));
    v.normalize();
    if (v.z() > 0.0) cloud.positions.push_back(v);
  }
  return cloud;
}

void print(const Row& r) {
  std::printf("| %-10s | %-28s | %8zu | %7zu | %9.2e | %9.2e | %9.2e | %d -> %d | %9.2e | %7.3f |\n", r.shape.c_str(),
              r.method.c_str(), r.before, r.after, r.corner, r.crease_mean, r.crease_max,
              static_cast<int>(r.loops_before), static_cast<int>(r.loops_after), r.boundary, r.seconds);
}

// Phase VI alone on a saved mesh: the best of three runs (the machine is shared).
int time_mesh(const std::string& path) {
  const Mesh in = io::read_mesh(path);
  SimplifyOptions o;
  o.ratio = ratio;
  double best = 1e300;
  std::size_t after = 0;
  for (int run = 0; run < 3; ++run) {
    const Simplification s = simplify(in, o);
    best = std::min(best, s.seconds);
    after = s.mesh.triangles.size();
  }
  std::printf("%s: %zu triangles to %zu in %.3f s (best of 3, %d threads)\n", path.c_str(), in.triangles.size(), after,
              best, thread_count());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::size_t big = 1'000'000;
  std::string mesh_path;
  for (int i = 1; i + 1 < argc; ++i)
    if (std::string(argv[i]) == "--big")
      big = std::strtoull(argv[i + 1], nullptr, 10);
    else if (std::string(argv[i]) == "--ratio")
      ratio = std::strtod(argv[i + 1], nullptr);
    else if (std::string(argv[i]) == "--mesh")
      mesh_path = argv[i + 1];
    else if (std::string(argv[i]) == "--threads")
      set_thread_count(std::atoi(argv[i + 1]));
  if (!mesh_path.empty()) return time_mesh(mesh_path);
  std::printf(
      "| shape | method | before | after | corner (max) | crease mean | crease max | loops | boundary max | seconds "
      "|\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|\n");
  const std::vector<std::pair<std::string, PointCloud>> inputs = {{"box", make_shape("box")->sample(50000, 1)},
                                                                  {"part", make_shape("part")->sample(50000, 1)},
                                                                  {"hemisphere", hemisphere(30000)}};
  for (const auto& [name, cloud] : inputs) {
    const Mesh in = phase_5_mesh(cloud);
    const bool box = name == "box";
    {
      Row row{name, "recon simplify"};
      SimplifyOptions o;
      o.ratio = ratio;
      const Simplification s = simplify(in, o);
      row.seconds = s.seconds;
      measure(in, s.mesh, box, row);
      print(row);
    }
    const char* ways[] = {"meshopt plain", "meshopt LockBorder", "meshopt split creases+Lock"};
    for (int way = 0; way < 3; ++way) {
      Row row{name, ways[way]};
      const Mesh out = meshopt(in, way, row.seconds);
      measure(in, out, box, row);
      print(row);
    }
  }
  if (big == 0) return 0;
  const Mesh in = phase_5_mesh(make_shape("torus")->sample(big, 2));
  SimplifyOptions o;
  o.ratio = ratio;
  const Simplification s = simplify(in, o);
  double meshopt_seconds = 0.0;
  const Mesh m = meshopt(in, 1, meshopt_seconds);
  std::printf(
      "\ntorus of %zu points: %zu triangles; recon simplify to %zu in %.3f s; meshopt (LockBorder) to %zu in %.3f s\n",
      big, in.triangles.size(), s.mesh.triangles.size(), s.seconds, m.triangles.size(), meshopt_seconds);
  return 0;
}
