#pragma once
// A DSMC run: N independent ensembles observed at t_m = m * observe_every, combined into means
// and confidence intervals (GRW05 §5.1), optionally with steady-state time averages (RW05 §4.2).
#include "granboltz/config/config.hpp"
#include "granboltz/driver/ensemble_driver.hpp"
#include "granboltz/io/hdf5_io.hpp"
#include "granboltz/io/record.hpp"

namespace granboltz {

/// The record of a DSMC run of this config, empty.
Record dsmc_layout(const Config& config);

/// Runs the ensembles of this shard that `record` does not hold yet, adding them to it.
void run_dsmc(const Config& config, const DriverOptions& options, Record& record);

/// Writes the datasets a user reads (docs/output.md), computed from the record only.
void present_dsmc(H5Writer& out, const Config& config, const Record& record);

/// The observation times t_m, m = 0..M.
std::vector<double> dsmc_times(const DsmcConfig& d);

}  // namespace granboltz
