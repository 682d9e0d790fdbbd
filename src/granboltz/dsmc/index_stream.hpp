#pragma once
// Uniform random indices, each with 32 further independent random bits, drawn in blocks by
// kLanes xoshiro256++ streams stepped side by side. The pairwise majorant draws its heavy
// partner by rejection from such indices (about three per event for hard spheres, two of them
// rejected) and its other partner from another: out of the event loop, with the streams' states
// in vector registers and no branch per draw, an index costs a few instructions.
#include <array>
#include <cstdint>
#include <cstring>

#include "granboltz/random/rng.hpp"

namespace granboltz {

struct IndexBits {
  std::uint32_t i;     ///< uniform on {0, ..., range - 1}
  std::uint32_t bits;  ///< 32 random bits: (bits + 1/2) 2^-32 is uniform on (0, 1)
};

class IndexStream {
 public:
  static constexpr unsigned kLanes = 4;
  static constexpr unsigned kBlock = 64;     // indices per block (a multiple of kLanes)
  static constexpr unsigned kPrefetch = 16;  // the data of an index are fetched this far ahead
  static constexpr unsigned kBuffer = kBlock + kPrefetch;

  IndexStream() = default;
  /// Indices in [0, range), 1 <= range < 2^32, from the lanes of (seed, ensemble, consumer).
  IndexStream(std::uint64_t seed, std::uint64_t ensemble, Consumer consumer, std::uint32_t range)
      : range_(range), threshold_(static_cast<std::uint32_t>(-range) % range) {
    for (unsigned l = 0; l < kLanes; ++l) set_lane(l, make_stream(seed, ensemble, consumer, l));
    fill(kPrefetch);  // entries [kPrefetch, kBuffer): the first block, used from its start
    pos_ = kPrefetch;
  }

  /// The next index. Prefetches w[k] and p[k] for the index k drawn kPrefetch ahead, and also
  /// w[k + 1], p[k + 1] if kNext (an index that may yet be shifted by one).
  template <bool kNext = false, class P>
  IndexBits next(const double* w, const P* p) {
    if (pos_ == kBlock) [[unlikely]] pos_ = refill();
    const std::uint32_t ahead = buffer_[pos_ + kPrefetch].i;
    __builtin_prefetch(&w[ahead]);
    __builtin_prefetch(&p[ahead], 1);
    if constexpr (kNext) {
      __builtin_prefetch(&w[ahead + 1]);
      __builtin_prefetch(&p[ahead + 1], 1);
    }
    return buffer_[pos_++];
  }

  /// Rejection sampling of an index i with probability proportional to w[i]: the first index
  /// with (bits + 1/2) scale < w[i], scale = 2^-32 bound, bound >= max w. Prefetches as next().
  template <class P>
  std::uint32_t select(const double* w, const P* p, double scale) {
    unsigned pos = pos_;  // in a register through the loop
    for (;;) {
      if (pos == kBlock) [[unlikely]] pos = refill();
      const std::uint32_t ahead = buffer_[pos + kPrefetch].i;
      __builtin_prefetch(&w[ahead]);
      __builtin_prefetch(&p[ahead], 1);
      const IndexBits c = buffer_[pos++];
      if ((static_cast<double>(c.bits) + 0.5) * scale < w[c.i]) {
        pos_ = pos;
        return c.i;
      }
    }
  }

  /// Numbers drawn by all lanes.
  std::uint64_t draws() const { return draws_; }

  // Checkpoint: the lanes (lane 0 carries the draw count), the buffer and the position in it.
  std::uint32_t range() const { return range_; }
  Engine lane(unsigned l) const {
    return Engine({s0_[l], s1_[l], s2_[l], s3_[l]}, l == 0 ? draws_ : 0);
  }
  const std::array<IndexBits, kBuffer>& buffer() const { return buffer_; }
  unsigned position() const { return pos_; }
  IndexStream(std::uint32_t range, const std::array<Engine, kLanes>& lanes,
              const std::array<IndexBits, kBuffer>& buffer, unsigned position)
      : buffer_(buffer),
        range_(range),
        threshold_(static_cast<std::uint32_t>(-range) % range),
        pos_(position),
        draws_(lanes[0].draws()) {
    for (unsigned l = 0; l < kLanes; ++l) set_lane(l, lanes[l]);
  }

 private:
  template <class V>
  static void load(V& a, V& b, const std::array<std::uint64_t, kLanes>& s) {
    std::memcpy(&a, s.data(), sizeof a);
    std::memcpy(&b, s.data() + 2, sizeof b);
  }
  template <class V>
  static void store(const V& a, const V& b, std::array<std::uint64_t, kLanes>& s) {
    std::memcpy(s.data(), &a, sizeof a);
    std::memcpy(s.data() + 2, &b, sizeof b);
  }
  void set_lane(unsigned l, const Engine& e) {
    s0_[l] = e.state()[0], s1_[l] = e.state()[1], s2_[l] = e.state()[2], s3_[l] = e.state()[3];
  }

  // Moves the kPrefetch indices drawn ahead to the front and draws the next kBlock after them;
  // returns the new position, 0.
  unsigned refill() {
    for (unsigned k = 0; k < kPrefetch; ++k) buffer_[k] = buffer_[kBlock + k];
    fill(kPrefetch);
    return 0;
  }

  // Lemire's exact method on 32 bits: i = (hi32 * range) >> 32, rejected if the low half of the
  // product is below 2^32 mod range (probability below range / 2^32). A rejected index is drawn
  // again from lane 0 after the block, so that the lanes' loop has no branch.
  void fill(unsigned from) {
    // The lanes as two vectors of two per state word (GCC/Clang vector extensions: SSE2 on
    // x86-64, NEON on ARM), so that the two halves are independent chains of instructions.
    using Pair = std::uint64_t __attribute__((vector_size(16)));
    static_assert(kLanes == 4);
    Pair a0, a1, a2, a3, b0, b1, b2, b3;
    load(a0, b0, s0_);
    load(a1, b1, s1_);
    load(a2, b2, s2_);
    load(a3, b3, s3_);
    // Each 64-bit output as its two 32-bit halves, the high one first.
    alignas(64) std::uint32_t high[kBlock], low[kBlock];
    for (unsigned k = 0; k < kBlock; k += kLanes) {
      const Pair ra = Engine::step(a0, a1, a2, a3);
      const Pair rb = Engine::step(b0, b1, b2, b3);
      for (unsigned l = 0; l < 2; ++l) {
        high[k + l] = static_cast<std::uint32_t>(ra[l] >> 32);
        low[k + l] = static_cast<std::uint32_t>(ra[l]);
        high[k + 2 + l] = static_cast<std::uint32_t>(rb[l] >> 32);
        low[k + 2 + l] = static_cast<std::uint32_t>(rb[l]);
      }
    }
    store(a0, b0, s0_);
    store(a1, b1, s1_);
    store(a2, b2, s2_);
    store(a3, b3, s3_);
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
        for (std::uint32_t h = high[k]; static_cast<std::uint32_t>(std::uint64_t{h} * range_) < threshold_;) {
          std::uint64_t l0 = s0_[0], l1 = s1_[0], l2 = s2_[0], l3 = s3_[0];
          const std::uint64_t r = Engine::step(l0, l1, l2, l3);
          s0_[0] = l0, s1_[0] = l1, s2_[0] = l2, s3_[0] = l3;
          ++draws_;
          h = static_cast<std::uint32_t>(r >> 32);
          out[k] = {static_cast<std::uint32_t>((std::uint64_t{h} * range_) >> 32),
                    static_cast<std::uint32_t>(r)};
        }
  }

  alignas(64) std::array<std::uint64_t, kLanes> s0_{}, s1_{}, s2_{}, s3_{};
  alignas(64) std::array<IndexBits, kBuffer> buffer_{};
  std::uint32_t range_ = 1, threshold_ = 0;
  unsigned pos_ = kBlock;
  std::uint64_t draws_ = 0;
};

}  // namespace granboltz
