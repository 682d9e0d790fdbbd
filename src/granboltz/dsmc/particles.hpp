#pragma once
// The particle system of GRW05 §4: velocities in R^3 with the time of their last kick.
#include <sys/mman.h>

#include <cstdint>
#include <cstdlib>
#include <new>
#include <vector>

#include "granboltz/physics/vec3.hpp"

namespace granboltz {

/// One particle: 32 bytes, so that a particle never straddles two cache lines.
struct alignas(32) Particle {
  Vec3 v;          ///< velocity
  double t = 0.0;  ///< time of the last kick (sigma_j in RW05 Algorithm 3)
};

/// Allocates large arrays on transparent huge pages: the event loop touches two random particles
/// per event, and with 4 KiB pages each touch of a 10^7-particle system also misses the TLB.
template <class T>
struct HugePageAllocator {
  using value_type = T;
  static constexpr std::size_t kHuge = std::size_t{1} << 21;       // 2 MiB pages
  static constexpr std::size_t kThreshold = std::size_t{1} << 23;  // from 8 MiB on

  HugePageAllocator() = default;
  template <class U>
  HugePageAllocator(const HugePageAllocator<U>&) {}

  T* allocate(std::size_t n) {
    if (n > std::size_t(PTRDIFF_MAX) / sizeof(T)) throw std::bad_array_new_length();
    std::size_t bytes = n * sizeof(T);
    if (bytes < kThreshold)
      return static_cast<T*>(::operator new(bytes, std::align_val_t(alignof(T))));
    bytes = (bytes + kHuge - 1) / kHuge * kHuge;
    void* p = std::aligned_alloc(kHuge, bytes);
    if (!p) throw std::bad_alloc();
    ::madvise(p, bytes, MADV_HUGEPAGE);  // advice only: harmless where unsupported
    return static_cast<T*>(p);
  }
  void deallocate(T* p, std::size_t n) {
    if (n * sizeof(T) < kThreshold) ::operator delete(p, std::align_val_t(alignof(T)));
    else std::free(p);
  }
  template <class U>
  bool operator==(const HugePageAllocator<U>&) const { return true; }
};

using Particles = std::vector<Particle, HugePageAllocator<Particle>>;

}  // namespace granboltz
