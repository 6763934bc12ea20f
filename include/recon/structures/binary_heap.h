#pragma once
// An indexed binary min-heap: the priority queue behind Prim's algorithm, and
// the default IndexedMinHeap (indexed_heap.h states the interface, the items
// and their order: by key, then by item, so every run is deterministic).
//
// Decrease-key is what Prim needs when it finds a cheaper edge to a vertex
// already waiting: the heap keeps, for every item, its slot in the array
// (`slot_`), so the item can be found in O(1) and sifted up in O(log n).
//
// Mesh simplification (simplification.h) also needs the other direction: a
// collapse raises the costs of the vertices around it, and a vertex that can
// no longer move leaves the queue. update_key sifts an item up or down from
// its slot, erase fills its slot with the last entry and sifts that.
//
// Costs: push, pop, decrease_key, update_key, erase O(log n); top, contains, key O(1);
// memory 2 ints per possible item plus a key per queued item.

#include "recon/structures/indexed_heap.h"

#include <cstdint>
#include <utility>
#include <vector>

namespace recon {

template <class Key>
class IndexedBinaryHeap {
 public:
  static constexpr std::uint32_t absent = UINT32_MAX;

  explicit IndexedBinaryHeap(std::size_t capacity = 0) : slot_(capacity, absent) {}

  [[nodiscard]] bool empty() const { return heap_.empty(); }
  [[nodiscard]] std::size_t size() const { return heap_.size(); }
  [[nodiscard]] std::size_t capacity() const { return slot_.size(); }
  /// The queries of indexed_heap.h: slot_ finds an item, the smallest is at the front of the array.
  /// Cost: O(1).
  /// Throws: nothing.
  /// Pre: contains(item) for key; !empty() for top and top_key.
  [[nodiscard]] bool contains(std::uint32_t item) const { return slot_[item] != absent; }
  [[nodiscard]] const Key& key(std::uint32_t item) const { return heap_[slot_[item]].key; }
  [[nodiscard]] std::uint32_t top() const { return heap_.front().item; }
  [[nodiscard]] const Key& top_key() const { return heap_.front().key; }

  /// Queues item (indexed_heap.h): a new last leaf, sifted up.
  /// Cost: O(log n).
  /// Throws: nothing.
  /// Pre: !contains(item) and item < capacity().
  void push(std::uint32_t item, Key key) {
    slot_[item] = static_cast<std::uint32_t>(heap_.size());
    heap_.push_back({std::move(key), item});
    sift_up(heap_.size() - 1);
  }

  /// Removes and returns the smallest item: the last leaf takes the root's place and is sifted down.
  /// Cost: O(log n).
  /// Throws: nothing.
  /// Pre: !empty().
  std::uint32_t pop() {
    const std::uint32_t item = heap_.front().item;
    move_to(0, heap_.back());
    heap_.pop_back();
    slot_[item] = absent;
    if (!heap_.empty()) sift_down(0);
    return item;
  }

  /// Lowers an item's key and sifts it up from its slot.
  /// Cost: O(log n).
  /// Throws: nothing.
  /// Pre: contains(item) and key <= key(item).
  void decrease_key(std::uint32_t item, Key key) {
    const std::size_t s = slot_[item];
    heap_[s].key = std::move(key);
    sift_up(s);
  }

  /// Gives an item a new key, larger or smaller: sifted up, then down.
  /// Cost: O(log n).
  /// Throws: nothing.
  /// Pre: contains(item).
  void update_key(std::uint32_t item, Key key) {
    const std::size_t s = slot_[item];
    heap_[s].key = std::move(key);
    sift_up(s);
    sift_down(slot_[item]);
  }

  /// Removes an item wherever it is: the last entry fills its slot and is sifted.
  /// Cost: O(log n).
  /// Throws: nothing.
  /// Pre: contains(item).
  void erase(std::uint32_t item) {
    const std::size_t s = slot_[item];
    slot_[item] = absent;
    Entry last = std::move(heap_.back());
    heap_.pop_back();
    if (s == heap_.size()) return;  // it was the last entry
    const std::uint32_t moved = last.item;
    move_to(s, std::move(last));
    sift_up(s);
    sift_down(slot_[moved]);
  }

  /// Empties the heap, freeing the slots of the queued items only.
  /// Cost: O(n).
  /// Throws: nothing.
  /// Pre: none.
  void clear() {
    for (const auto& e : heap_) slot_[e.item] = absent;
    heap_.clear();
  }

 private:
  struct Entry {
    Key key;
    std::uint32_t item;
  };

  static bool less(const Key& ka, std::uint32_t ia, const Key& kb, std::uint32_t ib) {
    return ka < kb || (!(kb < ka) && ia < ib);
  }
  static bool less(const Entry& a, const Entry& b) { return less(a.key, a.item, b.key, b.item); }

  void move_to(std::size_t s, Entry e) {
    slot_[e.item] = static_cast<std::uint32_t>(s);
    heap_[s] = std::move(e);
  }

  // Hole technique: carry the moving entry and shift the others into the
  // hole instead of swapping at every level.
  void sift_up(std::size_t s) {
    Entry moving = std::move(heap_[s]);
    while (s > 0) {
      const std::size_t parent = (s - 1) / 2;
      if (!less(moving, heap_[parent])) break;
      move_to(s, std::move(heap_[parent]));
      s = parent;
    }
    move_to(s, std::move(moving));
  }

  void sift_down(std::size_t s) {
    Entry moving = std::move(heap_[s]);
    const std::size_t n = heap_.size();
    while (true) {
      std::size_t child = 2 * s + 1;
      if (child >= n) break;
      if (child + 1 < n && less(heap_[child + 1], heap_[child])) ++child;
      if (!less(heap_[child], moving)) break;
      move_to(s, std::move(heap_[child]));
      s = child;
    }
    move_to(s, std::move(moving));
  }

  std::vector<Entry> heap_;
  std::vector<std::uint32_t> slot_;  // item -> position in heap_, or absent
};

static_assert(IndexedMinHeap<IndexedBinaryHeap<double>, double>);

}  // namespace recon
