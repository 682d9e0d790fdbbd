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
    ++draws_;
    return step(s_[0], s_[1], s_[2], s_[3]);
  }

  /// One step of xoshiro256++ on the four state words: the output, and the state advanced.
  /// U is std::uint64_t, or a vector of them (GCC/Clang vector extensions): several engines kept
  /// side by side, one word of each per vector, are then stepped together.
  template <class U>
  static U step(U& s0, U& s1, U& s2, U& s3) {
    const U r = rotl(s0 + s3, 23) + s0;
    const U t = s1 << 17;
    s2 ^= s0;
    s3 ^= s1;
    s1 ^= s2;
    s0 ^= s3;
    s2 ^= t;
    s3 = rotl(s3, 45);
    return r;
  }

  const State& state() const { return s_; }
  /// Numbers drawn since the stream was created.
  std::uint64_t draws() const { return draws_; }
  friend bool operator==(const Xoshiro256pp&, const Xoshiro256pp&) = default;

 private:
  template <class U>
  static U rotl(const U& x, int k) {
    return (x << k) | (x >> (64 - k));
  }
  State s_{1, 2, 3, 4};
  std::uint64_t draws_ = 0;
};

/// The engine behind every stream.
using Engine = Xoshiro256pp;

/// The independent consumers of randomness within one ensemble. Never renumber: outputs of
/// earlier versions would no longer be reproducible.
enum class Consumer : std::uint64_t {
  kInitial = 1,       ///< initial velocities
  kEvents = 2,        ///< waiting times, fictitious tests, directions, kicks of colliding pairs
  kPairs = 3,         ///< indices of collision partners (drawn ahead so they can be prefetched)
  kSweep = 4,         ///< kicks of all particles (observations, splitting kick steps)
  kReduce = 5,        ///< SWPM reduction: merge directions (dsmc.weights)
  kSplit = 6,         ///< SWPM importance splitting: roulette draws (dsmc.weights.split)
  kCandidates = 7,    ///< pairwise majorant: heavy-partner candidates (several lanes)
  kPartners = 8,      ///< pairwise majorant: the other partners and acceptance bits (several lanes)
  kInitialSpin = 11,  ///< rough particles: initial angular velocities (their own stream, so that
                      ///< a rough run starts with the smooth run's velocities)
  kIntruder = 16,     ///< TV06 intruder events
  kBath = 17,         ///< TV06 DSMC bath
  kNeedle = 18,       ///< TV06 needle events
};

/// The stream of `consumer` in ensemble `ensemble` of a run with master seed `seed` (`lane`: one
/// of several independent streams of the same consumer).
inline Engine make_stream(std::uint64_t seed, std::uint64_t ensemble, Consumer consumer,
                          std::uint64_t lane = 0) {
  using Philox = r123::Philox4x64;
  const Philox::key_type key = {{seed, 0x6772616e626f6c74ULL /* "granbolt" */}};
  const Philox::ctr_type ctr = {{ensemble, static_cast<std::uint64_t>(consumer), lane, 0}};
  const Philox::ctr_type out = Philox()(ctr, key);
  Engine::State s = {out[0], out[1], out[2], out[3]};
  if ((s[0] | s[1] | s[2] | s[3]) == 0) s[0] = 1;  // the all-zero state is a fixed point
  return Engine(s);
}

/// The master seed of a run continued from an earlier one (dsmc.initial.from) whose stored
/// config hashes to `source`: its streams are then independent of the source's even when both
/// configs give the same seed (the same seed would otherwise draw again the numbers that made
/// the state it starts from, and correlate the new kicks with it).
inline std::uint64_t continued_seed(std::uint64_t seed, std::uint64_t source) {
  using Philox = r123::Philox4x64;
  const Philox::key_type key = {{seed, source}};
  const Philox::ctr_type ctr = {{~0ULL, 0x636f6e74696e7565ULL /* "continue" */, 0, 0}};
  return Philox()(ctr, key)[0];
}

}  // namespace granboltz
