#include "recon/structures/union_find.h"

#include <numeric>
#include <utility>

namespace recon {

UnionFind::UnionFind(std::size_t n) : parent_(n), size_(n, 1), sets_(n) {
  std::iota(parent_.begin(), parent_.end(), 0u);
}

std::uint32_t UnionFind::add() {
  const auto x = static_cast<std::uint32_t>(parent_.size());
  parent_.push_back(x);
  size_.push_back(1);
  ++sets_;
  return x;
}

std::uint32_t UnionFind::find(std::uint32_t x) {
  ++finds_;
  while (parent_[x] != x) {
    parent_[x] = parent_[parent_[x]];  // halve the path: x now skips its parent
    x = parent_[x];
  }
  return x;
}

bool UnionFind::unite(std::uint32_t a, std::uint32_t b) {
  a = find(a);
  b = find(b);
  if (a == b) return false;
  if (size_[a] < size_[b]) std::swap(a, b);  // the smaller tree goes under the larger
  parent_[b] = a;
  size_[a] += size_[b];
  --sets_;
  ++unions_;
  return true;
}

}  // namespace recon
