#pragma once
// One run, described completely by one YAML config (schema: docs/config.md).
#include <cstdint>
#include <string>
#include <vector>

#include "granboltz/config/reader.hpp"
#include "granboltz/dsmc/run.hpp"
#include "granboltz/exec/run_frame.hpp"
#include "granboltz/tv06/run.hpp"

namespace granboltz {

/// A run config: the frame and a section per model (parse_config fills its model's only).
struct Config : RunFrame {
  DsmcConfig dsmc;
  IntruderConfig intruder;
  NeedleConfig needle;

  /// What a model's run reads, copied: the frame and its own section. The models sit below
  /// this file, so they cannot take a Config.
  operator DsmcRunConfig() const { return {*this, dsmc}; }
  operator Tv06RunConfig() const { return {*this, intruder, needle}; }

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

/// The worker threads a config's `threads` and the command line's --threads allow.
inline const IntegerRange kThreadsRange{0, 1024,
                                        "must satisfy 0 <= threads <= 1024 (0: all cores)"};

}  // namespace granboltz
