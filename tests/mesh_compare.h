#pragma once
// Comparing two meshes as sets of triangles (the tests of the textbook path
// and of tiled runs), and a point's distance to a mesh by brute force.

#include "recon/structures/kdtree.h"
#include "recon/structures/mesh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <set>
#include <vector>

namespace recon {

// Triangles as index triples of b's vertices, rotated to start at the
// smallest index (which keeps their orientation).
inline std::multiset<std::array<std::uint32_t, 3>> canonical(const std::vector<std::array<std::uint32_t, 3>>& triangles,
                                                             const std::vector<std::uint32_t>& to_b = {}) {
  std::multiset<std::array<std::uint32_t, 3>> out;
  for (auto t : triangles) {
    if (!to_b.empty())
      for (auto& v : t) v = to_b[v];
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
    out.insert(t);
  }
  return out;
}

// The same mesh: every vertex of a has a vertex of b within `tolerance`
// (one to one), and the triangles are the same, oriented the same way, in
// any order.
inline ::testing::AssertionResult same_mesh(const Mesh& a, const Mesh& b, double tolerance) {
  if (a.vertices.size() != b.vertices.size() || a.triangles.size() != b.triangles.size())
    return ::testing::AssertionFailure() << a.vertices.size() << " vertices and " << a.triangles.size()
                                         << " triangles against " << b.vertices.size() << " and " << b.triangles.size();
  const KdTree<3> tree(b.vertices);
  std::vector<std::uint32_t> to_b(a.vertices.size());
  std::vector<bool> taken(b.vertices.size(), false);
  for (std::size_t i = 0; i < a.vertices.size(); ++i) {
    const Neighbor nearest = tree.nearest(a.vertices[i]);
    if (std::sqrt(nearest.distance2) > tolerance || taken[nearest.index])
      return ::testing::AssertionFailure() << "vertex " << i << " has no vertex of its own within " << tolerance;
    taken[nearest.index] = true;
    to_b[i] = nearest.index;
  }
  if (canonical(a.triangles, to_b) != canonical(b.triangles))
    return ::testing::AssertionFailure() << "the triangles differ";
  return ::testing::AssertionSuccess();
}

// The oracle of a point's distance to a mesh: the nearest of all its
// triangles, by brute force.
inline double brute_force_distance(const Vec3& p, const Mesh& mesh) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& t : mesh.triangles)
    best = std::min(best, point_triangle_distance(p, mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]));
  return best;
}

}  // namespace recon
