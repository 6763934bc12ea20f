// Phase VI, simplification: what phase V found stays (creases, corners,
// boundary loops, separate objects), the error bound holds, the queues agree.
#include "recon/phase6_simplify/simplification.h"

#include "mesh_compare.h"
#include "recon/core/errors.h"
#include "recon/core/parallel.h"
#include "recon/core/shapes.h"
#include "recon/phase6_simplify/detail/simplify_plain.h"
#include "recon/reconstruct.h"
#include "recon/structures/mesh.h"

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <numeric>
#include <random>
#include <set>
#include <string>
#include <tuple>
#include <vector>

namespace recon {
namespace {

// ---- small meshes with a known truth ----

// A box [-1, 1]^3 with an n x n grid on each face, vertices shared.
Mesh grid_box(int n) {
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
Mesh lat_long(int rings, int sectors, bool upper_half, double centre_x = 0.0, double radius = 1.0) {
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

Mesh joined(const Mesh& a, const Mesh& b) {
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
std::map<std::uint64_t, std::vector<std::size_t>> edge_faces(const Mesh& m) {
  std::map<std::uint64_t, std::vector<std::size_t>> faces;
  for (std::size_t f = 0; f < m.triangles.size(); ++f)
    for (std::size_t e = 0; e < 3; ++e) faces[edge_key(m.triangles[f][e], m.triangles[f][(e + 1) % 3])].push_back(f);
  return faces;
}

Vec3 unit_normal(const Mesh& m, std::size_t f) {
  const auto& t = m.triangles[f];
  return (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]).normalized();
}

Features features(const Mesh& m) {
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

SimplifyOptions to_ratio(double ratio) {
  SimplifyOptions o;
  o.ratio = ratio;
  return o;
}

SimplifyOptions as_far_as_it_goes() {
  SimplifyOptions o;
  o.target_triangles = 1;
  return o;
}

SimplifyOptions in_blocks(SimplifyOptions o, std::size_t blocks) {
  o.block_vertices = blocks;
  return o;
}

double segment_distance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (p - (a + t * ab)).norm();
}

// One queue over the whole mesh, and rounds of blocks (simplification.h)
// so small that most vertices lie on a seam: what one keeps, the other
// must keep too.
constexpr std::array<std::size_t, 2> block_sizes{0, 64};

// ---- tests ----

// The box keeps its eight corners and nothing else: two triangles a face.
TEST(Simplification, BoxBecomesTwelveTrianglesOnItsCorners) {
  const Mesh box = grid_box(8);
  for (const std::size_t blocks : block_sizes) {
    SCOPED_TRACE("blocks of " + std::to_string(blocks));
    const Simplification s = simplify(box, in_blocks(as_far_as_it_goes(), blocks));
    EXPECT_EQ(s.mesh.triangles.size(), 12u);
    EXPECT_EQ(s.mesh.vertices.size(), 8u);
    for (const Vec3& v : s.mesh.vertices) EXPECT_DOUBLE_EQ(v.cwiseAbs().minCoeff(), 1.0) << v.transpose();
    const MeshTopology t = analyze_topology(s.mesh);
    EXPECT_TRUE(t.watertight());
    EXPECT_EQ(t.degenerate_triangles, 0u);
    EXPECT_NEAR(t.signed_volume, 8.0, 1e-12);
    EXPECT_EQ(s.corner_vertices, 8u);
  }
}

void expect_crease_vertices_on_the_edges(const Mesh& box, const Features& before, const Simplification& s);

// At a tenth of its triangles the box's crease vertices that survive are on
// its edges, every corner is there, and its faces are flat.
TEST(Simplification, BoxCreaseVerticesStayOnTheEdges) {
  const Mesh box = grid_box(12);
  const Features before = features(box);
  for (const std::size_t blocks : block_sizes) {
    SCOPED_TRACE("blocks of " + std::to_string(blocks));
    expect_crease_vertices_on_the_edges(box, before, simplify(box, in_blocks(to_ratio(0.1), blocks)));
  }
}

void expect_crease_vertices_on_the_edges(const Mesh& box, const Features& before, const Simplification& s) {
  EXPECT_LE(s.mesh.triangles.size(), box.triangles.size() / 10);
  const Features after = features(s.mesh);
  EXPECT_EQ(after.corners, before.corners);
  for (std::size_t v = 0; v < s.mesh.vertices.size(); ++v) {
    const Vec3 a = s.mesh.vertices[v].cwiseAbs();
    const int at_one = (a.x() == 1.0) + (a.y() == 1.0) + (a.z() == 1.0);
    EXPECT_GE(at_one, 1) << "off the box";
    if (after.on[v] == 2) {
      EXPECT_GE(at_one, 2) << "a crease vertex off the box's edges";
    }
  }
  EXPECT_NEAR(analyze_topology(s.mesh).signed_volume, 8.0, 1e-12);
}

void expect_one_round_rim(const Mesh& dome, const Simplification& s, std::size_t least, double farthest);

// An open hemisphere: one boundary loop before and after, every boundary
// vertex on the original circle, and the boundary polygon close to it.
TEST(Simplification, HemisphereKeepsItsBoundaryLoop) {
  const Mesh dome = lat_long(40, 64, true);
  // One queue keeps 21 rim vertices, the farthest input rim vertex 0.019
  // from the new rim; rounds of 64-vertex blocks, which make their
  // collapses in another order, 18 and 0.029. (Here the dome's curvature
  // keeps the rim: without the boundary planes, 20 and 0.019. The planes
  // are held by BoundaryPlanesKeepAWavyRimsShape.)
  const std::array<std::tuple<std::size_t, std::size_t, double>, 2> cases{{{0, 21, 0.02}, {64, 16, 0.03}}};
  for (const auto& [blocks, least, farthest] : cases) {
    SCOPED_TRACE("blocks of " + std::to_string(blocks));
    expect_one_round_rim(dome, simplify(dome, in_blocks(to_ratio(0.1), blocks)), least, farthest);
  }
}

// The largest distance from the input's rim vertices (z = 0) to the rim of `s`.
double rim_distance(const Mesh& dome, const Mesh& s) {
  const auto rim = boundary_edges(s);
  double far = 0.0;
  for (const Vec3& p : dome.vertices) {
    if (std::abs(p.z()) > 1e-12) continue;  // not on the rim (cos(pi / 2) is not 0 in doubles)
    double d = std::numeric_limits<double>::infinity();
    for (const auto& e : rim) d = std::min(d, segment_distance(p, s.vertices[e[0]], s.vertices[e[1]]));
    far = std::max(far, d);
  }
  return far;
}

void expect_one_round_rim(const Mesh& dome, const Simplification& s, std::size_t least, double farthest) {
  const MeshTopology t = analyze_topology(s.mesh);
  EXPECT_LE(s.mesh.triangles.size(), dome.triangles.size() / 10 + 1);
  EXPECT_EQ(t.boundary_loops, 1u);
  EXPECT_EQ(t.non_manifold_edges, 0u);
  EXPECT_EQ(t.euler_characteristic, 1);
  const auto rim = boundary_edges(s.mesh);
  for (const auto& e : rim) EXPECT_NEAR(s.mesh.vertices[e[0]].z(), 0.0, 1e-12);
  // The polygon's sag from the circle: 1 - cos(pi / n) for n sides.
  EXPECT_GE(rim.size(), least);
  EXPECT_LE(rim_distance(dome, s.mesh), farthest);
}

// Separate objects stay separate, each keeps its genus, no edge turns
// non-manifold, however far it goes.
TEST(Simplification, SeparateObjectsStaySeparateAndKeepTheirGenus) {
  const Mesh two = joined(lat_long(20, 30, false), lat_long(20, 30, false, 2.05));
  for (const std::size_t blocks : block_sizes) {
    SCOPED_TRACE("blocks of " + std::to_string(blocks));
    const Simplification s = simplify(two, in_blocks(as_far_as_it_goes(), blocks));
    const MeshTopology t = analyze_topology(s.mesh);
    EXPECT_EQ(t.components, 2u);
    EXPECT_TRUE(t.watertight());
    EXPECT_EQ(t.degenerate_triangles, 0u);
    for (const auto& c : t.component_list) {
      EXPECT_EQ(c.euler_characteristic, 2);
      EXPECT_GE(c.triangles, 4u);
    }
  }
}

// A torus as a grid of rings: its hole stays however far it goes (the link
// condition refuses the collapses that would pinch the handle).
Mesh grid_torus(int rings, int sectors) {
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

TEST(Simplification, TorusKeepsItsHole) {
  // Thin ones too: a tube of three sides, a ring of three sections, where
  // collapses would glue sheets (every edge has a third shared neighbour).
  for (const auto& [rings, sectors] : {std::pair{40, 16}, std::pair{30, 3}, std::pair{3, 16}, std::pair{4, 4}}) {
    const Mesh torus = grid_torus(rings, sectors);
    for (const std::size_t blocks : block_sizes) {
      const Simplification s = simplify(torus, in_blocks(as_far_as_it_goes(), blocks));
      const MeshTopology t = analyze_topology(s.mesh);
      EXPECT_EQ(t.euler_characteristic, 0) << rings << " x " << sectors << ", blocks of " << blocks;
      EXPECT_EQ(t.non_manifold_edges, 0u) << rings << " x " << sectors << ", blocks of " << blocks;
      EXPECT_TRUE(t.watertight()) << rings << " x " << sectors << ", blocks of " << blocks;
      EXPECT_EQ(t.degenerate_triangles, 0u) << rings << " x " << sectors << ", blocks of " << blocks;
    }
  }
}

// Every input vertex lies within max_error of the simplified mesh.
TEST(Simplification, ErrorBoundHolds) {
  const Mesh dome = lat_long(40, 64, true);
  for (const double bound : {0.002, 0.02}) {
    SimplifyOptions o;
    o.max_error = bound;
    o.block_vertices = bound > 0.01 ? 64 : 0;  // in blocks too
    const Simplification s = simplify(dome, o);
    EXPECT_LT(s.mesh.triangles.size(), dome.triangles.size() * 4 / 5) << bound;
    double worst = 0.0;
    for (const Vec3& v : dome.vertices) worst = std::max(worst, brute_force_distance(v, s.mesh));
    EXPECT_LE(worst, bound);
    EXPECT_LE(worst, s.vertex_error + 1e-15);
    EXPECT_LE(s.vertex_error, bound);
  }
}

// The three queues make the same collapses: the same mesh.
TEST(Simplification, QueuesGiveTheSameMesh) {
  const Mesh two = joined(lat_long(30, 40, true), grid_box(6));
  for (const std::size_t blocks : block_sizes) {
    SimplifyOptions o = to_ratio(0.15);
    o.max_error = 0.01;
    o.block_vertices = blocks;
    const Simplification heap = simplify(two, o);
    for (const SimplifyQueue q : {SimplifyQueue::pairing_heap, SimplifyQueue::lazy}) {
      o.queue = q;
      const Simplification other = simplify(two, o);
      EXPECT_EQ(other.mesh.triangles, heap.mesh.triangles) << "blocks of " << blocks;
      EXPECT_EQ(other.mesh.vertices, heap.mesh.vertices) << "blocks of " << blocks;
      EXPECT_EQ(other.collapses, heap.collapses) << "blocks of " << blocks;
    }
  }
}

TEST(Simplification, RefusesBadTargets) {
  const Mesh box = grid_box(2);
  const auto refuses = [&](SimplifyOptions o) { EXPECT_THROW((void)simplify(box, o), InvalidInputError); };
  refuses({});
  SimplifyOptions o;
  o.target_triangles = box.triangles.size() + 1;
  refuses(o);
  for (const double r : {-0.5, 1.0, 1.5, std::numeric_limits<double>::quiet_NaN()}) refuses(to_ratio(r));
  for (const double e : {-1.0, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    SimplifyOptions b;
    b.max_error = e;
    refuses(b);
  }
  Mesh bad = box;
  bad.triangles[0][1] = 99;
  EXPECT_THROW((void)simplify(bad, to_ratio(0.5)), InvalidInputError);
  // reconstruct() refuses a bad phase VI request before phase I (NaN
  // included, without an ordered comparison the sanitizer build would trap).
  const PointCloud cloud = make_shape("sphere")->sample(500, 1);
  for (const double r : {-0.5, 1.0, std::numeric_limits<double>::quiet_NaN()}) {
    ReconstructionOptions options;
    options.simplify.ratio = r;
    EXPECT_THROW((void)reconstruct(cloud, options), InvalidInputError) << r;
  }
  for (const double e : {-1.0, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    ReconstructionOptions options;
    options.simplify.ratio = 0.5;
    options.simplify.max_error = e;
    EXPECT_THROW((void)reconstruct(cloud, options), InvalidInputError) << e;
  }
}

// Colours travel with their vertices.
TEST(Simplification, ColoursStayWithTheirVertices) {
  Mesh dome = lat_long(20, 24, true);
  for (const Vec3& v : dome.vertices)
    dome.colors.push_back({static_cast<std::uint8_t>(100 + 100 * v.x()), static_cast<std::uint8_t>(100 + 100 * v.y()),
                           static_cast<std::uint8_t>(200 * v.z())});
  const Simplification s = simplify(dome, to_ratio(0.2));
  ASSERT_EQ(s.mesh.colors.size(), s.mesh.vertices.size());
  for (std::size_t i = 0; i < s.mesh.vertices.size(); ++i) {
    const Vec3& v = s.mesh.vertices[i];
    EXPECT_EQ(s.mesh.colors[i][0], static_cast<std::uint8_t>(100 + 100 * v.x()));
  }
}

// Phase VI after phase V on the fandisk-like part: a tenth of the triangles,
// the same topology, every sharp edge left (over 60 degrees) between
// vertices that lay on phase V's creases (over 25 degrees) at exactly their
// places; and the same mesh for 1 and 4 threads.
TEST(Simplification, PartKeepsItsCreasesForAnyThreadCount) {
  PointCloud cloud = make_shape("part")->sample(20000, 3);
  cloud.normals.clear();
  ReconstructionOptions options;
  options.simplify.ratio = 0.1;
  const int threads = thread_count();
  set_thread_count(1);
  const Reconstruction one = reconstruct(cloud, options);
  set_thread_count(4);
  const Reconstruction four = reconstruct(cloud, options);
  set_thread_count(threads);
  EXPECT_TRUE(one.mesh().vertices == four.mesh().vertices);
  EXPECT_TRUE(one.mesh().triangles == four.mesh().triangles);

  ASSERT_TRUE(one.refinement && one.simplification);
  const Mesh& before = one.refinement->mesh;
  const Mesh& after = one.mesh();
  EXPECT_LE(after.triangles.size(), before.triangles.size() / 10 + 1);
  const MeshTopology tb = analyze_topology(before), ta = analyze_topology(after);
  EXPECT_EQ(ta.components, tb.components);
  EXPECT_EQ(ta.euler_characteristic, tb.euler_characteristic);
  EXPECT_TRUE(ta.watertight());
  EXPECT_EQ(ta.degenerate_triangles, 0u);

  const Features creases = features(before);
  std::set<std::array<double, 3>> on_crease;
  for (std::size_t v = 0; v < before.vertices.size(); ++v)
    if (creases.on[v] > 0) on_crease.insert({before.vertices[v].x(), before.vertices[v].y(), before.vertices[v].z()});
  const auto normal = [&](std::size_t f) { return unit_normal(after, f); };
  std::size_t sharp = 0, off = 0;
  for (const auto& [key, list] : edge_faces(after)) {
    if (list.size() != 2 || normal(list[0]).dot(normal(list[1])) > 0.5) continue;
    ++sharp;
    for (const std::uint64_t v : {key >> 32, key & 0xffffffffu}) {
      const Vec3& p = after.vertices[v];
      const bool missing = on_crease.count({p.x(), p.y(), p.z()}) == 0;
      off += missing;
      if (missing) ADD_FAILURE() << "cos " << normal(list[0]).dot(normal(list[1])) << " at " << p.transpose();
    }
  }
  EXPECT_GT(sharp, 100u);
  EXPECT_EQ(off, 0u) << "ends of sharp edges that were not on phase V's creases";
}

// The result depends on the triangles, not on how the vertices are
// numbered (a tiled run's stitch numbers them otherwise than the run in
// memory): the grid box, all ties, and the hemisphere, renumbered at random
// and their triangles shuffled and rotated, give the same mesh.
Mesh renumbered(const Mesh& m, std::uint32_t seed) {
  std::vector<std::uint32_t> order(m.vertices.size());
  std::iota(order.begin(), order.end(), 0U);
  std::mt19937 random(seed);
  std::shuffle(order.begin(), order.end(), random);
  Mesh out;
  std::vector<std::uint32_t> to(order.size());
  for (std::uint32_t i = 0; i < order.size(); ++i) {
    to[order[i]] = i;
    out.vertices.push_back(m.vertices[order[i]]);
  }
  for (const auto& t : m.triangles) {
    std::array<std::uint32_t, 3> r{to[t[0]], to[t[1]], to[t[2]]};
    std::rotate(r.begin(), r.begin() + random() % 3, r.end());
    out.triangles.push_back(r);
  }
  std::shuffle(out.triangles.begin(), out.triangles.end(), random);
  return out;
}

// Two copies of a mesh a nanometre apart: every vertex has a twin in its
// Z-order cell (2^21 a side), so only the sort by coordinates before the
// Z-order tells the two apart (coincident twins could not be told apart
// by position at all).
Mesh twice_in_place(const Mesh& m) {
  Mesh out = m;
  const auto n = static_cast<std::uint32_t>(m.vertices.size());
  for (const Vec3& p : m.vertices) out.vertices.push_back(p + Vec3(1e-9, 1e-9, 1e-9));
  for (const auto& t : m.triangles) out.triangles.push_back({t[0] + n, t[1] + n, t[2] + n});
  return out;
}

TEST(Simplification, TheNumberingOfTheVerticesDoesNotMatter) {
  for (const Mesh& mesh : {grid_box(12), lat_long(16, 32, true), twice_in_place(grid_box(6))}) {
    SimplifyOptions options;
    options.ratio = 0.2;
    const Mesh once = simplify(mesh, options).mesh;
    for (const std::uint32_t seed : {1U, 2U}) {
      const Mesh again = simplify(renumbered(mesh, seed), options).mesh;
      EXPECT_EQ(again.vertices, once.vertices) << seed;
      EXPECT_EQ(again.triangles, once.triangles) << seed;
    }
  }
}

// ---- the fast loop against the plain one (detail/simplify_plain.h) ----

// Phase V's mesh of a generated shape, small enough for a test.
Mesh phase_5_mesh(const char* shape, std::size_t n) {
  PointCloud cloud = make_shape(shape)->sample(n, 5);
  cloud.normals.clear();
  return reconstruct(cloud, ReconstructionOptions{}).mesh();
}

void expect_same_as_plain(const Mesh& mesh, const SimplifyOptions& options, const char* name) {
  const Simplification plain = detail::simplify_plain(mesh, options);
  ASSERT_LT(plain.mesh.triangles.size(), mesh.triangles.size()) << name;
  for (const int threads : {1, 2}) {
    const int before = thread_count();
    set_thread_count(threads);
    const Simplification fast = simplify(mesh, options);
    set_thread_count(before);
    EXPECT_TRUE(fast.mesh.triangles == plain.mesh.triangles) << name << ", " << threads << " threads";
    EXPECT_TRUE(fast.mesh.vertices == plain.mesh.vertices) << name << ", " << threads << " threads";
    EXPECT_EQ(fast.collapses, plain.collapses) << name;
    EXPECT_EQ(fast.refused, plain.refused) << name;
  }
}

// simplify() caches each vertex's cheapest move and skips unchanged keys;
// the plain loop recomputes everything. Triangle for triangle the same,
// on meshes with creases, corners, a boundary, two objects and a handle,
// to a ratio, to the end and under an error bound.
TEST(Simplification, FastLoopGivesThePlainLoopsMesh) {
  SimplifyOptions to_the_end;
  to_the_end.target_triangles = 1;
  SimplifyOptions bounded = to_ratio(0.1);
  bounded.max_error = 0.004;
  expect_same_as_plain(grid_box(10), to_ratio(0.1), "box");
  expect_same_as_plain(grid_box(6), to_the_end, "box to the end");
  expect_same_as_plain(lat_long(30, 48, true), to_ratio(0.1), "hemisphere");
  expect_same_as_plain(lat_long(30, 48, true), bounded, "hemisphere, bounded");
  expect_same_as_plain(joined(lat_long(16, 24, false), grid_torus(24, 10)), to_the_end, "sphere and torus");
  expect_same_as_plain(phase_5_mesh("part", 6000), to_ratio(0.1), "part");
  expect_same_as_plain(phase_5_mesh("terrain", 4000), to_ratio(0.1), "terrain");
  // In rounds of blocks (the plain loop runs the blocks one after another,
  // the fast one on all threads).
  expect_same_as_plain(grid_box(6), in_blocks(to_the_end, 40), "box to the end, in blocks");
  expect_same_as_plain(lat_long(30, 48, true), in_blocks(bounded, 100), "hemisphere, bounded, in blocks");
  expect_same_as_plain(joined(lat_long(16, 24, false), grid_torus(24, 10)), in_blocks(to_the_end, 64),
                       "sphere and torus, in blocks");
  expect_same_as_plain(phase_5_mesh("part", 6000), in_blocks(to_ratio(0.1), 256), "part, in blocks");
}

// ---- the rounds ----

// The edges' lengths, each edge once.
std::vector<double> edge_lengths(const Mesh& m) {
  std::set<std::uint64_t> seen;
  std::vector<double> out;
  for (const auto& t : m.triangles)
    for (std::size_t e = 0; e < 3; ++e)
      if (seen.insert(edge_key(t[e], t[(e + 1) % 3])).second)
        out.push_back((m.vertices[t[e]] - m.vertices[t[(e + 1) % 3]]).norm());
  return out;
}

// The share of edges shorter than half the mean.
double short_edge_share(const Mesh& m) {
  const std::vector<double> lengths = edge_lengths(m);
  const double mean = std::accumulate(lengths.begin(), lengths.end(), 0.0) / static_cast<double>(lengths.size());
  return static_cast<double>(std::count_if(lengths.begin(), lengths.end(), [&](double l) { return l < 0.5 * mean; })) /
         static_cast<double>(lengths.size());
}

// In rounds of blocks the seams between the blocks are simplified like the
// rest: the same triangle count as one queue over the whole mesh, as few
// short edges, the input as close. A seam left whole would be a line of
// the input's short edges through the result.
TEST(Simplification, SeamsAreSimplifiedLikeTheRest) {
  const Mesh torus = grid_torus(240, 60);  // 14,400 vertices: 15 blocks
  const Simplification a = simplify(torus, in_blocks(to_ratio(0.1), 0));
  const Simplification b = simplify(torus, in_blocks(to_ratio(0.1), 1000));
  EXPECT_NE(a.mesh.triangles, b.mesh.triangles) << "the rounds did not run";
  EXPECT_EQ(b.mesh.triangles.size(), a.mesh.triangles.size());
  const double short_a = short_edge_share(a.mesh), short_b = short_edge_share(b.mesh);
  EXPECT_LE(short_b, 1.5 * short_a + 0.01) << short_a;
  double far_a = 0.0, far_b = 0.0;
  for (std::size_t v = 0; v < torus.vertices.size(); v += 7) {
    far_a = std::max(far_a, brute_force_distance(torus.vertices[v], a.mesh));
    far_b = std::max(far_b, brute_force_distance(torus.vertices[v], b.mesh));
  }
  EXPECT_LE(far_b, 1.5 * far_a) << far_a;
}

// Rounds never pass the target, even where every move costs the same: on
// the box's flat, regular faces all moves tie, so a round's limit lets
// every vertex move, and only each block's share of the collapses asked
// for holds the round back.
TEST(Simplification, RoundsStopAtTheTarget) {
  const Mesh box = grid_box(40);  // 19,200 triangles, 9,602 vertices
  for (const double ratio : {0.9, 0.5, 0.1}) {
    SimplifyOptions o = to_ratio(ratio);
    o.block_vertices = 500;
    const Simplification s = simplify(box, o);
    const auto target = static_cast<std::size_t>(ratio * static_cast<double>(box.triangles.size()));
    EXPECT_LE(s.mesh.triangles.size(), target) << ratio;
    EXPECT_GE(s.mesh.triangles.size(), target - 1) << ratio;
  }
}

// ---- the boundary planes ----

// A flat disc whose rim waves in and out: rings of vertices at radius
// i / rings of r(phi) = 1 + 0.15 sin(5 phi), triangulated as lat_long.
Mesh wavy_disc(int rings, int sectors) {
  Mesh m;
  const auto at = [&](int i, int j) {
    const double phi = 2.0 * std::numbers::pi * j / sectors;
    const double r = (1.0 + 0.15 * std::sin(5.0 * phi)) * i / rings;
    return Vec3(r * std::cos(phi), r * std::sin(phi), 0.0);
  };
  m.vertices.push_back(Vec3::Zero());
  for (int i = 1; i <= rings; ++i)
    for (int j = 0; j < sectors; ++j) m.vertices.push_back(at(i, j));
  const auto id = [&](int i, int j) { return static_cast<std::uint32_t>(1 + (i - 1) * sectors + (j % sectors)); };
  for (int j = 0; j < sectors; ++j) m.triangles.push_back({0, id(1, j), id(1, j + 1)});
  for (int i = 1; i < rings; ++i)
    for (int j = 0; j < sectors; ++j) {
      m.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return m;
}

void expect_wavy_rim_kept(const Mesh& disc, const Simplification& s);

// On flat ground every move costs nothing but the short-edge tie-break;
// only the planes through the boundary edges make cutting across the
// rim's waves cost. With them, at a tenth of the triangles, the rim's
// vertices are input rim vertices and every input rim vertex stays within
// 0.01 of the new rim (measured: 0.0013 with the planes, the rim keeping
// 130 of its 160 vertices; 0.029 with them weighted 0, 41 left, the
// waves cut across).
TEST(Simplification, BoundaryPlanesKeepAWavyRimsShape) {
  const Mesh disc = wavy_disc(16, 160);
  for (const std::size_t blocks : block_sizes) {
    SCOPED_TRACE("blocks of " + std::to_string(blocks));
    expect_wavy_rim_kept(disc, simplify(disc, in_blocks(to_ratio(0.1), blocks)));
  }
}

void expect_wavy_rim_kept(const Mesh& disc, const Simplification& s) {
  ASSERT_LE(s.mesh.triangles.size(), disc.triangles.size() / 10 + 1);
  EXPECT_EQ(analyze_topology(s.mesh).boundary_loops, 1u);
  const auto rim_before = boundary_edges(disc);
  const auto rim_after = boundary_edges(s.mesh);
  std::set<std::array<double, 3>> input_rim;
  for (const auto& e : rim_before) input_rim.insert({disc.vertices[e[0]].x(), disc.vertices[e[0]].y(), 0.0});
  for (const auto& e : rim_after) {
    const Vec3& p = s.mesh.vertices[e[0]];
    EXPECT_EQ(input_rim.count({p.x(), p.y(), p.z()}), 1u)
        << "a rim vertex that was not on the input's rim: " << p.transpose();
  }
  double farthest = 0.0;
  for (const auto& e : rim_before) {
    double nearest = std::numeric_limits<double>::infinity();
    for (const auto& r : rim_after)
      nearest = std::min(nearest, segment_distance(disc.vertices[e[0]], s.mesh.vertices[r[0]], s.mesh.vertices[r[1]]));
    farthest = std::max(farthest, nearest);
  }
  EXPECT_LT(farthest, 0.01);
}

// ---- normals carried ----

// A surviving vertex keeps exactly the normal it came with.
TEST(Simplification, NormalsStayWithTheirVertices) {
  Mesh dome = lat_long(20, 24, true);
  for (const Vec3& v : dome.vertices) dome.normals.push_back(Vec3(v.y(), v.z() + 2.0, -v.x()));  // any, one per vertex
  const Simplification s = simplify(dome, to_ratio(0.2));
  ASSERT_EQ(s.mesh.normals.size(), s.mesh.vertices.size());
  ASSERT_LT(s.mesh.vertices.size(), dome.vertices.size());
  for (std::size_t i = 0; i < s.mesh.vertices.size(); ++i) {
    const Vec3& v = s.mesh.vertices[i];
    EXPECT_TRUE(s.mesh.normals[i] == Vec3(v.y(), v.z() + 2.0, -v.x())) << i;
  }
}

// reconstruct with vertex normals and simplification: one unit normal per
// vertex of the final mesh; where phase V fitted one at that vertex, that
// one, bit for bit; elsewhere the area-weighted mean of the FINAL mesh's
// triangles around it (not the unsimplified mesh's).
TEST(Simplification, VertexNormalsAfterSimplifyingAreFittedOrFromTheFinalFaces) {
  PointCloud cloud = make_shape("part")->sample(6000, 4);
  cloud.normals.clear();
  ReconstructionOptions options;
  options.simplify.ratio = 0.1;
  options.vertex_normals = true;
  const Reconstruction r = reconstruct(cloud, options);
  ASSERT_TRUE(r.refinement && r.simplification);
  const Mesh& before = r.refinement->mesh;
  const Mesh& after = r.mesh();
  ASSERT_EQ(after.normals.size(), after.vertices.size());
  ASSERT_EQ(before.normals.size(), before.vertices.size());
  std::map<std::array<double, 3>, Vec3> fitted;
  for (std::size_t v = 0; v < before.vertices.size(); ++v)
    fitted[{before.vertices[v].x(), before.vertices[v].y(), before.vertices[v].z()}] = before.normals[v];
  std::vector<Vec3> from_faces(after.vertices.size(), Vec3::Zero());
  for (const auto& t : after.triangles) {
    const Vec3 n = (after.vertices[t[1]] - after.vertices[t[0]]).cross(after.vertices[t[2]] - after.vertices[t[0]]);
    for (const std::uint32_t v : t) from_faces[v] += n;
  }
  std::size_t kept = 0, filled = 0;
  for (std::size_t v = 0; v < after.vertices.size(); ++v) {
    const Vec3& p = after.vertices[v];
    const Vec3& n = after.normals[v];
    EXPECT_NEAR(n.norm(), 1.0, 1e-12) << v;
    const auto source = fitted.find({p.x(), p.y(), p.z()});
    ASSERT_NE(source, fitted.end()) << "a vertex phase V did not have";
    if (source->second != Vec3::Zero()) {
      ++kept;
      EXPECT_TRUE(n == source->second) << v;
    } else {
      ++filled;
      EXPECT_LT((n - from_faces[v].normalized()).norm(), 1e-12) << v;
    }
  }
  // Both kinds are many (the test is not vacuous): at a tenth of this small
  // part about half the survivors are crease and corner vertices, which the
  // feature rules keep (147 of 296 fitted, measured).
  EXPECT_GT(kept, after.vertices.size() / 3);
  EXPECT_GT(filled, 10u);  // the part's crease vertices
}

// ---- phase V's meshes of creased shapes with known crease lines ----

// gen_synthetic.py's box (1 x 0.8 x 0.6, turned by Rz(35) Ry(15) Rx(25)
// degrees so that no edge follows the lattice), reconstructed from `n`
// samples: its edges are the twelve lines between the turned corners.
struct TurnedBox {
  Eigen::Matrix3d turn;
  Vec3 half{0.5, 0.4, 0.3};
  [[nodiscard]] Vec3 local(const Vec3& p) const { return turn.transpose() * p; }
  [[nodiscard]] double diagonal() const { return 2.0 * half.norm(); }
  // Distance to the surface, and to the nearest edge (both in the box's frame).
  [[nodiscard]] double to_surface(const Vec3& p) const {
    const Vec3 d = local(p).cwiseAbs() - half;
    return std::abs(d.cwiseMax(0.0).norm() + std::min(d.maxCoeff(), 0.0));
  }
  [[nodiscard]] double to_edge(const Vec3& p) const {
    Vec3 d = (local(p).cwiseAbs() - half).cwiseAbs();
    std::sort(d.data(), d.data() + 3);
    return std::hypot(d[0], d[1]);
  }
  [[nodiscard]] double to_corner(const Vec3& p) const { return (local(p).cwiseAbs() - half).norm(); }
};

TurnedBox turned_box() {
  const auto radians = [](double d) { return d * std::numbers::pi / 180.0; };
  TurnedBox box;
  box.turn = (Eigen::AngleAxisd(radians(35), Vec3::UnitZ()) * Eigen::AngleAxisd(radians(15), Vec3::UnitY()) *
              Eigen::AngleAxisd(radians(25), Vec3::UnitX()))
                 .toRotationMatrix();
  return box;
}

Reconstruction reconstructed_turned_box(const TurnedBox& box, std::size_t n, const SimplifyStep& simplify) {
  PointCloud cloud = make_box(2.0 * box.half)->sample(n, 1);
  for (Vec3& p : cloud.positions) p = box.turn * p;
  cloud.normals.clear();
  ReconstructionOptions options;
  options.simplify = simplify;
  return reconstruct(cloud, options);
}

// The ends of the output's sharp edges (dihedral over 25 degrees).
std::vector<std::uint32_t> crease_ends(const Mesh& m) {
  const Features f = features(m);
  std::vector<std::uint32_t> ends;
  for (std::uint32_t v = 0; v < m.vertices.size(); ++v)
    if (f.on[v] > 0) ends.push_back(v);
  return ends;
}

// Phase V's turned box asked for 12 triangles gives exactly the box: two
// triangles a face, on the eight vertices of phase V's mesh nearest the
// corners (phase V's own corner accuracy: up to 0.7 % of the diagonal off).
// Before, phase V's near-corner vertices and the fans it tilts with
// triangles across a crease made 32 "corners" (74 triangles).
TEST(Simplification, PhaseFiveBoxBecomesTwelveTrianglesOnItsCorners) {
  const TurnedBox box = turned_box();
  SimplifyStep twelve;
  twelve.triangles = 12;
  const Reconstruction r = reconstructed_turned_box(box, 20000, twelve);
  const Mesh& m = r.mesh();
  ASSERT_TRUE(r.refinement);
  std::set<std::array<double, 3>> nearest;  // per corner, phase V's vertex nearest it
  for (const int sx : {-1, 1})
    for (const int sy : {-1, 1})
      for (const int sz : {-1, 1}) {
        const Vec3 corner = box.turn * box.half.cwiseProduct(Vec3(sx, sy, sz));
        const auto& vs = r.refinement->mesh.vertices;
        const Vec3 v = *std::min_element(vs.begin(), vs.end(), [&](const Vec3& a, const Vec3& b) {
          return (a - corner).squaredNorm() < (b - corner).squaredNorm();
        });
        EXPECT_LT((v - corner).norm(), 0.01 * box.diagonal());
        nearest.insert({v.x(), v.y(), v.z()});
      }
  EXPECT_EQ(m.triangles.size(), 12u);
  EXPECT_EQ(m.vertices.size(), 8u);
  for (const Vec3& v : m.vertices) EXPECT_EQ(nearest.count({v.x(), v.y(), v.z()}), 1u) << v.transpose();
  const MeshTopology t = analyze_topology(m);
  EXPECT_TRUE(t.watertight());
  EXPECT_EQ(t.degenerate_triangles, 0u);
  EXPECT_NEAR(t.signed_volume, 0.48, 0.48 * 0.02);
  EXPECT_EQ(r.simplification->corner_vertices, 8u);
  // The crease rule holds the vertices phase V put on the edges: nearly all
  // of them move only along their edge (those left are next to gaps in
  // phase V's crease lines), and hardly any other.
  std::size_t on_edges = 0;
  for (const Vec3& v : r.refinement->mesh.vertices) on_edges += box.to_edge(v) < 1e-6 * box.diagonal();
  EXPECT_GT(r.simplification->crease_vertices, on_edges * 7 / 10) << on_edges << " on the edges";
  EXPECT_LT(r.simplification->crease_vertices, on_edges * 11 / 10) << on_edges << " on the edges";
}

// The fandisk-like part at a hundredth of phase V's triangles: every end of
// a sharp edge lies on one of the part's true creases (the slab's twelve
// edges, the holes' six rims), and every corner stays (phase V's vertex
// nearest it). Before, vertices of a hole's wall below its rim, taken for
// corners by their fans, stayed as ends of sharp edges (0.03 to 0.06 off).
TEST(Simplification, PartCreaseVerticesStayOnTheCreasesAtOneHundredth) {
  PointCloud cloud = make_shape("part")->sample(20000, 3);
  cloud.normals.clear();
  ReconstructionOptions options;
  options.simplify.ratio = 0.01;
  const Reconstruction r = reconstruct(cloud, options);
  ASSERT_TRUE(r.refinement);
  const Mesh& m = r.mesh();
  // The true creases: |x| = 1, |y| = 0.5, |z| = 0.2 two at a time, and the
  // circles of radius 0.18 about (-0.6, 0), (0, 0), (0.6, 0) at z = +-0.2.
  const Vec3 half(1.0, 0.5, 0.2);
  const auto to_crease = [&](const Vec3& p) {
    Vec3 d = (p.cwiseAbs() - half).cwiseAbs();
    std::sort(d.data(), d.data() + 3);
    double best = std::hypot(d[0], d[1]);
    for (const double x : {-0.6, 0.0, 0.6})
      best = std::min(best, std::hypot(std::hypot(p.x() - x, p.y()) - 0.18, std::abs(p.z()) - 0.2));
    return best;
  };
  const std::vector<std::uint32_t> ends = crease_ends(m);
  EXPECT_GT(ends.size(), 50u);
  for (const std::uint32_t v : ends) EXPECT_LT(to_crease(m.vertices[v]), 0.005) << m.vertices[v].transpose();
  std::set<std::array<double, 3>> kept;
  for (const Vec3& v : m.vertices) kept.insert({v.x(), v.y(), v.z()});
  for (const int sx : {-1, 1})
    for (const int sy : {-1, 1})
      for (const int sz : {-1, 1}) {
        const Vec3 corner = half.cwiseProduct(Vec3(sx, sy, sz));
        const auto& vs = r.refinement->mesh.vertices;
        const Vec3 v = *std::min_element(vs.begin(), vs.end(), [&](const Vec3& a, const Vec3& b) {
          return (a - corner).squaredNorm() < (b - corner).squaredNorm();
        });
        EXPECT_EQ(kept.count({v.x(), v.y(), v.z()}), 1u) << "lost the corner " << corner.transpose();
      }
  EXPECT_EQ(analyze_topology(m).euler_characteristic, -4);
}

}  // namespace
}  // namespace recon
