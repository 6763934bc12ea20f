#pragma once
// The interface the four heaps share: an indexed min-heap, the priority queue
// with decrease-key that Prim's algorithm needs (minimum_spanning_tree.h).
//
// Items are the integers 0..capacity-1, each in the heap at most once, with a
// key. Order: by key, then by item, so that equal keys leave in a fixed order
// and every heap gives the same sequence of pops (Prim the same tree). Keys
// are compared with operator< alone. The operations of a heap type H:
//   H(capacity)                  an empty heap for items 0..capacity-1
//   H::absent                    UINT32_MAX, "no item" in the heap's links
//   empty(), size(), capacity()  as for a container; size() counts the queued items
//   contains(item)               whether item is queued
//   key(item)                    its key                                Pre: contains(item)
//   top(), top_key()             the smallest item, its key             Pre: !empty()
//   push(item, key)              queues item                            Pre: !contains(item), item < capacity()
//   pop()                        removes and returns the smallest item  Pre: !empty()
//   decrease_key(item, key)      lowers item's key                      Pre: contains(item), key <= key(item)
//   clear()                      empties the heap
// push_or_decrease (below) is written once, over these, for every heap.
// Throws: none of them throws, unless Key's operator< or its moves do. No
// precondition is checked. Each heap's header gives the costs of its own.
//
// Why a concept: the heaps repeat this interface by hand, each reading alone
// (binary_heap.h, pairing_heap.h, fibonacci_heap.h, list_heap.h), and Prim,
// the alternatives lab and counting_queue.h take any of them as a template
// argument. IndexedMinHeap states the interface once; each heap's header
// checks the heap against it, and a template constrained by it says what it
// needs. Prim needs less, and asks for less: DecreaseKeyQueue, the part of
// the interface its loop calls (H(capacity), empty, top_key, pop, push,
// decrease_key), which IndexedMinHeap refines.

#include <concepts>
#include <cstddef>
#include <cstdint>

namespace recon {

/// Q is a priority queue of items with keys of type Key and decrease-key:
/// what Prim's loop asks of its queue (minimum_spanning_tree.h).
template <class Q, class Key>
concept DecreaseKeyQueue = std::constructible_from<Q, std::size_t> &&
    requires(Q& queue, const Q& queued, std::uint32_t item, const Key& key) {
  { queued.empty() } -> std::same_as<bool>;
  { queued.top_key() } -> std::convertible_to<const Key&>;
  queue.push(item, key);
  { queue.pop() } -> std::same_as<std::uint32_t>;
  queue.decrease_key(item, key);
};

/// H is an indexed min-heap of items with keys of type Key (see the header
/// comment). Only the forms are checked; the order and the costs are each
/// heap's to keep.
template <class H, class Key>
concept IndexedMinHeap = DecreaseKeyQueue<H, Key> && requires(H& heap, const H& queued, std::uint32_t item) {
  { H::absent } -> std::convertible_to<std::uint32_t>;
  { queued.size() } -> std::same_as<std::size_t>;
  { queued.capacity() } -> std::same_as<std::size_t>;
  { queued.contains(item) } -> std::same_as<bool>;
  { queued.key(item) } -> std::convertible_to<const Key&>;
  { queued.top() } -> std::same_as<std::uint32_t>;
  heap.clear();
};

/// Prim's relaxation step in one call: pushes item when it is absent, lowers
/// its key when it is present with a larger one; returns whether its key changed.
/// Cost: one comparison, plus the heap's push or decrease_key.
/// Throws: nothing.
/// Pre: item < heap.capacity().
template <class H, class Key>
requires IndexedMinHeap<H, Key>
bool push_or_decrease(H& heap, std::uint32_t item, const Key& key) {
  if (!heap.contains(item)) {
    heap.push(item, key);
    return true;
  }
  if (!(key < heap.key(item))) return false;
  heap.decrease_key(item, key);
  return true;
}

}  // namespace recon
