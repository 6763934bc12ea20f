// The priority queues with decrease-key of the alternatives lab: every queue
// against one oracle, the same order everywhere (by key, then by item), and
// the counts of CountingQueue.

#include "recon/alternatives/counting_queue.h"
#include "recon/structures/binary_heap.h"
#include "recon/structures/fibonacci_heap.h"
#include "recon/structures/indexed_heap.h"
#include "recon/structures/list_heap.h"
#include "recon/structures/pairing_heap.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <numeric>
#include <random>
#include <set>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace recon {
namespace {

// The oracle: the queued (key, item) pairs in an ordered set, whose order is
// the queues' order, plus each item's key.
class Oracle {
 public:
  explicit Oracle(std::size_t capacity) : key_of_(capacity), queued_(capacity, false) {}

  [[nodiscard]] bool empty() const { return set_.empty(); }
  [[nodiscard]] std::size_t size() const { return set_.size(); }
  [[nodiscard]] bool contains(std::uint32_t item) const { return queued_[item]; }
  [[nodiscard]] double key(std::uint32_t item) const { return key_of_[item]; }
  [[nodiscard]] std::pair<double, std::uint32_t> top() const { return *set_.begin(); }

  void push(std::uint32_t item, double key) {
    set_.insert({key, item});
    key_of_[item] = key;
    queued_[item] = true;
  }
  std::uint32_t pop() {
    const std::uint32_t item = set_.begin()->second;
    set_.erase(set_.begin());
    queued_[item] = false;
    return item;
  }
  void decrease_key(std::uint32_t item, double key) {
    set_.erase({key_of_[item], item});
    push(item, key);
  }
  void clear() {
    set_.clear();
    std::fill(queued_.begin(), queued_.end(), false);
  }
  void erase(std::uint32_t item) {
    set_.erase({key_of_[item], item});
    queued_[item] = false;
  }

 private:
  std::set<std::pair<double, std::uint32_t>> set_;
  std::vector<double> key_of_;
  std::vector<bool> queued_;
};

template <class Queue>
::testing::AssertionResult agrees(const Queue& queue, const Oracle& oracle, std::uint32_t item) {
  if (queue.size() != oracle.size() || queue.empty() != oracle.empty())
    return ::testing::AssertionFailure() << "size " << queue.size() << ", expected " << oracle.size();
  if (!oracle.empty()) {
    const auto [key, top] = oracle.top();
    if (queue.top() != top || queue.top_key() != key)
      return ::testing::AssertionFailure()
             << "top " << queue.top() << " with key " << queue.top_key() << ", expected " << top << " with key " << key;
  }
  if (queue.contains(item) != oracle.contains(item))
    return ::testing::AssertionFailure() << "contains(" << item << ") is " << queue.contains(item);
  if (oracle.contains(item) && queue.key(item) != oracle.key(item))
    return ::testing::AssertionFailure() << "key(" << item << ") is " << queue.key(item) << ", expected "
                                         << oracle.key(item);
  return ::testing::AssertionSuccess();
}

template <class Queue>
::testing::AssertionResult agrees_on_every_item(const Queue& queue, const Oracle& oracle) {
  for (std::uint32_t item = 0; item < queue.capacity(); ++item) {
    const auto result = agrees(queue, oracle, item);
    if (!result) return result;
  }
  return ::testing::AssertionSuccess();
}

// Pops everything, returning the items in the order they left.
template <class Queue>
std::vector<std::uint32_t> pop_all(Queue& queue) {
  std::vector<std::uint32_t> items;
  while (!queue.empty()) items.push_back(queue.pop());
  return items;
}

// The items 0..n-1 in a random order.
std::vector<std::uint32_t> shuffled_items(std::uint32_t n, std::mt19937& rng) {
  std::vector<std::uint32_t> items(n);
  std::iota(items.begin(), items.end(), 0u);
  std::shuffle(items.begin(), items.end(), rng);
  return items;
}

// Keys are small integers, so ties (broken by item) are common.
double small_key(std::mt19937& rng) { return std::uniform_int_distribution<int>(0, 20)(rng); }

// Prim's relaxation step: the queue's own push_or_decrease where it has one
// (CountingQueue counts it), else indexed_heap.h's.
template <class Queue>
bool relax(Queue& queue, std::uint32_t item, double key) {
  if constexpr (requires { queue.push_or_decrease(item, key); }) {
    return queue.push_or_decrease(item, key);
  } else {
    return push_or_decrease(queue, item, key);
  }
}

// One step on the queue and the oracle alike: a push, or a pop when there
// is something to pop.
template <class Queue>
void push_both(Queue& queue, Oracle& oracle, std::uint32_t item, double key) {
  queue.push(item, key);
  oracle.push(item, key);
}
template <class Queue>
void pop_both(Queue& queue, Oracle& oracle, int step) {
  if (!oracle.empty()) {
    ASSERT_EQ(queue.pop(), oracle.pop()) << "step " << step;
  }
}

// Long random sequences checked step by step against the oracle: for seeds 1
// to 4, a queue of capacity 1 + seed * capacity_per_seed runs 20,000 calls
// step(queue, oracle, rng, op, item, i), op and item drawn here (op below
// `ops`); after each the queue must agree with the oracle on the item (on
// every item each 500 steps), and at the end pop in the oracle's order.
template <class Queue, class Step>
void run_against_oracle(std::uint32_t capacity_per_seed, std::uint32_t ops, Step&& step) {
  for (std::uint32_t seed = 1; seed <= 4; ++seed) {
    std::mt19937 rng(seed);
    const std::uint32_t capacity = 1 + seed * capacity_per_seed;
    Queue queue(capacity);
    Oracle oracle(capacity);
    for (int i = 0; i < 20000; ++i) {
      const auto op = rng() % ops;
      const std::uint32_t item = static_cast<std::uint32_t>(rng() % capacity);
      step(queue, oracle, rng, op, item, i);
      if (::testing::Test::HasFatalFailure()) return;
      ASSERT_TRUE(agrees(queue, oracle, item)) << "step " << i;
      if (i % 500 == 0) {
        ASSERT_TRUE(agrees_on_every_item(queue, oracle)) << "step " << i;
      }
    }
    while (!oracle.empty()) ASSERT_EQ(queue.pop(), oracle.pop());
    ASSERT_TRUE(agrees_on_every_item(queue, oracle));
  }
}

template <class Queue>
class PriorityQueue : public ::testing::Test {};

using Queues = ::testing::Types<IndexedBinaryHeap<double>, FibonacciHeap<double>, PairingHeap<double>, ListHeap<double>,
                                CountingQueue<IndexedBinaryHeap>, CountingQueue<FibonacciHeap>,
                                CountingQueue<PairingHeap>, CountingQueue<ListHeap>>;

struct QueueNames {
  template <class Queue>
  static std::string GetName(int) {
    if constexpr (std::is_same_v<Queue, IndexedBinaryHeap<double>>) return "BinaryHeap";
    if constexpr (std::is_same_v<Queue, FibonacciHeap<double>>) return "FibonacciHeap";
    if constexpr (std::is_same_v<Queue, PairingHeap<double>>) return "PairingHeap";
    if constexpr (std::is_same_v<Queue, ListHeap<double>>) return "ListHeap";
    if constexpr (std::is_same_v<Queue, CountingQueue<IndexedBinaryHeap>>) return "CountingBinaryHeap";
    if constexpr (std::is_same_v<Queue, CountingQueue<FibonacciHeap>>) return "CountingFibonacciHeap";
    if constexpr (std::is_same_v<Queue, CountingQueue<PairingHeap>>) return "CountingPairingHeap";
    if constexpr (std::is_same_v<Queue, CountingQueue<ListHeap>>) return "CountingListHeap";
    return "Unnamed";
  }
};

TYPED_TEST_SUITE(PriorityQueue, Queues, QueueNames);

// Every operation against the oracle; decrease_key often leaves the key as
// it was.
TYPED_TEST(PriorityQueue, MatchesOrderedSetOracle) {
  run_against_oracle<TypeParam>(
      61, 1000, [](TypeParam& queue, Oracle& oracle, std::mt19937& rng, auto op, std::uint32_t item, int step) {
        if (op < 300) {
          if (!oracle.contains(item)) push_both(queue, oracle, item, small_key(rng));
        } else if (op < 530) {
          pop_both(queue, oracle, step);
        } else if (op < 780) {
          if (oracle.contains(item)) {
            const double k = oracle.key(item) - static_cast<double>(rng() % 4);
            queue.decrease_key(item, k);
            oracle.decrease_key(item, k);
          }
        } else if (op < 999) {
          const double k = small_key(rng);
          const bool lowers = !oracle.contains(item) || k < oracle.key(item);
          ASSERT_EQ(relax(queue, item, k), lowers) << "step " << step;
          if (lowers && oracle.contains(item)) {
            oracle.decrease_key(item, k);
          } else if (lowers) {
            oracle.push(item, k);
          }
        } else {
          queue.clear();
          oracle.clear();
          ASSERT_TRUE(agrees_on_every_item(queue, oracle)) << "after clear at step " << step;
        }
        const std::uint32_t other = static_cast<std::uint32_t>(rng() % queue.capacity());
        ASSERT_TRUE(agrees(queue, oracle, other)) << "step " << step;
      });
}

TYPED_TEST(PriorityQueue, SingleItem) {
  TypeParam queue(1);
  EXPECT_EQ(queue.capacity(), 1u);
  EXPECT_TRUE(queue.empty());
  EXPECT_FALSE(queue.contains(0));
  queue.push(0, 3.5);
  EXPECT_FALSE(queue.empty());
  EXPECT_EQ(queue.size(), 1u);
  EXPECT_TRUE(queue.contains(0));
  EXPECT_EQ(queue.top(), 0u);
  EXPECT_EQ(queue.top_key(), 3.5);
  queue.decrease_key(0, 3.5);
  queue.decrease_key(0, 1.0);
  EXPECT_EQ(queue.key(0), 1.0);
  EXPECT_EQ(queue.pop(), 0u);
  EXPECT_TRUE(queue.empty());
  EXPECT_FALSE(queue.contains(0));
  EXPECT_TRUE(relax(queue, 0, 2.0));
  EXPECT_EQ(queue.top_key(), 2.0);
  EXPECT_EQ(queue.pop(), 0u);
  EXPECT_TRUE(queue.empty());
}

TYPED_TEST(PriorityQueue, CapacityZero) {
  for (TypeParam queue : {TypeParam(), TypeParam(0)}) {
    EXPECT_EQ(queue.capacity(), 0u);
    EXPECT_EQ(queue.size(), 0u);
    EXPECT_TRUE(queue.empty());
    queue.clear();
    EXPECT_TRUE(queue.empty());
  }
}

// Lowering a key to the value it has changes nothing, and a key lowered to
// equal others' takes its place among them by item.
TYPED_TEST(PriorityQueue, DecreaseToEqualKey) {
  TypeParam queue(6);
  const double keys[] = {5, 3, 3, 7, 3, 9};
  for (std::uint32_t item = 0; item < 6; ++item) queue.push(item, keys[item]);
  queue.decrease_key(3, 7.0);  // equal, not the top
  queue.decrease_key(1, 3.0);  // equal, the top
  EXPECT_FALSE(relax(queue, 4, 3.0));
  EXPECT_EQ(queue.top(), 1u);
  queue.decrease_key(5, 3.0);  // joins items 1, 2 and 4 at key 3, after them
  EXPECT_EQ(pop_all(queue), (std::vector<std::uint32_t>{1, 2, 4, 5, 0, 3}));
}

TYPED_TEST(PriorityQueue, DecreaseTheTop) {
  TypeParam queue(4);
  for (std::uint32_t item = 0; item < 4; ++item) queue.push(item, 1.0 + item);
  queue.decrease_key(0, 0.5);
  EXPECT_EQ(queue.top(), 0u);
  EXPECT_EQ(queue.top_key(), 0.5);
  queue.decrease_key(3, 0.5);  // ties with the top: the smaller item stays first
  EXPECT_EQ(queue.top(), 0u);
  queue.decrease_key(3, 0.25);
  EXPECT_EQ(queue.top(), 3u);
  EXPECT_EQ(queue.top_key(), 0.25);
  EXPECT_EQ(pop_all(queue), (std::vector<std::uint32_t>{3, 0, 1, 2}));
}

// Pushed in a random order with many equal keys, then some keys lowered:
// popping everything gives the (key, item) pairs sorted.
TYPED_TEST(PriorityQueue, PopAllIsSortedOrder) {
  const std::uint32_t n = 1000;
  std::mt19937 rng(7);
  std::vector<std::uint32_t> items = shuffled_items(n, rng);
  std::vector<double> key(n);
  TypeParam queue(n);
  for (std::uint32_t item : items) {
    key[item] = static_cast<double>(rng() % 50);
    queue.push(item, key[item]);
  }
  for (std::uint32_t item = 0; item < n; item += 3) {
    key[item] -= static_cast<double>(rng() % 30);
    queue.decrease_key(item, key[item]);
  }
  std::sort(items.begin(), items.end(),
            [&](std::uint32_t a, std::uint32_t b) { return std::pair(key[a], a) < std::pair(key[b], b); });
  EXPECT_EQ(pop_all(queue), items);
}

TYPED_TEST(PriorityQueue, ReuseAfterClear) {
  const std::uint32_t n = 40;
  TypeParam queue(n);
  for (std::uint32_t item = 0; item < n; ++item) queue.push(item, static_cast<double>(item % 7));
  for (int i = 0; i < 5; ++i) queue.pop();  // leaves trees behind in the linked heaps
  queue.decrease_key(30, -1.0);
  queue.decrease_key(17, -1.0);
  queue.clear();
  EXPECT_TRUE(queue.empty());
  EXPECT_EQ(queue.size(), 0u);
  for (std::uint32_t item = 0; item < n; ++item) EXPECT_FALSE(queue.contains(item)) << item;
  queue.clear();  // clearing an empty queue
  EXPECT_TRUE(queue.empty());

  std::vector<std::uint32_t> expected;
  for (std::uint32_t item = n; item-- > 0;) {
    queue.push(item, 1.0);
    expected.insert(expected.begin(), item);
  }
  EXPECT_EQ(queue.size(), n);
  EXPECT_EQ(pop_all(queue), expected);
}

TYPED_TEST(PriorityQueue, PushOrDecreaseOnlyLowers) {
  TypeParam queue(4);
  EXPECT_TRUE(relax(queue, 2, 5.0));
  EXPECT_FALSE(relax(queue, 2, 7.0));
  EXPECT_FALSE(relax(queue, 2, 5.0));
  EXPECT_EQ(queue.key(2), 5.0);
  EXPECT_TRUE(relax(queue, 2, 1.0));
  EXPECT_EQ(queue.key(2), 1.0);
  queue.clear();
  EXPECT_TRUE(queue.empty());
  EXPECT_FALSE(queue.contains(2));
}

// CountingQueue over each heap.

template <class Queue>
class PriorityQueueCounts : public ::testing::Test {};

using CountingQueues = ::testing::Types<CountingQueue<IndexedBinaryHeap>, CountingQueue<FibonacciHeap>,
                                        CountingQueue<PairingHeap>, CountingQueue<ListHeap>>;
TYPED_TEST_SUITE(PriorityQueueCounts, CountingQueues, QueueNames);

TYPED_TEST(PriorityQueueCounts, ExactForAScriptedSequence) {
  TypeParam queue(8);
  queue.push(0, 5.0);
  queue.push(1, 3.0);
  queue.push(2, 8.0);
  queue.push(3, 3.0);
  queue.push(4, 1.0);
  queue.decrease_key(2, 2.0);
  queue.decrease_key(0, 0.5);
  EXPECT_TRUE(queue.push_or_decrease(5, 4.0));   // a push
  EXPECT_TRUE(queue.push_or_decrease(1, 1.0));   // a decrease_key
  EXPECT_FALSE(queue.push_or_decrease(3, 9.0));  // nothing
  EXPECT_FALSE(queue.push_or_decrease(3, 3.0));  // nothing
  EXPECT_EQ(queue.pop(), 0u);
  EXPECT_EQ(queue.pop(), 1u);
  EXPECT_EQ(queue.pop(), 4u);
  queue.clear();

  OperationCounts expected;
  expected.pushes = 6;
  expected.pops = 3;
  expected.decrease_keys = 3;
  expected.comparisons = queue.counts().comparisons;
  EXPECT_EQ(queue.counts(), expected);
  EXPECT_GT(queue.counts().comparisons, 0u);
}

// Each queue counts its own comparisons, even when two queues on one thread
// take turns.
TYPED_TEST(PriorityQueueCounts, InterleavedQueuesCountSeparately) {
  auto run = [](TypeParam& queue, std::uint32_t step, double scale) {
    const auto item = static_cast<std::uint32_t>(step % 16);
    if (step % 5 == 4) {
      if (!queue.empty()) queue.pop();
    } else {
      queue.push_or_decrease(item, scale * static_cast<double>((step * 7) % 11));
    }
  };
  TypeParam alone_a(16), alone_b(16), a(16), b(16);
  for (std::uint32_t step = 0; step < 200; ++step) run(alone_a, step, 1.0);
  for (std::uint32_t step = 0; step < 200; ++step) run(alone_b, step, -1.0);
  for (std::uint32_t step = 0; step < 200; ++step) {
    run(a, step, 1.0);
    run(b, step, -1.0);
  }
  EXPECT_EQ(a.counts(), alone_a.counts());
  EXPECT_EQ(b.counts(), alone_b.counts());
}

TEST(PriorityQueueCounts, CountedKeyCountsEachComparison) {
  const std::uint64_t before = CountedKey::comparisons;
  EXPECT_TRUE(CountedKey{1.0} < CountedKey{2.0});
  EXPECT_FALSE(CountedKey{2.0} < CountedKey{2.0});
  EXPECT_EQ(CountedKey::comparisons - before, 2u);
}

// The list heap's pop scans the items left: at size s it compares the s - 1
// items that stay, s - 2 comparisons of (key, item) pairs; with distinct keys
// each costs one or two calls of operator< on keys. (The smallest is cached,
// so it is not compared again.)
TEST(PriorityQueueCounts, ListHeapPopScansTheItemsLeft) {
  const std::uint32_t n = 50;
  std::mt19937 rng(3);
  const std::vector<std::uint32_t> order = shuffled_items(n, rng);
  CountingQueue<ListHeap> queue(n);
  for (std::uint32_t i = 0; i < n; ++i) queue.push(order[i], static_cast<double>(i));  // distinct keys
  while (queue.size() > 1) {
    const std::uint64_t scan = queue.size() - 2;
    const std::uint64_t before = queue.counts().comparisons;
    queue.pop();
    const std::uint64_t made = queue.counts().comparisons - before;
    EXPECT_GE(made, scan);
    EXPECT_LE(made, 2 * scan);
  }
}

// Decrease-key-heavy: m items, each lowered once to a new minimum, after a
// pop has built the Fibonacci heap's trees.
// - Binary heap: a new minimum climbs to the root, one comparison per level
//   (true at once: one operator< call). No other item ever moves up meanwhile,
//   so each item climbs at least from the depth of its slot when the decreases
//   began, and these slots are 0..m-1: at least sum floor(log2 k), k = 1..m.
// - Fibonacci heap: at most one comparison with the parent, one with the
//   minimum, and one more per cascading cut; a cut unmarks a node that a
//   decrease marked (none was marked before), so over m decreases at most 3m
//   comparisons of (key, item) pairs, at most 2 calls of operator< each.
// - Pairing heap: one meld per decrease, at most 2 calls of operator<.
TEST(PriorityQueueCounts, FibonacciComparesLessThanBinaryOnDecreaseKeys) {
  const std::uint32_t m = 1023;
  CountingQueue<IndexedBinaryHeap> binary(m + 1);
  CountingQueue<FibonacciHeap> fibonacci(m + 1);
  CountingQueue<PairingHeap> pairing(m + 1);
  auto decreases = [&](auto& queue) {
    for (std::uint32_t item = 0; item <= m; ++item) queue.push(item, 1000.0 + item);
    EXPECT_EQ(queue.pop(), 0u);
    const std::uint64_t before = queue.counts().comparisons;
    for (std::uint32_t item = 1; item <= m; ++item) queue.decrease_key(item, -static_cast<double>(item));
    const std::uint64_t made = queue.counts().comparisons - before;
    std::vector<std::uint32_t> expected(m);
    std::iota(expected.rbegin(), expected.rend(), 1u);
    EXPECT_EQ(pop_all(queue), expected);
    return made;
  };
  std::uint64_t binary_bound = 0;
  for (std::uint32_t k = 2; k <= m; ++k) binary_bound += static_cast<std::uint64_t>(std::bit_width(k) - 1);

  const std::uint64_t binary_made = decreases(binary);
  const std::uint64_t fibonacci_made = decreases(fibonacci);
  const std::uint64_t pairing_made = decreases(pairing);
  EXPECT_GE(binary_made, binary_bound);
  EXPECT_LE(fibonacci_made, 6u * m);
  EXPECT_LE(pairing_made, 2u * m);
  EXPECT_GT(binary_made, fibonacci_made);
}

}  // namespace
}  // namespace recon

namespace recon {
namespace {

// The heaps that also raise keys and remove items (mesh simplification,
// simplification.h): update_key either way and erase, against the oracle.
template <class Queue>
class UpdatableQueue : public ::testing::Test {};
using UpdatableQueues = ::testing::Types<IndexedBinaryHeap<double>, PairingHeap<double>>;
TYPED_TEST_SUITE(UpdatableQueue, UpdatableQueues);

TYPED_TEST(UpdatableQueue, UpdateAndEraseMatchTheOracle) {
  run_against_oracle<TypeParam>(
      53, 100, [](TypeParam& queue, Oracle& oracle, std::mt19937& rng, auto op, std::uint32_t item, int step) {
        const double k = small_key(rng);
        if (op < 30) {
          if (!oracle.contains(item)) push_both(queue, oracle, item, k);
        } else if (op < 50) {
          pop_both(queue, oracle, step);
        } else if (op < 80) {
          if (oracle.contains(item)) {
            queue.update_key(item, k);  // up or down
            oracle.decrease_key(item, k);
          }
        } else if (oracle.contains(item)) {
          queue.erase(item);
          oracle.erase(item);
        }
      });
}

TYPED_TEST(UpdatableQueue, EraseTheTopTheLastAndTheOnlyItem) {
  TypeParam queue(4);
  queue.push(0, 1.0);
  queue.erase(0);
  EXPECT_TRUE(queue.empty());
  queue.push(1, 1.0);
  queue.push(2, 2.0);
  queue.push(3, 3.0);
  queue.erase(1);  // the top
  EXPECT_EQ(queue.top(), 2u);
  queue.erase(3);
  EXPECT_EQ(queue.pop(), 2u);
  EXPECT_TRUE(queue.empty());
  queue.push(1, 5.0);
  queue.push(2, 6.0);
  queue.update_key(1, 7.0);  // raised past 2
  EXPECT_EQ(queue.pop(), 2u);
  EXPECT_EQ(queue.pop(), 1u);
}

}  // namespace
}  // namespace recon
