#pragma once
// A DSMC run: N independent ensembles observed at t_m = m * observe_every, combined into means
// and confidence intervals (GRW05 §5.1), optionally with steady-state time averages (RW05 §4.2).
#include <cstdint>
#include <vector>

#include "granboltz/config.hpp"
#include "granboltz/int128.hpp"
#include "granboltz/ensemble_driver.hpp"
#include "granboltz/hdf5_io.hpp"
#include "granboltz/observables.hpp"
#include "granboltz/statistics.hpp"

namespace granboltz {

struct DsmcResult {
  std::vector<double> times;       ///< t_m, m = 0..M
  std::uint64_t ensembles = 0;     ///< ensembles combined in this result
  std::vector<Moments2> series;    ///< [(M+1) * kNumScalars]
  std::vector<std::uint64_t> histogram;       ///< sum over ensembles of shell counts [(M+1)(K+1)]
  std::vector<uint128> histogram_sq;  ///< sum of squared shell counts
  std::vector<Moments2> steady;    ///< [kNumScalars], over (ensemble, t_m > steady_from)
  std::uint64_t steady_samples = 0;
  // Per ensemble, in ensemble order.
  std::vector<std::uint64_t> ensemble_index, collisions, fictitious, kicks;
  std::vector<double> u_max_final;
};

/// Runs the ensembles of this shard of the config.
DsmcResult run_dsmc(const Config& config, const DriverOptions& options);

/// Writes a result; the file layout is documented in docs/output.md.
void write_dsmc(H5Writer& out, const Config& config, const DsmcResult& result);

}  // namespace granboltz
