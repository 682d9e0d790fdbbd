#pragma once
// Random streams addressed by (master seed, ensemble index, consumer).
//
// Each stream is a PCG64 engine (pcg-cpp, O'Neill 2014) whose 128-bit state and 127-bit stream
// selector are derived by the counter-based Philox4x64-10 bijection (Random123, Salmon et al.
// 2011) keyed by the seed, with the counter (ensemble, consumer). Philox is a bijection of the
// counter for a fixed key, so distinct (ensemble, consumer) give distinct engines. Because an
// ensemble's streams depend on nothing else, results do not depend on the number of threads,
// on sharding, or on restarts.
#include <Random123/philox.h>

#include <cstdint>
#include <pcg_random.hpp>

namespace granboltz {

/// The engine behind every stream: 64-bit output, standard engine interface.
using Engine = pcg64;

/// The independent consumers of randomness within one ensemble. Never renumber: outputs of
/// earlier versions would no longer be reproducible.
enum class Consumer : std::uint64_t {
  kInitial = 1,   ///< initial velocities
  kEvents = 2,    ///< waiting times, fictitious tests, directions, kicks of colliding pairs
  kPairs = 3,     ///< indices of collision partners (drawn ahead so they can be prefetched)
  kSweep = 4,     ///< kicks of all particles (observations, splitting kick steps)
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
  const pcg_extras::pcg128_t state = (static_cast<pcg_extras::pcg128_t>(out[0]) << 64) | out[1];
  const pcg_extras::pcg128_t stream = (static_cast<pcg_extras::pcg128_t>(out[2]) << 64) | out[3];
  return Engine(state, stream);
}

}  // namespace granboltz
