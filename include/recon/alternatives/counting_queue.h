#pragma once
// Instrumentation for the alternatives lab: a priority queue that counts what
// it does, so that the lab can print, beside each run's time, how many
// pushes, pops, decrease-keys and key comparisons each queue needed.
//
// CountingQueue<Heap> wraps Heap<CountedKey> (Heap is IndexedBinaryHeap,
// FibonacciHeap, PairingHeap or ListHeap: any IndexedMinHeap, indexed_heap.h)
// and is an IndexedMinHeap with double keys itself, so Prim can be
// instantiated with it in place of IndexedBinaryHeap<double>. The heaps themselves are not touched: counting
// happens only here, and the default path (a plain heap of doubles) counts
// nothing.
//
// How comparisons are counted: CountedKey's operator< adds one to a running
// total, `CountedKey::comparisons`, kept per thread (thread_local) so that
// queues on different threads neither race nor mix their counts. The total
// is never reset; each CountingQueue call reads it before and after calling
// the heap and adds the difference to its own counts, so several queues on
// one thread each count only their own comparisons. Counted are calls to
// operator< on keys: a tie between equal keys costs two (a < b, then b < a),
// and the tie-break by item, which compares no keys, costs none.
//
// Costs: those of Heap, plus two reads of a thread-local per call. Memory:
// that of Heap<CountedKey> (a CountedKey is a double) plus the counts.

#include "recon/core/operation_counts.h"
#include "recon/structures/indexed_heap.h"

#include <cstddef>
#include <cstdint>

namespace recon {

/// A double key that counts its comparisons (see the header comment).
struct CountedKey {
  double value;

  /// Calls to operator< on this thread so far: a running total, never reset.
  inline static thread_local std::uint64_t comparisons = 0;

  friend bool operator<(const CountedKey& a, const CountedKey& b) {
    ++comparisons;
    return a.value < b.value;
  }
};

template <template <class> class Heap>
requires IndexedMinHeap<Heap<CountedKey>, CountedKey>
class CountingQueue {
 public:
  static constexpr std::uint32_t absent = Heap<CountedKey>::absent;

  explicit CountingQueue(std::size_t capacity = 0) : heap_(capacity) {}

  [[nodiscard]] bool empty() const { return heap_.empty(); }
  [[nodiscard]] std::size_t size() const { return heap_.size(); }
  [[nodiscard]] std::size_t capacity() const { return heap_.capacity(); }
  /// indexed_heap.h's operations, passed on to Heap; push, pop and decrease_key also count
  /// themselves and the comparisons they make.
  /// Cost: Heap's, plus two reads of a thread-local per counted call.
  /// Throws: nothing.
  /// Pre: those of indexed_heap.h.
  [[nodiscard]] bool contains(std::uint32_t item) const { return heap_.contains(item); }
  [[nodiscard]] double key(std::uint32_t item) const { return heap_.key(item).value; }
  [[nodiscard]] std::uint32_t top() const { return heap_.top(); }
  [[nodiscard]] double top_key() const { return heap_.top_key().value; }

  void push(std::uint32_t item, double key) {
    const ComparisonTally tally{counts_.comparisons};
    heap_.push(item, CountedKey{key});
    ++counts_.pushes;
  }

  std::uint32_t pop() {
    const ComparisonTally tally{counts_.comparisons};
    ++counts_.pops;
    return heap_.pop();
  }

  void decrease_key(std::uint32_t item, double key) {
    const ComparisonTally tally{counts_.comparisons};
    heap_.decrease_key(item, CountedKey{key});
    ++counts_.decrease_keys;
  }

  /// indexed_heap.h's push_or_decrease on the wrapped heap, counted as the push or the decrease_key it
  /// turned out to be (nothing when the key was not lower), plus its comparisons.
  /// Cost: that of push_or_decrease on Heap.
  /// Throws: nothing.
  /// Pre: item < capacity().
  bool push_or_decrease(std::uint32_t item, const double& key) {
    const ComparisonTally tally{counts_.comparisons};
    const bool was_queued = heap_.contains(item);
    if (!recon::push_or_decrease(heap_, item, CountedKey{key})) return false;
    ++(was_queued ? counts_.decrease_keys : counts_.pushes);
    return true;
  }

  /// Empties the queue; the counts go on accumulating.
  void clear() { heap_.clear(); }

  /// Everything counted since construction; only the priority-queue fields
  /// (pushes, pops, decrease_keys, comparisons) are ever non-zero.
  [[nodiscard]] const OperationCounts& counts() const { return counts_; }

 private:
  // Adds to `total` the comparisons made on this thread during its lifetime.
  struct ComparisonTally {
    std::uint64_t& total;
    std::uint64_t start = CountedKey::comparisons;
    ~ComparisonTally() { total += CountedKey::comparisons - start; }
  };

  Heap<CountedKey> heap_;
  OperationCounts counts_;
};

}  // namespace recon
