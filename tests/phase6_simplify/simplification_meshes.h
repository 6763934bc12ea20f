// What both halves of phase VI's tests (simplification_test.cpp,
// simplification_rounds_test.cpp) build on: small meshes whose truth is known
// (creases, corners, boundary loops, genus), the tests' own count of those
// features (not the library's), and the options they simplify with.

#pragma once

#include "recon/phase6_simplify/simplification.h"
#include "recon/structures/mesh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <numbers>
#include <vector>

namespace recon::simplification_testing {

// ---- small meshes with a known truth ----

// A box [-1, 1]^3 with an n x n grid on each face, vertices shared.
inline Mesh grid_box(int n) {
  Mesh m;
  std::map<std::array<long, 3>, std::uint32_t> index;
  const auto vertex = [&](const Vec3& p) {
    const std::array<long, 3> key{std::lround(p.x() * 1e6), std::lround(p.y() * 1e6), std::lround(p.z() * 1e6)};
    const auto [it, added] = index.emplace(key, static_cast<std::uint32_t>(m.vertices.size()));
    if (added) m.vertices.push_back(p);
    return it->second;
  };
  for (int axis = 0; axis < 3; ++axis)
    for (const int side : {-1, 1}) {
      const int a = (axis + 1) % 3, b = (axis + 2) % 3;
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          std::array<std::uint32_t, 4> q{};
          for (std::size_t c = 0; c < 4; ++c) {
            Vec3 p;
            p[axis] = side;
            p[a] = -1.0 + 2.0 * (i + (c == 1 || c == 2)) / n;
            p[b] = -1.0 + 2.0 * (j + (c >= 2)) / n;
            q[c] = vertex(p);
          }
          // (a, b, axis) is right-handed: counter-clockwise in (a, b) faces +axis.
          if (side > 0) {
            m.triangles.push_back({q[0], q[1], q[2]});
            m.triangles.push_back({q[0], q[2], q[3]});
          } else {
            m.triangles.push_back({q[0], q[2], q[1]});
            m.triangles.push_back({q[0], q[3], q[2]});
          }
        }
    }
  return m;
}

// A latitude-longitude sphere (closed) or its upper half (open at z = 0).
inline Mesh lat_long(int rings, int sectors, bool upper_half, double centre_x = 0.0, double radius = 1.0) {
  const auto point = [&](double x, double y, double z) { return Vec3(centre_x + radius * x, radius * y, radius * z); };
  Mesh m;
  const int last = upper_half ? rings / 2 : rings;  // rings of vertices below the pole
  const auto at = [&](int ring, int sector) {
    const double theta = std::numbers::pi * ring / rings, phi = 2.0 * std::numbers::pi * sector / sectors;
    return point(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
  };
  m.vertices.push_back(point(0, 0, 1));  // the north pole
  for (int r = 1; r <= last; ++r)
    for (int s = 0; s < sectors; ++s) m.vertices.push_back(at(r, s));
  const auto id = [&](int r, int s) { return static_cast<std::uint32_t>(1 + (r - 1) * sectors + (s % sectors)); };
  for (int s = 0; s < sectors; ++s) m.triangles.push_back({0, id(1, s), id(1, s + 1)});
  for (int r = 1; r < std::min(last, rings - 1); ++r)
    for (int s = 0; s < sectors; ++s) {
      m.triangles.push_back({id(r, s), id(r + 1, s), id(r + 1, s + 1)});
      m.triangles.push_back({id(r, s), id(r + 1, s + 1), id(r, s + 1)});
    }
  if (!upper_half) {
    const auto south = static_cast<std::uint32_t>(m.vertices.size());
    m.vertices.push_back(point(0, 0, -1));
    for (int s = 0; s < sectors; ++s) m.triangles.push_back({id(rings - 1, s), south, id(rings - 1, s + 1)});
  }
  return m;
}

inline Mesh joined(const Mesh& a, const Mesh& b) {
  Mesh m = a;
  const auto first = static_cast<std::uint32_t>(a.vertices.size());
  m.vertices.insert(m.vertices.end(), b.vertices.begin(), b.vertices.end());
  for (auto t : b.triangles) m.triangles.push_back({t[0] + first, t[1] + first, t[2] + first});
  return m;
}

// ---- the test's own feature count (not the library's) ----

struct Features {
  std::set<std::uint64_t> crease_edges;  // dihedral over 25 degrees
  std::vector<int> on;                   // per vertex: crease and boundary edges on it
  std::size_t corners = 0;               // vertices on 1 or 3+ feature edges
};

// Every edge (edge_key) with the triangles that have it.
inline std::map<std::uint64_t, std::vector<std::size_t>> edge_faces(const Mesh& m) {
  std::map<std::uint64_t, std::vector<std::size_t>> faces;
  for (std::size_t f = 0; f < m.triangles.size(); ++f)
    for (std::size_t e = 0; e < 3; ++e) faces[edge_key(m.triangles[f][e], m.triangles[f][(e + 1) % 3])].push_back(f);
  return faces;
}

inline Vec3 unit_normal(const Mesh& m, std::size_t f) {
  const auto& t = m.triangles[f];
  return (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]).normalized();
}

inline Features features(const Mesh& m) {
  const auto normal = [&](std::size_t f) { return unit_normal(m, f); };
  Features out;
  out.on.assign(m.vertices.size(), 0);
  for (const auto& [key, list] : edge_faces(m)) {
    const bool feature =
        list.size() != 2 || normal(list[0]).dot(normal(list[1])) < std::cos(25.0 * std::numbers::pi / 180.0);
    if (!feature) continue;
    if (list.size() == 2) out.crease_edges.insert(key);
    ++out.on[key >> 32];
    ++out.on[key & 0xffffffffu];
  }
  for (const int n : out.on) out.corners += n == 1 || n > 2;
  return out;
}

inline SimplifyOptions to_ratio(double ratio) {
  SimplifyOptions o;
  o.ratio = ratio;
  return o;
}

inline SimplifyOptions as_far_as_it_goes() {
  SimplifyOptions o;
  o.target_triangles = 1;
  return o;
}

inline SimplifyOptions in_blocks(SimplifyOptions o, std::size_t blocks) {
  o.block_vertices = blocks;
  return o;
}

inline double segment_distance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (p - (a + t * ab)).norm();
}

// One queue over the whole mesh, and rounds of blocks (simplification.h)
// so small that most vertices lie on a seam: what one keeps, the other
// must keep too.
inline constexpr std::array<std::size_t, 2> block_sizes{0, 64};

// A torus as a grid of rings: its hole stays however far it goes (the link
// condition refuses the collapses that would pinch the handle).
inline Mesh grid_torus(int rings, int sectors) {
  Mesh m;
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < sectors; ++j) {
      const double a = 2.0 * std::numbers::pi * i / rings, b = 2.0 * std::numbers::pi * j / sectors;
      m.vertices.emplace_back((1.0 + 0.3 * std::cos(b)) * std::cos(a), (1.0 + 0.3 * std::cos(b)) * std::sin(a),
                              0.3 * std::sin(b));
    }
  const auto id = [&](int i, int j) { return static_cast<std::uint32_t>((i % rings) * sectors + (j % sectors)); };
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < sectors; ++j) {
      m.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return m;
}

}  // namespace recon::simplification_testing
