#include "recon/alternatives/uniform_grid.h"

#include "recon/alternatives/brute_force_search.h"
#include "recon/core/errors.h"
#include "recon/core/parallel.h"
#include "recon/structures/kdtree.h"
#include "search_clouds.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <sstream>
#include <string>

namespace recon {
namespace {

using namespace testing;  // search_clouds.h

// The cell sizes every comparison runs with: the default; a thousandth of
// it (rings far too many: the search falls back to visiting the occupied
// cells); the smallest the guard allows; one cell wider than the points;
// a size beyond any coordinate (taken as 4 * max_coordinate).
template <int D>
std::vector<double> cell_sizes(const std::vector<Vec<D>>& points) {
  const double standard = UniformGrid<D>::default_cell_size(points);
  const double widest = bounding_box<D>(points).extent().maxCoeff();
  std::vector<double> sizes = {standard, standard / 1000.0, 1e300};
  if (widest > 0.0) {
    sizes.push_back(widest * 2.0 / static_cast<double>(UniformGrid<D>::max_cells_across));
    sizes.push_back(widest * 1e6);
  }
  return sizes;
}

std::string describe(Cloud cloud, std::size_t n, double cell, int k = 0) {
  std::ostringstream s;
  s << name_of(cloud) << ", n = " << n << ", cell size " << cell;
  if (k > 0) s << ", k = " << k;
  return s.str();
}

template <int D>
void check_all_knn_against_kdtree() {
  for (const Cloud cloud : all_clouds) {
    for (const std::size_t n : {1u, 2u, 7u, 150u, 1500u}) {
      const auto points = make_cloud<D>(cloud, n, static_cast<std::uint32_t>(n) + 21);
      const KdTree<D> tree(points);
      std::vector<double> sizes = cell_sizes<D>(points);
      if (cloud == Cloud::integer_lattice) sizes.insert(sizes.end(), {1.0, 0.5, 2.0});  // points on cell faces
      const int nn = static_cast<int>(n);
      for (const double cell : sizes) {
        const UniformGrid<D> grid(points, cell);
        for (const int k : {1, 4, 16, nn}) {
          if (k > nn || (k == nn && n > 150)) continue;  // k = n: the kd-tree's sorted insertion is O(k) an offer
          SCOPED_TRACE(describe(cloud, n, cell, k));
          ASSERT_TRUE(same_table(grid.all_knn(k), tree.all_knn(k)));
        }
      }
    }
  }
}

TEST(UniformGrid, AllKnnEqualsKdTree3D) { check_all_knn_against_kdtree<3>(); }
TEST(UniformGrid, AllKnnEqualsKdTree2D) { check_all_knn_against_kdtree<2>(); }

TEST(UniformGrid, DefaultGridEqualsKdTreeOnASurface) {
  const auto points = make_cloud<3>(Cloud::surface, 20000, 22);
  const UniformGrid<3> grid(points);
  const KdTree<3> tree(points);
  for (const int k : {8, 15, 20}) EXPECT_TRUE(same_table(grid.all_knn(k), tree.all_knn(k))) << "k = " << k;
}

// Queries inside the box, beyond it, and very far (a query's cell is then
// the one just beyond the grid's face, its bounds from its true position).
template <int D>
void check_queries_not_in_the_set() {
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> around(-0.5, 1.5);
  for (const Cloud cloud : all_clouds) {
    const auto points = make_cloud<D>(cloud, 400, 24);
    const KdTree<D> tree(points);
    for (const double cell : cell_sizes<D>(points)) {
      const UniformGrid<D> grid(points, cell);
      for (int trial = 0; trial < 40; ++trial) {
        Vec<D> q;
        for (int a = 0; a < D; ++a) q[a] = around(rng);
        if (trial % 8 == 3) q *= 1e6;
        if (trial % 8 == 7) q = Vec<D>::Constant(trial % 16 == 7 ? -max_coordinate : max_coordinate);
        for (const int k : {1, 9, 400}) {
          SCOPED_TRACE(describe(cloud, 400, cell, k));
          ASSERT_TRUE(same_neighbors(grid.knn(q, k), tree.knn(q, k))) << "query " << q.transpose();
        }
      }
    }
  }
}

TEST(UniformGrid, KnnAtPointsNotInTheSet) {
  check_queries_not_in_the_set<3>();
  check_queries_not_in_the_set<2>();
}

// Points on cell faces (integer coordinates, cells of edge 1 or 1/2) and
// queries halfway between them: after ring 0 the nearest unsearched point
// lies exactly as far as the nearest face, and ties the k-th found. The
// search must go on, for the tie goes to the smaller index, given here to
// the point beyond the face.
template <int D>
void check_ties_on_cell_faces() {
  std::vector<Vec<D>> points;
  for (int x = 8; x >= 0; --x) {  // decreasing x: the point to the right has the smaller index
    Vec<D> p = Vec<D>::Zero();
    p[0] = x;
    points.push_back(p);
  }
  const auto lattice = make_cloud<D>(Cloud::integer_lattice, 300, 31);
  std::mt19937 rng(32);
  for (const double cell : {1.0, 0.5}) {
    const UniformGrid<D> line(points, cell);
    for (int x = 0; x < 8; ++x) {
      Vec<D> q = Vec<D>::Zero();
      q[0] = x + 0.5;
      for (const int k : {1, 2, 3})
        ASSERT_TRUE(same_neighbors(line.knn(q, k), brute_force_knn<D>(points, q, k)))
            << "cell " << cell << ", q " << q.transpose();
    }
    const UniformGrid<D> grid(lattice, cell);
    for (int trial = 0; trial < 200; ++trial) {
      Vec<D> q;
      for (int a = 0; a < D; ++a) q[a] = static_cast<double>(rng() % 9) * 0.5;  // 0, 0.5, ..., 4
      for (const int k : {1, 5, 30})
        ASSERT_TRUE(same_neighbors(grid.knn(q, k), brute_force_knn<D>(lattice, q, k)))
            << "cell " << cell << ", q " << q.transpose();
    }
  }
}

TEST(UniformGrid, TiesOnCellFacesGoToTheSmallerIndex) {
  check_ties_on_cell_faces<3>();
  check_ties_on_cell_faces<2>();
}

// On a surface sample, the grid's rings look at far fewer points than brute
// force's n * n, and at no fewer than k a point.
TEST(UniformGrid, CountsFewerDistancesThanBruteForceOnASurface) {
  const std::size_t n = 10000;
  const auto points = make_cloud<3>(Cloud::surface, n, 25);
  const int k = 15;
  OperationCounts grid_counts, brute_counts, tree_counts;
  const KnnTable by_grid = UniformGrid<3>(points).all_knn(k, &grid_counts);
  const KnnTable by_brute_force = brute_force_all_knn<3>(points, k, &brute_counts);
  const KnnTable by_tree = KdTree<3>(points).all_knn(k, &tree_counts);
  EXPECT_TRUE(same_table(by_grid, by_brute_force));
  EXPECT_TRUE(same_table(by_tree, by_brute_force));
  EXPECT_EQ(brute_counts.distance_evaluations, n * n);
  EXPECT_LT(grid_counts.distance_evaluations, brute_counts.distance_evaluations);
  EXPECT_GE(grid_counts.distance_evaluations, n * static_cast<std::size_t>(k));
  // Far fewer, in fact: about 75 a point at the default cell size (measured).
  EXPECT_LT(grid_counts.distance_evaluations, 150 * n);
  // A single query counts its own.
  OperationCounts one;
  (void)UniformGrid<3>(points).knn(Vec3(0.0, 0.0, 0.1), k, &one);
  EXPECT_GE(one.distance_evaluations, static_cast<std::uint64_t>(k));
  EXPECT_LT(one.distance_evaluations, n);
}

TEST(UniformGrid, TableAndCountsDoNotDependOnTheThreadCount) {
  const auto points = make_cloud<3>(Cloud::integer_lattice, 6000, 26);  // ties everywhere
  const UniformGrid<3> grid(points, 1.0);
  const int threads = thread_count();
  set_thread_count(1);
  OperationCounts one;
  const KnnTable alone = grid.all_knn(12, &one);
  set_thread_count(2);
  OperationCounts two;
  const KnnTable shared = grid.all_knn(12, &two);
  set_thread_count(threads);
  EXPECT_TRUE(same_table(shared, alone));
  EXPECT_EQ(one, two);
}

TEST(UniformGrid, DefaultCellHoldsAHandfulOfSurfacePoints) {
  const auto torus = make_cloud<3>(Cloud::surface, 10000, 27);
  const UniformGrid<3> grid(torus);
  const double diagonal = bounding_box<3>(torus).diagonal();
  EXPECT_DOUBLE_EQ(grid.cell_size(), diagonal * std::sqrt(UniformGrid<3>::target_points_per_cell / 10000.0));
  const double per_cell = 10000.0 / static_cast<double>(grid.occupied_cells());  // 7 measured at 1M points
  EXPECT_GT(per_cell, 4.0);
  EXPECT_LT(per_cell, 10.0);

  const auto curve = make_cloud<2>(Cloud::surface, 2000, 28);
  const UniformGrid<2> grid2d(curve);
  EXPECT_DOUBLE_EQ(grid2d.cell_size(),
                   2.0 * bounding_box<2>(curve).diagonal() * UniformGrid<2>::target_points_per_cell / 2000.0);
  const double per_cell2d = 2000.0 / static_cast<double>(grid2d.occupied_cells());
  EXPECT_GT(per_cell2d, 4.0);
  EXPECT_LT(per_cell2d, 10.0);

  // Copies of one point: one cell of edge 1, every neighbour at distance 0.
  const std::vector<Vec3> copies(30, Vec3(1.0, -2.0, 3.0));
  const UniformGrid<3> one_cell(copies);
  EXPECT_EQ(one_cell.cell_size(), 1.0);
  EXPECT_EQ(one_cell.occupied_cells(), 1u);
  EXPECT_TRUE(one_cell.cells_across() == UniformGrid<3>::Cell::Ones());
  EXPECT_TRUE(same_table(one_cell.all_knn(30), KdTree<3>(copies).all_knn(30)));
}

TEST(UniformGrid, EmptyGridAnswersNothing) {
  const UniformGrid<3> grid(std::span<const Vec3>{});
  EXPECT_EQ(grid.size(), 0u);
  EXPECT_EQ(grid.occupied_cells(), 0u);
  EXPECT_THROW((void)grid.all_knn(1), InvalidInputError);
  EXPECT_THROW((void)grid.knn(Vec3::Zero(), 1), InvalidInputError);
}

TEST(UniformGrid, RefusesWhatItCannotAnswer) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const std::vector<Vec3> points = make_cloud<3>(Cloud::uniform, 20, 29);
  const UniformGrid<3> grid(points);
  EXPECT_THROW((void)grid.all_knn(0), InvalidInputError);
  EXPECT_THROW((void)grid.all_knn(21), InvalidInputError);
  EXPECT_THROW((void)grid.knn(Vec3::Zero(), 0), InvalidInputError);
  EXPECT_THROW((void)grid.knn(Vec3::Zero(), 21), InvalidInputError);
  EXPECT_THROW((void)grid.knn(Vec3(nan, 0, 0), 1), InvalidInputError);
  EXPECT_THROW((void)grid.knn(Vec3(0, -inf, 0), 1), InvalidInputError);
  EXPECT_THROW((void)grid.knn(Vec3(0, 0, 2e15), 1), InvalidInputError);
  for (const double cell : {0.0, -1.0, nan, inf, -inf})
    EXPECT_THROW((void)UniformGrid<3>(points, cell), InvalidInputError) << "cell size " << cell;
  for (const double bad : {nan, inf, -2e15}) {
    std::vector<Vec3> broken(points);
    broken[7].y() = bad;
    EXPECT_THROW((void)UniformGrid<3>{broken}, InvalidInputError) << bad;
    EXPECT_THROW((void)UniformGrid<3>(broken, 0.1), InvalidInputError) << bad;
  }
  // The guard: at most 2^21 cells across in 3D, 2^31 in 2D (the key's bits).
  const double widest = bounding_box<3>(points).extent().maxCoeff();
  EXPECT_THROW((void)UniformGrid<3>(points, widest / 0x1p22), InvalidInputError);
  EXPECT_THROW((void)UniformGrid<3>(points, 5e-324), InvalidInputError);  // would overflow a division
  EXPECT_NO_THROW((void)UniformGrid<3>(points, widest / 0x1p20));
  const std::vector<Vec2> flat = make_cloud<2>(Cloud::uniform, 20, 30);
  const double widest2d = bounding_box<2>(flat).extent().maxCoeff();
  EXPECT_THROW((void)UniformGrid<2>(flat, widest2d / 0x1p32), InvalidInputError);
  EXPECT_NO_THROW((void)UniformGrid<2>(flat, widest2d / 0x1p30));
}

}  // namespace
}  // namespace recon
