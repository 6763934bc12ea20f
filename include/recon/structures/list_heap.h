#pragma once
// The naive "list heap": an unsorted array of the queued items, the baseline
// of the alternatives lab. With it Prim's algorithm is the O(V^2) textbook
// version, the right one for dense graphs: there most edges lower a key, and
// a heap's O(log n) per decrease_key costs more than one scan per pop.
//
// push appends, decrease_key overwrites the key in place, and the position of
// the smallest item is kept (`min_`) so top is O(1). Only pop works: it moves
// the last item into the popped one's place and scans all the items left for
// the new smallest.
//
// The interface, the items and their order (by key, then by item, as every
// heap here, so that Prim grows the same tree): IndexedMinHeap, indexed_heap.h.
//
// Costs: push, decrease_key O(1) (one comparison with the cached smallest);
// pop O(n) (the scan compares the n - 1 items left: n - 2 comparisons); top,
// contains, key O(1) (the smallest is cached, not searched); clear O(n).
// Memory: an int per possible item plus a key and an int per queued item, as
// the binary heap.

#include "recon/structures/indexed_heap.h"

#include <cstdint>
#include <utility>
#include <vector>

namespace recon {

template <class Key>
class ListHeap {
 public:
  static constexpr std::uint32_t absent = UINT32_MAX;

  explicit ListHeap(std::size_t capacity = 0) : slot_(capacity, absent) {}

  [[nodiscard]] bool empty() const { return list_.empty(); }
  [[nodiscard]] std::size_t size() const { return list_.size(); }
  [[nodiscard]] std::size_t capacity() const { return slot_.size(); }
  /// The queries of indexed_heap.h: slot_ finds an item, min_ is where the smallest is.
  /// Cost: O(1).
  /// Throws: nothing.
  /// Pre: contains(item) for key; !empty() for top and top_key.
  [[nodiscard]] bool contains(std::uint32_t item) const { return slot_[item] != absent; }
  [[nodiscard]] const Key& key(std::uint32_t item) const { return list_[slot_[item]].key; }
  [[nodiscard]] std::uint32_t top() const { return list_[min_].item; }
  [[nodiscard]] const Key& top_key() const { return list_[min_].key; }

  /// Queues item (indexed_heap.h): appended, and compared with the smallest.
  /// Cost: O(1).
  /// Throws: nothing.
  /// Pre: !contains(item) and item < capacity().
  void push(std::uint32_t item, Key key) {
    const std::size_t s = list_.size();
    slot_[item] = static_cast<std::uint32_t>(s);
    list_.push_back({std::move(key), item});
    if (s == 0 || less(list_[s], list_[min_])) min_ = s;
  }

  /// Removes and returns the smallest item: the last takes its place, then a scan finds the new smallest.
  /// Cost: O(n).
  /// Throws: nothing.
  /// Pre: !empty().
  std::uint32_t pop() {
    const std::uint32_t item = list_[min_].item;
    move_to(min_, std::move(list_.back()));
    list_.pop_back();
    slot_[item] = absent;
    min_ = position_of_smallest();
    return item;
  }

  /// Lowers an item's key in place, and compares it with the smallest.
  /// Cost: O(1).
  /// Throws: nothing.
  /// Pre: contains(item) and key <= key(item).
  void decrease_key(std::uint32_t item, Key key) {
    const std::size_t s = slot_[item];
    list_[s].key = std::move(key);
    if (s != min_ && less(list_[s], list_[min_])) min_ = s;
  }

  /// Empties the queue, freeing the slots of the queued items only.
  /// Cost: O(n).
  /// Throws: nothing.
  /// Pre: none.
  void clear() {
    for (const auto& e : list_) slot_[e.item] = absent;
    list_.clear();
    min_ = 0;
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
    list_[s] = std::move(e);
  }

  // The linear scan; 0 when the list is empty.
  std::size_t position_of_smallest() const {
    std::size_t best = 0;
    for (std::size_t s = 1; s < list_.size(); ++s) {
      if (less(list_[s], list_[best])) best = s;
    }
    return best;
  }

  std::vector<Entry> list_;          // the queued items, in no order
  std::vector<std::uint32_t> slot_;  // item -> position in list_, or absent
  std::size_t min_ = 0;              // position of the smallest in list_; 0 when empty
};

static_assert(IndexedMinHeap<ListHeap<double>, double>);

}  // namespace recon
