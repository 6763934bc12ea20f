#include "recon/structures/mesh_embedding.h"

#include "recon/core/errors.h"
#include "recon/core/fp_traps.h"
#include "recon/core/parallel.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

#ifdef RECON_HAVE_CGAL
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>
#endif

namespace recon {
namespace {

using Pairs = std::vector<std::array<std::uint32_t, 2>>;

Mesh mesh_of(std::vector<Vec3> vertices, std::vector<std::array<std::uint32_t, 3>> triangles) {
  Mesh m;
  m.vertices = std::move(vertices);
  m.triangles = std::move(triangles);
  return m;
}

// Unit cube, each face split in two, counter-clockwise from outside.
Mesh cube() {
  Mesh mesh;
  for (int i = 0; i < 8; ++i) mesh.vertices.emplace_back(i & 1, (i >> 1) & 1, (i >> 2) & 1);
  const std::array<std::array<std::uint32_t, 4>, 6> quads = {
      {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}}};
  for (const auto& q : quads) {
    mesh.triangles.push_back({q[0], q[1], q[2]});
    mesh.triangles.push_back({q[0], q[2], q[3]});
  }
  return mesh;
}

TEST(MeshEmbedding, ClosedMeshesAreEmbedded) {
  const MeshEmbedding e = check_embedding(cube());
  EXPECT_TRUE(e.embedded());
  EXPECT_EQ(e.intersecting_pairs, 0u);
  EXPECT_TRUE(check_embedding(Mesh{}).embedded());
}

// ---- Nothing shared ----
TEST(MeshEmbedding, DisjointTrianglesMeetAtAnyCommonPoint) {
  const std::vector<Vec3> base = {{0, 0, 0}, {4, 0, 0}, {0, 4, 0}};
  auto with = [&](Vec3 a, Vec3 b, Vec3 c) {
    std::vector<Vec3> v = base;
    v.insert(v.end(), {a, b, c});
    return check_embedding(mesh_of(v, {{0, 1, 2}, {3, 4, 5}})).intersecting_pairs;
  };
  EXPECT_EQ(with({1, 1, -1}, {1, 1, 1}, {2, 1, 1}), 1u);       // pierces the interior
  EXPECT_EQ(with({1, 1, 0}, {1, 1, 1}, {2, 1, 1}), 1u);        // a vertex touches the interior
  EXPECT_EQ(with({2, 2, 0}, {3, 3, 1}, {2, 3, 1}), 1u);        // a vertex touches the hypotenuse
  EXPECT_EQ(with({1, 1, 0}, {5, 1, 0}, {1, 5, 0}), 1u);        // coplanar overlap
  EXPECT_EQ(with({1, 1, 1e-9}, {1, 1, 1}, {2, 1, 1}), 0u);     // just above
  EXPECT_EQ(with({2.5, 2.5, 0}, {5, 5, 0}, {2.5, 5, 0}), 0u);  // coplanar, apart (just past the hypotenuse)
  EXPECT_EQ(with({2, 2, -1}, {2, 2, 1}, {9, 9, 0}), 1u);       // an edge through the hypotenuse
  EXPECT_EQ(with({0, 0, 0}, {-1, 0, 1}, {0, -1, 1}), 1u);      // a coincident vertex (other index)
  const double above = std::nextafter(0.0, 1.0) * 0x1p1000;    // the least step above 0 in range
  EXPECT_EQ(with({1, 1, above}, {1, 1, 1}, {2, 1, 1}), 0u);
}

// ---- A shared edge ----
TEST(MeshEmbedding, SharedEdgeMeetsOnlyWhenFolded) {
  auto pair = [](Vec3 b) {
    return check_embedding(mesh_of({{0, 0, 0}, {2, 0, 0}, {1, 1, 0}, b}, {{0, 1, 2}, {1, 0, 3}})).intersecting_pairs;
  };
  EXPECT_EQ(pair({1, -1, 0}), 0u);       // coplanar, across: a flat pair
  EXPECT_EQ(pair({1, -1, 0.5}), 0u);     // bent
  EXPECT_EQ(pair({1, 2, 0}), 1u);        // coplanar, the same side: folded onto each other
  EXPECT_EQ(pair({5, 0.1, 0}), 1u);      // a sliver fold
  EXPECT_EQ(pair({1, 0.5, 1e-12}), 0u);  // nearly folded, not quite
}

// ---- A shared vertex ----
TEST(MeshEmbedding, SharedVertexMeetsOnlyElsewhere) {
  auto pair = [](Vec3 b1, Vec3 b2) {
    return check_embedding(mesh_of({{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, b1, b2}, {{0, 1, 2}, {0, 3, 4}}))
        .intersecting_pairs;
  };
  EXPECT_EQ(pair({-1, 0, 1}, {0, -1, 1}), 0u);           // only the vertex
  EXPECT_EQ(pair({-2, 0, 0}, {0, -2, 0}), 0u);           // coplanar, opposite wedges
  EXPECT_EQ(pair({1, 1, 0}, {3, 1, 0}), 1u);             // coplanar, overlapping
  EXPECT_EQ(pair({1, 0.5, 0}, {1, 0.5, 1}), 1u);         // an edge from the vertex along the other's face
  EXPECT_EQ(pair({2, 0, 0}, {0, 0, 3}), 1u);             // an edge from the vertex along the other's edge
  EXPECT_EQ(pair({-1, 0, 0}, {0, 0, 3}), 0u);            // along the edge's line, the other way
  EXPECT_EQ(pair({1, 1, -1}, {1, 1, 1}), 1u);            // the opposite edge pierces the face
  EXPECT_EQ(pair({1.5, 0.25, -1}, {0.5, 0.25, 1}), 1u);  // again, nearer an edge
  EXPECT_EQ(pair({0.5, 0.5, -1}, {-1, -1, 1}), 0u);      // passes beside the vertex, outside
}

// ---- Topology ----
TEST(MeshEmbedding, PinchedVerticesAndNonManifoldEdges) {
  // A bow tie: two triangles sharing only vertex 0.
  const MeshEmbedding bow =
      check_embedding(mesh_of({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}}, {{0, 1, 2}, {0, 3, 4}}));
  EXPECT_EQ(bow.non_manifold_vertices, 1u);
  EXPECT_EQ(bow.pinched, std::vector<std::uint32_t>{0});
  EXPECT_EQ(bow.intersecting_pairs, 0u);
  EXPECT_FALSE(bow.embedded());
  // A fan closing around its vertex is one fan; an open fan is one fan.
  const MeshEmbedding fan =
      check_embedding(mesh_of({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}}, {{0, 1, 2}, {0, 2, 3}}));
  EXPECT_EQ(fan.non_manifold_vertices, 0u);
  // Three triangles on one edge.
  const MeshEmbedding three = check_embedding(
      mesh_of({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}}, {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}}));
  EXPECT_EQ(three.non_manifold_edges, 1u);
}

TEST(MeshEmbedding, DegenerateTrianglesAreCountedAndSkipped) {
  const MeshEmbedding e =
      check_embedding(mesh_of({{0, 0, 0}, {1, 1, 1}, {3, 3, 3}, {0, 0, 1}}, {{0, 1, 2}, {0, 1, 1}, {0, 1, 3}}));
  EXPECT_EQ(e.degenerate_triangles, 2u);  // collinear, a repeated index
  EXPECT_EQ(e.intersecting_pairs, 0u);
  // One ulp off the line is not degenerate.
  const MeshEmbedding off =
      check_embedding(mesh_of({{0, 0, 0}, {1, 1, 1}, {3, 3, std::nextafter(3.0, 4.0)}}, {{0, 1, 2}}));
  EXPECT_EQ(off.degenerate_triangles, 0u);
}

TEST(MeshEmbedding, BadInputIsRefused) {
  EXPECT_THROW((void)check_embedding(mesh_of({{0, 0, 0}}, {{0, 0, 1}})), InvalidInputError);
  EXPECT_THROW((void)check_embedding(mesh_of({{0, 0, 0}, {1, 0, 0}, {0, 1e300, 0}}, {{0, 1, 2}})), InvalidInputError);
  // An unused vertex out of range does not matter.
  EXPECT_NO_THROW((void)check_embedding(mesh_of({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1e300, 0, 0}}, {{0, 1, 2}})));
}

// ---- Random meshes with planted crossings, folds and touching ----

// Patches of a height field on a small integer grid (heights 0 to 2),
// each turned (its axes permuted) and shifted by an integer offset in a
// small box, so that they cross, touch and lie in one plane often; in some,
// a vertex moved within its flat patch folds its triangles.
Mesh random_patches(std::uint64_t seed, int patches = 4, int box = 3) {
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> height(0, 2), offset(0, box), flat(0, 2), axes(0, 2), coin(0, 1);
  Mesh mesh;
  for (int p = 0; p < patches; ++p) {
    const int n = 4;
    const bool is_flat = flat(rng) == 0;
    const int turn = axes(rng);
    const Vec3 shift(offset(rng), offset(rng), offset(rng));
    const auto first = static_cast<std::uint32_t>(mesh.vertices.size());
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        Vec3 q(i, j, is_flat ? 0 : height(rng));
        Vec3 r;
        for (int k = 0; k < 3; ++k) r[(k + turn) % 3] = q[k];
        mesh.vertices.push_back(r + shift);
      }
    if (is_flat && coin(rng)) {  // fold: an inner vertex pushed across a neighbour, within the plane
      Vec3& v = mesh.vertices[first + 1 + n];
      const Vec3 along = mesh.vertices[first + 3 + n] - mesh.vertices[first + 1 + n];
      v += along * 0.75;
    }
    for (int j = 0; j + 1 < n; ++j)
      for (int i = 0; i + 1 < n; ++i) {
        const std::uint32_t a = first + static_cast<std::uint32_t>(j * n + i), b = a + 1, c = a + n, d = c + 1;
        mesh.triangles.push_back({a, b, d});
        mesh.triangles.push_back({a, d, c});
      }
  }
  return mesh;
}

TEST(MeshEmbedding, SameForEveryThreadCount) {
  const Mesh m = random_patches(3, 3000, 60);  // (thousands of cells: many blocks)
  const int before = thread_count();
  set_thread_count(1);
  const MeshEmbedding one = check_embedding(m);
  set_thread_count(4);
  const MeshEmbedding four = check_embedding(m);
  set_thread_count(before);
  EXPECT_EQ(one.pairs, four.pairs);
  EXPECT_GT(one.intersecting_pairs, 0u);
}

// The candidate grid misses nothing: every pair tested directly gives the same list.
TEST(MeshEmbedding, GridAgreesWithAllPairs) {
  for (std::uint64_t seed = 0; seed < 40; ++seed) {
    const Mesh m = random_patches(seed);
    Pairs all;
    for (std::uint32_t a = 0; a < m.triangles.size(); ++a)
      for (std::uint32_t b = a + 1; b < m.triangles.size(); ++b)
        if (triangles_intersect(m, a, b)) all.push_back({a, b});
    EXPECT_EQ(check_embedding(m).pairs, all) << seed;
  }
}

#ifdef RECON_HAVE_CGAL
// CGAL's exact kernel and Polygon_mesh_processing::self_intersections, the
// oracle: the same pairs on the random patches. (Traps off around it: CGAL's
// interval filters compute with infinities on purpose.)
Pairs cgal_pairs(const Mesh& m) {
  using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
  using SurfaceMesh = CGAL::Surface_mesh<Kernel::Point_3>;
  SurfaceMesh s;
  std::vector<SurfaceMesh::Vertex_index> v;
  for (const Vec3& p : m.vertices) v.push_back(s.add_vertex(Kernel::Point_3(p.x(), p.y(), p.z())));
  for (const auto& t : m.triangles) {
    const auto f = s.add_face(v[t[0]], v[t[1]], v[t[2]]);
    if (f == SurfaceMesh::null_face()) ADD_FAILURE() << "CGAL refused a face";
  }
  std::vector<std::pair<SurfaceMesh::Face_index, SurfaceMesh::Face_index>> found;
  CGAL::Polygon_mesh_processing::self_intersections(s, std::back_inserter(found));
  Pairs pairs;
  for (const auto& [a, b] : found) {
    const auto i = static_cast<std::uint32_t>(a.idx()), j = static_cast<std::uint32_t>(b.idx());
    pairs.push_back({std::min(i, j), std::max(i, j)});
  }
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

TEST(MeshEmbedding, AgreesWithCgalOnRandomPatches) {
  const bool traps = fp_traps_enabled();
  std::size_t crossings = 0, compared = 0;
  for (std::uint64_t seed = 0; seed < 60; ++seed) {
    const Mesh m = random_patches(seed);
    const MeshEmbedding e = check_embedding(m);
    if (e.degenerate_triangles > 0) continue;  // (CGAL's precondition)
    set_fp_traps(false);
    const Pairs oracle = cgal_pairs(m);
    set_fp_traps(traps);
    ASSERT_EQ(e.pairs, oracle) << "seed " << seed;
    crossings += oracle.size();
    ++compared;
  }
  EXPECT_GT(compared, 45u);
  EXPECT_GT(crossings, 150u);
}
#endif

}  // namespace
}  // namespace recon
