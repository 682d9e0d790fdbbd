#pragma once
// Slot C, observers: what a DSMC run measures at its observation rows. One class per file, each
// declaring its record sums, observing the particle view of an ensemble (dsmc/engine.hpp) at a
// row into per-ensemble rows that checkpoints keep, adding an ensemble's rows to the record, and
// presenting its datasets (each listed in the output's manifest). dsmc/observers/registry.cpp
// builds the observers a config needs, one line each; run.cpp schedules them generically.
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "granboltz/dsmc/config.hpp"
#include "granboltz/dsmc/engine.hpp"
#include "granboltz/dsmc/observables.hpp"
#include "granboltz/dsmc/observers/presenter.hpp"
#include "granboltz/h5/hdf5_io.hpp"
#include "granboltz/record/record.hpp"
#include "granboltz/stats/correlator.hpp"

namespace granboltz {

/// Where in the record an observer's sums are declared. The record's order fixes the layout of
/// outputs and checkpoints, and it has grown by appending: the observers that were there before
/// the slot existed keep their places between the run's own sums (dsmc_layout). A new observer
/// declares in kAppended only, after everything else.
enum class LayoutPhase {
  kSeries,            ///< first: the whole gas's series
  kRows,              ///< after the whole gas's series
  kSteadySums,        ///< the whole gas's steady sums and speed moments, before the event columns
  kSteadyAverages,    ///< after the event columns, before the whole gas's per-ensemble averages
  kEnsembleAverages,  ///< the whole gas's per-ensemble averages and cross sums
  kWeights,           ///< weighted particles, before the weighted engine's columns
  kCoolingRate,       ///< after the weighted engine's columns
  kComponent,         ///< after the weighted sums, before the general gas's row sets
  kGeneralGas,        ///< the species' and the rotation's row sets, before per-species events
  kRatios,            ///< after the per-species event columns
  kAppended,          ///< after everything: every observer added since
};

/// One ensemble's rows of one observer: what it has observed so far (all rows allocated at the
/// start), saved with the ensemble in a mid-run checkpoint.
struct ObserverRows {
  std::vector<std::uint64_t> counts;
  std::vector<double> values;
  std::vector<MultipleTauCorrelator> correlators;  ///< time correlations (sampled between rows)
};

/// What an observer sees at observation row m, after the engine's own pass (Observer::target).
struct ObservedRow {
  const ParticleView& view;
  const Observation& whole;  ///< the whole gas's scalars at this row (kObservables)
  std::uint64_t m;
};

/// The rows of a run: the observation times and the start of the steady window.
struct RunRows {
  const std::vector<double>& times;
  double steady_after;  ///< rows t_m > steady_after are steady (dsmc.steady_from)
};

/// A finished ensemble, as every observer's accumulate sees it.
struct FinishedEnsemble {
  const RunRows& run;
  const Ensemble& ensemble;
  std::uint64_t index;                    ///< its ensemble number e (for error messages)
  const std::vector<ObserverRows>& rows;  ///< every observer's rows, in make_observers' order
};

class Observer {
 public:
  virtual ~Observer() = default;
  Observer() = default;
  Observer(const Observer&) = delete;
  Observer& operator=(const Observer&) = delete;

  /// Its name in the manifest's `observer` column.
  virtual const char* name() const = 0;
  /// Declares its sums of `phase` (most observers: kAppended only).
  virtual void declare(Record& record, LayoutPhase phase) const = 0;
  /// The rows of a new ensemble, zero. `weighted`: the engine's particles carry weights. An
  /// observer without rows of its own (it sums what the engine or other observers keep) leaves
  /// start, observe, save and load as they are.
  virtual ObserverRows start(bool /*weighted*/) const { return {}; }
  /// Where the engine's own pass over its particles at row m writes what it measures for this
  /// observer (the speed moments, the species' rows): the tuned loops measure everything in one
  /// pass, in the order that fixes the bits. Most observers measure in observe() instead.
  virtual void target(ObserverRows& /*rows*/, std::uint64_t /*m*/, RowTargets& /*out*/) const {}
  /// Observes row m of one ensemble.
  virtual void observe(const ObservedRow& /*row*/, ObserverRows& /*rows*/) const {}
  /// Sampling between the rows (time correlations): the time of the next sample, +infinity when
  /// there is none; the run advances the ensemble there (samples at a row's time before the
  /// row) and calls sample(). Most observers sample nothing.
  virtual double next_sample(const ObserverRows& /*rows*/) const {
    return std::numeric_limits<double>::infinity();
  }
  virtual void sample(const ParticleView& /*view*/, double /*t*/, ObserverRows& /*rows*/) const {}
  /// The rows 0..next-1 into an ensemble's checkpoint group, and back (std::runtime_error naming
  /// the file and the group when they do not fit the config).
  virtual void save(H5Writer& /*out*/, const std::string& /*group*/, const ObserverRows& /*rows*/,
                    std::uint64_t /*next*/) const {}
  virtual ObserverRows load(const H5Reader& /*in*/, const std::string& /*group*/, bool /*weighted*/,
                            std::uint64_t /*next*/) const {
    return {};
  }
  /// Adds one finished ensemble to the record's exact sums (order-independent).
  virtual void accumulate(const FinishedEnsemble& ensemble, const ObserverRows& rows,
                          Record& record) const = 0;
  /// Its datasets, from the record only.
  virtual void present(Presenter& out, const Record& record) const = 0;
};

}  // namespace granboltz
