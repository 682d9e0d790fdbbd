#pragma once
// A row set: observation rows of some scalars and speed moments with accumulators of their own,
// and the statistics presented from them. The whole gas (the moments observer), each species of
// a mixture and the rotational temperature are row sets; the engine's own pass over its
// particles fills their rows (RowTargets), and these functions sum and present them the same way
// for each.
#include <cstdint>
#include <string>
#include <vector>

#include "granboltz/dsmc/config.hpp"
#include "granboltz/dsmc/observables.hpp"
#include "granboltz/dsmc/observers/presenter.hpp"
#include "granboltz/h5/hdf5_io.hpp"
#include "granboltz/record/record.hpp"
#include "granboltz/stats/steady.hpp"

namespace granboltz {

/// A set of observation rows with accumulators of its own: the rows of the whole gas (prefix "",
/// the layout of every one-species run), and for the general gas each species' rows and the
/// rotational temperature.
struct RowSet {
  std::string prefix;   ///< of the record's accumulators ("series" -> prefix + "series")
  std::string group;    ///< of the output datasets: "" at the top, "/species/<name>"
  std::uint64_t width;  ///< scalars per row: kNumScalars, or 1 (T_rot)
  std::uint64_t P;      ///< speed moments per row
};
/// The observation times t_m, m = 0..M: m * observe_every (t_M = t_end), or 0 and dsmc.observe's.
std::vector<double> dsmc_times(const DsmcConfig& d);

/// The whole gas's row set.
RowSet whole_gas_rows(const DsmcConfig& d);
/// The row sets beyond the first: one per species of dsmc.species, then T_rot (dsmc.roughness).
std::vector<RowSet> extra_row_sets(const DsmcConfig& d);

/// Ensembles from which the steady-state interval comes from their spread (dsmc.steady_ci:
/// batch); with fewer, from blocking within the ensembles.
inline constexpr std::uint64_t kSteadyMinEnsembles = 10;

/// The observation rows t_m > steady_from in each ensemble.
std::uint64_t steady_rows(const DsmcConfig& d);
/// Blocking levels l = 0..L-1 (blocks of 2^l rows) with at least 2 full blocks per ensemble.
std::uint64_t steady_block_levels(const DsmcConfig& d);
/// The rows t_m > this are steady (a margin below one observation interval past steady_from).
double steady_after(const DsmcConfig& d);

/// The accumulators of a row set other than the whole gas's, contiguous (the whole gas's are
/// interleaved with the run's own: MomentsObserver).
void declare_row_set(Record& r, const DsmcConfig& d, const RowSet& s);

/// One ensemble's rows of a row set into a checkpoint group g: g/observations [next, width] and,
/// with speed moments, g/moment_observations [next, P]; and back into rows allocated for the
/// whole run (std::runtime_error "malformed ensemble state" where they do not fit).
void save_row_set(H5Writer& out, const std::string& g, const RowSet& s, const double* obs,
                  const double* moments, std::uint64_t next);
void load_row_set(const H5Reader& in, const std::string& g, const std::string& ensemble_group,
                  const RowSet& s, double* obs, double* moments, std::uint64_t next);

/// Adds one ensemble's rows of a row set to its accumulators: the series, the speed moments and
/// their cross products, and with steady_from the steady sums and the per-ensemble averages and
/// blocks. `count_samples`: the whole gas counts the steady samples for all.
void add_rows(const DsmcConfig& d, const std::vector<double>& times, const RowSet& set,
              const double* obs, const double* moments, std::uint64_t e, bool count_samples,
              Record& record);

/// The steady-state statistics of scalar k of a row set (k < set.width a row scalar, then its
/// speed moments). `batch`: the batch estimator even where the config asks for steady_ci:
/// independent.
SteadyStats row_set_steady_stats(const DsmcConfig& d, const Record& record, const RowSet& set,
                                 std::uint64_t k, bool batch);

/// Writes mean, ci and variance of observable `o` from sums laid out as [rows][stride].
void write_observable(Presenter& out, const std::string& prefix, const ObservableInfo& o,
                      const std::vector<Moments2>& sums, std::uint64_t stride, std::uint64_t rows,
                      std::uint64_t samples, bool scalar_rows);
/// The /steady group of one observable of a row set (`base`: its first scalar in the set).
void write_steady_observable(Presenter& out, const DsmcConfig& d, const Record& record,
                             const ObservableInfo& o, std::uint64_t base, const RowSet& set);
/// Every observable of kObservables, from sums laid out as [rows][kNumScalars].
void write_moments(Presenter& out, const std::string& prefix, const std::vector<Moments2>& sums,
                   std::uint64_t rows, std::uint64_t samples, bool scalar_rows);
/// The speed moments moment_2 ... moment_2P, from sums laid out as [rows][P].
void write_speed_moments(Presenter& out, const std::string& prefix,
                         const std::vector<Moments2>& sums, std::uint64_t P, std::uint64_t rows,
                         std::uint64_t samples, bool scalar_rows);
/// The steady groups of the speed moments of a row set.
void write_steady_speed_moments(Presenter& out, const DsmcConfig& d, const Record& record,
                                const RowSet& set);
/// a2 (and with P >= 3 a3) of a row set: per row and, with steady_from, steady.
void write_sonine(Presenter& out, const DsmcConfig& d, const Record& record, const RowSet& set);

}  // namespace granboltz
