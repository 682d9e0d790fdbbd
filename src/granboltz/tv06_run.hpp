#pragma once
// TV06 runs (intruder and needle): ensembles of event-driven simulations and their output.
#include "granboltz/config.hpp"
#include "granboltz/ensemble_driver.hpp"
#include "granboltz/hdf5_io.hpp"

namespace granboltz {

/// Runs a `model: intruder` or `model: needle` config and writes its datasets to `out`.
void run_tv06(H5Writer& out, const Config& config, const DriverOptions& options);

/// Peak memory of a TV06 run in bytes, beyond the program itself.
double tv06_memory_estimate(const Config& config, unsigned threads);

}  // namespace granboltz
