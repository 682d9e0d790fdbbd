#pragma once
// A DSMC run: N independent ensembles observed at t_m (m * observe_every, or dsmc.observe's
// log grid or list), combined into means
// and confidence intervals (GRW05 §5.1), optionally with steady-state time averages (RW05 §4.2).
#include <string>
#include <vector>

#include "granboltz/dsmc/config.hpp"
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

/// The observation times t_m, m = 0..M: m * observe_every (t_M = t_end), or 0 and dsmc.observe's.
std::vector<double> dsmc_times(const DsmcConfig& d);

/// A set of observation rows with accumulators of its own: the rows of the whole gas (prefix "",
/// the layout of every one-species run), and for the general gas each species' rows and the
/// rotational temperature.
struct RowSet {
  std::string prefix;    ///< of the record's accumulators ("series" -> prefix + "series")
  std::string group;     ///< of the output datasets: "" at the top, "/species/<name>"
  std::uint64_t width;   ///< scalars per row: kNumScalars, or 1 (T_rot)
  std::uint64_t P;       ///< speed moments per row
};
/// The row sets beyond the first: one per species of dsmc.species, then T_rot (dsmc.roughness).
std::vector<RowSet> extra_row_sets(const DsmcConfig& d);

/// A ratio x/y of two row scalars stored as an observable of its own: theta = T_rot/T of rough
/// particles (/theta) and T_a/T_b of the species of a mixture (/temperature_ratio/<a>_over_<b>).
/// Its mean is the ratio of the ensemble means; its interval the delta method with the variances
/// and the covariance of (x, y) over the ensembles (docs/output.md), whose cross sums
/// prefix + "cross" ([rows]) and prefix + "steady_cross" ([1], of the ensembles' time averages)
/// it keeps: exact sums like every other, so shards, merges and resumed runs give the same bits.
struct RatioSet {
  std::string prefix;        ///< of its accumulators
  std::string group;         ///< of its datasets, and under /steady
  std::size_t x_set, y_set;  ///< row sets: 0 the whole gas, k + 1 extra_row_sets()[k]
  std::uint64_t x_k, y_k;    ///< the scalar of each row
  std::string numerator, denominator;  ///< names written as attributes (species names for T_a/T_b)
};
/// theta = T_rot/T with dsmc.roughness, then T_a/T_b for every pair a < b of dsmc.species in the
/// order the species are listed.
std::vector<RatioSet> ratio_sets(const DsmcConfig& d);

/// Ensembles from which the steady-state interval comes from their spread (dsmc.steady_ci:
/// batch); with fewer, from blocking within the ensembles.
inline constexpr std::uint64_t kSteadyMinEnsembles = 10;

/// The steady-state statistics of one scalar (stats/steady.hpp): index k < kNumScalars is a
/// component of an Observation, kNumScalars + p - 1 the speed moment <|v - V|^{2p}>
/// (docs/output.md).
/// `batch`: the batch estimator even where the config asks for steady_ci: independent.
SteadyStats steady_stats(const DsmcRunConfig& config, const Record& record, std::uint64_t k,
                         bool batch = false);
/// The same for scalar k of a row set (k < set.width a row scalar, then its speed moments).
SteadyStats steady_stats(const DsmcRunConfig& config, const Record& record, const RowSet& set,
                         std::uint64_t k, bool batch = false);

/// The observation rows t_m > steady_from in each ensemble.
std::uint64_t steady_rows(const DsmcConfig& d);
/// Blocking levels l = 0..L-1 (blocks of 2^l rows) with at least 2 full blocks per ensemble.
std::uint64_t steady_block_levels(const DsmcConfig& d);

}  // namespace granboltz
