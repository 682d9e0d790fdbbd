#pragma once
// Uniform random indices, each with 32 further independent random bits, drawn in blocks by
// kLanes xoshiro256++ streams stepped side by side. The pairwise majorant draws its heavy
// partner by rejection from such indices (about three per event for hard spheres, two of them
// rejected) and its other partner from another: out of the event loop, with the streams' states
// in vector registers and no branch per draw, an index costs a few instructions.
#include <array>
#include <cstdint>

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
  /// p[k + 1] if kNext (an index that may yet be shifted by one; w[k + 1] is mostly on the same
  /// cache line as w[k]).
  template <bool kNext = false, class P>
  IndexBits next(const double* w, const P* p) {
    if (pos_ == kBlock) [[unlikely]]
      pos_ = refill();
    const std::uint32_t ahead = buffer_[pos_ + kPrefetch].i;
    __builtin_prefetch(&w[ahead]);
    __builtin_prefetch(&p[ahead], 1);
    if constexpr (kNext) __builtin_prefetch(&p[ahead + 1], 1);
    return buffer_[pos_++];
  }

  /// Rejection sampling of an index i with probability proportional to w[i]: the first index
  /// with (bits + 1/2) scale < w[i], scale = 2^-32 bound, bound >= max w. Prefetches as next().
  template <class P>
  std::uint32_t select(const double* w, const P* p, double scale) {
    unsigned pos = pos_;  // in a register through the loop
    for (;;) {
      if (pos == kBlock) [[unlikely]]
        pos = refill();
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

  // Draws kBlock indices into buffer_[from, from + kBlock) (index_stream.cpp).
  void fill(unsigned from);

  alignas(64) std::array<std::uint64_t, kLanes> s0_{}, s1_{}, s2_{}, s3_{};
  alignas(64) std::array<IndexBits, kBuffer> buffer_{};
  std::uint32_t range_ = 1, threshold_ = 0;
  unsigned pos_ = kBlock;
  std::uint64_t draws_ = 0;
};

}  // namespace granboltz
