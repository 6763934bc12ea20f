#pragma once
// An indexed Fibonacci heap (Fredman & Tarjan 1987): the priority queue with
// which Prim's algorithm runs in O(E + V log V), an alternative to the binary
// heap (binary_heap.h) for the alternatives lab.
//
// The heap is a forest of heap-ordered trees whose roots lie on a ring; `min_`
// is the smallest root. It does as little as it can until it must:
// - push makes the item a tree of its own on the root ring;
// - decrease_key cuts the item from its parent if it is now smaller than it
//   and makes it a root. A parent that loses a second child is cut too
//   ("cascading cut": each node is marked when it loses its first child),
//   which keeps a tree of degree d at least Fibonacci(d + 2) nodes large;
// - pop removes the minimum, makes its children roots, and only then tidies
//   up ("consolidation"): roots of equal degree are linked, the larger under
//   the smaller, until all roots differ in degree, then the new minimum is
//   found among the O(log n) roots left.
//
// The interface, the items and their order (by key, then by item, as every
// heap here, so that Prim grows the same tree): IndexedMinHeap, indexed_heap.h.
//
// Costs: push, decrease_key O(1) amortized; pop O(log n) amortized; top,
// contains, key O(1); clear O(n). Memory: a node per possible item (its key,
// four links, its degree and two flags) and up to n ints of scratch; Key must
// be default-constructible.

#include "recon/structures/indexed_heap.h"

#include <cstdint>
#include <utility>
#include <vector>

namespace recon {

template <class Key>
class FibonacciHeap {
 public:
  static constexpr std::uint32_t absent = UINT32_MAX;

  explicit FibonacciHeap(std::size_t capacity = 0) : nodes_(capacity) {}

  [[nodiscard]] bool empty() const { return size_ == 0; }
  [[nodiscard]] std::size_t size() const { return size_; }
  [[nodiscard]] std::size_t capacity() const { return nodes_.size(); }
  /// The queries of indexed_heap.h: an item's node holds its key and flag, min_ the smallest root.
  /// Cost: O(1).
  /// Throws: nothing.
  /// Pre: contains(item) for key; !empty() for top and top_key.
  [[nodiscard]] bool contains(std::uint32_t item) const { return nodes_[item].queued; }
  [[nodiscard]] const Key& key(std::uint32_t item) const { return nodes_[item].key; }
  [[nodiscard]] std::uint32_t top() const { return min_; }
  [[nodiscard]] const Key& top_key() const { return nodes_[min_].key; }

  /// Queues item (indexed_heap.h): a tree of its own on the root ring.
  /// Cost: O(1).
  /// Throws: nothing.
  /// Pre: !contains(item) and item < capacity().
  void push(std::uint32_t item, Key key) {
    Node& node = nodes_[item];
    node = Node{};
    node.key = std::move(key);
    node.queued = true;
    ++size_;
    add_root(item);
  }

  /// Removes and returns the smallest item; its children become roots, then the roots are consolidated.
  /// Cost: O(log n) amortized; O(n) for one pop after n pushes.
  /// Throws: nothing.
  /// Pre: !empty().
  std::uint32_t pop() {
    const std::uint32_t popped = min_;
    // The other roots and the popped node's children are the trees left.
    pending_.clear();
    for_each_on_ring(popped, [&](std::uint32_t x) {
      if (x != popped) pending_.push_back(x);
    });
    if (nodes_[popped].child != absent) {
      for_each_on_ring(nodes_[popped].child, [&](std::uint32_t x) { pending_.push_back(x); });
    }
    nodes_[popped].queued = false;
    --size_;
    consolidate();
    return popped;
  }

  /// Lowers an item's key; an item now smaller than its parent is cut to the roots (cascading cut).
  /// Cost: O(1) amortized.
  /// Throws: nothing.
  /// Pre: contains(item) and key <= key(item).
  void decrease_key(std::uint32_t item, Key key) {
    nodes_[item].key = std::move(key);
    const std::uint32_t parent = nodes_[item].parent;
    if (parent == absent) {
      if (less(item, min_)) min_ = item;
      return;
    }
    if (!less(item, parent)) return;  // still in heap order
    cut(item);
    cascading_cut(parent);
  }

  /// Empties the heap, visiting the queued nodes only.
  /// Cost: O(n).
  /// Throws: nothing.
  /// Pre: none.
  void clear() {
    // Walk the forest ring by ring: pending_ holds one node of each ring
    // still to visit.
    pending_.clear();
    if (min_ != absent) pending_.push_back(min_);
    while (!pending_.empty()) {
      const std::uint32_t first = pending_.back();
      pending_.pop_back();
      for_each_on_ring(first, [&](std::uint32_t x) {
        nodes_[x].queued = false;
        if (nodes_[x].child != absent) pending_.push_back(nodes_[x].child);
      });
    }
    min_ = absent;
    size_ = 0;
  }

 private:
  // A node's siblings form a circular doubly linked ring (`left`, `right`);
  // a parent points to any one of its children.
  struct Node {
    Key key{};
    std::uint32_t parent = absent;
    std::uint32_t child = absent;
    std::uint32_t left = absent;
    std::uint32_t right = absent;
    std::uint32_t degree = 0;  // number of children
    bool marked = false;       // lost a child since it last became a child itself
    bool queued = false;
  };

  static bool less(const Key& ka, std::uint32_t ia, const Key& kb, std::uint32_t ib) {
    return ka < kb || (!(kb < ka) && ia < ib);
  }
  bool less(std::uint32_t a, std::uint32_t b) const { return less(nodes_[a].key, a, nodes_[b].key, b); }

  template <class Visit>
  void for_each_on_ring(std::uint32_t first, Visit&& visit) {
    std::uint32_t x = first;
    do {
      const std::uint32_t next = nodes_[x].right;  // read first: visit may relink x
      visit(x);
      x = next;
    } while (x != first);
  }

  // Puts x, which is on no ring, on the ring of `member`, to its right.
  void insert_into_ring(std::uint32_t member, std::uint32_t x) {
    const std::uint32_t right = nodes_[member].right;
    nodes_[x].left = member;
    nodes_[x].right = right;
    nodes_[member].right = x;
    nodes_[right].left = x;
  }

  // Takes x off its ring, leaving the ring closed.
  void remove_from_ring(std::uint32_t x) {
    nodes_[nodes_[x].left].right = nodes_[x].right;
    nodes_[nodes_[x].right].left = nodes_[x].left;
  }

  // Puts x, which is on no ring, on the root ring (reached through min_) and
  // keeps min_ the smallest root.
  void add_root(std::uint32_t x) {
    nodes_[x].parent = absent;
    nodes_[x].marked = false;
    if (min_ == absent) {
      nodes_[x].left = nodes_[x].right = x;
      min_ = x;
      return;
    }
    insert_into_ring(min_, x);
    if (less(x, min_)) min_ = x;
  }

  // Makes root y, which is on no ring, a child of root x.
  void make_child(std::uint32_t y, std::uint32_t x) {
    nodes_[y].parent = x;
    nodes_[y].marked = false;
    if (nodes_[x].child == absent) {
      nodes_[y].left = nodes_[y].right = y;
      nodes_[x].child = y;
    } else {
      insert_into_ring(nodes_[x].child, y);
    }
    ++nodes_[x].degree;
  }

  // Moves x, with its subtree, from its parent's children to the roots.
  void cut(std::uint32_t x) {
    Node& parent = nodes_[nodes_[x].parent];
    if (parent.child == x) parent.child = nodes_[x].right != x ? nodes_[x].right : absent;
    --parent.degree;
    remove_from_ring(x);
    add_root(x);
  }

  // x has just lost a child: the first loss marks it, the second cuts it,
  // and its parent has then lost a child in turn.
  void cascading_cut(std::uint32_t x) {
    while (nodes_[x].parent != absent) {
      if (!nodes_[x].marked) {
        nodes_[x].marked = true;
        return;
      }
      const std::uint32_t parent = nodes_[x].parent;
      cut(x);
      x = parent;
    }
  }

  // Links the trees in pending_ (their ring links are stale) until no two
  // roots have the same degree, then rebuilds the root ring and finds min_.
  void consolidate() {
    for (std::uint32_t x : pending_) {
      std::uint32_t degree = nodes_[x].degree;
      while (degree < root_of_degree_.size() && root_of_degree_[degree] != absent) {
        std::uint32_t y = std::exchange(root_of_degree_[degree], absent);
        if (less(y, x)) std::swap(x, y);
        make_child(y, x);
        ++degree;
      }
      if (degree >= root_of_degree_.size()) root_of_degree_.resize(degree + 1, absent);
      root_of_degree_[degree] = x;
    }
    min_ = absent;
    for (std::uint32_t& root : root_of_degree_) {
      if (root != absent) add_root(std::exchange(root, absent));
    }
  }

  std::vector<Node> nodes_;     // one per possible item
  std::uint32_t min_ = absent;  // the smallest root, or absent when empty
  std::size_t size_ = 0;
  std::vector<std::uint32_t> pending_;         // scratch: trees to consolidate, rings to clear
  std::vector<std::uint32_t> root_of_degree_;  // scratch of consolidate: absent between calls
};

static_assert(IndexedMinHeap<FibonacciHeap<double>, double>);

}  // namespace recon
