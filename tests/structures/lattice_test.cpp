// The lattice (lattice.h) and its hash table (lattice_table.h): the table
// agrees with std::unordered_map, keeps slots in insertion order through its
// growth, and the lattice's keys, positions and cells agree with each other.

#include "recon/structures/lattice.h"
#include "recon/structures/lattice_table.h"

#include "recon/core/errors.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <random>
#include <span>
#include <unordered_map>
#include <vector>

namespace recon {
namespace {

// Keys of two kinds: corners of a small lattice region (many repeats, the
// walk's case) and arbitrary 64-bit integers.
std::vector<std::uint64_t> random_keys(std::size_t n, std::uint32_t seed, bool lattice_like) {
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<std::int32_t> coordinate(0, 40);
  std::vector<std::uint64_t> keys;
  for (std::size_t i = 0; i < n; ++i)
    keys.push_back(lattice_like ? Lattice<3>::key({coordinate(rng), coordinate(rng), coordinate(rng)}) : rng());
  return keys;
}

TEST(LatticeTable, AgreesWithAnUnorderedMapAndNumbersKeysInInsertionOrder) {
  for (const bool lattice_like : {true, false}) {
    const std::vector<std::uint64_t> keys = random_keys(100'000, lattice_like ? 1 : 2, lattice_like);
    LatticeTable table;
    std::unordered_map<std::uint64_t, std::uint32_t> oracle;
    for (const std::uint64_t key : keys) {
      const auto [slot, added] = table.insert(key);
      const auto [it, oracle_added] = oracle.try_emplace(key, static_cast<std::uint32_t>(oracle.size()));
      ASSERT_EQ(added, oracle_added);
      ASSERT_EQ(slot, it->second);  // a new key gets the next slot; an old one keeps its own
      ASSERT_EQ(table.size(), oracle.size());
    }
    if (lattice_like) {
      EXPECT_LT(table.size(), keys.size());  // repeats did occur
    }
    for (const auto& [key, slot] : oracle) {
      ASSERT_EQ(table.find(key), slot);
      ASSERT_EQ(table.key(slot), key);
    }
    // Keys never inserted are absent.
    for (const std::uint64_t key : random_keys(10'000, 3, lattice_like))
      if (!oracle.contains(key)) {
        ASSERT_EQ(table.find(key), LatticeTable::absent);
      }
  }
}

TEST(LatticeTable, GrowsByDoublingAndStaysAtMostHalfFull) {
  LatticeTable table;
  EXPECT_EQ(table.size(), 0u);
  EXPECT_EQ(table.find(0), LatticeTable::absent);
  std::size_t growths = 0, capacity = table.capacity();
  for (std::uint64_t k = 0; k < 200'000; ++k) {
    table.insert(k * 7919);
    EXPECT_LE(2 * table.size(), table.capacity());
    if (table.capacity() != capacity) {
      EXPECT_EQ(table.capacity(), 2 * capacity);
      capacity = table.capacity();
      ++growths;
      // Every key is still found, in its slot, just after a growth.
      for (std::uint64_t j = 0; j <= k; ++j) ASSERT_EQ(table.find(j * 7919), j);
    }
  }
  EXPECT_GE(growths, 8u);
  EXPECT_EQ(capacity & (capacity - 1), 0u);  // a power of two
}

// The hash keeps each 4 x 4 x 4 block of corners together: its 64 corners
// fill one aligned run of 64 cells of the table.
TEST(LatticeTable, HashKeepsABlockOfCornersTogether) {
  for (const Lattice<3>::Index base : {Lattice<3>::Index{0, 0, 0}, Lattice<3>::Index{40, 8, 1200}}) {
    const std::size_t first = LatticeTable::hash(Lattice<3>::key(base), 16);
    for (std::int32_t k = 0; k < 4; ++k)
      for (std::int32_t j = 0; j < 4; ++j)
        for (std::int32_t i = 0; i < 4; ++i) {
          const std::size_t h = LatticeTable::hash(Lattice<3>::key({base[0] + i, base[1] + j, base[2] + k}), 16);
          EXPECT_LT(h, std::size_t{1} << 16);
          EXPECT_EQ(h >> 6, first >> 6);
          EXPECT_EQ(h & 63u, static_cast<std::size_t>(i + 4 * j + 16 * k));
        }
  }
}

TEST(Lattice, KeysRoundTripAndKeepAxesApart) {
  std::mt19937 rng(4);
  std::uniform_int_distribution<std::int32_t> c3(0, Lattice<3>::max_cells_per_axis);
  std::uniform_int_distribution<std::int32_t> c2(0, Lattice<2>::max_cells_per_axis);
  for (int n = 0; n < 1000; ++n) {
    const Lattice<3>::Index i{c3(rng), c3(rng), c3(rng)};
    EXPECT_EQ(Lattice<3>::index(Lattice<3>::key(i)), i);
    const Lattice<2>::Index j{c2(rng), c2(rng)};
    EXPECT_EQ(Lattice<2>::index(Lattice<2>::key(j)), j);
  }
  EXPECT_NE(Lattice<3>::key({1, 0, 0}), Lattice<3>::key({0, 1, 0}));
  EXPECT_NE(Lattice<3>::key({0, 1, 0}), Lattice<3>::key({0, 0, 1}));
  EXPECT_EQ(Lattice<3>::key({1, 2, 3}), 1u | (2u << 21) | (std::uint64_t{3} << 42));
  EXPECT_EQ(Lattice<2>::key({1, 2}), 1u | (std::uint64_t{2} << 32));
}

template <int D>
void check_lattice_over(std::span<const Vec<D>> seeds, double cell) {
  const Lattice<D> lattice = make_lattice<D>(seeds, cell);
  EXPECT_EQ(lattice.cell, cell);
  Box<D> box = bounding_box(seeds);
  for (int a = 0; a < D; ++a) {
    // lattice_margin cells of room below the lowest seed and above the highest.
    EXPECT_DOUBLE_EQ(lattice.origin[a], box.min[a] - lattice_margin * cell);
    const double top = lattice.origin[a] + lattice.size[static_cast<std::size_t>(a)] * cell;
    EXPECT_GE(top, box.max[a] + lattice_margin * cell - 1e-12);
    EXPECT_LT(top, box.max[a] + (lattice_margin + 1.0) * cell + 1e-12);
  }
  for (const Vec<D>& p : seeds) {
    const auto i = lattice.cell_of(p);
    EXPECT_TRUE(lattice.contains(i));
    auto upper = i;
    for (auto& c : upper) ++c;
    for (int a = 0; a < D; ++a) {  // p lies in its cell
      EXPECT_LE(lattice.position(i)[a], p[a]);
      EXPECT_GT(lattice.position(upper)[a], p[a]);
    }
  }
  typename Lattice<D>::Index outside{};
  outside[0] = -1;
  EXPECT_FALSE(lattice.contains(outside));
  outside[0] = lattice.size[0];
  EXPECT_FALSE(lattice.contains(outside));
}

TEST(Lattice, LiesOverTheSeedsWithItsMarginIn2DAnd3D) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-3.0, 7.0);
  std::vector<Vec3> seeds3;
  std::vector<Vec2> seeds2;
  for (int n = 0; n < 500; ++n) {
    seeds3.emplace_back(u(rng), u(rng), 0.1 * u(rng));
    seeds2.emplace_back(u(rng), 0.5 * u(rng));
  }
  check_lattice_over<3>(seeds3, 0.07);
  check_lattice_over<2>(seeds2, 0.13);
}

TEST(Lattice, RefusesBadCellsAndTooManyCellsPerAxis) {
  const std::vector<Vec3> seeds3 = {Vec3(0, 0, 0), Vec3(1, 1, 1)};
  const std::vector<Vec2> seeds2 = {Vec2(0, 0), Vec2(1, 1)};
  for (const double cell :
       {0.0, -1.0, std::numeric_limits<double>::infinity(), std::numeric_limits<double>::quiet_NaN()}) {
    EXPECT_THROW((void)make_lattice<3>(seeds3, cell), InvalidInputError) << cell;
    EXPECT_THROW((void)make_lattice<2>(seeds2, cell), InvalidInputError) << cell;
  }
  // 2^21 - 2 cubes along an axis fit the keys; 2^30 squares.
  EXPECT_THROW((void)make_lattice<3>(seeds3, 1.0 / (1 << 21)), ResourceLimitError);
  EXPECT_NO_THROW((void)make_lattice<3>(seeds3, 1.0 / (1 << 20)));
  EXPECT_THROW((void)make_lattice<2>(seeds2, 1.0 / (1 << 30)), ResourceLimitError);
  EXPECT_NO_THROW((void)make_lattice<2>(seeds2, 1.0 / (1 << 29)));
}

}  // namespace
}  // namespace recon
