#include "recon/structures/mesh_embedding.h"

#include "recon/core/errors.h"
#include "recon/structures/exact_predicates.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>
#include <utility>

namespace recon {
namespace {

using Triangle = std::array<std::uint32_t, 3>;

// ---- Exact tests on points -------------------------------------------------

// A coordinate plane on which the non-degenerate triangle pqr projects to a
// non-degenerate triangle (the largest component of its rounded normal
// first, then the others), or -1 when pqr has zero area.
int projection_axis(const Vec3& p, const Vec3& q, const Vec3& r) {
  const Vec3 n = (q - p).cross(r - p).cwiseAbs();
  std::array<int, 3> axes = {0, 1, 2};
  std::sort(axes.begin(), axes.end(), [&n](int a, int b) { return n[a] > n[b]; });
  for (const int axis : axes)
    if (orient2d_dropping(p, q, r, axis) != 0) return axis;
  return -1;
}

// x in the closed triangle pqr, all in its plane, on the projection `axis`.
bool in_triangle_2d(const Vec3& x, const Vec3& p, const Vec3& q, const Vec3& r, int axis) {
  const int sigma = orient2d_dropping(p, q, r, axis);
  return orient2d_dropping(p, q, x, axis) * sigma >= 0 && orient2d_dropping(q, r, x, axis) * sigma >= 0 &&
         orient2d_dropping(r, p, x, axis) * sigma >= 0;
}

// x on the closed segment ab, given the three collinear (in the projection).
bool within_2d(const Vec3& x, const Vec3& a, const Vec3& b, int axis) {
  for (const int k : {(axis + 1) % 3, (axis + 2) % 3})
    if (x[k] < std::min(a[k], b[k]) || x[k] > std::max(a[k], b[k])) return false;
  return true;
}

// The closed segments ab and cd meet, all in one plane, on the projection `axis`.
bool segments_meet_2d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, int axis) {
  const int o1 = orient2d_dropping(a, b, c, axis), o2 = orient2d_dropping(a, b, d, axis);
  const int o3 = orient2d_dropping(c, d, a, axis), o4 = orient2d_dropping(c, d, b, axis);
  if (o1 * o2 < 0 && o3 * o4 < 0) return true;
  return (o1 == 0 && within_2d(c, a, b, axis)) || (o2 == 0 && within_2d(d, a, b, axis)) ||
         (o3 == 0 && within_2d(a, c, d, axis)) || (o4 == 0 && within_2d(b, c, d, axis));
}

// The closed segment ab meets the closed triangle pqr, all in one plane.
bool segment_meets_triangle_2d(const Vec3& a, const Vec3& b, const Vec3& p, const Vec3& q, const Vec3& r, int axis) {
  return in_triangle_2d(a, p, q, r, axis) || in_triangle_2d(b, p, q, r, axis) || segments_meet_2d(a, b, p, q, axis) ||
         segments_meet_2d(a, b, q, r, axis) || segments_meet_2d(a, b, r, p, axis);
}

// The closed segment ab meets the closed, non-degenerate triangle pqr.
bool segment_meets_triangle(const Vec3& a, const Vec3& b, const Vec3& p, const Vec3& q, const Vec3& r) {
  const int oa = orient3d(p, q, r, a), ob = orient3d(p, q, r, b);
  if (oa * ob > 0) return false;  // both strictly on one side of the plane
  if (oa == 0 && ob == 0) return segment_meets_triangle_2d(a, b, p, q, r, projection_axis(p, q, r));
  // The line ab crosses the plane once, inside the segment: it passes inside
  // the triangle when it passes no two of its edges on opposite sides.
  const int s1 = orient3d(a, b, p, q), s2 = orient3d(a, b, q, r), s3 = orient3d(a, b, r, p);
  const bool positive = s1 > 0 || s2 > 0 || s3 > 0, negative = s1 < 0 || s2 < 0 || s3 < 0;
  return !(positive && negative);
}

// The plane of pqr has the three points of abc strictly on one side.
bool one_side(const Vec3& p, const Vec3& q, const Vec3& r, const Vec3& a, const Vec3& b, const Vec3& c) {
  const int sa = orient3d(p, q, r, a), sb = orient3d(p, q, r, b), sc = orient3d(p, q, r, c);
  return sa != 0 && sa == sb && sa == sc;
}

// ---- The three rules, by what the triangles share ----------------------------

// No vertex shared: any common point.
bool disjoint_meet(const std::array<Vec3, 3>& p, const std::array<Vec3, 3>& q) {
  if (one_side(p[0], p[1], p[2], q[0], q[1], q[2]) || one_side(q[0], q[1], q[2], p[0], p[1], p[2])) return false;
  for (std::size_t e = 0; e < 3; ++e) {
    if (segment_meets_triangle(p[e], p[(e + 1) % 3], q[0], q[1], q[2])) return true;
    if (segment_meets_triangle(q[e], q[(e + 1) % 3], p[0], p[1], p[2])) return true;
  }
  return false;
}

// The triangles (u, v, a) and (u, v, b) meet off their edge uv: a fold.
bool edge_fold(const Vec3& u, const Vec3& v, const Vec3& a, const Vec3& b) {
  if (orient3d(u, v, a, b) != 0) return false;
  const int axis = projection_axis(u, v, a);
  return orient2d_dropping(u, v, a, axis) * orient2d_dropping(u, v, b, axis) > 0;
}

// The edge from s to x, of another triangle, runs into the triangle (s, b1,
// b2) beyond s: x in its plane, inside its angle at s.
bool into_angle(const Vec3& s, const Vec3& b1, const Vec3& b2, const Vec3& x) {
  if (orient3d(s, b1, b2, x) != 0) return false;
  const int axis = projection_axis(s, b1, b2);
  const int sigma = orient2d_dropping(s, b1, b2, axis);
  return orient2d_dropping(s, b1, x, axis) * sigma >= 0 && orient2d_dropping(s, x, b2, axis) * sigma >= 0;
}

// The triangles (s, a1, a2) and (s, b1, b2) meet off their vertex s.
bool vertex_meet(const Vec3& s, const Vec3& a1, const Vec3& a2, const Vec3& b1, const Vec3& b2) {
  // The common case: one triangle's other corners strictly on one side of
  // the other's plane, which it then touches at s alone.
  const int o1 = orient3d(s, b1, b2, a1), o2 = orient3d(s, b1, b2, a2);
  if (o1 != 0 && o1 == o2) return false;
  const int o3 = orient3d(s, a1, a2, b1), o4 = orient3d(s, a1, a2, b2);
  if (o3 != 0 && o3 == o4) return false;
  return segment_meets_triangle(a1, a2, s, b1, b2) || segment_meets_triangle(b1, b2, s, a1, a2) ||
         into_angle(s, b1, b2, a1) || into_angle(s, b1, b2, a2) || into_angle(s, a1, a2, b1) ||
         into_angle(s, a1, a2, b2);
}

bool degenerate(const Mesh& mesh, const Triangle& t) {
  if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) return true;
  const Vec3 &p = mesh.vertices[t[0]], &q = mesh.vertices[t[1]], &r = mesh.vertices[t[2]];
  return orient2d_dropping(p, q, r, 0) == 0 && orient2d_dropping(p, q, r, 1) == 0 && orient2d_dropping(p, q, r, 2) == 0;
}

// Rotates t so that its corners listed in `first` come first, in t's cyclic order.
Triangle rotated(const Triangle& t, std::size_t start) { return {t[start], t[(start + 1) % 3], t[(start + 2) % 3]}; }

bool pair_meets(const Mesh& mesh, const Triangle& t1, const Triangle& t2) {
  const auto& x = mesh.vertices;
  int shared = 0;
  std::size_t i1 = 0, i2 = 0;  // a shared corner in each
  for (std::size_t i = 0; i < 3; ++i)
    for (std::size_t j = 0; j < 3; ++j)
      if (t1[i] == t2[j]) {
        ++shared;
        i1 = i;
        i2 = j;
      }
  if (shared == 0) return disjoint_meet({x[t1[0]], x[t1[1]], x[t1[2]]}, {x[t2[0]], x[t2[1]], x[t2[2]]});
  if (shared == 1) {
    const Triangle a = rotated(t1, i1), b = rotated(t2, i2);
    return vertex_meet(x[a[0]], x[a[1]], x[a[2]], x[b[1]], x[b[2]]);
  }
  if (shared == 2) {
    // The corner of each not in the other, and the shared edge.
    std::size_t o1 = 0, o2 = 0;
    for (std::size_t i = 0; i < 3; ++i) {
      if (t1[i] != t2[0] && t1[i] != t2[1] && t1[i] != t2[2]) o1 = i;
      if (t2[i] != t1[0] && t2[i] != t1[1] && t2[i] != t1[2]) o2 = i;
    }
    const Triangle a = rotated(t1, o1);
    return edge_fold(x[a[1]], x[a[2]], x[a[0]], x[t2[o2]]);
  }
  return true;  // the same three vertices twice: the triangles coincide
}

// ---- Candidate pairs: a uniform grid ----------------------------------------

struct Box {
  Vec3 lo, hi;
};

struct Grid {
  Vec3 origin;
  double cell = 1.0;
  [[nodiscard]] std::array<std::int64_t, 3> cell_of(const Vec3& p) const {
    std::array<std::int64_t, 3> c{};
    for (int k = 0; k < 3; ++k)
      c[static_cast<std::size_t>(k)] = static_cast<std::int64_t>(std::floor((p[k] - origin[k]) / cell));
    return c;
  }
  [[nodiscard]] static std::uint64_t key(const std::array<std::int64_t, 3>& c) {
    return static_cast<std::uint64_t>(c[0]) | static_cast<std::uint64_t>(c[1]) << 21 |
           static_cast<std::uint64_t>(c[2]) << 42;
  }
};

// Cells about the mean size of a triangle's box, no more than 2^20 along an
// axis (so a key holds them) and no fewer than 1/16 of the largest box (so no
// triangle fills too many cells).
Grid make_grid(const std::vector<Box>& boxes, const std::vector<std::uint32_t>& live) {
  Grid g;
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  double sum = 0.0, largest = 0.0;
  for (const std::uint32_t t : live) {
    lo = lo.cwiseMin(boxes[t].lo);
    hi = hi.cwiseMax(boxes[t].hi);
    const double extent = (boxes[t].hi - boxes[t].lo).maxCoeff();
    sum += extent;
    largest = std::max(largest, extent);
  }
  g.origin = lo;
  const double mean = live.empty() ? 0.0 : sum / static_cast<double>(live.size());
  g.cell = std::max({mean, largest / 16.0, live.empty() ? 0.0 : (hi - lo).maxCoeff() / 1048576.0});
  if (!(g.cell > 0.0)) g.cell = 1.0;
  return g;
}

bool boxes_overlap(const Box& a, const Box& b) {
  for (int k = 0; k < 3; ++k)
    if (a.hi[k] < b.lo[k] || b.hi[k] < a.lo[k]) return false;
  return true;
}

struct CellEntry {
  std::uint64_t key;
  std::uint32_t triangle;
  bool operator<(const CellEntry& o) const { return key != o.key ? key < o.key : triangle < o.triangle; }
};

std::vector<CellEntry> fill_cells(const Grid& g, const std::vector<Box>& boxes,
                                  const std::vector<std::uint32_t>& live) {
  std::vector<CellEntry> entries;
  for (const std::uint32_t t : live) {
    const auto lo = g.cell_of(boxes[t].lo), hi = g.cell_of(boxes[t].hi);
    for (std::int64_t x = lo[0]; x <= hi[0]; ++x)
      for (std::int64_t y = lo[1]; y <= hi[1]; ++y)
        for (std::int64_t z = lo[2]; z <= hi[2]; ++z) entries.push_back({Grid::key({x, y, z}), t});
  }
  std::sort(entries.begin(), entries.end());
  return entries;
}

// The pairs of one run of entries (one cell) that meet, tested here only when
// this cell holds the least corner of their boxes' overlap.
void test_cell(const Mesh& mesh, const Grid& g, const std::vector<Box>& boxes, const CellEntry* begin,
               const CellEntry* end, std::vector<std::array<std::uint32_t, 2>>& out) {
  for (const CellEntry* i = begin; i != end; ++i)
    for (const CellEntry* j = i + 1; j != end; ++j) {
      const Box &a = boxes[i->triangle], &b = boxes[j->triangle];
      if (!boxes_overlap(a, b)) continue;
      if (Grid::key(g.cell_of(a.lo.cwiseMax(b.lo))) != i->key) continue;
      if (pair_meets(mesh, mesh.triangles[i->triangle], mesh.triangles[j->triangle]))
        out.push_back({i->triangle, j->triangle});
    }
}

std::vector<std::array<std::uint32_t, 2>> intersecting_pairs(const Mesh& mesh, const std::vector<std::uint32_t>& live) {
  std::vector<Box> boxes(mesh.triangles.size());
  for (const std::uint32_t t : live) {
    const auto& tri = mesh.triangles[t];
    const Vec3 &p = mesh.vertices[tri[0]], &q = mesh.vertices[tri[1]], &r = mesh.vertices[tri[2]];
    boxes[t] = {p.cwiseMin(q).cwiseMin(r), p.cwiseMax(q).cwiseMax(r)};
  }
  const Grid g = make_grid(boxes, live);
  const std::vector<CellEntry> entries = fill_cells(g, boxes, live);
  std::vector<std::size_t> runs;  // the first entry of each cell, then the end
  for (std::size_t e = 0; e < entries.size(); ++e)
    if (e == 0 || entries[e].key != entries[e - 1].key) runs.push_back(e);
  runs.push_back(entries.size());
  // Blocks of cells in parallel, each with its own list; joined in order.
  constexpr std::size_t block = 1024;
  const std::size_t cells = runs.size() - 1;
  const std::size_t blocks = (cells + block - 1) / block;
  std::vector<std::vector<std::array<std::uint32_t, 2>>> found(blocks);
#pragma omp parallel for schedule(dynamic) if (blocks > 1)
  for (std::size_t b = 0; b < blocks; ++b)
    for (std::size_t c = b * block; c < std::min(cells, (b + 1) * block); ++c)
      test_cell(mesh, g, boxes, entries.data() + runs[c], entries.data() + runs[c + 1], found[b]);
  std::vector<std::array<std::uint32_t, 2>> pairs;
  for (const auto& f : found) pairs.insert(pairs.end(), f.begin(), f.end());
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

// ---- Topology: edges of three triangles, vertices of two fans --------------

std::size_t non_manifold_edges(const Mesh& mesh, const std::vector<std::uint32_t>& proper) {
  std::vector<std::uint64_t> keys;
  keys.reserve(3 * proper.size());
  for (const std::uint32_t t : proper)
    for (std::size_t e = 0; e < 3; ++e) keys.push_back(edge_key(mesh.triangles[t][e], mesh.triangles[t][(e + 1) % 3]));
  std::sort(keys.begin(), keys.end());
  std::size_t count = 0;
  for (std::size_t i = 0; i < keys.size();) {
    std::size_t j = i;
    while (j < keys.size() && keys[j] == keys[i]) ++j;
    if (j - i >= 3) ++count;
    i = j;
  }
  return count;
}

// The number of fans around one vertex: its triangles joined through the
// edges from it (`around`: its triangles, each with its two other corners).
std::size_t fans(std::vector<std::array<std::uint32_t, 2>>& ends) {  // (other corner, local triangle)
  std::uint32_t n = 0;
  for (const auto& e : ends) n = std::max(n, e[1] + 1);
  std::vector<std::uint32_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0U);
  auto find = [&parent](std::uint32_t a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  };
  std::sort(ends.begin(), ends.end());
  std::size_t sets = n;
  for (std::size_t i = 1; i < ends.size(); ++i)
    if (ends[i][0] == ends[i - 1][0]) {
      const std::uint32_t a = find(ends[i][1]), b = find(ends[i - 1][1]);
      if (a != b) {
        parent[a] = b;
        --sets;
      }
    }
  return sets;
}

std::vector<std::uint32_t> pinched_vertices(const Mesh& mesh, const std::vector<std::uint32_t>& proper) {
  std::vector<std::uint32_t> start(mesh.vertices.size() + 1, 0);
  for (const std::uint32_t t : proper)
    for (const std::uint32_t v : mesh.triangles[t]) ++start[v + 1];
  std::partial_sum(start.begin(), start.end(), start.begin());
  std::vector<std::uint32_t> incident(start.back()), next(start.begin(), start.end() - 1);
  for (const std::uint32_t t : proper)
    for (const std::uint32_t v : mesh.triangles[t]) incident[next[v]++] = t;
  std::vector<std::uint32_t> pinched;
  std::vector<std::array<std::uint32_t, 2>> ends;
  for (std::uint32_t v = 0; v < mesh.vertices.size(); ++v) {
    if (start[v + 1] - start[v] < 2) continue;
    ends.clear();
    for (std::uint32_t i = start[v]; i < start[v + 1]; ++i)
      for (const std::uint32_t w : mesh.triangles[incident[i]])
        if (w != v) ends.push_back({w, i - start[v]});
    if (fans(ends) > 1) pinched.push_back(v);
  }
  return pinched;
}

void check_mesh(const Mesh& mesh) {
  std::vector<std::uint8_t> used(mesh.vertices.size(), 0);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (const std::uint32_t v : mesh.triangles[t]) {
      if (v >= mesh.vertices.size())
        throw InvalidInputError("check_embedding: triangle " + std::to_string(t) + " uses vertex " + std::to_string(v) +
                                " of " + std::to_string(mesh.vertices.size()));
      used[v] = 1;
    }
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
    if (used[v] && !coordinates_in_exact_range(mesh.vertices[v]))
      throw InvalidInputError("check_embedding: vertex " + std::to_string(v) +
                              " has a coordinate that is not finite or outside [2^-290, 2^290] in magnitude, where "
                              "the exact predicates hold");
}

}  // namespace

bool triangles_intersect(const Mesh& mesh, std::uint32_t t1, std::uint32_t t2) {
  const Triangle &a = mesh.triangles[t1], &b = mesh.triangles[t2];
  if (degenerate(mesh, a) || degenerate(mesh, b)) return false;
  return pair_meets(mesh, a, b);
}

MeshEmbedding check_embedding(const Mesh& mesh) {
  check_mesh(mesh);
  MeshEmbedding result;
  std::vector<std::uint32_t> live, proper;  // non-degenerate; without a repeated index
  for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t) {
    const Triangle& tri = mesh.triangles[t];
    const bool repeated = tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2];
    if (!repeated) proper.push_back(t);
    if (degenerate(mesh, tri))
      result.degenerate.push_back(t);
    else
      live.push_back(t);
  }
  result.degenerate_triangles = result.degenerate.size();
  result.pairs = intersecting_pairs(mesh, live);
  result.intersecting_pairs = result.pairs.size();
  result.non_manifold_edges = non_manifold_edges(mesh, proper);
  result.pinched = pinched_vertices(mesh, proper);
  result.non_manifold_vertices = result.pinched.size();
  return result;
}

}  // namespace recon
