// Vector arguments of the inline xoshiro step below cross no ABI boundary.
#pragma GCC diagnostic ignored "-Wpsabi"
#include "granboltz/random/index_stream.hpp"

#include <cstring>

// The block's arithmetic is integer only, so every instruction set gives the same numbers; on
// x86-64 the loader picks the widest one the CPU has (GCC function multiversioning), where a
// 64-bit rotate of four lanes is one instruction (AVX-512VL) or three (AVX2) instead of six.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && \
    !defined(__SANITIZE_ADDRESS__)
#define GRANBOLTZ_CLONES \
  __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#else
#define GRANBOLTZ_CLONES
#endif

namespace granboltz {

// Lemire's exact method on 32 bits: i = (hi32 * range) >> 32, rejected if the low half of the
// product is below 2^32 mod range (probability below range / 2^32). A rejected index is drawn
// again from lane 0 after the block, so that the lanes' loop has no branch.
GRANBOLTZ_CLONES void IndexStream::fill(unsigned from) {
  // The lanes as one vector per state word (GCC/Clang vector extensions).
  using Lanes = std::uint64_t __attribute__((vector_size(8 * kLanes)));
  Lanes s0, s1, s2, s3;
  std::memcpy(&s0, s0_.data(), sizeof s0);
  std::memcpy(&s1, s1_.data(), sizeof s1);
  std::memcpy(&s2, s2_.data(), sizeof s2);
  std::memcpy(&s3, s3_.data(), sizeof s3);
  // Each 64-bit output as its two 32-bit halves.
  alignas(64) std::uint32_t high[kBlock], low[kBlock];
  for (unsigned k = 0; k < kBlock; k += kLanes) {
    const Lanes r = Engine::step(s0, s1, s2, s3);
    for (unsigned l = 0; l < kLanes; ++l) {
      high[k + l] = static_cast<std::uint32_t>(r[l] >> 32);
      low[k + l] = static_cast<std::uint32_t>(r[l]);
    }
  }
  std::memcpy(s0_.data(), &s0, sizeof s0);
  std::memcpy(s1_.data(), &s1, sizeof s1);
  std::memcpy(s2_.data(), &s2, sizeof s2);
  std::memcpy(s3_.data(), &s3, sizeof s3);
  draws_ += kBlock;
  std::uint32_t index[kBlock];
  std::uint32_t rejected = 0;
  for (unsigned k = 0; k < kBlock; ++k) {
    const std::uint64_t m = static_cast<std::uint64_t>(high[k]) * range_;
    index[k] = static_cast<std::uint32_t>(m >> 32);
    rejected |= static_cast<std::uint32_t>(m) < threshold_;
  }
  IndexBits* out = buffer_.data() + from;
  for (unsigned k = 0; k < kBlock; ++k) out[k] = {index[k], low[k]};
  if (rejected) [[unlikely]]
    for (unsigned k = 0; k < kBlock; ++k)
      for (std::uint32_t h = high[k];
           static_cast<std::uint32_t>(std::uint64_t{h} * range_) < threshold_;) {
        std::uint64_t l0 = s0_[0], l1 = s1_[0], l2 = s2_[0], l3 = s3_[0];
        const std::uint64_t r = Engine::step(l0, l1, l2, l3);
        s0_[0] = l0, s1_[0] = l1, s2_[0] = l2, s3_[0] = l3;
        ++draws_;
        h = static_cast<std::uint32_t>(r >> 32);
        out[k] = {static_cast<std::uint32_t>((std::uint64_t{h} * range_) >> 32),
                  static_cast<std::uint32_t>(r)};
      }
}

}  // namespace granboltz
