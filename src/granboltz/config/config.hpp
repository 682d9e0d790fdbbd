#pragma once
// One run, described completely by one YAML config (schema: docs/config.md).
#include <cstdint>
#include <string>
#include <vector>

#include "granboltz/config/reader.hpp"
#include "granboltz/dsmc/config.hpp"
#include "granboltz/stats/int128.hpp"
#include "granboltz/tv06/config.hpp"

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

struct Config {
  Model model = Model::kDsmc;
  std::uint64_t seed = 0;
  std::uint64_t ensembles = 1;
  unsigned threads = 0;  ///< 0: all hardware threads; never changes results
  Shard shard;
  CheckpointSpec checkpoint;
  DsmcConfig dsmc;
  IntruderConfig intruder;
  NeedleConfig needle;

  /// The ensembles this shard runs: [first, last) (in 128 bits: N * index may exceed 2^64).
  std::uint64_t first_ensemble() const {
    return static_cast<std::uint64_t>(uint128{ensembles} * shard.index / shard.count);
  }
  std::uint64_t last_ensemble() const {
    return static_cast<std::uint64_t>(uint128{ensembles} * (shard.index + 1) / shard.count);
  }

  /// The complete config with every default made explicit. With physics_only, the keys that
  /// cannot change results (threads, shard, checkpoint) are left out: this text is what every
  /// output file stores, so that shards and thread counts give identical files.
  std::string to_yaml(bool physics_only) const;
};

/// Reads, overrides and validates a config; throws ConfigError naming the offending key.
Config parse_config(const std::string& yaml_text, const std::string& origin,
                    const std::vector<std::string>& overrides = {});
Config load_config(const std::string& path, const std::vector<std::string>& overrides = {});

std::string model_name(Model m);

}  // namespace granboltz
