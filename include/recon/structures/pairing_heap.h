#pragma once
// An indexed pairing heap (Fredman, Sedgewick, Sleator & Tarjan 1986): a
// priority queue with decrease-key, simpler than the Fibonacci heap and
// usually faster, an alternative to the binary heap (binary_heap.h) for the
// alternatives lab.
//
// The heap is one heap-ordered tree with any number of children per node.
// Everything is built from "meld": of two trees, the one with the larger root
// becomes the first child of the other (one comparison).
// - push melds the new item, a tree of one node, with the root;
// - decrease_key cuts the item's subtree from its parent and melds it with
//   the root (nothing to do when the item is the root);
// - pop removes the root and melds its children in two passes: first in
//   pairs from left to right, then the pairs from right to left into one
//   tree. The two passes are what keep the tree shallow.
//
// The interface, the items and their order (by key, then by item, as every
// heap here, so that Prim grows the same tree): IndexedMinHeap, indexed_heap.h.
//
// Mesh simplification (simplification.h) also raises keys and removes
// items: erase cuts the item out, melds its children into one tree (pop's
// two passes) and melds that with the root; update_key is decrease_key when
// the key falls, erase and push when it rises.
//
// Costs: push O(1); pop O(log n) amortized, and so erase and a rising
// update_key; decrease_key O(1) work, but its amortized cost is only known
// to lie between Omega(log log n) (Fredman 1999) and O(2^(2 sqrt(log log
// n))) (Pettie 2005), in practice close to O(1); top, contains, key O(1);
// clear O(n). Memory: a node per possible item (its key, three links and a
// flag) and up to n ints of scratch; Key must be default-constructible.

#include "recon/structures/indexed_heap.h"

#include <cstdint>
#include <utility>
#include <vector>

namespace recon {

template <class Key>
class PairingHeap {
 public:
  static constexpr std::uint32_t absent = UINT32_MAX;

  explicit PairingHeap(std::size_t capacity = 0) : nodes_(capacity) {}

  [[nodiscard]] bool empty() const { return size_ == 0; }
  [[nodiscard]] std::size_t size() const { return size_; }
  [[nodiscard]] std::size_t capacity() const { return nodes_.size(); }
  /// The queries of indexed_heap.h: an item's node holds its key and flag, the smallest is the root.
  /// Cost: O(1).
  /// Throws: nothing.
  /// Pre: contains(item) for key; !empty() for top and top_key.
  [[nodiscard]] bool contains(std::uint32_t item) const { return nodes_[item].queued; }
  [[nodiscard]] const Key& key(std::uint32_t item) const { return nodes_[item].key; }
  [[nodiscard]] std::uint32_t top() const { return root_; }
  [[nodiscard]] const Key& top_key() const { return nodes_[root_].key; }

  /// Queues item (indexed_heap.h): a tree of one node, melded with the root.
  /// Cost: O(1).
  /// Throws: nothing.
  /// Pre: !contains(item) and item < capacity().
  void push(std::uint32_t item, Key key) {
    Node& node = nodes_[item];
    node = Node{};
    node.key = std::move(key);
    node.queued = true;
    ++size_;
    root_ = root_ == absent ? item : meld(root_, item);
  }

  /// Removes and returns the smallest item, the root; its children are melded in two passes.
  /// Cost: O(log n) amortized.
  /// Throws: nothing.
  /// Pre: !empty().
  std::uint32_t pop() {
    const std::uint32_t popped = root_;
    root_ = merge_children(popped);
    nodes_[popped].queued = false;
    --size_;
    return popped;
  }

  /// Lowers an item's key: its subtree is cut from its parent and melded with the root.
  /// Cost: O(1) work; amortized between Omega(log log n) and O(2^(2 sqrt(log log n))) (header comment).
  /// Throws: nothing.
  /// Pre: contains(item) and key <= key(item).
  void decrease_key(std::uint32_t item, Key key) {
    nodes_[item].key = std::move(key);
    if (item == root_) return;
    cut(item);
    root_ = meld(root_, item);
  }

  /// Removes an item wherever it is: cut out, its children melded into one tree, that melded with the root.
  /// Cost: O(log n) amortized, as pop.
  /// Throws: nothing.
  /// Pre: contains(item).
  void erase(std::uint32_t item) {
    if (item == root_) {
      pop();
      return;
    }
    cut(item);
    const std::uint32_t children = merge_children(item);
    nodes_[item].child = absent;
    nodes_[item].queued = false;
    --size_;
    if (children != absent) root_ = meld(root_, children);
  }

  /// Gives an item a new key: decrease_key when it falls, erase and push when it rises.
  /// Cost: that of decrease_key, or O(log n) amortized when it rises.
  /// Throws: nothing.
  /// Pre: contains(item).
  void update_key(std::uint32_t item, Key key) {
    if (!less(nodes_[item].key, item, key, item)) {
      decrease_key(item, std::move(key));
      return;
    }
    erase(item);
    push(item, std::move(key));
  }

  /// Empties the heap, visiting the queued nodes only.
  /// Cost: O(n).
  /// Throws: nothing.
  /// Pre: none.
  void clear() {
    // Every node but the root is reached as a first child or as a next
    // sibling; pending_ holds the nodes still to visit.
    pending_.clear();
    if (root_ != absent) pending_.push_back(root_);
    while (!pending_.empty()) {
      const std::uint32_t x = pending_.back();
      pending_.pop_back();
      nodes_[x].queued = false;
      if (nodes_[x].child != absent) pending_.push_back(nodes_[x].child);
      if (nodes_[x].next != absent) pending_.push_back(nodes_[x].next);
    }
    root_ = absent;
    size_ = 0;
  }

 private:
  // Children are a doubly linked list, first child first: `next` is the next
  // sibling, `previous` the previous sibling or, for a first child, the parent.
  struct Node {
    Key key{};
    std::uint32_t child = absent;  // first child
    std::uint32_t next = absent;
    std::uint32_t previous = absent;
    bool queued = false;
  };

  static bool less(const Key& ka, std::uint32_t ia, const Key& kb, std::uint32_t ib) {
    return ka < kb || (!(kb < ka) && ia < ib);
  }
  bool less(std::uint32_t a, std::uint32_t b) const { return less(nodes_[a].key, a, nodes_[b].key, b); }

  // Melds two roots, neither with siblings; returns the new root.
  std::uint32_t meld(std::uint32_t a, std::uint32_t b) {
    if (less(b, a)) std::swap(a, b);
    const std::uint32_t first = nodes_[a].child;
    nodes_[b].next = first;
    nodes_[b].previous = a;
    if (first != absent) nodes_[first].previous = b;
    nodes_[a].child = b;
    return a;
  }

  // Detaches x, with its subtree, from its parent and siblings.
  void cut(std::uint32_t x) {
    const std::uint32_t previous = nodes_[x].previous;
    const std::uint32_t next = nodes_[x].next;
    if (nodes_[previous].child == x) {
      nodes_[previous].child = next;  // x was a first child: previous is its parent
    } else {
      nodes_[previous].next = next;
    }
    if (next != absent) nodes_[next].previous = previous;
    nodes_[x].next = nodes_[x].previous = absent;
  }

  // The two passes of pop over the children of `parent`; returns the root of
  // the tree they make, or absent when there are no children.
  std::uint32_t merge_children(std::uint32_t parent) {
    // First pass, left to right: meld the children in pairs.
    pending_.clear();
    std::uint32_t a = nodes_[parent].child;
    while (a != absent) {
      const std::uint32_t b = nodes_[a].next;
      const std::uint32_t after = b == absent ? absent : nodes_[b].next;
      nodes_[a].next = nodes_[a].previous = absent;
      if (b == absent) {
        pending_.push_back(a);
      } else {
        nodes_[b].next = nodes_[b].previous = absent;
        pending_.push_back(meld(a, b));
      }
      a = after;
    }
    if (pending_.empty()) return absent;
    // Second pass, right to left: meld each pair into the tree so far.
    std::uint32_t root = pending_.back();
    for (std::size_t i = pending_.size() - 1; i-- > 0;) root = meld(pending_[i], root);
    return root;
  }

  std::vector<Node> nodes_;      // one per possible item
  std::uint32_t root_ = absent;  // absent when empty
  std::size_t size_ = 0;
  std::vector<std::uint32_t> pending_;  // scratch: pairs of pop, nodes to clear
};

static_assert(IndexedMinHeap<PairingHeap<double>, double>);

}  // namespace recon
