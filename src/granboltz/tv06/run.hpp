#pragma once
// TV06 runs (intruder and needle): ensembles of event-driven simulations and their output.
#include "granboltz/exec/ensemble_pool.hpp"
#include "granboltz/exec/run_frame.hpp"
#include "granboltz/h5/hdf5_io.hpp"
#include "granboltz/record/record.hpp"
#include "granboltz/tv06/config.hpp"

namespace granboltz {

/// What a TV06 run reads of its config: the frame and its model's section.
struct Tv06RunConfig : RunFrame {
  IntruderConfig intruder;  ///< model: intruder
  NeedleConfig needle;      ///< model: needle
};

/// The record of a `model: intruder` or `model: needle` run of this config, empty.
Record tv06_layout(const Tv06RunConfig& config);

/// Runs the ensembles of this shard that `record` does not hold yet, adding them to it.
void run_tv06(const Tv06RunConfig& config, const DriverOptions& options, Record& record);

/// Writes the datasets a user reads (docs/tv06.md), computed from the record only.
void present_tv06(H5Writer& out, const Tv06RunConfig& config, const Record& record);

/// Peak memory of a TV06 run in bytes, beyond the program itself.
double tv06_memory_estimate(const Tv06RunConfig& config, unsigned threads);

}  // namespace granboltz
