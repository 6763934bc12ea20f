#include "recon/phase4_contour/marching_cubes.h"

#include "recon/core/errors.h"
#include "recon/core/shapes.h"
#include "recon/phase4_contour/detail/seed_wave.h"
#include "recon/phase4_contour/marching_cubes_table.h"
#include "recon/structures/mesh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <random>
#include <set>

namespace recon {
namespace {

using EdgeKey = std::pair<int, int>;

// Whether cube edge e lies on the face with normal `axis` at side `side`.
bool edge_on_face(int e, int axis, int side) {
  const auto ends = mc::edge_corners(e);
  return ((ends[0] >> axis) & 1) == side && ((ends[1] >> axis) & 1) == side;
}

bool share_a_face(int e0, int e1) {
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side)
      if (edge_on_face(e0, axis, side) && edge_on_face(e1, axis, side)) return true;
  return false;
}

TEST(MarchingCubesTable, EdgesJoinCornersThatDifferAlongTheirAxis) {
  std::set<EdgeKey> seen;
  for (int e = 0; e < 12; ++e) {
    const auto ends = mc::edge_corners(e);
    EXPECT_EQ(ends[0] ^ ends[1], 1 << mc::edge_axis(e));
    EXPECT_EQ((ends[0] >> mc::edge_axis(e)) & 1, 0);
    EXPECT_TRUE(seen.insert({ends[0], ends[1]}).second);
  }
}

// Every configuration: the crossings used are exactly the edges whose corners
// differ; each piece of the cube's surface is a closed loop or bounded only
// by segments lying on the cube's faces (shared with the neighbour cube);
// interior triangle edges are used exactly twice.
TEST(MarchingCubesTable, EveryConfigurationIsBoundedOnlyByFaceSegments) {
  for (unsigned config = 0; config < 256; ++config) {
    const mc::CubeCase& c = mc::cube_case(config);
    auto inside = [&](int corner) { return ((config >> corner) & 1u) != 0; };
    std::set<int> crossed;
    for (int e = 0; e < 12; ++e) {
      const auto ends = mc::edge_corners(e);
      if (inside(ends[0]) != inside(ends[1])) crossed.insert(e);
    }
    std::set<int> used;
    std::map<EdgeKey, int> directed;  // (from, to) -> count
    for (int t = 0; t < c.triangle_count; ++t) {
      const auto& tri = c.triangles[static_cast<std::size_t>(t)];
      ASSERT_TRUE(tri[0] != tri[1] && tri[1] != tri[2] && tri[0] != tri[2]) << config;
      for (int v = 0; v < 3; ++v) {
        if (tri[static_cast<std::size_t>(v)] < 12) used.insert(tri[static_cast<std::size_t>(v)]);
        ++directed[{tri[static_cast<std::size_t>(v)], tri[static_cast<std::size_t>((v + 1) % 3)]}];
      }
    }
    EXPECT_EQ(used, crossed) << "configuration " << config;
    if (config == 0 || config == 255) {
      EXPECT_EQ(c.triangle_count, 0);
    }
    for (const auto& [edge, count] : directed) {
      EXPECT_EQ(count, 1) << "configuration " << config << ": a directed edge used twice";
      const bool twin = directed.count({edge.second, edge.first}) > 0;
      if (twin) continue;  // interior edge, used once each way
      // A boundary edge of the cube's patch: a segment on a cube face.
      ASSERT_LT(edge.first, 12) << "configuration " << config << ": boundary through a loop centre";
      ASSERT_LT(edge.second, 12) << "configuration " << config;
      EXPECT_TRUE(share_a_face(edge.first, edge.second)) << "configuration " << config;
    }
    // Inner diagonals never lie on a face: the neighbour could draw them too.
    for (const auto& [edge, count] : directed) {
      if (edge.first >= 12 || edge.second >= 12 || !directed.count({edge.second, edge.first})) continue;
      EXPECT_FALSE(share_a_face(edge.first, edge.second)) << "configuration " << config;
    }
  }
}

// No triangle has its three vertices on one face of its cube (a loop's
// centre is inside it): a triangle's centroid lies inside its cube, which
// names the cube (triangle_cube).
TEST(MarchingCubesTable, NoTriangleLiesInAFace) {
  for (unsigned config = 0; config < 256; ++config) {
    const mc::CubeCase& c = mc::cube_case(config);
    for (int t = 0; t < c.triangle_count; ++t) {
      const auto& tri = c.triangles[static_cast<std::size_t>(t)];
      for (int axis = 0; axis < 3; ++axis)
        for (int side = 0; side < 2; ++side) {
          bool all_on_face = true;
          for (const auto v : tri) all_on_face = all_on_face && v < 12 && edge_on_face(v, axis, side);
          EXPECT_FALSE(all_on_face) << "configuration " << config << ", triangle " << t;
        }
    }
  }
}

TEST(MarchingCubesTable, ComplementaryConfigurationsCrossTheSameEdges) {
  for (unsigned config = 0; config < 256; ++config) {
    std::set<int> a, b;
    for (int t = 0; t < mc::cube_case(config).triangle_count; ++t)
      for (auto v : mc::cube_case(config).triangles[static_cast<std::size_t>(t)])
        if (v < 12) a.insert(v);
    for (int t = 0; t < mc::cube_case(255 - config).triangle_count; ++t)
      for (auto v : mc::cube_case(255 - config).triangles[static_cast<std::size_t>(t)])
        if (v < 12) b.insert(v);
    EXPECT_EQ(a, b) << config;
  }
}

// A field given by values at the corners of an n^3 block of the lattice,
// lattice corner (a, b, c) being at cell * (a, b, c); the block starts at
// corner (3, 3, 3), and the field is 1 (outside) beyond it.
struct LatticeField {
  double cell;
  int n;
  std::vector<double> values;  // NaN = undefined
  std::optional<double> operator()(const Vec3& p) const {
    const Vec3 q = p / cell;
    const int i = static_cast<int>(std::lround(q.x())) - 3, j = static_cast<int>(std::lround(q.y())) - 3,
              k = static_cast<int>(std::lround(q.z())) - 3;
    if (i < 0 || j < 0 || k < 0 || i >= n || j >= n || k >= n) return 1.0;
    const double v = values[static_cast<std::size_t>((k * n + j) * n + i)];
    if (std::isnan(v)) return std::nullopt;
    return v;
  }
};

// Random fields, positive on the block's outer layer: the surface is
// closed, edge-manifold, consistently oriented, and has no zero-area
// triangle, for every mix of ambiguous faces the random signs produce,
// including exact zeros at corners.
TEST(MarchingCubes, RandomFieldsGiveClosedManifoldSurfaces) {
  const int n = 12;
  const double cell = 0.5;
  // marching_cubes puts lattice corner (0,0,0) lattice_margin cubes below
  // the seeds' minimum: a seed there makes it the origin. The other seeds,
  // one per cube of the block, make the walk visit every cube.
  std::vector<Vec3> seeds = {Vec3::Constant(lattice_margin * cell)};
  for (int k = 0; k + 1 < n; ++k)
    for (int j = 0; j + 1 < n; ++j)
      for (int i = 0; i + 1 < n; ++i) seeds.push_back(cell * Vec3(i + 3.5, j + 3.5, k + 3.5));
  std::size_t ambiguous_faces_seen = 0;
  for (std::uint32_t seed = 1; seed <= 40; ++seed) {
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> pick(-2, 2);
    LatticeField field{cell, n, std::vector<double>(static_cast<std::size_t>(n * n * n))};
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const bool border = i == 0 || j == 0 || k == 0 || i == n - 1 || j == n - 1 || k == n - 1;
          // Every fourth seed: values in {-1, -0.5, 0, 0.5, 1}, so exact zeros are common.
          const double v = seed % 4 == 0 ? pick(rng) / 2.0 : std::uniform_real_distribution<double>(-1, 1)(rng);
          field.values[static_cast<std::size_t>((k * n + j) * n + i)] = border ? 1.0 : v;
        }
    for (int k = 0; k + 1 < n; ++k)  // count ambiguous faces (normal z) to show they occur
      for (int j = 0; j + 1 < n; ++j)
        for (int i = 0; i + 1 < n; ++i) {
          auto neg = [&](int a, int b) { return field.values[static_cast<std::size_t>((k * n + b) * n + a)] < 0; };
          if (neg(i, j) == neg(i + 1, j + 1) && neg(i + 1, j) == neg(i, j + 1) && neg(i, j) != neg(i + 1, j))
            ++ambiguous_faces_seen;
        }
    MarchingCubesOptions options;
    options.cell = cell;
    options.keep_triangle_cubes = true;
    const MarchingCubesResult r = marching_cubes(std::cref(field), seeds, options);
    ASSERT_FALSE(r.mesh.triangles.empty()) << seed;
    for (std::size_t tri = 0; tri < r.mesh.triangles.size(); ++tri)  // the centroid names the cube
      ASSERT_EQ(triangle_cube(r, tri), r.triangle_cubes[tri]) << "seed " << seed << ", triangle " << tri;
    ASSERT_NEAR(r.origin.norm(), 0.0, 1e-12);
    const MeshTopology t = analyze_topology(r.mesh);
    EXPECT_EQ(t.boundary_edges, 0u) << "seed " << seed;
    EXPECT_EQ(t.non_manifold_edges, 0u) << "seed " << seed;
    EXPECT_EQ(t.inconsistent_edges, 0u) << "seed " << seed;
    EXPECT_EQ(t.degenerate_triangles, 0u) << "seed " << seed;
    EXPECT_GT(t.signed_volume, 0.0) << "seed " << seed;  // outward: the negative blobs are enclosed
    EXPECT_EQ(r.undefined_cubes, 0u);
  }
  EXPECT_GT(ambiguous_faces_seen, 100u);
}

TEST(MarchingCubes, UndefinedCornersLeaveTheSurfaceOpenThere) {
  // Sphere field, undefined on the cap z > 0.6: an open surface with one
  // boundary loop, no triangle above the cap's edge.
  const ScalarField f = [](const Vec3& p) -> std::optional<double> {
    if (p.z() > 0.6) return std::nullopt;
    return p.norm() - 1.0;
  };
  const PointCloud seeds = make_sphere()->sample(3000, 1);
  MarchingCubesOptions options;
  options.cell = 0.05;
  const MarchingCubesResult r = marching_cubes(f, seeds.positions, options);
  const MeshTopology t = analyze_topology(r.mesh);
  EXPECT_EQ(t.components, 1u);
  EXPECT_EQ(t.boundary_loops, 1u);
  EXPECT_EQ(t.euler_characteristic, 1);  // a disc
  EXPECT_GT(r.undefined_cubes, 0u);
  for (const Vec3& v : r.mesh.vertices) EXPECT_LE(v.z(), 0.6 + 1e-12);
}

// The unit sphere's signed distance contoured with cubes of side `cell`,
// seeded at `seeds`.
MarchingCubesResult contour_unit_sphere(const PointCloud& seeds, double cell) {
  const ScalarField f = [](const Vec3& p) { return std::optional<double>(p.norm() - 1.0); };
  MarchingCubesOptions options;
  options.cell = cell;
  return marching_cubes(f, seeds.positions, options);
}

TEST(MarchingCubes, SphereIsOutwardFacingAndAccurate) {
  const MarchingCubesResult r = contour_unit_sphere(make_sphere()->sample(2000, 2), 0.05);
  const MeshTopology t = analyze_topology(r.mesh);
  EXPECT_TRUE(t.watertight());
  EXPECT_EQ(t.components, 1u);
  EXPECT_EQ(t.euler_characteristic, 2);
  // Volume of the polyhedron: a little below 4/3 pi (inscribed).
  EXPECT_NEAR(t.signed_volume, 4.0 / 3.0 * std::numbers::pi, 0.02);
  for (const Vec3& v : r.mesh.vertices) EXPECT_NEAR(v.norm(), 1.0, 0.05 * 0.05);  // linear interpolation error ~ h^2
}

// sort_by_cube gives one order whatever the walk: from every sample, or
// from one (another start, other waves), the sorted meshes are the same
// bytes, though the walks' own orders differ. The vertex edges follow.
TEST(MarchingCubes, SortByCubeDoesNotDependOnTheWalk) {
  const ScalarField f = [](const Vec3& p) { return std::optional<double>(p.norm() - 1.0); };
  const PointCloud seeds = make_sphere()->sample(3000, 4);
  Box<3> box;
  for (const Vec3& p : seeds.positions) box.extend(p);
  MarchingCubesOptions options;
  options.cell = 0.1;
  options.keep_vertex_edges = true;
  options.keep_triangle_cubes = true;
  LatticeRegion region;
  region.lattice = make_lattice<3>(box, options.cell);
  region.walk_hi = region.own_hi = region.lattice.size;
  options.region = region;
  MarchingCubesResult all = marching_cubes(f, seeds.positions, options);
  MarchingCubesResult one = marching_cubes(f, std::span<const Vec3>(&seeds.positions.back(), 1), options);
  ASSERT_EQ(all.mesh.triangles.size(), one.mesh.triangles.size());
  EXPECT_NE(all.mesh.triangles, one.mesh.triangles) << "the walks' orders should differ, or the test shows nothing";
  sort_by_cube(all);
  sort_by_cube(one);
  EXPECT_EQ(all.mesh.vertices, one.mesh.vertices);
  EXPECT_EQ(all.mesh.triangles, one.mesh.triangles);
  EXPECT_EQ(all.vertex_edges, one.vertex_edges);
  EXPECT_TRUE(std::is_sorted(all.triangle_cubes.begin(), all.triangle_cubes.end()));
  for (std::size_t t = 0; t < all.mesh.triangles.size(); ++t) EXPECT_EQ(triangle_cube(all, t), all.triangle_cubes[t]);
  // Each vertex still lies on its edge: between the edge's corners on its axis.
  for (std::size_t v = 0; v < all.mesh.vertices.size(); ++v) {
    const VertexEdge e = all.vertex_edges[v];
    const Vec3 corner = region.lattice.position(Lattice<3>::index(e.corner));
    for (std::size_t a = 0; a < 3; ++a) {
      const double along = all.mesh.vertices[v][static_cast<Eigen::Index>(a)] - corner[static_cast<Eigen::Index>(a)];
      if (a == e.axis) {
        EXPECT_GT(along, 0.0);
        EXPECT_LT(along, options.cell);
      } else {
        EXPECT_NEAR(along, 0.0, 1e-12);
      }
    }
  }
}

// Time and memory follow the surface: halving the cell visits about 4 times
// the cubes (area), not 8 (volume).
TEST(MarchingCubes, VisitedCubesGrowWithAreaNotVolume) {
  const PointCloud seeds = make_sphere()->sample(20000, 3);
  const auto coarse = contour_unit_sphere(seeds, 0.04);
  const auto fine = contour_unit_sphere(seeds, 0.02);
  const double ratio = static_cast<double>(fine.visited_cubes) / static_cast<double>(coarse.visited_cubes);
  EXPECT_GT(ratio, 3.5);
  EXPECT_LT(ratio, 4.5);
  const double corner_ratio =
      static_cast<double>(fine.evaluated_corners) / static_cast<double>(coarse.evaluated_corners);
  EXPECT_LT(corner_ratio, 4.5);
  // And a vanishing fraction of the lattice's volume.
  const double lattice = static_cast<double>(fine.size[0]) * fine.size[1] * fine.size[2];
  EXPECT_LT(static_cast<double>(fine.visited_cubes), 0.1 * lattice);
}

// The first wave, found by brute force: the cubes that hold a seed, each
// once, in seed order, and every corner of those cubes, once each, in the
// order the walk meets them (each cube's corners in marching-cubes order).
TEST(MarchingCubes, SeedWaveHoldsTheCubesOfTheSeedsAndTheirCorners) {
  const PointCloud seeds = make_torus()->sample(4000, 4);
  const SeedWave wave(seeds.positions, 0.07);
  const Lattice<3>& lattice = wave.lattice();
  EXPECT_EQ(lattice.cell, 0.07);
  std::set<std::array<std::int32_t, 3>> cubes, seen;
  std::vector<std::array<std::int32_t, 3>> expected;
  for (const Vec3& p : seeds.positions) {
    std::array<std::int32_t, 3> cube{};
    for (std::size_t a = 0; a < 3; ++a) {
      cube[a] =
          static_cast<std::int32_t>(std::floor((p[static_cast<int>(a)] - lattice.origin[static_cast<int>(a)]) / 0.07));
      ASSERT_GE(cube[a], 0);
      ASSERT_LT(cube[a], lattice.size[a]);
      // The seed lies in its cube.
      EXPECT_LE(lattice.position(cube)[static_cast<int>(a)], p[static_cast<int>(a)]);
    }
    if (!cubes.insert(cube).second) continue;
    for (int c = 0; c < 8; ++c) {
      const std::array<std::int32_t, 3> corner{cube[0] + (c & 1), cube[1] + ((c >> 1) & 1), cube[2] + ((c >> 2) & 1)};
      if (seen.insert(corner).second) expected.push_back(corner);
    }
  }
  EXPECT_EQ(wave.cube_count(), cubes.size());
  ASSERT_EQ(wave.corner_count(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) ASSERT_EQ(wave.corner(i), expected[i]) << i;
  EXPECT_GT(expected.size(), 1000u);
  // The lattice is the walk's own, and so is the first wave.
  MarchingCubesOptions options;
  options.cell = 0.07;
  const ScalarField f = [](const Vec3& p) { return std::optional<double>(p.norm() - 1.0); };
  const MarchingCubesResult r = marching_cubes(f, seeds.positions, options);
  EXPECT_EQ(r.origin, lattice.origin);
  EXPECT_EQ(r.size, lattice.size);
  EXPECT_EQ(r.seed_cubes, cubes.size());
  EXPECT_THROW((void)SeedWave(std::span<const Vec3>(), 0.07), InvalidInputError);
  EXPECT_THROW((void)SeedWave(seeds.positions, 0.0), InvalidInputError);
}

// Values known beforehand at the first wave's corners are taken, not
// evaluated again, and the mesh is the one the walk makes on its own; with
// wrong values it would differ.
TEST(MarchingCubes, SeedWaveValuesAreTakenAndChangeNothing) {
  std::atomic<std::size_t> calls{0};
  const ScalarField f = [&](const Vec3& p) -> std::optional<double> {
    ++calls;
    if (p.z() > 0.6) return std::nullopt;  // an open surface: undefined corners are known too
    return p.norm() - 1.0;
  };
  const PointCloud seeds = make_sphere()->sample(3000, 5);
  MarchingCubesOptions options;
  options.cell = 0.06;
  options.keep_corners = true;
  const MarchingCubesResult plain = marching_cubes(f, seeds.positions, options);
  const std::size_t plain_calls = calls.exchange(0);
  EXPECT_EQ(plain_calls, plain.evaluated_corners);

  auto give_values = [&](SeedWave& wave, double shift, std::size_t every) {
    for (std::size_t i = 0; i < wave.corner_count(); i += every) {
      const auto v = f(wave.lattice().position(wave.corner(i)));
      wave.set_value(i, v ? *v + shift : std::numeric_limits<double>::quiet_NaN());
    }
  };
  SeedWave wave(seeds.positions, options.cell);
  const std::size_t known = wave.corner_count();
  EXPECT_TRUE(std::isnan(wave.value(0)));  // none given yet
  give_values(wave, 0.0, 1);
  calls = 0;
  const MarchingCubesResult with = marching_cubes(f, std::move(wave), options);
  EXPECT_EQ(calls.load(), plain.evaluated_corners - known);  // the known ones, not again
  EXPECT_GT(known, plain.evaluated_corners / 2);
  EXPECT_TRUE(with.mesh.vertices == plain.mesh.vertices);
  EXPECT_TRUE(with.mesh.triangles == plain.mesh.triangles);
  EXPECT_EQ(with.seed_cubes, plain.seed_cubes);
  EXPECT_EQ(with.visited_cubes, plain.visited_cubes);
  EXPECT_EQ(with.evaluated_corners, plain.evaluated_corners);
  EXPECT_EQ(with.undefined_corners, plain.undefined_corners);
  EXPECT_GT(with.undefined_corners, 0u);
  // The corners keep their slots: they come out in the same order.
  ASSERT_EQ(with.corners.size(), plain.corners.size());
  for (std::size_t i = 0; i < plain.corners.size(); ++i) {
    ASSERT_EQ(with.corners[i].index, plain.corners[i].index) << i;
    ASSERT_EQ(with.corners[i].defined, plain.corners[i].defined) << i;
    ASSERT_EQ(with.corners[i].value, plain.corners[i].value) << i;
  }
  // Values given at every third corner only: f is asked at the others.
  SeedWave some(seeds.positions, options.cell);
  give_values(some, 0.0, 3);
  calls = 0;
  const MarchingCubesResult partly = marching_cubes(f, std::move(some), options);
  EXPECT_EQ(calls.load(), plain.evaluated_corners - (known + 2) / 3);
  EXPECT_TRUE(partly.mesh.triangles == plain.mesh.triangles);
  // Without values, the walk from a wave asks f everywhere and agrees.
  calls = 0;
  const MarchingCubesResult asked = marching_cubes(f, SeedWave(seeds.positions, options.cell), options);
  EXPECT_EQ(calls.load(), plain.evaluated_corners);
  EXPECT_TRUE(asked.mesh.triangles == plain.mesh.triangles);

  SeedWave shifted(seeds.positions, options.cell);  // the field moved by a tenth of a cell: another mesh
  give_values(shifted, 0.1 * options.cell, 1);
  const MarchingCubesResult other = marching_cubes(f, std::move(shifted), options);
  EXPECT_FALSE(other.mesh.vertices == plain.mesh.vertices);

  EXPECT_THROW((void)marching_cubes(f, SeedWave(seeds.positions, 2.0 * options.cell), options), InvalidInputError);
  SeedWave once(seeds.positions, options.cell);
  EXPECT_THROW(once.set_value(once.corner_count(), 0.0), InvalidInputError);
  EXPECT_THROW((void)once.corner(once.corner_count()), InvalidInputError);
  (void)marching_cubes(f, std::move(once), options);
  EXPECT_EQ(once.corner_count(), 0u);  // NOLINT(bugprone-use-after-move): moved-from is empty, by contract
  EXPECT_THROW((void)marching_cubes(f, std::move(once), options), InvalidInputError);
}

TEST(MarchingCubes, RefusesBadCellsAndHugeLattices) {
  const ScalarField f = [](const Vec3& p) { return std::optional<double>(p.norm() - 1.0); };
  const std::vector<Vec3> seeds = {Vec3(0, 0, 0), Vec3(1, 1, 1)};
  MarchingCubesOptions options;
  options.cell = 0.0;
  EXPECT_THROW((void)marching_cubes(f, seeds, options), InvalidInputError);
  options.cell = 1e-9;  // 1e9 cubes along each axis
  EXPECT_THROW((void)marching_cubes(f, seeds, options), ResourceLimitError);
  options.cell = 0.001;
  options.max_cubes = 1000;
  EXPECT_THROW((void)marching_cubes(f, make_sphere()->sample(5000, 1).positions, options), ResourceLimitError);
}

}  // namespace
}  // namespace recon
