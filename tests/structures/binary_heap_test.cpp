#include "recon/structures/binary_heap.h"

#include <gtest/gtest.h>

#include <random>
#include <set>

namespace recon {
namespace {

// Long random sequences of push / pop / decrease-key, checked step by step
// against an ordered set of (key, item) pairs.
TEST(BinaryHeap, MatchesOrderedSetOracle) {
  for (std::uint32_t seed = 1; seed <= 5; ++seed) {
    std::mt19937 rng(seed);
    const std::uint32_t capacity = 1 + seed * 97;
    IndexedBinaryHeap<double> heap(capacity);
    std::set<std::pair<double, std::uint32_t>> oracle;
    std::vector<double> key_of(capacity);
    // Few distinct keys so that ties (broken by item) are common.
    std::uniform_int_distribution<int> small_key(0, 20);
    for (int step = 0; step < 50000; ++step) {
      const int op = static_cast<int>(rng() % 3);
      const std::uint32_t item = static_cast<std::uint32_t>(rng() % capacity);
      if (op == 0 && !heap.contains(item)) {
        const double k = small_key(rng);
        heap.push(item, k);
        oracle.insert({k, item});
        key_of[item] = k;
      } else if (op == 1 && heap.contains(item)) {
        const double k = key_of[item] - static_cast<double>(rng() % 4);
        oracle.erase({key_of[item], item});
        oracle.insert({k, item});
        heap.decrease_key(item, k);
        key_of[item] = k;
      } else if (op == 2 && !heap.empty()) {
        const auto expected = *oracle.begin();
        ASSERT_EQ(heap.top(), expected.second);
        ASSERT_EQ(heap.top_key(), expected.first);
        ASSERT_EQ(heap.pop(), expected.second);
        oracle.erase(oracle.begin());
      }
      ASSERT_EQ(heap.size(), oracle.size());
    }
    while (!heap.empty()) {
      ASSERT_EQ(heap.pop(), oracle.begin()->second);
      oracle.erase(oracle.begin());
    }
    ASSERT_TRUE(oracle.empty());
  }
}

}  // namespace
}  // namespace recon
