#pragma once
// TV06 runs (intruder and needle): ensembles of event-driven simulations and their output.
#include "granboltz/config/config.hpp"
#include "granboltz/driver/ensemble_driver.hpp"
#include "granboltz/io/hdf5_io.hpp"
#include "granboltz/io/record.hpp"

namespace granboltz {

/// The record of a `model: intruder` or `model: needle` run of this config, empty.
Record tv06_layout(const Config& config);

/// Runs the ensembles of this shard that `record` does not hold yet, adding them to it.
void run_tv06(const Config& config, const DriverOptions& options, Record& record);

/// Writes the datasets a user reads (docs/tv06.md), computed from the record only.
void present_tv06(H5Writer& out, const Config& config, const Record& record);

/// Peak memory of a TV06 run in bytes, beyond the program itself.
double tv06_memory_estimate(const Config& config, unsigned threads);

}  // namespace granboltz
