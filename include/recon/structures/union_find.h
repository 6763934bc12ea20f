#pragma once
// Disjoint sets (union-find) over the integers 0..n-1: the structure behind
// Kruskal's and Borůvka's minimum spanning trees, connected pieces of the
// Riemannian graph and the components of a mesh.
//
// Every set is a tree of parent links whose root names the set. find(x)
// walks up to the root; unite(a, b) hangs one root under the other.
// Two rules keep the trees flat:
//   - union by size: the smaller tree goes under the larger, so a tree of
//     height h holds at least 2^h elements;
//   - path halving: on its way up, find makes every other node it passes
//     point to its grandparent, so later walks from there are shorter.
// Together they make any sequence of m operations cost O(m alpha(n)), where
// alpha, the inverse Ackermann function, is below 5 for any n that fits in
// memory. Memory: 2 ints per element.
//
// Counters: finds() is the number of calls to find, the two that every
// unite makes and the one in set_size included; unions() the number of
// unites that joined two sets. root() changes nothing and counts nothing,
// so that many threads may call it at once. Counting is one instruction per
// call and costs nothing measurable (docs/benchmarks.md).

#include <cstddef>
#include <cstdint>
#include <vector>

namespace recon {

class UnionFind {
 public:
  /// n singleton sets {0}, {1}, ..., {n-1}.
  /// Cost: O(n).
  /// Throws: nothing.
  /// Pre: n < 2^32.
  explicit UnionFind(std::size_t n);

  /// Adds the singleton set {size()} and returns its element.
  /// Cost: O(1) amortized.
  /// Throws: nothing.
  /// Pre: size() < 2^32 - 1.
  std::uint32_t add();
  [[nodiscard]] std::size_t size() const { return parent_.size(); }

  /// The root of x's set. Shortens the path it walks (path halving).
  /// Cost: O(alpha(n)) amortized; O(log n) at worst (union by size).
  /// Throws: nothing.
  /// Pre: x < size().
  std::uint32_t find(std::uint32_t x);
  /// The same without shortening paths: safe from many threads at once
  /// while nothing is united.
  /// Cost: O(log n) (union by size bounds the height).
  /// Throws: nothing.
  /// Pre: x < size().
  [[nodiscard]] std::uint32_t root(std::uint32_t x) const {
    while (parent_[x] != x) x = parent_[x];
    return x;
  }
  /// Joins the sets of a and b. Returns false when they were already one.
  /// Cost: O(alpha(n)) amortized, two finds.
  /// Throws: nothing.
  /// Pre: a, b < size().
  bool unite(std::uint32_t a, std::uint32_t b);

  [[nodiscard]] std::size_t set_count() const { return sets_; }
  [[nodiscard]] std::uint32_t set_size(std::uint32_t x) { return size_[find(x)]; }

  /// Calls to find so far (see the header comment).
  [[nodiscard]] std::uint64_t finds() const { return finds_; }
  /// Unites so far that joined two sets.
  [[nodiscard]] std::uint64_t unions() const { return unions_; }

 private:
  std::vector<std::uint32_t> parent_;  // a root is its own parent
  std::vector<std::uint32_t> size_;    // elements in the set, valid at roots only
  std::size_t sets_;
  std::uint64_t finds_ = 0;
  std::uint64_t unions_ = 0;
};

}  // namespace recon
