#include "granboltz/dsmc/particles.hpp"

#include <sys/mman.h>

#include <cstdint>
#include <new>

namespace granboltz::detail {

namespace {
constexpr std::size_t kPage = std::size_t{1} << 12;
constexpr std::size_t kHugePage = std::size_t{1} << 21;

/// The mapped length of a block of `bytes`: whole pages, whole huge pages from kHugeBytes on.
std::size_t mapped_length(std::size_t bytes) {
  const std::size_t unit = bytes >= kHugeBytes ? kHugePage : kPage;
  return (bytes + unit - 1) / unit * unit;
}

void* map(std::size_t length) {
  if (length < kHugeBytes) {
    void* p = ::mmap(nullptr, length, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (p == MAP_FAILED) throw std::bad_alloc();
    return p;
  }
  // Over-map by one huge page and cut the ends, so that the block starts on a 2 MiB boundary.
  const std::size_t over = length + kHugePage;
  void* raw = ::mmap(nullptr, over, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (raw == MAP_FAILED) throw std::bad_alloc();
  const auto a = reinterpret_cast<std::uintptr_t>(raw);
  const std::uintptr_t start = (a + kHugePage - 1) / kHugePage * kHugePage;
  if (start > a) ::munmap(raw, start - a);
  if (a + over > start + length)
    ::munmap(reinterpret_cast<void*>(start + length), a + over - start - length);
  void* p = reinterpret_cast<void*>(start);
  ::madvise(p, length, MADV_HUGEPAGE);  // advice only: harmless where unsupported
  return p;
}

/// This thread's last freed block, kept for its next ensemble of the same size.
struct Spare {
  void* p = nullptr;
  std::size_t length = 0;
  ~Spare() {
    if (p) ::munmap(p, length);
  }
};
thread_local Spare spare;
}  // namespace

void* allocate_large(std::size_t bytes) {
  const std::size_t length = mapped_length(bytes);
  if (spare.p && spare.length == length) {
    void* p = spare.p;
    spare.p = nullptr;
    return p;
  }
  return map(length);
}

void release_large(void* p, std::size_t bytes) noexcept {
  const std::size_t length = mapped_length(bytes);
  if (spare.p) ::munmap(spare.p, spare.length);
  spare.p = p;
  spare.length = length;
}

}  // namespace granboltz::detail
