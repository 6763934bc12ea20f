#include "recon/phase4_contour/marching_cubes_table.h"

#include "recon/core/point_cloud.h"

#include <Eigen/Geometry>

#include <vector>

namespace recon::mc {
namespace {

Vec3 corner_position(int c) { return Vec3(c & 1, (c >> 1) & 1, (c >> 2) & 1); }

// Edges are numbered axis * 4 + j, where j's two bits give the corner's
// coordinates on the two other axes, in increasing axis order.
int corner_of(int axis, int j, int along) {
  const int b = (axis + 1) % 3, c = (axis + 2) % 3;
  const int lo = std::min(b, c), hi = std::max(b, c);
  return (along << axis) | ((j & 1) << lo) | (((j >> 1) & 1) << hi);
}

int edge_between(int c0, int c1) {
  const int diff = c0 ^ c1;
  const int axis = diff == 1 ? 0 : diff == 2 ? 1 : 2;
  const int base = c0 & ~diff;
  const int b = (axis + 1) % 3, c = (axis + 2) % 3;
  const int lo = std::min(b, c), hi = std::max(b, c);
  return axis * 4 + ((base >> lo) & 1) + 2 * ((base >> hi) & 1);
}

// Whether two cube edges lie on a common face: they are parallel and differ
// in one of the other coordinates, or perpendicular and touch.
bool share_face(int e0, int e1) {
  const auto a = edge_corners(e0), b = edge_corners(e1);
  // All four corners on one face: some axis where all four agree.
  for (int axis = 0; axis < 3; ++axis) {
    const int bit = 1 << axis;
    const int v = a[0] & bit;
    if ((a[1] & bit) == v && (b[0] & bit) == v && (b[1] & bit) == v) return true;
  }
  return false;
}

Vec3 edge_midpoint(int e) {
  const auto ends = edge_corners(e);
  return 0.5 * (corner_position(ends[0]) + corner_position(ends[1]));
}

using Successors = std::array<int, 12>;  // per edge: the crossing its segment leads to, or -1

// Step 1 on one face (normal axis a, side s): each inside corner that is cut
// off on this face, or each run of inside corners, gives one segment between
// the crossings around it, entered in `next`.
void join_face(unsigned config, int a, int s, Successors& next) {
  auto inside = [config](int c) { return ((config >> c) & 1u) != 0; };
  const int b = (a + 1) % 3, c = (a + 2) % 3;
  // The face's corners in cyclic order around it.
  const std::array<int, 4> ring = {(s << a), (s << a) | (1 << b), (s << a) | (1 << b) | (1 << c), (s << a) | (1 << c)};
  int inside_count = 0;
  for (int corner : ring) inside_count += inside(corner) ? 1 : 0;
  if (inside_count == 0 || inside_count == 4) return;
  Vec3 outward = Vec3::Zero();
  outward[a] = s == 0 ? -1.0 : 1.0;
  for (int r = 0; r < 4; ++r) {
    const int here = ring[static_cast<std::size_t>(r)];
    const int prev = ring[static_cast<std::size_t>((r + 3) % 4)];
    if (!inside(here) || inside(prev)) continue;  // start of an inside run
    int last = r;
    while (inside(ring[static_cast<std::size_t>((last + 1) % 4)])) last = (last + 1) % 4;
    const int after = ring[static_cast<std::size_t>((last + 1) % 4)];
    // (edge entering the inside run, edge leaving it). Diagonal inside
    // corners give two runs of one corner each: two segments, each cutting
    // off its inside corner (the fixed rule).
    int e0 = edge_between(prev, here), e1 = edge_between(ring[static_cast<std::size_t>(last)], after);
    // Direct the segment so that, seen from outside the cube, the inside
    // corners are on its right: then loops run clockwise around the inside,
    // i.e. counter-clockwise seen from the outside region.
    const Vec3 p = edge_midpoint(e0), q = edge_midpoint(e1);
    const int corner = edge_corners(e0)[inside(edge_corners(e0)[0]) ? 0 : 1];
    const double side = (q - p).cross(corner_position(corner) - p).dot(outward);
    if (side > 0.0) std::swap(e0, e1);
    next[static_cast<std::size_t>(e0)] = e1;
  }
}

// Step 2: every crossing has one segment on each of its two faces, so the
// segments chain into closed loops (of edges), taken from the lowest edge.
std::vector<std::vector<int>> chain_loops(const Successors& next) {
  std::vector<std::vector<int>> loops;
  std::array<bool, 12> used{};
  for (int start = 0; start < 12; ++start) {
    if (next[static_cast<std::size_t>(start)] < 0 || used[static_cast<std::size_t>(start)]) continue;
    std::vector<int>& loop = loops.emplace_back();
    for (int e = start; !used[static_cast<std::size_t>(e)]; e = next[static_cast<std::size_t>(e)]) {
      used[static_cast<std::size_t>(e)] = true;
      loop.push_back(e);
    }
  }
  return loops;
}

// An apex whose diagonals all cross the cube's interior, or -1. A diagonal
// between two crossings on one face would also be drawn by the neighbour
// across that face when it fans its own loop there: an edge of four
// triangles.
int fan_apex(const std::vector<int>& loop) {
  const std::size_t size = loop.size();
  for (std::size_t r = 0; r < size; ++r) {
    bool clean = true;
    for (std::size_t i = 2; i + 1 < size && clean; ++i) clean = !share_face(loop[r], loop[(r + i) % size]);
    if (clean) return static_cast<int>(r);
  }
  return -1;
}

// Step 3: loop l becomes a fan of triangles from its apex, or, when no apex
// avoids the faces, around the loop's centre.
void triangulate(const std::vector<int>& loop, CubeCase& result) {
  const int l = result.loop_count++;
  auto& loop_edges = result.loops[static_cast<std::size_t>(l)];
  loop_edges.size = static_cast<int>(loop.size());
  for (std::size_t i = 0; i < loop.size(); ++i) loop_edges.edges[i] = static_cast<std::uint8_t>(loop[i]);
  auto add = [&](int a, int b, int c) {
    result.triangles[static_cast<std::size_t>(result.triangle_count++)] = {
        static_cast<std::uint8_t>(a), static_cast<std::uint8_t>(b), static_cast<std::uint8_t>(c)};
  };
  const std::size_t size = loop.size();
  if (const int apex = fan_apex(loop); apex >= 0) {
    const auto r = static_cast<std::size_t>(apex);
    for (std::size_t i = 1; i + 1 < size; ++i) add(loop[r], loop[(r + i) % size], loop[(r + i + 1) % size]);
  } else {
    loop_edges.centred = true;
    for (std::size_t i = 0; i < size; ++i) add(loop_centre + l, loop[i], loop[(i + 1) % size]);
  }
}

// A configuration's case, in the three steps of the header: join the
// crossings on each face, chain the segments into loops, cut the loops into
// triangles.
CubeCase build_case(unsigned config) {
  Successors next;
  next.fill(-1);
  for (int a = 0; a < 3; ++a)
    for (int s = 0; s < 2; ++s) join_face(config, a, s, next);
  CubeCase result;
  for (const std::vector<int>& loop : chain_loops(next)) triangulate(loop, result);
  return result;
}

std::array<CubeCase, 256> build_table() {
  std::array<CubeCase, 256> table;
  for (unsigned config = 0; config < 256; ++config) table[config] = build_case(config);
  return table;
}

}  // namespace

int edge_axis(int e) { return e / 4; }

std::array<int, 2> edge_corners(int e) {
  const int axis = e / 4, j = e % 4;
  return {corner_of(axis, j, 0), corner_of(axis, j, 1)};
}

const CubeCase& cube_case(unsigned configuration) {
  static const std::array<CubeCase, 256> table = build_table();
  return table[configuration & 255u];
}

}  // namespace recon::mc
