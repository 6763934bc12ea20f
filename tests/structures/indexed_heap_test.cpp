// The concepts of indexed_heap.h: every heap and CountingQueue are an
// IndexedMinHeap, a type missing an operation or with a wrong signature is
// not, and a queue with only what Prim calls is a DecreaseKeyQueue. All checked at compile time: this file compiles or
// the test fails. (push_or_decrease, written once over the concept, is tested on every queue in
// priority_queues_test.cpp.)

#include "recon/structures/indexed_heap.h"
#include "recon/alternatives/counting_queue.h"
#include "recon/structures/binary_heap.h"
#include "recon/structures/fibonacci_heap.h"
#include "recon/structures/list_heap.h"
#include "recon/structures/pairing_heap.h"

#include <cstddef>
#include <cstdint>
#include <type_traits>

namespace recon {
namespace {

static_assert(IndexedMinHeap<IndexedBinaryHeap<double>, double>);
static_assert(IndexedMinHeap<PairingHeap<double>, double>);
static_assert(IndexedMinHeap<FibonacciHeap<double>, double>);
static_assert(IndexedMinHeap<ListHeap<double>, double>);
static_assert(IndexedMinHeap<IndexedBinaryHeap<int>, int>);
static_assert(IndexedMinHeap<PairingHeap<CountedKey>, CountedKey>);
static_assert(IndexedMinHeap<CountingQueue<IndexedBinaryHeap>, double>);
static_assert(IndexedMinHeap<CountingQueue<FibonacciHeap>, double>);
static_assert(IndexedMinHeap<CountingQueue<PairingHeap>, double>);
static_assert(IndexedMinHeap<CountingQueue<ListHeap>, double>);

// A complete heap interface, declared only (the concept reads forms alone),
// with one operation taken away or changed at a time by the flags.
struct Has {
  bool decrease_key = true;
  bool pop_returns_item = true;
  bool clear = true;
  bool sized = true;
};

template <Has has>
struct FakeHeap {
  static constexpr std::uint32_t absent = UINT32_MAX;
  explicit FakeHeap(std::size_t capacity);
  [[nodiscard]] bool empty() const;
  [[nodiscard]] std::size_t size() const requires(has.sized);
  [[nodiscard]] std::size_t capacity() const;
  [[nodiscard]] bool contains(std::uint32_t item) const;
  [[nodiscard]] const double& key(std::uint32_t item) const;
  [[nodiscard]] std::uint32_t top() const;
  [[nodiscard]] const double& top_key() const;
  void push(std::uint32_t item, double key);
  auto pop() -> std::conditional_t<has.pop_returns_item, std::uint32_t, void>;
  void decrease_key(std::uint32_t item, double key) requires(has.decrease_key);
  void clear() requires(has.clear);
};

static_assert(IndexedMinHeap<FakeHeap<Has{}>, double>, "the complete fake is a heap");
static_assert(!IndexedMinHeap<FakeHeap<Has{.decrease_key = false}>, double>, "no decrease_key");
static_assert(!IndexedMinHeap<FakeHeap<Has{.pop_returns_item = false}>, double>, "pop returns nothing");
static_assert(!IndexedMinHeap<FakeHeap<Has{.clear = false}>, double>, "no clear");
static_assert(!IndexedMinHeap<FakeHeap<Has{.sized = false}>, double>, "no size");
static_assert(!IndexedMinHeap<FakeHeap<Has{}>, const char*>, "keys of another type");

// What Prim's loop calls, and no more (minimum_spanning_tree_test.cpp's
// TallyingQueue): a DecreaseKeyQueue, not an IndexedMinHeap.
struct PrimsQueue {
  explicit PrimsQueue(std::size_t capacity);
  [[nodiscard]] bool empty() const;
  [[nodiscard]] double top_key() const;
  void push(std::uint32_t item, double key);
  std::uint32_t pop();
  void decrease_key(std::uint32_t item, double key);
};
static_assert(DecreaseKeyQueue<PrimsQueue, double>);
static_assert(!IndexedMinHeap<PrimsQueue, double>);
static_assert(DecreaseKeyQueue<FakeHeap<Has{.clear = false}>, double>, "clear is not Prim's");
static_assert(!DecreaseKeyQueue<FakeHeap<Has{.decrease_key = false}>, double>);

// A plain priority queue without items (std::priority_queue's interface).
struct PlainQueue {
  explicit PlainQueue(std::size_t capacity);
  [[nodiscard]] bool empty() const;
  [[nodiscard]] std::size_t size() const;
  [[nodiscard]] const double& top() const;
  void push(double key);
  void pop();
};
static_assert(!IndexedMinHeap<PlainQueue, double>);
static_assert(!DecreaseKeyQueue<PlainQueue, double>);

}  // namespace
}  // namespace recon
