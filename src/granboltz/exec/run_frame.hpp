#pragma once
// The top-level keys of a run config (model, seed, ensembles and how it executes): what every
// model's run reads besides its own section. Here, below the models, so that a model's run needs
// its own parameters and this frame, not the whole Config (app/config.hpp).
#include <cstdint>

#include "granboltz/core/int128.hpp"

namespace granboltz {

enum class Model { kDsmc, kIntruder, kNeedle };

/// Which ensembles of the run this process computes: [begin, end) of ensembles.
struct Shard {
  std::uint64_t index = 0;
  std::uint64_t count = 1;
};

struct CheckpointSpec {
  double every_seconds = 0.0;  ///< 0: no checkpoints
};

struct RunFrame {
  Model model = Model::kDsmc;
  std::uint64_t seed = 0;
  std::uint64_t ensembles = 1;
  unsigned threads = 0;  ///< 0: all hardware threads; never changes results
  Shard shard;
  CheckpointSpec checkpoint;

  /// The ensembles this shard runs: [first, last) (in 128 bits: N * index may exceed 2^64).
  std::uint64_t first_ensemble() const {
    return static_cast<std::uint64_t>(uint128{ensembles} * shard.index / shard.count);
  }
  std::uint64_t last_ensemble() const {
    return static_cast<std::uint64_t>(uint128{ensembles} * (shard.index + 1) / shard.count);
  }
};

}  // namespace granboltz
