#pragma once
// The particle system of GRW05 §4: velocities in R^3 with the time of their last kick.
#include <cstdint>
#include <cstdlib>
#include <new>
#include <vector>

#include "granboltz/core/vec3.hpp"

namespace granboltz {

/// One particle: 32 bytes, so that a particle never straddles two cache lines.
struct alignas(32) Particle {
  Vec3 v;          ///< velocity
  double t = 0.0;  ///< time of the last kick (sigma_j in RW05 Algorithm 3)
};

namespace detail {
/// Large blocks (from kLargeBytes on) come straight from mmap, those from kHugeBytes on aligned to
/// 2 MiB with transparent-huge-page advice: the event loop touches two random particles per
/// event, and with 4 KiB pages each touch of a 10^7-particle system also misses the TLB.
/// glibc's malloc kept such blocks of finished ensembles (its adaptive mmap threshold moved them
/// to the heap, whose holes the next aligned block did not fit): a run's memory grew by one
/// particle array per ensemble, to 19 GB for RW05's N = 10^4 ensembles of 65 536 particles.
/// Each thread keeps its last freed block for its next ensemble, which then skips the kernel's
/// page faults and zeroing.
inline constexpr std::size_t kLargeBytes = std::size_t{1} << 16;  // 64 KiB: n >= 2048
inline constexpr std::size_t kHugeBytes = std::size_t{1} << 23;   // 8 MiB
void* allocate_large(std::size_t bytes);
void release_large(void* p, std::size_t bytes) noexcept;
}  // namespace detail

/// The allocator of the particle arrays and other per-particle arrays (see detail above).
template <class T>
struct HugePageAllocator {
  using value_type = T;

  HugePageAllocator() = default;
  template <class U>
  HugePageAllocator(const HugePageAllocator<U>&) {}

  T* allocate(std::size_t n) {
    if (n > std::size_t(PTRDIFF_MAX) / sizeof(T)) throw std::bad_array_new_length();
    const std::size_t bytes = n * sizeof(T);
    if (bytes < detail::kLargeBytes)
      return static_cast<T*>(::operator new(bytes, std::align_val_t(alignof(T))));
    return static_cast<T*>(detail::allocate_large(bytes));
  }
  void deallocate(T* p, std::size_t n) noexcept {
    const std::size_t bytes = n * sizeof(T);
    if (bytes < detail::kLargeBytes)
      ::operator delete(p, std::align_val_t(alignof(T)));
    else
      detail::release_large(p, bytes);
  }
  template <class U>
  bool operator==(const HugePageAllocator<U>&) const {
    return true;
  }
};

using Particles = std::vector<Particle, HugePageAllocator<Particle>>;

}  // namespace granboltz
