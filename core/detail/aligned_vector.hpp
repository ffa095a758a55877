// std::vector with 64-byte aligned storage: SIMD kernels load and store whole
// cache lines of it with aligned instructions.
#pragma once

#include <cstddef>
#include <new>
#include <vector>

namespace soda {

template <class T>
struct AlignedAllocator {
  using value_type = T;
  AlignedAllocator() = default;
  template <class U>
  AlignedAllocator(const AlignedAllocator<U>&) {}
  T* allocate(std::size_t n) { return static_cast<T*>(::operator new(n * sizeof(T), std::align_val_t{64})); }
  void deallocate(T* p, std::size_t) { ::operator delete(p, std::align_val_t{64}); }
  template <class U>
  bool operator==(const AlignedAllocator<U>&) const { return true; }
};

template <class T>
using AVec = std::vector<T, AlignedAllocator<T>>;

} // namespace soda
