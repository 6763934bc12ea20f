#pragma once
// An allocator for vectors of plain numbers whose resize() leaves the new
// elements unwritten instead of zeroing them, for arrays that parallel
// threads fill right after the resize (the Riemannian graph's targets,
// Graph::targets): the serial zeroing pass is saved, and the pages are first
// touched by the threads that fill them. Internal machinery, not part of
// the library's contracts.

#include <memory>
#include <new>
#include <utility>

namespace recon::detail {

template <class T>
struct UninitializedAllocator : std::allocator<T> {
  template <class U>
  struct rebind {
    using other = UninitializedAllocator<U>;
  };
  UninitializedAllocator() = default;
  template <class U>
  explicit UninitializedAllocator(const UninitializedAllocator<U>&) noexcept {}
  template <class U>
  void construct(U* p) noexcept {
    ::new (static_cast<void*>(p)) U;  // default-initialised: no value for a plain number
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

}  // namespace recon::detail
