#include "recon/alternatives/brute_force_search.h"

#include "recon/core/errors.h"
#include "recon/core/parallel.h"
#include "recon/structures/kdtree.h"
#include "search_clouds.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>

namespace recon {
namespace {

using namespace testing;  // search_clouds.h

// Brute force and the kd-tree must give one table, entry for entry, on every
// kind of cloud, for k from 1 to n.
template <int D>
void check_all_knn_against_kdtree() {
  for (const Cloud cloud : all_clouds) {
    for (const std::size_t n : {1u, 2u, 7u, 150u, 1500u}) {
      const auto points = make_cloud<D>(cloud, n, static_cast<std::uint32_t>(n) + 11);
      const KdTree<D> tree(points);
      const int nn = static_cast<int>(n);
      for (const int k : {1, 4, 16, nn}) {
        if (k > nn || (k == nn && n > 150)) continue;  // k = n: the kd-tree's sorted insertion is O(k) an offer
        SCOPED_TRACE(name_of(cloud) + ", n = " + std::to_string(n) + ", k = " + std::to_string(k));
        EXPECT_TRUE(same_table(brute_force_all_knn<D>(points, k), tree.all_knn(k)));
      }
    }
  }
}

TEST(BruteForceSearch, AllKnnEqualsKdTree3D) { check_all_knn_against_kdtree<3>(); }
TEST(BruteForceSearch, AllKnnEqualsKdTree2D) { check_all_knn_against_kdtree<2>(); }

template <int D>
void check_queries_not_in_the_set() {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> around(-0.5, 1.5);
  for (const Cloud cloud : all_clouds) {
    const auto points = make_cloud<D>(cloud, 500, 6);
    const KdTree<D> tree(points);
    for (int trial = 0; trial < 40; ++trial) {
      Vec<D> q;
      for (int a = 0; a < D; ++a) q[a] = around(rng);
      if (trial % 4 == 3) q *= 1e6;  // far outside
      for (const int k : {1, 9, 500}) {
        SCOPED_TRACE(name_of(cloud) + ", k = " + std::to_string(k));
        ASSERT_TRUE(same_neighbors(brute_force_knn<D>(points, q, k), tree.knn(q, k)));
      }
    }
  }
}

TEST(BruteForceSearch, KnnAtPointsNotInTheSet) {
  check_queries_not_in_the_set<3>();
  check_queries_not_in_the_set<2>();
}

// n distances a query, n * n for every point: counted, and added to what the
// counts already hold.
TEST(BruteForceSearch, CountsEveryPairOnce) {
  const auto points = make_cloud<3>(Cloud::uniform, 1234, 7);
  OperationCounts counts;
  counts.pushes = 5;
  counts.distance_evaluations = 10;
  (void)brute_force_all_knn<3>(points, 8, &counts);
  EXPECT_EQ(counts.distance_evaluations, 10u + 1234u * 1234u);
  (void)brute_force_knn<3>(points, Vec3(0.5, 0.5, 0.5), 3, &counts);
  EXPECT_EQ(counts.distance_evaluations, 10u + 1234u * 1234u + 1234u);
  EXPECT_EQ(counts.pushes, 5u);  // nothing else counted
  OperationCounts counts2d;
  (void)brute_force_all_knn<2>(make_cloud<2>(Cloud::integer_lattice, 300, 8), 300, &counts2d);
  EXPECT_EQ(counts2d.distance_evaluations, 300u * 300u);
}

TEST(BruteForceSearch, TableDoesNotDependOnTheThreadCount) {
  const auto points = make_cloud<3>(Cloud::integer_lattice, 3000, 9);  // ties everywhere
  const int threads = thread_count();
  set_thread_count(1);
  OperationCounts one;
  const KnnTable alone = brute_force_all_knn<3>(points, 12, &one);
  set_thread_count(2);
  OperationCounts two;
  const KnnTable shared = brute_force_all_knn<3>(points, 12, &two);
  set_thread_count(threads);
  EXPECT_TRUE(same_table(shared, alone));
  EXPECT_EQ(one, two);
}

TEST(BruteForceSearch, RefusesWhatItCannotAnswer) {
  std::vector<Vec3> points = make_cloud<3>(Cloud::uniform, 20, 10);
  EXPECT_THROW((void)brute_force_all_knn<3>(points, 0, nullptr), InvalidInputError);
  EXPECT_THROW((void)brute_force_all_knn<3>(points, 21, nullptr), InvalidInputError);
  EXPECT_THROW((void)brute_force_knn<3>(points, Vec3::Zero(), 0), InvalidInputError);
  EXPECT_THROW((void)brute_force_knn<3>(points, Vec3::Zero(), 21), InvalidInputError);
  EXPECT_THROW((void)brute_force_all_knn<3>(std::span<const Vec3>{}, 1), InvalidInputError);
  EXPECT_THROW((void)brute_force_knn<3>(points, Vec3(0, std::numeric_limits<double>::quiet_NaN(), 0), 1),
               InvalidInputError);
  EXPECT_THROW((void)brute_force_knn<3>(points, Vec3(0, 0, 2e15), 1), InvalidInputError);
  for (const double bad : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(), -2e15}) {
    std::vector<Vec3> broken(points);
    broken[7].x() = bad;
    EXPECT_THROW((void)brute_force_all_knn<3>(broken, 3), InvalidInputError);
    EXPECT_THROW((void)brute_force_knn<3>(broken, Vec3::Zero(), 3), InvalidInputError);
  }
}

}  // namespace
}  // namespace recon
