#pragma once
// Phase VI's queues of cheapest moves (collapser.h runs on any of them).

#include "recon/core/operation_counts.h"
#include "recon/structures/binary_heap.h"
#include "recon/structures/pairing_heap.h"

#include <cstddef>
#include <cstdint>
#include <queue>
#include <vector>

namespace recon::simplification_steps {

// ---------------------------------------------------------------------------
// The three queues, one interface: push, update (either way), erase, pop
// the smallest (cost, vertex). Each counts its operations.

// An indexed heap with update_key and erase (binary or pairing): the same
// adapter for both.
template <class Heap>
class IndexedQueue {
 public:
  explicit IndexedQueue(std::size_t n) : heap_(n) {}
  [[nodiscard]] bool contains(std::uint32_t v) const { return heap_.contains(v); }
  void set(std::uint32_t v, double cost, OperationCounts& counts) {
    if (heap_.contains(v)) {
      ++counts.decrease_keys;
      heap_.update_key(v, cost);
    } else {
      ++counts.pushes;
      heap_.push(v, cost);
    }
  }
  void erase(std::uint32_t v) {
    if (heap_.contains(v)) heap_.erase(v);
  }
  [[nodiscard]] bool empty() { return heap_.empty(); }
  std::uint32_t pop(OperationCounts& counts) {
    ++counts.pops;
    return heap_.pop();
  }

 private:
  Heap heap_;
};
using HeapQueue = IndexedQueue<IndexedBinaryHeap<double>>;
using PairingQueue = IndexedQueue<PairingHeap<double>>;

// No update at all: a new key is a new entry, and the old ones are left in
// the queue, recognised as stale when they surface (their version is old).
class LazyQueue {
 public:
  explicit LazyQueue(std::size_t n) : version_(n, 0), queued_(n, 0) {}
  [[nodiscard]] bool contains(std::uint32_t v) const { return queued_[v] != 0; }
  void set(std::uint32_t v, double cost, OperationCounts& counts) {
    ++counts.pushes;
    queued_[v] = 1;
    entries_.push({cost, v, ++version_[v]});
  }
  void erase(std::uint32_t v) {
    queued_[v] = 0;
    ++version_[v];
  }
  [[nodiscard]] bool empty() {
    drop_stale();
    return entries_.empty();
  }
  std::uint32_t pop(OperationCounts& counts) {
    drop_stale();
    ++counts.pops;
    const std::uint32_t v = entries_.top().vertex;
    entries_.pop();
    queued_[v] = 0;
    ++version_[v];
    return v;
  }

 private:
  struct Entry {
    double cost;
    std::uint32_t vertex;
    std::uint32_t version;
    // std::priority_queue pops its largest: the larger entry is the later one.
    bool operator<(const Entry& o) const { return o.cost < cost || (!(cost < o.cost) && o.vertex < vertex); }
  };
  void drop_stale() {
    while (!entries_.empty() && entries_.top().version != version_[entries_.top().vertex]) {
      entries_.pop();
    }
  }
  std::priority_queue<Entry> entries_;
  std::vector<std::uint32_t> version_;
  std::vector<std::uint8_t> queued_;
};

}  // namespace recon::simplification_steps
