#pragma once
// dsmc.initial.from: the final state of an earlier run, as the start of a new one. The source
// is not stored particle by particle: its ensemble e is simulated again from its stored config
// and seed to its t_end (bit for bit the state its output observed last), so a continued run is
// determined by its config, its seed and the source's config, whatever the threads or shards.
#include <cstdint>
#include <vector>

#include "granboltz/core/vec3.hpp"
#include "granboltz/dsmc/config.hpp"

namespace granboltz {

struct SourceState {
  std::vector<Vec3> velocities;
  std::vector<Vec3> spins;  ///< rough particles; empty otherwise
};

/// The state of the source's ensemble `ensemble` at its t_end (d.source must be set).
SourceState source_state(const DsmcConfig& d, std::uint64_t ensemble);

}  // namespace granboltz
