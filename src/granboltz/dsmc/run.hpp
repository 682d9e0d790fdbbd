#pragma once
// A DSMC run: N independent ensembles observed at t_m (m * observe_every, or dsmc.observe's
// log grid or list), combined into means
// and confidence intervals (GRW05 §5.1), optionally with steady-state time averages (RW05 §4.2).
#include <string>
#include <vector>

#include "granboltz/dsmc/config.hpp"
#include "granboltz/dsmc/observers/row_set.hpp"  // RowSet, steady_rows
#include "granboltz/exec/ensemble_pool.hpp"
#include "granboltz/exec/run_frame.hpp"
#include "granboltz/h5/hdf5_io.hpp"
#include "granboltz/record/record.hpp"
#include "granboltz/stats/steady.hpp"

namespace granboltz {

/// What a DSMC run reads of its config: the frame and the `dsmc:` section.
struct DsmcRunConfig : RunFrame {
  DsmcConfig dsmc;
};

/// The record of a DSMC run of this config, empty.
Record dsmc_layout(const DsmcRunConfig& config);

/// Runs the ensembles of this shard that `record` does not hold yet, adding them to it.
void run_dsmc(const DsmcRunConfig& config, const DriverOptions& options, Record& record);

/// Writes the datasets a user reads (docs/output.md), computed from the record only.
void present_dsmc(H5Writer& out, const DsmcRunConfig& config, const Record& record);

/// The steady-state statistics of one scalar (stats/steady.hpp): index k < kNumScalars is a
/// component of an Observation, kNumScalars + p - 1 the speed moment <|v - V|^{2p}>
/// (docs/output.md).
/// `batch`: the batch estimator even where the config asks for steady_ci: independent.
SteadyStats steady_stats(const DsmcRunConfig& config, const Record& record, std::uint64_t k,
                         bool batch = false);

}  // namespace granboltz
