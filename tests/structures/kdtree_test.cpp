#include "recon/structures/kdtree.h"

#include "recon/core/errors.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>

namespace recon {
namespace {

enum class Layout { uniform, clustered, duplicates };

template <int D>
std::vector<Vec<D>> make_points(std::size_t n, Layout layout, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> gauss(0.0, 0.01);
  std::vector<Vec<D>> pts;
  std::vector<Vec<D>> centres(5);
  for (auto& c : centres)
    for (int a = 0; a < D; ++a) c[a] = unit(rng);
  for (std::size_t i = 0; i < n; ++i) {
    Vec<D> p;
    switch (layout) {
      case Layout::uniform:
        for (int a = 0; a < D; ++a) p[a] = unit(rng);
        break;
      case Layout::clustered:
        p = centres[i % centres.size()];
        for (int a = 0; a < D; ++a) p[a] += gauss(rng);
        break;
      case Layout::duplicates:
        // Few distinct positions, many copies: exercises the tie-breaking.
        for (int a = 0; a < D; ++a) p[a] = std::floor(unit(rng) * 4.0) / 4.0;
        break;
    }
    pts.push_back(p);
  }
  return pts;
}

template <int D>
std::vector<Neighbor> brute_force(const std::vector<Vec<D>>& pts, const Vec<D>& q) {
  std::vector<Neighbor> all;
  for (std::size_t i = 0; i < pts.size(); ++i)
    all.push_back({static_cast<std::uint32_t>(i), (pts[i] - q).squaredNorm()});
  std::sort(all.begin(), all.end());
  return all;
}

// How the tree searched is made: built over the points, or built over
// other points and refitted to them (KdTree::refit): points near the ones
// they replace (as tangent-plane origins near their samples), or points
// unrelated to them (children's ranges overlapping everywhere).
enum class Fit { built, refit_near, refit_far };

template <int D>
KdTree<D> make_tree(const std::vector<Vec<D>>& pts, int leaf, Fit fit, std::mt19937& rng) {
  if (fit == Fit::built) return KdTree<D>(pts, {leaf});
  std::normal_distribution<double> jitter(0.0, 0.003);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Vec<D>> shape(pts);
  for (Vec<D>& p : shape)
    for (int a = 0; a < D; ++a) p[a] = fit == Fit::refit_near ? p[a] + jitter(rng) : unit(rng);
  return KdTree<D>(shape, {leaf}).refit(pts);
}

template <int D>
void check_against_brute_force(Layout layout, std::uint32_t seed, Fit fit = Fit::built) {
  std::mt19937 rng(seed + 100);
  std::uniform_real_distribution<double> unit(-0.1, 1.1);
  for (std::size_t n : {1u, 2u, 7u, 100u, 2000u}) {
    const auto pts = make_points<D>(n, layout, seed);
    for (int leaf : {1, 3, 8}) {
      const KdTree<D> tree = make_tree<D>(pts, leaf, fit, rng);
      ASSERT_EQ(tree.size(), n);
      for (int trial = 0; trial < 30; ++trial) {
        // Half the queries are data points (their own neighbour), half random.
        Vec<D> q;
        if (trial % 2 == 0) {
          q = pts[rng() % n];
        } else {
          for (int a = 0; a < D; ++a) q[a] = unit(rng);
        }
        const auto expected = brute_force(pts, q);
        for (int k : {1, 4, 15, 40}) {
          const auto got = tree.knn(q, k);
          const std::size_t want = std::min<std::size_t>(static_cast<std::size_t>(k), n);
          ASSERT_EQ(got.size(), want);
          for (std::size_t j = 0; j < want; ++j)
            ASSERT_EQ(got[j], expected[j]) << "n=" << n << " k=" << k << " j=" << j;
        }
        ASSERT_EQ(tree.nearest(q), expected[0]);
        // A bounded k-NN: the first k of the points within the bound
        // (inclusive), whether the bound holds more than k or fewer.
        for (const std::size_t within : {std::size_t{0}, std::size_t{3}, std::size_t{12}}) {
          const double bound2 = expected[std::min(n - 1, within)].distance2;
          std::vector<Neighbor> out(8);
          out.resize(tree.knn(q, std::span<Neighbor>(out), bound2));
          std::vector<Neighbor> want;
          for (const Neighbor& nb : expected)
            if (nb.distance2 <= bound2 && want.size() < 8) want.push_back(nb);
          ASSERT_EQ(out, want) << "n=" << n << " bound to neighbour " << within;
        }
        const double r2 = expected[std::min<std::size_t>(n - 1, 9)].distance2;
        // Some point within the ball: at the nearest's own distance (inclusive)
        // yes, a hair below it no.
        ASSERT_TRUE(tree.any_within(q, expected[0].distance2));
        ASSERT_TRUE(tree.any_within(q, r2));
        ASSERT_EQ(tree.any_within(q, expected[0].distance2 * (1.0 - 1e-9) - 1e-300), false)
            << "nearest at " << expected[0].distance2;
        const auto in_ball = tree.radius(q, r2);
        const auto expected_ball =
            std::count_if(expected.begin(), expected.end(), [&](const Neighbor& nb) { return nb.distance2 <= r2; });
        ASSERT_EQ(in_ball.size(), static_cast<std::size_t>(expected_ball));
        for (std::size_t j = 0; j < in_ball.size(); ++j) ASSERT_EQ(in_ball[j], expected[j]);
      }
    }
  }
}

TEST(KdTree, KnnNearestRadiusMatchBruteForce3D) {
  check_against_brute_force<3>(Layout::uniform, 1);
  check_against_brute_force<3>(Layout::clustered, 2);
  check_against_brute_force<3>(Layout::duplicates, 3);
}

TEST(KdTree, KnnNearestRadiusMatchBruteForce2D) {
  check_against_brute_force<2>(Layout::uniform, 4);
  check_against_brute_force<2>(Layout::clustered, 5);
  check_against_brute_force<2>(Layout::duplicates, 6);
}

TEST(KdTree, RefittedTreeMatchesBruteForce) {
  for (const Fit fit : {Fit::refit_near, Fit::refit_far}) {
    check_against_brute_force<3>(Layout::uniform, 31, fit);
    check_against_brute_force<3>(Layout::clustered, 32, fit);
    check_against_brute_force<3>(Layout::duplicates, 33, fit);
    check_against_brute_force<2>(Layout::uniform, 34, fit);
    check_against_brute_force<2>(Layout::duplicates, 35, fit);
  }
}

TEST(KdTree, RefitKeepsTheShapeAndBoundsTheNewPoints) {
  std::mt19937 rng(36);
  const auto pts = make_points<3>(3000, Layout::clustered, 37);
  const KdTree<3> built(pts, {8});
  const KdTree<3> tree = make_tree<3>(pts, 8, Fit::refit_far, rng);
  ASSERT_EQ(tree.nodes().size(), built.nodes().size());
  for (std::size_t id = 0; id < tree.nodes().size(); ++id) {
    const auto& node = tree.nodes()[id];
    const Box<3>& box = tree.boxes()[id];
    for (auto t = node.begin; t < node.end; ++t) {
      const Vec3& p = pts[tree.order()[t]];
      ASSERT_EQ(tree.points()[t], p);
      ASSERT_TRUE((p.array() >= box.min.array()).all() && (p.array() <= box.max.array()).all());
    }
    if (!node.is_leaf()) {
      EXPECT_EQ(node.left_max, tree.boxes()[node.left].max[node.axis]);
      EXPECT_EQ(node.right_min, tree.boxes()[node.right].min[node.axis]);
    }
  }
  EXPECT_THROW((void)built.refit(std::span<const Vec3>(pts).first(10)), InvalidInputError);
  std::vector<Vec3> bad(pts);
  bad[5].y() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW((void)built.refit(bad), InvalidInputError);
}

TEST(KdTree, EmptyTreeAnswersNothing) {
  const KdTree<3> tree(std::span<const Vec3>{});
  EXPECT_TRUE(tree.empty());
  EXPECT_TRUE(tree.knn(Vec3::Zero(), 3).empty());
  EXPECT_TRUE(tree.radius(Vec3::Zero(), 1.0).empty());
}

TEST(KdTree, AllKnnRowsEqualSingleQueries) {
  // More points than two chunks of the parallel loop (4096), so that more
  // than one thread answers.
  const auto pts = make_points<3>(10000, Layout::clustered, 7);
  const KdTree<3> tree(pts);
  const KnnTable table = tree.all_knn(10);
  ASSERT_EQ(table.size(), pts.size());
  for (std::size_t i = 0; i < pts.size(); i += 37) {  // a sample of the rows: brute force is slow
    const auto row = table.row(i);
    const auto expected = brute_force(pts, pts[i]);
    for (std::size_t j = 0; j < 10; ++j) ASSERT_EQ(row[j], expected[j]);
  }
}

// The lab's counted all_knn: the same table as the plain one, and a count
// between k a point (every query looks at k points at least) and brute
// force's n * n, added to what the counts already hold.
TEST(KdTree, CountedAllKnnEqualsAllKnn) {
  const auto pts = make_points<3>(10000, Layout::clustered, 11);
  const KdTree<3> tree(pts);
  OperationCounts counts;
  counts.distance_evaluations = 7;
  const KnnTable counted = tree.all_knn(10, &counts);
  EXPECT_EQ(counted.k, 10);
  EXPECT_EQ(counted.entries, tree.all_knn(10).entries);
  EXPECT_EQ(tree.all_knn(10, nullptr).entries, counted.entries);
  EXPECT_GE(counts.distance_evaluations, 7u + 10000u * 10u);
  EXPECT_LT(counts.distance_evaluations, 10000u * 10000u / 10u);
  OperationCounts again;
  (void)tree.all_knn(10, &again);
  EXPECT_EQ(again.distance_evaluations + 7u, counts.distance_evaluations);  // the same searches, whatever the threads
  EXPECT_EQ(again.pushes + again.pops + again.comparisons, 0u);

  const auto flat = make_points<2>(3000, Layout::duplicates, 12);
  const KdTree<2> tree2d(flat, {4});
  OperationCounts counts2d;
  EXPECT_EQ(tree2d.all_knn(25, &counts2d).entries, tree2d.all_knn(25).entries);
  EXPECT_GE(counts2d.distance_evaluations, 3000u * 25u);
  EXPECT_THROW((void)tree.all_knn(0, &counts), InvalidInputError);
  EXPECT_THROW((void)tree.all_knn(10001, &counts), InvalidInputError);
}

TEST(KdTree, IsBalancedAndCoversEveryPointOnce) {
  const auto pts = make_points<3>(10000, Layout::duplicates, 8);  // heavy duplicates
  const KdTree<3> tree(pts, {8});
  // Median splits: depth is ceil(log2(n / leaf)) at most.
  EXPECT_LE(tree.depth(), static_cast<int>(std::ceil(std::log2(10000.0 / 8.0))));
  std::vector<int> seen(pts.size(), 0);
  for (auto i : tree.order()) ++seen[i];
  EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](int c) { return c == 1; }));
  for (const auto& node : tree.nodes()) {
    if (node.is_leaf()) {
      EXPECT_LE(node.end - node.begin, 8u);
      continue;
    }
    EXPECT_LE(node.left_max, node.right_min);
    for (auto t = node.begin; t < node.end; ++t) {
      const Vec3& p = pts[tree.order()[t]];
      const Box<3>& box = tree.boxes()[static_cast<std::size_t>(&node - tree.nodes().data())];
      EXPECT_TRUE((p.array() >= box.min.array()).all() && (p.array() <= box.max.array()).all());
    }
  }
}

TEST(KdTree, NearestWithOtherLabelMatchesBruteForce) {
  const auto pts = make_points<3>(2000, Layout::clustered, 9);
  std::vector<std::int32_t> labels(pts.size());
  std::mt19937 rng(10);
  for (std::size_t i = 0; i < pts.size(); ++i) labels[i] = static_cast<std::int32_t>(i % 5 == 0 ? rng() % 3 : i % 5);
  const KdTree<3> tree(pts, {4});
  const auto node_labels = tree.node_labels(labels);
  for (std::size_t q = 0; q < pts.size(); q += 13) {
    Neighbor expected{KdTree<3>::no_child, std::numeric_limits<double>::infinity()};
    for (const auto& nb : brute_force(pts, pts[q]))
      if (labels[nb.index] != labels[q]) {
        expected = nb;
        break;
      }
    const auto got =
        tree.nearest_with_other_label(pts[q], labels[q], labels, node_labels, std::numeric_limits<double>::infinity());
    ASSERT_EQ(got, expected);
    // A bound below the answer finds nothing; a bound equal to it finds it.
    const auto none = tree.nearest_with_other_label(pts[q], labels[q], labels, node_labels, expected.distance2 * 0.999);
    EXPECT_EQ(none.index, KdTree<3>::no_child);
    EXPECT_EQ(tree.nearest_with_other_label(pts[q], labels[q], labels, node_labels, expected.distance2), expected);
  }
}

// Masses of copies of one point (a scanner's "no return" as 0 0 0, over and
// over) take the searches' shortcuts: nodes of identical points, pruning by
// index once k copies are found. Results must stay those of brute force,
// with the tree numbered as built and by leaf order.
TEST(KdTree, MassesOfCopiesMatchBruteForce) {
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Vec3> input;
  for (int i = 0; i < 1500; ++i) input.emplace_back(unit(rng), unit(rng), unit(rng));
  const std::vector<Vec3> masses = {Vec3(0, 0, 0), input[7], Vec3(0.5, 0.5, 0.5)};
  for (const Vec3& m : masses) input.insert(input.end(), 400, m);
  std::shuffle(input.begin(), input.end(), rng);
  for (const int variant : {0, 1, 2}) {
    const bool renumber = variant >= 1;
    KdTree<3> tree(input, {8});
    if (renumber) (void)tree.renumber_by_leaf_order();
    if (variant == 2) {  // refitted to the very same points: copies stay copies, in index order
      std::vector<Vec3> same(tree.points().size());
      for (std::size_t t = 0; t < same.size(); ++t) same[tree.order()[t]] = tree.points()[t];
      tree = tree.refit(same);
    }
    // Positions as the tree numbers them.
    const std::vector<Vec3> pts(tree.points().begin(), tree.points().end());
    std::vector<Vec3> at(pts.size());
    for (std::size_t t = 0; t < pts.size(); ++t) at[tree.order()[t]] = pts[t];
    std::vector<std::int32_t> labels(at.size());
    for (std::size_t i = 0; i < at.size(); ++i) {
      labels[i] = static_cast<std::int32_t>(rng() % 4);
      for (std::size_t m = 0; m < 2; ++m)  // two masses of one label each, the third mixed
        if (at[i] == masses[m]) labels[i] = 10 + static_cast<std::int32_t>(m);
    }
    const auto node_labels = tree.node_labels(labels);
    std::vector<Vec3> queries(masses);
    for (int j = 0; j < 20; ++j) queries.emplace_back(unit(rng), unit(rng), unit(rng));
    for (int j = 0; j < 20; ++j) queries.push_back(at[rng() % at.size()]);
    for (const Vec3& q : queries) {
      const auto expected = brute_force(at, q);
      for (int k : {1, 5, 20}) {
        const auto got = tree.knn(q, k);
        for (std::size_t j = 0; j < got.size(); ++j) ASSERT_EQ(got[j], expected[j]) << "k=" << k << " j=" << j;
      }
      for (const std::int32_t own : {0, 10, 11}) {
        Neighbor want{KdTree<3>::no_child, std::numeric_limits<double>::infinity()};
        for (const Neighbor& nb : expected)
          if (labels[nb.index] != own) {
            want = nb;
            break;
          }
        ASSERT_EQ(tree.nearest_with_other_label(q, own, labels, node_labels, std::numeric_limits<double>::infinity()),
                  want)
            << "label " << own << (renumber ? ", leaf-numbered" : "") << (variant == 2 ? ", refitted" : "");
      }
    }
  }
}

}  // namespace
}  // namespace recon
