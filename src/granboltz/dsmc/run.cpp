#include "granboltz/dsmc/run.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>

#include "granboltz/config/reader.hpp"
#include "granboltz/dsmc/engine.hpp"
#include "granboltz/dsmc/observables.hpp"
#include "granboltz/dsmc/observers/registry.hpp"
#include "granboltz/exec/safe_points.hpp"

namespace granboltz {

namespace {
struct ColumnSpec {
  const char* path;
  bool floating;
};
const ColumnSpec kColumns[] = {{"/events/collisions", false},
                               {"/events/fictitious", false},
                               {"/events/kicks", false},
                               {"/events/u_max_final", true}};

bool checkpoint_has(const std::vector<std::uint64_t>& sorted, std::uint64_t e) {
  return std::binary_search(sorted.begin(), sorted.end(), e);
}
}  // namespace

Record dsmc_layout(const DsmcRunConfig& config) {
  const DsmcConfig& d = config.dsmc;
  Record r;
  // Each observer declares its sums at its phases (LayoutPhase), between the engine's event
  // columns, so that the order of every existing output and checkpoint stays.
  const auto observers = make_observers(d);
  auto declare = [&](LayoutPhase phase) {
    for (const auto& o : observers) o->declare(r, phase);
  };
  declare(LayoutPhase::kSeries);
  declare(LayoutPhase::kRows);
  declare(LayoutPhase::kSteadySums);
  for (const ColumnSpec& c : kColumns) r.declare_column(c.path, c.floating);
  declare(LayoutPhase::kSteadyAverages);
  declare(LayoutPhase::kEnsembleAverages);
  declare(LayoutPhase::kWeights);
  if (d.weights.swpm) {
    r.declare_column("/events/reductions", false);
    r.declare_column("/events/particles_final", false);
    // The Gaussian thermostat: per ensemble the mean cooling rate over the steady window (or the
    // whole run); its sums are the cooling-rate observer's.
    if (d.thermostat == Thermostat::kGaussian) r.declare_column("/events/cooling_rate", true);
  }
  declare(LayoutPhase::kCoolingRate);
  declare(LayoutPhase::kComponent);
  declare(LayoutPhase::kGeneralGas);
  if (d.species_written)
    for (const auto& sp : d.species)
      r.declare_column("/events/species/" + sp.name + "/collisions", false);
  declare(LayoutPhase::kRatios);
  declare(LayoutPhase::kAppended);
  return r;
}

namespace {

/// An ensemble under way: the particle system and what has been observed so far.
struct InProgress {
  std::unique_ptr<Ensemble> ensemble;
  std::uint64_t next = 0;              // the next observation index m
  std::vector<ObserverRows> observed;  // one per observer (make_observers)
};

std::string in_progress_group(std::uint64_t e) { return "/in_progress/" + std::to_string(e); }

using Observers = std::vector<std::unique_ptr<Observer>>;

bool has_radial_histogram(const Observers& observers) {
  for (const auto& o : observers)
    if (std::string(o->name()) == "histogram") return true;
  return false;
}

void save_in_progress(H5Writer& out, std::uint64_t e, const InProgress& w,
                      const Observers& observers) {
  const std::string g = in_progress_group(e);
  w.ensemble->save(out, g);
  for (std::size_t k = 0; k < observers.size(); ++k)
    observers[k]->save(out, g, w.observed[k], w.next);
  // Checkpoints have always held the radial histogram's rows, empty without dsmc.histogram.
  if (!has_radial_histogram(observers)) {
    out.write(g + "/histogram", std::vector<std::uint64_t>{}, {0});
    if (w.ensemble->weighted()) out.write(g + "/histogram_weight", std::vector<double>{}, {0});
  }
  out.attr(g, "next_observation", w.next);
}

InProgress load_in_progress(const DsmcConfig& d, const H5Reader& in, std::uint64_t e,
                            std::uint64_t rows, const Observers& observers, ProgressSlot* slot) {
  const std::string g = in_progress_group(e);
  InProgress w;
  w.ensemble = restore_ensemble(d, in, g, slot);
  w.next = in.attr_uint64(g, "next_observation");
  if (w.next == 0 || w.next > rows)
    throw std::runtime_error(in.path() + ": malformed ensemble state " + g);
  for (const auto& o : observers)
    w.observed.push_back(o->load(in, g, w.ensemble->weighted(), w.next));
  return w;
}

}  // namespace

void run_dsmc(const DsmcRunConfig& config, const DriverOptions& options, Record& record) {
  const DsmcConfig& d = config.dsmc;
  const std::vector<double> times = dsmc_times(d);
  const std::uint64_t rows = times.size();
  const Observers observers = make_observers(d);
  const RunRows run_rows{times, steady_after(d)};
  bool sampling = false;
  for (const auto& o : observers)
    sampling = sampling || std::isfinite(o->next_sample(o->start(false)));

  // Ensembles saved in progress by an interrupted run come first, then those not yet started.
  std::vector<std::uint64_t> todo, resumed;
  std::unique_ptr<H5Reader> checkpoint;
  if (!options.resume_from.empty()) {
    checkpoint = std::make_unique<H5Reader>(options.resume_from);
    for (std::uint64_t e = config.first_ensemble(); e < config.last_ensemble(); ++e)
      if (!record.has_ensemble(e) && checkpoint->exists(in_progress_group(e))) resumed.push_back(e);
  }
  todo = resumed;
  for (std::uint64_t e = config.first_ensemble(); e < config.last_ensemble(); ++e)
    if (!record.has_ensemble(e) && !checkpoint_has(resumed, e)) todo.push_back(e);

  // One lock for the record and the pause protocol of checkpoints: when one is due, every
  // ensemble under way parks at its next safe point, the checkpoint is written, and they go on.
  SafePoints<InProgress> safe;
  const DriverOptions opts =
      safe.options(options, [&](const std::map<std::uint64_t, const InProgress*>& parked) {
        options.checkpoint(record, [&](H5Writer& out) {
          for (const auto& [e, w] : parked) save_in_progress(out, e, *w, observers);
        });
      });

  for_each_ensemble(todo, opts, [&](std::uint64_t e, ProgressSlot& slot) {
    InProgress w;
    SafePoints<InProgress>::Member member(safe);
    if (checkpoint_has(resumed, e)) {
      std::lock_guard<std::mutex> lock(safe.mutex());  // HDF5 (serial build) is not thread-safe
      w = load_in_progress(d, *checkpoint, e, rows, observers, &slot);
    } else {
      w.ensemble = make_ensemble(d, config.seed, e, &slot);
      for (const auto& o : observers) w.observed.push_back(o->start(w.ensemble->weighted()));
    }
    Ensemble& ens = *w.ensemble;
    // Samples between the rows (time correlations), each taken where the ensemble is advanced to
    // its time, in place where the engine allows (Ensemble::advance_lazily: no kick, no fold, so
    // the run goes on as if unobserved); those due at or before row time t come before the row.
    auto sample_until = [&](double t) {
      if (!sampling) return;
      for (;;) {
        double s = std::numeric_limits<double>::infinity();
        for (std::size_t k = 0; k < observers.size(); ++k)
          s = std::min(s, observers[k]->next_sample(w.observed[k]));
        if (!(s <= t)) return;
        // A sample at a row's time takes the row's stop (the fold and the majorant are due there
        // anyway, and the row then sees the true velocities); between the rows it is in place.
        const bool at_row = s == t;
        if (s > ens.time()) {
          if (at_row)
            while (!ens.advance_to(s, safe.pause_flag())) safe.park(e, &w);
          else
            while (!ens.advance_lazily(s, safe.pause_flag())) safe.park(e, &w);
        }
        const ParticleView view = at_row ? ens.view() : ens.lazy_view();
        for (std::size_t k = 0; k < observers.size(); ++k)
          if (observers[k]->next_sample(w.observed[k]) == s)
            observers[k]->sample(view, s, w.observed[k]);
      }
    };
    for (; w.next < rows; ++w.next) {
      const std::uint64_t m = w.next;
      sample_until(times[m]);
      if (m > 0 && times[m] > ens.time())
        while (!ens.advance_to(times[m], safe.pause_flag())) safe.park(e, &w);
      // The engine measures the row in one pass, into the observers' targets; then each observer
      // sees the particles and the whole gas's scalars.
      RowTargets row;
      for (std::size_t k = 0; k < observers.size(); ++k)
        observers[k]->target(w.observed[k], m, row);
      const Observation whole = ens.observe(d, row);
      const ParticleView view = ens.view();
      const ObservedRow observed{view, whole, m};
      for (std::size_t k = 0; k < observers.size(); ++k)
        observers[k]->observe(observed, w.observed[k]);
      // An engine's own time averages (the weighted engine's cooling rate) run over the rows the
      // steady observables use: from the last row outside that window on.
      if (!(times[m] > run_rows.steady_after)) ens.mark_window();
    }
    // Exact sums: the order in which ensembles arrive here does not matter.
    std::lock_guard<std::mutex> lock(safe.mutex());
    member.leave();
    const FinishedEnsemble finished{run_rows, ens, e, w.observed};
    for (std::size_t k = 0; k < observers.size(); ++k)
      observers[k]->accumulate(finished, w.observed[k], record);
    record.add_ensemble(e, ens.event_columns());
  });
}

SteadyStats steady_stats(const DsmcRunConfig& config, const Record& record, std::uint64_t k,
                         bool batch) {
  return row_set_steady_stats(config.dsmc, record, whole_gas_rows(config.dsmc), k, batch);
}

void present_dsmc(H5Writer& file, const DsmcRunConfig& config, const Record& record) {
  const std::vector<double> times = dsmc_times(config.dsmc);
  Presenter out(file);
  out.observer("time");
  out.write("/time", times, {times.size()}, "the observation times t_m, m = 0..M");
  for (const auto& o : make_observers(config.dsmc)) {
    out.observer(o->name());
    o->present(out, record);
  }
  out.write_manifest();
}

}  // namespace granboltz
