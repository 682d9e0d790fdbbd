#pragma once
// Runs one config of any model and writes its self-describing HDF5 output.
#include <cstdint>
#include <string>

#include "granboltz/app/config.hpp"
#include "granboltz/core/text_hash.hpp"
#include "granboltz/exec/ensemble_pool.hpp"

namespace granboltz {

/// Bytes the run will need at its peak on `threads` threads (particle systems and accumulators).
std::uint64_t estimate_memory(const Config& config, unsigned threads);

/// Bytes of memory available now (MemAvailable, else the physical memory; 0 if unknown).
std::uint64_t available_memory();

/// Runs the config and writes `path` atomically (temporary name, renamed when complete).
/// `command` is recorded as provenance. Throws ConfigError for a run that cannot fit in memory.
void run_to_file(const Config& config, const std::string& path, const DriverOptions& options,
                 const std::string& command);

}  // namespace granboltz
