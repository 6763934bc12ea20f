#include "recon/structures/union_find.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>
#include <vector>

namespace recon {
namespace {

// Oracle: a label per element; a union relabels the whole of one set.
struct NaiveSets {
  std::vector<std::uint32_t> label;
  explicit NaiveSets(std::size_t n) : label(n) {
    for (std::uint32_t i = 0; i < n; ++i) label[i] = i;
  }
  bool unite(std::uint32_t a, std::uint32_t b) {
    const std::uint32_t from = label[b], to = label[a];
    if (from == to) return false;
    std::replace(label.begin(), label.end(), from, to);
    return true;
  }
  [[nodiscard]] std::size_t set_count() const { return std::set<std::uint32_t>(label.begin(), label.end()).size(); }
  [[nodiscard]] std::uint32_t set_size(std::uint32_t x) const {
    return static_cast<std::uint32_t>(std::count(label.begin(), label.end(), label[x]));
  }
};

TEST(UnionFind, MatchesNaiveLabelling) {
  for (std::uint32_t seed = 1; seed <= 10; ++seed) {
    std::mt19937 rng(seed);
    const std::size_t n = 1 + seed * 37;
    auto any = [&] { return static_cast<std::uint32_t>(rng() % n); };
    UnionFind sets(n);
    NaiveSets oracle(n);
    for (std::size_t step = 0; step < 2 * n; ++step) {
      const std::uint32_t a = any(), b = any();
      ASSERT_EQ(sets.unite(a, b), oracle.unite(a, b));
      ASSERT_EQ(sets.set_count(), oracle.set_count());
      // A few random pairs: one set for the union-find exactly when one label.
      for (int probe = 0; probe < 5; ++probe) {
        const std::uint32_t x = any(), y = any();
        ASSERT_EQ(sets.find(x) == sets.find(y), oracle.label[x] == oracle.label[y]);
        ASSERT_EQ(sets.root(x), sets.find(x));
        ASSERT_EQ(sets.set_size(x), oracle.set_size(x));
      }
    }
  }
}

TEST(UnionFind, CountsFindsAndUnions) {
  UnionFind sets(6);
  EXPECT_EQ(sets.finds(), 0u);
  EXPECT_EQ(sets.unions(), 0u);
  EXPECT_TRUE(sets.unite(0, 1));  // two finds, a union
  EXPECT_TRUE(sets.unite(2, 3));
  EXPECT_FALSE(sets.unite(1, 0));  // two finds, no union
  EXPECT_EQ(sets.finds(), 6u);
  EXPECT_EQ(sets.unions(), 2u);
  (void)sets.find(4);
  (void)sets.set_size(2);  // a find
  (void)sets.root(5);      // changes nothing, counts nothing
  EXPECT_EQ(sets.finds(), 8u);
  EXPECT_EQ(sets.unions(), 2u);
  EXPECT_EQ(sets.set_count(), 4u);
}

TEST(UnionFind, UnionBySizeKeepsTheLargerRoot) {
  UnionFind sets(5);
  sets.unite(1, 2);
  sets.unite(1, 3);
  const std::uint32_t big = sets.find(1);
  sets.unite(4, 1);  // the singleton goes under the set of three
  EXPECT_EQ(sets.find(4), big);
  EXPECT_EQ(sets.set_size(4), 4u);
}

TEST(UnionFind, Empty) {
  UnionFind sets(0);
  EXPECT_EQ(sets.set_count(), 0u);
}

// Sets added one at a time (the stitch of tiles.h grows its sets as it reads).
TEST(UnionFind, AddGrowsBySingletons) {
  UnionFind sets(0);
  for (std::uint32_t i = 0; i < 5; ++i) EXPECT_EQ(sets.add(), i);
  EXPECT_EQ(sets.size(), 5u);
  EXPECT_EQ(sets.set_count(), 5u);
  EXPECT_TRUE(sets.unite(0, 4));
  EXPECT_EQ(sets.add(), 5u);
  EXPECT_TRUE(sets.unite(5, 4));
  EXPECT_EQ(sets.set_count(), 4u);
  EXPECT_EQ(sets.find(5), sets.find(0));
  EXPECT_EQ(sets.set_size(5), 3u);
}

}  // namespace
}  // namespace recon
