#pragma once
// Random streams addressed by (master seed, ensemble index, consumer).
//
// Each stream is a xoshiro256++ engine (Blackman & Vigna, ACM TOMS 47, 2021: period 2^256 - 1,
// passes BigCrush and PractRand) whose 256-bit starting state is the output of the counter-based
// Philox4x64-10 bijection (Salmon et al., SC'11; Debian's Random123) keyed by the seed, at the
// counter (ensemble, consumer). Philox is a bijection of the counter for a fixed key, so distinct
// (ensemble, consumer) start from distinct, effectively random points of the period. Because an
// ensemble's streams depend on nothing else, results do not depend on the number of threads, on
// sharding, or on restarts.
#include <Random123/philox.h>

#include <array>
#include <cstdint>
#include <limits>

namespace granboltz {

/// xoshiro256++ with a count of the numbers drawn (for the benchmark floor and diagnostics).
/// Standard uniform random bit generator interface.
class Xoshiro256pp {
 public:
  using result_type = std::uint64_t;
  using State = std::array<std::uint64_t, 4>;

  Xoshiro256pp() = default;
  explicit Xoshiro256pp(const State& s, std::uint64_t draws = 0) : s_(s), draws_(draws) {}

  static constexpr result_type min() { return 0; }
  static constexpr result_type max() { return std::numeric_limits<result_type>::max(); }

  result_type operator()() {
    const std::uint64_t r = rotl(s_[0] + s_[3], 23) + s_[0];
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    ++draws_;
    return r;
  }

  const State& state() const { return s_; }
  /// Numbers drawn since the stream was created.
  std::uint64_t draws() const { return draws_; }
  friend bool operator==(const Xoshiro256pp&, const Xoshiro256pp&) = default;

 private:
  static std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  State s_{1, 2, 3, 4};
  std::uint64_t draws_ = 0;
};

/// The engine behind every stream.
using Engine = Xoshiro256pp;

/// The independent consumers of randomness within one ensemble. Never renumber: outputs of
/// earlier versions would no longer be reproducible.
enum class Consumer : std::uint64_t {
  kInitial = 1,   ///< initial velocities
  kEvents = 2,    ///< waiting times, fictitious tests, directions, kicks of colliding pairs
  kPairs = 3,     ///< indices of collision partners (drawn ahead so they can be prefetched)
  kSweep = 4,     ///< kicks of all particles (observations, splitting kick steps)
  kReduce = 5,    ///< SWPM reduction: merge directions (dsmc.weights)
  kSplit = 6,     ///< SWPM importance splitting: roulette draws (dsmc.weights.split)
  kIntruder = 16, ///< TV06 intruder events
  kBath = 17,     ///< TV06 DSMC bath
  kNeedle = 18,   ///< TV06 needle events
};

/// The stream of `consumer` in ensemble `ensemble` of a run with master seed `seed`.
inline Engine make_stream(std::uint64_t seed, std::uint64_t ensemble, Consumer consumer) {
  using Philox = r123::Philox4x64;
  const Philox::key_type key = {{seed, 0x6772616e626f6c74ULL /* "granbolt" */}};
  const Philox::ctr_type ctr = {{ensemble, static_cast<std::uint64_t>(consumer), 0, 0}};
  const Philox::ctr_type out = Philox()(ctr, key);
  Engine::State s = {out[0], out[1], out[2], out[3]};
  if ((s[0] | s[1] | s[2] | s[3]) == 0) s[0] = 1;  // the all-zero state is a fixed point
  return Engine(s);
}

}  // namespace granboltz
