#pragma once
// An array that grows by fixed blocks of 2^16 elements rather than by
// reallocation: no moment holds both an old and a new copy, and elements
// never move (with tens of millions of lattice corners, a doubling vector's
// growth alone can add hundreds of megabytes to the peak).

#include <cstddef>
#include <memory>
#include <vector>

namespace recon::detail {

template <class T>
class BlockArray {
 public:
  [[nodiscard]] std::size_t size() const { return size_; }
  T& operator[](std::size_t i) { return blocks_[i >> block_bits][i & block_mask]; }
  const T& operator[](std::size_t i) const { return blocks_[i >> block_bits][i & block_mask]; }
  void push_back(const T& value) {
    if ((size_ & block_mask) == 0) blocks_.push_back(std::make_unique<T[]>(block_mask + 1));
    (*this)[size_++] = value;
  }

 private:
  static constexpr int block_bits = 16;
  static constexpr std::size_t block_mask = (std::size_t{1} << block_bits) - 1;
  std::vector<std::unique_ptr<T[]>> blocks_;
  std::size_t size_ = 0;
};

}  // namespace recon::detail
