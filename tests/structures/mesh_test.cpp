#include "recon/structures/mesh.h"

#include "recon/core/errors.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>
#include <ostream>
#include <random>

namespace recon {
namespace {

using Triangle = std::array<std::uint32_t, 3>;

// Unit right-angled tetrahedron, faces counter-clockwise seen from outside.
Mesh tetrahedron(const Vec3& offset = Vec3::Zero()) {
  Mesh mesh;
  mesh.vertices = {offset + Vec3(0, 0, 0), offset + Vec3(1, 0, 0), offset + Vec3(0, 1, 0), offset + Vec3(0, 0, 1)};
  mesh.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  return mesh;
}

// Unit cube; vertex x + 2y + 4z at (x, y, z), each square face split in two.
Mesh cube() {
  Mesh mesh;
  for (int i = 0; i < 8; ++i) mesh.vertices.emplace_back(i & 1, (i >> 1) & 1, (i >> 2) & 1);
  const std::array<std::array<std::uint32_t, 4>, 6> quads = {{
      {0, 2, 3, 1},
      {4, 5, 7, 6},
      {0, 1, 5, 4},
      {2, 6, 7, 3},
      {0, 4, 6, 2},
      {1, 3, 7, 5},
  }};
  for (const auto& q : quads) {
    mesh.triangles.push_back({q[0], q[1], q[2]});
    mesh.triangles.push_back({q[0], q[2], q[3]});
  }
  return mesh;
}

// A torus sampled on an n x m grid that wraps in both directions.
Mesh torus(std::uint32_t n, std::uint32_t m) {
  Mesh mesh;
  const double major = 2.0;
  const double minor = 0.5;
  for (std::uint32_t i = 0; i < n; ++i) {
    const double u = 2.0 * std::numbers::pi * i / n;
    for (std::uint32_t j = 0; j < m; ++j) {
      const double v = 2.0 * std::numbers::pi * j / m;
      mesh.vertices.emplace_back((major + minor * std::cos(v)) * std::cos(u),
                                 (major + minor * std::cos(v)) * std::sin(u), minor * std::sin(v));
    }
  }
  const auto id = [m](std::uint32_t i, std::uint32_t j) { return i * m + j; };
  for (std::uint32_t i = 0; i < n; ++i) {
    for (std::uint32_t j = 0; j < m; ++j) {
      const std::uint32_t i1 = (i + 1) % n;
      const std::uint32_t j1 = (j + 1) % m;
      mesh.triangles.push_back({id(i, j), id(i1, j), id(i1, j1)});
      mesh.triangles.push_back({id(i, j), id(i1, j1), id(i, j1)});
    }
  }
  return mesh;
}

Mesh unit_square() {
  Mesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  return mesh;
}

Mesh flipped(Mesh mesh) {
  for (Triangle& t : mesh.triangles) std::swap(t[1], t[2]);
  return mesh;
}

// Every count analyze_topology() makes, as one value, so that a test states a
// mesh's whole expected topology at once (a count left out is expected 0).
struct Counts {
  std::size_t vertices = 0;
  std::size_t edges = 0;
  std::size_t triangles = 0;
  long euler_characteristic = 0;
  std::size_t components = 0;
  std::size_t boundary_edges = 0;
  std::size_t boundary_loops = 0;
  std::size_t non_manifold_edges = 0;
  std::size_t inconsistent_edges = 0;
  std::size_t degenerate_triangles = 0;
  bool operator==(const Counts&) const = default;
};

Counts counts_of(const MeshTopology& t) {
  return {t.vertices,       t.edges,          t.triangles,          t.euler_characteristic, t.components,
          t.boundary_edges, t.boundary_loops, t.non_manifold_edges, t.inconsistent_edges,   t.degenerate_triangles};
}

void PrintTo(const Counts& c, std::ostream* os) {
  *os << "V " << c.vertices << ", E " << c.edges << ", F " << c.triangles << ", chi " << c.euler_characteristic
      << ", components " << c.components << ", boundary edges " << c.boundary_edges << " in " << c.boundary_loops
      << " loops, non-manifold " << c.non_manifold_edges << ", inconsistent " << c.inconsistent_edges << ", degenerate "
      << c.degenerate_triangles;
}

TEST(MeshTopology, TetrahedronIsClosedWithPositiveVolume) {
  const MeshTopology topology = analyze_topology(tetrahedron());
  EXPECT_EQ(counts_of(topology),
            (Counts{.vertices = 4, .edges = 6, .triangles = 4, .euler_characteristic = 2, .components = 1}));
  EXPECT_TRUE(topology.watertight());
  EXPECT_NEAR(topology.signed_volume, 1.0 / 6.0, 1e-15);
  EXPECT_NEAR(topology.area, 1.5 + std::sqrt(3.0) / 2.0, 1e-14);
  ASSERT_EQ(topology.component_list.size(), 1U);
  EXPECT_EQ(topology.component_list[0].triangles, 4U);
  EXPECT_EQ(topology.component_list[0].euler_characteristic, 2);
  EXPECT_EQ(topology.component_list[0].boundary_edges, 0U);
  EXPECT_NEAR(topology.component_list[0].signed_volume, 1.0 / 6.0, 1e-15);
}

TEST(MeshTopology, CubeAndItsMirrorImage) {
  const MeshTopology outward = analyze_topology(cube());
  EXPECT_EQ(outward.vertices, 8U);
  EXPECT_EQ(outward.edges, 18U);
  EXPECT_EQ(outward.euler_characteristic, 2);
  EXPECT_TRUE(outward.watertight());
  EXPECT_NEAR(outward.signed_volume, 1.0, 1e-14);
  EXPECT_NEAR(outward.area, 6.0, 1e-14);

  const MeshTopology inward = analyze_topology(flipped(cube()));
  EXPECT_TRUE(inward.watertight());  // consistently inward is still consistent
  EXPECT_EQ(inward.euler_characteristic, 2);
  EXPECT_NEAR(inward.signed_volume, -1.0, 1e-14);
  EXPECT_NEAR(inward.component_list[0].signed_volume, -1.0, 1e-14);
}

TEST(MeshTopology, VolumeDoesNotDependOnWhereTheMeshIs) {
  Mesh far = cube();
  for (Vec3& v : far.vertices) v += Vec3(1e6, -2e6, 3e6);
  EXPECT_NEAR(analyze_topology(far).signed_volume, 1.0, 1e-9);
}

TEST(MeshTopology, TorusHasEulerCharacteristicZero) {
  const MeshTopology topology = analyze_topology(torus(24, 12));
  EXPECT_EQ(counts_of(topology),
            (Counts{.vertices = 24 * 12, .edges = 3 * 24 * 12, .triangles = 2 * 24 * 12, .components = 1}));
  EXPECT_TRUE(topology.watertight());
  // The polyhedron is a little smaller than the smooth torus 2 pi^2 R r^2.
  const double smooth = 2.0 * std::numbers::pi * std::numbers::pi * 2.0 * 0.25;
  EXPECT_GT(std::abs(topology.signed_volume), 0.9 * smooth);
  EXPECT_LT(std::abs(topology.signed_volume), smooth);
  EXPECT_NEAR(analyze_topology(flipped(torus(24, 12))).signed_volume, -topology.signed_volume, 1e-12);
}

TEST(MeshTopology, SquareHasOneBoundaryLoop) {
  const MeshTopology topology = analyze_topology(unit_square());
  EXPECT_EQ(counts_of(topology), (Counts{.vertices = 4,
                                         .edges = 5,
                                         .triangles = 2,
                                         .euler_characteristic = 1,
                                         .components = 1,
                                         .boundary_edges = 4,
                                         .boundary_loops = 1}));
  EXPECT_FALSE(topology.watertight());
  EXPECT_NEAR(topology.area, 1.0, 1e-15);
  EXPECT_EQ(topology.component_list[0].boundary_edges, 4U);
}

TEST(MeshTopology, AnnulusHasTwoBoundaryLoops) {
  // A 3 x 3 square with the middle square cut out.
  Mesh mesh;
  mesh.vertices = {{0, 0, 0}, {3, 0, 0}, {3, 3, 0}, {0, 3, 0}, {1, 1, 0}, {2, 1, 0}, {2, 2, 0}, {1, 2, 0}};
  for (std::uint32_t k = 0; k < 4; ++k) {
    const std::uint32_t next = (k + 1) % 4;
    mesh.triangles.push_back({k, next, 4 + next});
    mesh.triangles.push_back({k, 4 + next, 4 + k});
  }
  const MeshTopology topology = analyze_topology(mesh);
  EXPECT_EQ(topology.euler_characteristic, 0);
  EXPECT_EQ(topology.boundary_edges, 8U);
  EXPECT_EQ(topology.boundary_loops, 2U);
  EXPECT_EQ(topology.inconsistent_edges, 0U);
  EXPECT_NEAR(topology.area, 8.0, 1e-14);
}

TEST(MeshTopology, BoundaryEdgesAreTheOnesOfOneTriangleAsTraversed) {
  EXPECT_TRUE(boundary_edges(tetrahedron()).empty());
  EXPECT_TRUE(boundary_edges(cube()).empty());
  // The square's four sides, each in its triangle's direction; the diagonal
  // is shared.
  const auto square = boundary_edges(unit_square());
  const MeshTopology t = analyze_topology(unit_square());
  ASSERT_EQ(square.size(), t.boundary_edges);
  const Mesh mesh = unit_square();
  for (const auto& [a, b] : square) {
    int uses = 0;
    for (const auto& tri : mesh.triangles)
      for (int c = 0; c < 3; ++c) {
        const auto x = tri[static_cast<std::size_t>(c)], y = tri[static_cast<std::size_t>((c + 1) % 3)];
        uses += (x == a && y == b) ? 1 : 0;
        EXPECT_FALSE(x == b && y == a) << "edge " << a << "-" << b << " is used in both directions";
      }
    EXPECT_EQ(uses, 1);
  }
  // A collapsed triangle adds no edge.
  Mesh with_collapsed = tetrahedron();
  with_collapsed.triangles.push_back({0, 0, 1});
  EXPECT_TRUE(boundary_edges(with_collapsed).empty());
  // Removing one face of the tetrahedron opens its three edges.
  Mesh open = tetrahedron();
  open.triangles.pop_back();
  EXPECT_EQ(boundary_edges(open).size(), 3U);
}

TEST(MeshTopology, TwoDisjointTetrahedraAreTwoComponents) {
  Mesh mesh = tetrahedron();
  const Mesh second = tetrahedron(Vec3(5, 0, 0));
  for (const Vec3& v : second.vertices) mesh.vertices.push_back(v);
  for (const Triangle& t : second.triangles) mesh.triangles.push_back({t[0] + 4, t[1] + 4, t[2] + 4});

  const MeshTopology topology = analyze_topology(mesh);
  EXPECT_EQ(topology.components, 2U);
  EXPECT_EQ(topology.euler_characteristic, 4);
  EXPECT_TRUE(topology.watertight());
  EXPECT_NEAR(topology.signed_volume, 2.0 / 6.0, 1e-14);
  ASSERT_EQ(topology.component_list.size(), 2U);
  for (const auto& component : topology.component_list) {
    EXPECT_EQ(component.triangles, 4U);
    EXPECT_EQ(component.euler_characteristic, 2);
    EXPECT_EQ(component.boundary_edges, 0U);
    EXPECT_NEAR(component.signed_volume, 1.0 / 6.0, 1e-14);
  }
}

TEST(MeshTopology, ComponentsAreListedLargestFirst) {
  Mesh mesh = unit_square();  // 2 triangles
  const Mesh big = cube();    // 12 triangles
  for (const Vec3& v : big.vertices) mesh.vertices.push_back(v + Vec3(3, 0, 0));
  for (const Triangle& t : big.triangles) mesh.triangles.push_back({t[0] + 4, t[1] + 4, t[2] + 4});
  const MeshTopology topology = analyze_topology(mesh);
  ASSERT_EQ(topology.component_list.size(), 2U);
  EXPECT_EQ(topology.component_list[0].triangles, 12U);
  EXPECT_EQ(topology.component_list[0].euler_characteristic, 2);
  EXPECT_EQ(topology.component_list[1].triangles, 2U);
  EXPECT_EQ(topology.component_list[1].euler_characteristic, 1);
  EXPECT_EQ(topology.component_list[1].boundary_edges, 4U);
}

TEST(MeshTopology, TrianglesSharingOnlyAVertexAreSeparateComponents) {
  Mesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}};
  mesh.triangles = {{0, 1, 2}, {0, 3, 4}};
  const MeshTopology topology = analyze_topology(mesh);
  EXPECT_EQ(topology.components, 2U);
  EXPECT_EQ(topology.vertices, 5U);
  EXPECT_EQ(topology.euler_characteristic, 1);  // 5 - 6 + 2
  EXPECT_EQ(topology.component_list[0].euler_characteristic, 1);
  EXPECT_EQ(topology.component_list[1].euler_characteristic, 1);
  EXPECT_EQ(topology.boundary_loops, 1U);  // the two triangles' boundaries touch at vertex 0
}

TEST(MeshTopology, FlippedTriangleMakesAnInconsistentEdge) {
  Mesh mesh = unit_square();
  mesh.triangles[1] = {0, 3, 2};
  const MeshTopology topology = analyze_topology(mesh);
  EXPECT_EQ(topology.inconsistent_edges, 1U);
  EXPECT_EQ(topology.non_manifold_edges, 0U);
  EXPECT_EQ(topology.components, 1U);
  EXPECT_FALSE(topology.watertight());
}

TEST(MeshTopology, ThreeTrianglesOnOneEdgeAreNonManifold) {
  Mesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0.5, -1, 0}, {0.5, 0, 1}};
  mesh.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  const MeshTopology topology = analyze_topology(mesh);
  EXPECT_EQ(topology.non_manifold_edges, 1U);
  EXPECT_EQ(topology.inconsistent_edges, 0U);
  EXPECT_EQ(topology.edges, 7U);
  EXPECT_EQ(topology.boundary_edges, 6U);
  EXPECT_EQ(topology.components, 1U);
  EXPECT_FALSE(topology.watertight());
}

TEST(MeshTopology, DegenerateTriangles) {
  Mesh mesh = unit_square();
  mesh.vertices.emplace_back(2, 0, 0);
  mesh.triangles.push_back({1, 1, 2});  // repeated corner: left out of the topology
  mesh.triangles.push_back({0, 1, 4});  // three collinear corners: zero area, kept
  const MeshTopology topology = analyze_topology(mesh);
  EXPECT_EQ(topology.triangles, 4U);
  EXPECT_EQ(topology.degenerate_triangles, 2U);
  EXPECT_EQ(topology.vertices, 5U);
  EXPECT_EQ(topology.edges, 7U);
  EXPECT_EQ(topology.euler_characteristic, 5 - 7 + 3);
  EXPECT_NEAR(topology.area, 1.0, 1e-15);
}

TEST(MeshTopology, TinyButWellShapedTrianglesAreNotDegenerate) {
  Mesh mesh = unit_square();
  mesh.vertices.emplace_back(5, 5, 0);
  mesh.vertices.emplace_back(5 + 1e-5, 5, 0);
  mesh.vertices.emplace_back(5, 5 + 1e-5, 0);
  mesh.triangles.push_back({4, 5, 6});  // area 5e-11, a hundred times 1e-14 * 50
  EXPECT_EQ(analyze_topology(mesh).degenerate_triangles, 0U);
}

TEST(MeshTopology, EmptyMesh) {
  const MeshTopology topology = analyze_topology(Mesh{});
  EXPECT_EQ(topology.vertices, 0U);
  EXPECT_EQ(topology.components, 0U);
  EXPECT_EQ(topology.euler_characteristic, 0);
  EXPECT_TRUE(topology.component_list.empty());
}

TEST(MeshTopology, UnusedVerticesAreNotCounted) {
  Mesh mesh = tetrahedron();
  mesh.vertices.emplace_back(9, 9, 9);
  EXPECT_EQ(analyze_topology(mesh).vertices, 4U);
  EXPECT_EQ(analyze_topology(mesh).euler_characteristic, 2);
}

TEST(MeshTopology, IndexOutOfRangeThrows) {
  Mesh mesh = tetrahedron();
  mesh.triangles.push_back({0, 1, 7});
  EXPECT_THROW(static_cast<void>(analyze_topology(mesh)), InvalidInputError);
}

// Against brute force: the minimum over a fine barycentric grid of the
// triangle is at least the exact distance, and exceeds it by no more than the
// grid can miss (half a grid step times the longest edge).
TEST(PointTriangleDistance, AgreesWithADenseSampleOfTheTriangle) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  constexpr int steps = 200;
  for (int trial = 0; trial < 200; ++trial) {
    const Vec3 a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng)), c(u(rng), u(rng), u(rng));
    const Vec3 p = 1.5 * Vec3(u(rng), u(rng), u(rng));
    double sampled = std::numeric_limits<double>::infinity();
    for (int i = 0; i <= steps; ++i)
      for (int j = 0; i + j <= steps; ++j) {
        const double s = static_cast<double>(i) / steps, t = static_cast<double>(j) / steps;
        sampled = std::min(sampled, (a + s * (b - a) + t * (c - a) - p).norm());
      }
    const double exact = point_triangle_distance(p, a, b, c);
    const double slack = std::max({(b - a).norm(), (c - a).norm(), (c - b).norm()}) / steps;
    EXPECT_LE(exact, sampled + 1e-12) << trial;
    EXPECT_GE(exact, sampled - slack) << trial;
  }
  // On the triangle itself, and straight above its interior.
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  EXPECT_NEAR(point_triangle_distance(Vec3(0.2, 0.2, 0.0), a, b, c), 0.0, 1e-15);
  EXPECT_DOUBLE_EQ(point_triangle_distance(Vec3(0.2, 0.2, 0.5), a, b, c), 0.5);
  EXPECT_DOUBLE_EQ(point_triangle_distance(Vec3(2.0, 0.0, 0.0), a, b, c), 1.0);
}

}  // namespace
}  // namespace recon
