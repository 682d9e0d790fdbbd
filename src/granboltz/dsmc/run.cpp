#include "granboltz/dsmc/run.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>

#include "granboltz/config/reader.hpp"
#include "granboltz/dsmc/engine.hpp"
#include "granboltz/dsmc/observables.hpp"
#include "granboltz/dsmc/observers/registry.hpp"
#include "granboltz/exec/safe_points.hpp"
#include "granboltz/stats/blocking.hpp"
#include "granboltz/stats/delta_method.hpp"

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

std::vector<double> dsmc_times(const DsmcConfig& d) {
  if (!d.observe_times.empty()) {  // dsmc.observe: the times as read
    std::vector<double> t{0.0};
    t.insert(t.end(), d.observe_times.begin(), d.observe_times.end());
    return t;
  }
  const std::uint64_t M = d.observations();
  std::vector<double> t(M + 1);
  for (std::uint64_t m = 0; m <= M; ++m)
    t[m] = m == M ? d.t_end : static_cast<double>(m) * d.observe_every;
  return t;
}

std::uint64_t steady_rows(const DsmcConfig& d) {
  if (!d.steady) return 0;
  std::uint64_t rows = 0;
  for (double t : dsmc_times(d)) rows += t > d.steady_from + 1e-9 * d.observe_every;
  return rows;
}

std::uint64_t steady_block_levels(const DsmcConfig& d) { return block_levels(steady_rows(d)); }

std::vector<RowSet> extra_row_sets(const DsmcConfig& d) {
  std::vector<RowSet> out;
  if (d.species_written)
    for (std::size_t a = 0; a < d.species.size(); ++a)
      out.push_back({"species_" + std::to_string(a) + "_", "/species/" + d.species[a].name,
                     static_cast<std::uint64_t>(kNumScalars), static_cast<std::uint64_t>(d.moments)});
  if (d.roughness.on) out.push_back({"rotation_", "", 1, 0});
  return out;
}

namespace {
/// The offset of T in an Observation (kObservables).
constexpr std::uint64_t kTemperature = 4;
}  // namespace

std::vector<RatioSet> ratio_sets(const DsmcConfig& d) {
  std::vector<RatioSet> out;
  const std::size_t extra = extra_row_sets(d).size();
  // T_rot is the last extra row set, its only scalar; T the whole gas's (translational).
  if (d.roughness.on)
    out.push_back({"theta_", "/theta", extra, 0, 0, kTemperature, "temperature_rotational",
                   "temperature"});
  if (d.species_written)
    for (std::size_t a = 0; a < d.species.size(); ++a)
      for (std::size_t b = a + 1; b < d.species.size(); ++b) {
        const std::string& x = d.species[a].name;
        const std::string& y = d.species[b].name;
        out.push_back({"ratio_" + std::to_string(a) + "_" + std::to_string(b) + "_",
                       "/temperature_ratio/" + x + "_over_" + y, a + 1, b + 1, kTemperature,
                       kTemperature, x, y});
      }
  return out;
}

namespace {
/// The accumulators of a row set other than the first (the layout of the first is written out in
/// dsmc_layout, in the order outputs of earlier versions have).
void declare_row_set(Record& r, const DsmcConfig& d, const RowSet& s) {
  const std::uint64_t rows = d.observations() + 1, W = s.width, P = s.P;
  r.declare_moments(s.prefix + "series", rows * W);
  if (d.steady) r.declare_moments(s.prefix + "steady", W);
  if (P) r.declare_moments(s.prefix + "moment_series", rows * P);
  if (P && d.steady) r.declare_moments(s.prefix + "moment_steady", P);
  if (d.steady) {
    r.declare_moments(s.prefix + "steady_ensemble", W + P);
    if (const std::uint64_t L = steady_block_levels(d))
      r.declare_moments(s.prefix + "steady_blocks", L * (W + P));
  }
  if (const std::uint64_t C = cross_pairs(P)) {
    r.declare_moments(s.prefix + "moment_cross", rows * C);
    if (d.steady) r.declare_moments(s.prefix + "steady_moment_cross", C);
  }
}
}  // namespace

Record dsmc_layout(const DsmcRunConfig& config) {
  const DsmcConfig& d = config.dsmc;
  const std::uint64_t rows = d.observations() + 1;
  Record r;
  // The observers' sums go between the whole gas's own at their phases (LayoutPhase), so that
  // the order of every existing output and checkpoint stays.
  const auto observers = make_observers(d);
  auto declare = [&](LayoutPhase phase) {
    for (const auto& o : observers) o->declare(r, phase);
  };
  r.declare_moments("series", rows * kNumScalars);
  declare(LayoutPhase::kRows);
  if (d.steady) {
    r.declare_moments("steady", kNumScalars);
    r.declare_total("steady_samples");
  }
  // The speed moments have sums of their own, so that the other sums keep their layout.
  const auto P = static_cast<std::uint64_t>(d.moments);
  if (P) r.declare_moments("moment_series", rows * P);
  if (P && d.steady) r.declare_moments("moment_steady", P);
  for (const ColumnSpec& c : kColumns) r.declare_column(c.path, c.floating);
  declare(LayoutPhase::kSteadyAverages);
  if (d.steady) {
    // Consecutive rows of an ensemble are correlated: per ensemble its time average of every
    // scalar and speed moment, and for each blocking level the blocked variance of that average.
    // Kept with steady_ci: independent too, whose outputs show the honest interval beside theirs.
    const std::uint64_t K = kNumScalars + P;
    r.declare_moments("steady_ensemble", K);
    if (const std::uint64_t L = steady_block_levels(d)) r.declare_moments("steady_blocks", L * K);
  }
  // a2 and a3 from M2, M4, M6: their intervals by the delta method need the ensembles' cross
  // sums (only `sum` is used). Pairs (M2, M4), then with P >= 3 (M2, M6), (M4, M6).
  if (const std::uint64_t C = cross_pairs(P)) {
    r.declare_moments("moment_cross", rows * C);
    if (d.steady) r.declare_moments("steady_moment_cross", C);
  }
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
  // The general gas: each species' rows, the rotational temperature, per-species events.
  for (const RowSet& s : extra_row_sets(d)) declare_row_set(r, d, s);
  if (d.species_written)
    for (const auto& sp : d.species) r.declare_column("/events/species/" + sp.name + "/collisions", false);
  // The ratios theta and T_a/T_b: the cross sums of their two scalars, per row and of the
  // ensembles' steady time averages (the other sums they need are the row sets' own).
  for (const RatioSet& x : ratio_sets(d)) {
    r.declare_moments(x.prefix + "cross", rows);
    if (d.steady) r.declare_moments(x.prefix + "steady_cross", 1);
  }
  declare(LayoutPhase::kAppended);
  return r;
}

namespace {

/// An ensemble under way: the particle system and what has been observed so far.
struct InProgress {
  std::unique_ptr<Ensemble> ensemble;
  std::uint64_t next = 0;              // the next observation index m
  std::vector<Observation> obs;        // [rows]
  std::vector<double> moments;         // [rows * P]: <|v - V|^{2p}>, p = 1..P
  std::vector<ObserverRows> observed;  // one per observer (make_observers)
  // The general gas: for each of extra_row_sets(), [rows * width] scalars and [rows * P] moments.
  std::vector<std::vector<double>> xobs, xmoments;
};

// An observable that overflowed: named with the values that make a run overflow, instead of
// the exact sums' bare refusal of a non-finite number.
[[noreturn]] void throw_not_finite(int k, double value, double t, std::uint64_t e) {
  const char* name = "an observable";
  for (const auto& o : kObservables) {
    if (k < 0) break;
    const int width = o.rank == 0 ? 1 : o.rank == 1 ? 3 : 9;
    if (k >= o.offset && k < o.offset + width) name = o.name;
  }
  throw std::runtime_error(std::string("dsmc: ") + name + " = " + format_real(value) +
                           " at t = " + format_real(t) + " in ensemble " + std::to_string(e) +
                           ": the simulation overflowed; are dsmc.beta, dsmc.initial.temperature "
                           "or dsmc.kernel.C far too large?");
}

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
  for (std::size_t k = 0; k < observers.size(); ++k) observers[k]->save(out, g, w.observed[k]);
  // Checkpoints have always held the radial histogram's rows, empty without dsmc.histogram.
  if (!has_radial_histogram(observers)) {
    out.write(g + "/histogram", std::vector<std::uint64_t>{}, {0});
    if (w.ensemble->weighted()) out.write(g + "/histogram_weight", std::vector<double>{}, {0});
  }
  for (std::size_t k = 0; k < w.xobs.size(); ++k) {
    const std::string x = g + "/row_set_" + std::to_string(k);
    const std::uint64_t W = w.xobs[k].size() / w.obs.size(), P = w.xmoments[k].size() / w.obs.size();
    out.write(x + "/observations",
              std::vector<double>(w.xobs[k].begin(),
                                  w.xobs[k].begin() + static_cast<std::ptrdiff_t>(w.next * W)),
              {w.next, W});
    if (P)
      out.write(x + "/moment_observations",
                std::vector<double>(w.xmoments[k].begin(),
                                    w.xmoments[k].begin() + static_cast<std::ptrdiff_t>(w.next * P)),
                {w.next, P});
  }
  std::vector<double> obs;
  for (std::uint64_t m = 0; m < w.next; ++m) obs.insert(obs.end(), w.obs[m].begin(), w.obs[m].end());
  out.write(g + "/observations", obs, {w.next, kNumScalars});
  const std::uint64_t P = w.moments.size() / w.obs.size();
  if (P)
    out.write(g + "/moment_observations",
              std::vector<double>(w.moments.begin(),
                                  w.moments.begin() + static_cast<std::ptrdiff_t>(w.next * P)),
              {w.next, P});
  out.attr(g, "next_observation", w.next);
}

InProgress load_in_progress(const DsmcConfig& d, const H5Reader& in, std::uint64_t e,
                            std::uint64_t rows, const Observers& observers, ProgressSlot* slot) {
  const std::string g = in_progress_group(e);
  InProgress w;
  w.ensemble = restore_ensemble(d, in, g, slot);
  for (const auto& o : observers) w.observed.push_back(o->load(in, g, w.ensemble->weighted()));
  w.next = in.attr_uint64(g, "next_observation");
  const auto obs = in.read_double(g + "/observations");
  if (w.next == 0 || w.next > rows || obs.size() != w.next * kNumScalars)
    throw std::runtime_error(in.path() + ": malformed ensemble state " + g);
  w.obs.resize(rows);
  for (std::uint64_t m = 0; m < w.next; ++m)
    std::copy_n(obs.begin() + static_cast<std::ptrdiff_t>(m * kNumScalars), kNumScalars,
                w.obs[m].begin());
  const auto P = static_cast<std::uint64_t>(d.moments);
  w.moments.assign(rows * P, 0.0);
  if (P) {
    const std::string path = g + "/moment_observations";
    if (!in.exists(path) || in.dims(path) != Dims{w.next, P})
      throw std::runtime_error(in.path() + ": malformed ensemble state " + g);
    const auto moments = in.read_double(path);
    std::copy(moments.begin(), moments.end(), w.moments.begin());
  }
  const std::vector<RowSet> extra = extra_row_sets(d);
  for (std::size_t k = 0; k < extra.size(); ++k) {
    const std::string x = g + "/row_set_" + std::to_string(k);
    const std::uint64_t W = extra[k].width, Q = extra[k].P;
    w.xobs.emplace_back(rows * W, 0.0);
    w.xmoments.emplace_back(rows * Q, 0.0);
    if (!in.exists(x + "/observations") || in.dims(x + "/observations") != Dims{w.next, W} ||
        (Q && (!in.exists(x + "/moment_observations") ||
               in.dims(x + "/moment_observations") != Dims{w.next, Q})))
      throw std::runtime_error(in.path() + ": malformed ensemble state " + g);
    const auto o = in.read_double(x + "/observations");
    std::copy(o.begin(), o.end(), w.xobs[k].begin());
    if (Q) {
      const auto mm = in.read_double(x + "/moment_observations");
      std::copy(mm.begin(), mm.end(), w.xmoments[k].begin());
    }
  }
  return w;
}

/// One ensemble's contribution to steady_ensemble and steady_blocks. Computed from its rows alone
/// in a fixed order, so the same ensemble always adds the same doubles to the exact sums.
void add_steady_blocks(const DsmcConfig& d, const std::vector<double>& times, const RowSet& set,
                       const double* obs, const double* moments, Record& record) {
  const double steady_after = d.steady_from + 1e-9 * d.observe_every;
  const std::uint64_t P = set.P, W = set.width;
  const std::uint64_t K = W + P, L = steady_block_levels(d);
  std::uint64_t first = 0;
  while (first < times.size() && !(times[first] > steady_after)) ++first;
  const std::uint64_t R = times.size() - first;
  auto& ens = record.moments(set.prefix + "steady_ensemble");
  auto* blocks = L ? &record.moments(set.prefix + "steady_blocks") : nullptr;
  std::vector<double> x(R), avg(K);
  for (std::uint64_t k = 0; k < K; ++k) {
    for (std::uint64_t i = 0; i < R; ++i)
      x[i] = k < W ? obs[(first + i) * W + k] : moments[(first + i) * P + (k - W)];
    avg[k] = row_average(x.data(), R);
    ens[k].add(avg[k]);
    for (std::uint64_t l = 0; l < L; ++l)
      (*blocks)[l * K + k].add(blocked_variance(x.data(), R, std::uint64_t{1} << l));
  }
  if (cross_pairs(P))
    add_cross(record.moments(set.prefix + "steady_moment_cross").data(), &avg[W], P);
}

/// Adds one ensemble's rows of a row set to its accumulators: the series, the speed moments and
/// their cross products, and with steady_from the steady sums and the per-ensemble averages and
/// blocks. `count_samples`: the first set counts the steady samples for all.
void add_rows(const DsmcConfig& d, const std::vector<double>& times, const RowSet& set,
              const double* obs, const double* moments, std::uint64_t e, bool count_samples,
              Record& record) {
  const double steady_after = d.steady_from + 1e-9 * d.observe_every;
  const std::uint64_t rows = times.size(), W = set.width, P = set.P;
  auto& series = record.moments(set.prefix + "series");
  for (std::uint64_t m = 0; m < rows; ++m) {
    const double* o = obs + m * W;
    for (std::uint64_t k = 0; k < W; ++k)
      if (!std::isfinite(o[k])) throw_not_finite(set.group.empty() && W == kNumScalars ? static_cast<int>(k) : -1, o[k], times[m], e);
    for (std::uint64_t k = 0; k < W; ++k) series[m * W + k].add(o[k]);
    const double* mm = moments + m * P;
    if (P) {
      // After the other observables, so that a run overflowing anyway fails as before.
      for (std::uint64_t k = 0; k < P; ++k)
        if (!(std::fabs(mm[k]) <= kMomentLimit))
          throw std::runtime_error(
              "dsmc.moments = " + std::to_string(P) + ": " +
              moment_name(static_cast<int>(k) + 1) + " = " + format_real(mm[k]) +
              " at t = " + format_real(times[m]) + " in ensemble " + std::to_string(e) +
              " exceeds 1e150 (its square would overflow); ask for fewer moments");
      auto& mseries = record.moments(set.prefix + "moment_series");
      for (std::uint64_t k = 0; k < P; ++k) mseries[m * P + k].add(mm[k]);
      if (const std::uint64_t C = cross_pairs(P))
        add_cross(record.moments(set.prefix + "moment_cross").data() + m * C, mm, P);
    }
    if (d.steady && times[m] > steady_after) {
      auto& steady = record.moments(set.prefix + "steady");
      for (std::uint64_t k = 0; k < W; ++k) steady[k].add(o[k]);
      if (P) {
        auto& msteady = record.moments(set.prefix + "moment_steady");
        for (std::uint64_t k = 0; k < P; ++k) msteady[k].add(mm[k]);
      }
      if (count_samples) ++record.total("steady_samples");
    }
  }
  if (d.steady) add_steady_blocks(d, times, set, obs, moments, record);
}

/// One ensemble's cross sums of the ratios: x y per row and, with steady_from, the product of its
/// time averages of x and y over the steady rows, each summed as add_steady_blocks sums it (in
/// row order, then divided by R), so that they are the averages in steady_ensemble.
/// obs[s], width[s]: the rows of row set s (0 the whole gas, k + 1 extra_row_sets()[k]).
void add_ratios(const DsmcConfig& d, const std::vector<double>& times,
                const std::vector<const double*>& obs, const std::vector<std::uint64_t>& width,
                Record& record) {
  const double steady_after = d.steady_from + 1e-9 * d.observe_every;
  const std::uint64_t rows = times.size();
  std::uint64_t first = 0;
  while (first < rows && !(times[first] > steady_after)) ++first;
  auto average = [&](const double* o, std::uint64_t W) {
    double sum = 0.0;
    for (std::uint64_t m = first; m < rows; ++m) sum += o[m * W];
    return sum / static_cast<double>(rows - first);
  };
  for (const RatioSet& r : ratio_sets(d)) {
    const double* x = obs[r.x_set] + r.x_k;
    const double* y = obs[r.y_set] + r.y_k;
    const std::uint64_t wx = width[r.x_set], wy = width[r.y_set];
    auto& cross = record.moments(r.prefix + "cross");
    for (std::uint64_t m = 0; m < rows; ++m) cross[m].sum.add(x[m * wx] * y[m * wy]);
    if (d.steady && first < rows)
      record.moments(r.prefix + "steady_cross")[0].sum.add(average(x, wx) * average(y, wy));
  }
}

}  // namespace

void run_dsmc(const DsmcRunConfig& config, const DriverOptions& options, Record& record) {
  const DsmcConfig& d = config.dsmc;
  const std::vector<double> times = dsmc_times(d);
  const std::uint64_t rows = times.size();
  const double steady_after = d.steady_from + 1e-9 * d.observe_every;
  const auto P = static_cast<std::uint64_t>(d.moments);
  const Observers observers = make_observers(d);
  const RunRows run_rows{times, steady_after};

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
      for (const RowSet& x : extra_row_sets(d)) {
        w.xobs.emplace_back(rows * x.width, 0.0);
        w.xmoments.emplace_back(rows * x.P, 0.0);
      }
      w.obs.resize(rows);
      w.moments.assign(rows * P, 0.0);
    }
    Ensemble& ens = *w.ensemble;
    for (; w.next < rows; ++w.next) {
      const std::uint64_t m = w.next;
      if (m > 0)
        while (!ens.advance_to(times[m], safe.pause_flag())) safe.park(e, &w);
      RowTargets row;
      row.moments = {w.moments.data() + m * P, P};
      for (std::size_t k = 0; k < w.xobs.size(); ++k) {
        row.rows.push_back(w.xobs[k].data() + m * (w.xobs[k].size() / rows));
        row.row_moments.push_back(w.xmoments[k].data() + m * (w.xmoments[k].size() / rows));
      }
      w.obs[m] = ens.observe(d, row);
      if (!observers.empty()) {
        const ParticleView view = ens.view();
        const ObservedRow observed{view, w.obs[m], m};
        for (std::size_t k = 0; k < observers.size(); ++k) observers[k]->observe(observed, w.observed[k]);
      }
      // An engine's own time averages (the weighted engine's cooling rate) run over the rows the
      // steady observables use: from the last row outside that window on.
      if (!(times[m] > steady_after)) ens.mark_window();
    }
    // Exact sums: the order in which ensembles arrive here does not matter.
    std::lock_guard<std::mutex> lock(safe.mutex());
    member.leave();
    const RowSet whole{"", "", kNumScalars, P};
    add_rows(d, times, whole, w.obs.data()->data(), w.moments.data(), e, true, record);
    const std::vector<RowSet> extra = extra_row_sets(d);
    for (std::size_t k = 0; k < extra.size(); ++k)
      add_rows(d, times, extra[k], w.xobs[k].data(), w.xmoments[k].data(), e, false, record);
    if (!extra.empty()) {
      std::vector<const double*> rows_of{w.obs.data()->data()};
      std::vector<std::uint64_t> width{kNumScalars};
      for (std::size_t k = 0; k < extra.size(); ++k) {
        rows_of.push_back(w.xobs[k].data());
        width.push_back(extra[k].width);
      }
      add_ratios(d, times, rows_of, width, record);
    }
    for (std::size_t k = 0; k < observers.size(); ++k)
      observers[k]->accumulate(run_rows, w.observed[k], ens, record);
    record.add_ensemble(e, ens.event_columns());
  });
}

namespace {

Dims shape_of(const ObservableInfo& o, std::uint64_t rows) {
  if (o.rank == 0) return {rows};
  if (o.rank == 1) return {rows, 3};
  return {rows, 3, 3};
}

/// Writes mean, ci and variance of observable `o` from sums laid out as [rows][stride].
void write_observable(Presenter& out, const std::string& prefix, const ObservableInfo& o,
                      const std::vector<Moments2>& sums, std::uint64_t stride, std::uint64_t rows,
                      std::uint64_t samples, bool scalar_rows) {
  const int size = observable_size(o);
  std::vector<double> mean, ci, var;
  for (std::uint64_t m = 0; m < rows; ++m)
    for (int k = 0; k < size; ++k) {
      const MeanCi s = sums[m * stride + o.offset + k].stats(samples);
      mean.push_back(s.mean);
      ci.push_back(s.ci);
      var.push_back(s.variance);
    }
  Dims dims = shape_of(o, rows);
  if (scalar_rows) dims.erase(dims.begin());
  const std::string g = prefix + "/" + o.name;
  const std::string what = std::string(o.description) + (scalar_rows ? "" : "; per row t_m");
  out.write(g + "/mean", mean, dims, what + ": mean over the ensembles");
  out.write(g + "/ci", ci, dims, what + ": confidence half-width (lambda_p: root attribute confidence_lambda_p)");
  out.write(g + "/variance", var, dims, what + ": variance over the ensembles");
  out.attr(g, "description", std::string(o.description));
}

/// The /steady group of one observable: mean, ci, variance as write_observable, plus sigma and
/// the estimator's attributes (the largest tau_int over the components, the smallest N_eff).
/// With steady_ci: independent the batch estimator's sigma and ci follow in a `batch` subgroup.
void write_steady_observable(Presenter& out, const DsmcRunConfig& config, const Record& record,
                             const ObservableInfo& o, std::uint64_t base, const RowSet& set) {
  const int size = observable_size(o);
  const std::string g = "/steady" + set.group + "/" + std::string(o.name);
  Dims dims = shape_of(o, 1);
  dims.erase(dims.begin());
  auto write = [&](const std::string& group, bool batch) {
    std::vector<double> mean, ci, var, sigma;
    double tau = 0.0, neff = 0.0;
    std::uint64_t block_rows = 0;
    const char* estimator = "independent";
    for (int k = 0; k < size; ++k) {
      const SteadyStats s =
          steady_stats(config, record, set, base + static_cast<std::uint64_t>(o.offset + k), batch);
      mean.push_back(s.mean);
      ci.push_back(s.ci);
      var.push_back(s.variance);
      sigma.push_back(s.sigma);
      if (k == 0 || s.tau_int > tau || std::isnan(s.tau_int)) tau = s.tau_int;
      if (k == 0 || s.effective_samples < neff || std::isnan(s.effective_samples))
        neff = s.effective_samples;
      block_rows = std::max(block_rows, s.block_rows);
      estimator = s.estimator;
    }
    if (group == g) {
      const std::string what = std::string(o.description) + "; steady average over t_m > steady_from";
      out.write(g + "/mean", mean, dims, what + ": mean");
      out.write(g + "/ci", ci, dims, what + ": confidence half-width");
      out.write(g + "/variance", var, dims, what + ": variance");
      out.attr(g, "description", std::string(o.description));
    } else {
      out.write(group + "/ci", ci, dims,
                "the batch estimator's confidence half-width of " + g + "/mean");
      out.attr(group, "description",
               std::string("the batch estimator's interval (dsmc.steady_ci: batch), which "
                           "accounts for the correlation of consecutive rows"));
    }
    out.write(group + "/sigma", sigma, dims, "the standard error of " + g + "/mean (" + estimator + ")");
    out.attr(group, "estimator", std::string(estimator));
    out.attr(group, "tau_int", tau);
    out.attr(group, "effective_samples", neff);
    out.attr(group, "samples", record.total("steady_samples"));
    out.attr(group, "from", config.dsmc.steady_from);
    if (std::string(estimator) == "blocking") out.attr(group, "block_rows", block_rows);
  };
  write(g, false);
  if (config.dsmc.steady_ci_independent) write(g + "/batch", true);
}

void write_moments(Presenter& out, const std::string& prefix, const std::vector<Moments2>& sums,
                   std::uint64_t rows, std::uint64_t samples, bool scalar_rows) {
  for (const auto& o : kObservables)
    write_observable(out, prefix, o, sums, kNumScalars, rows, samples, scalar_rows);
}

/// The speed moment <|v - V|^{2(k+1)}> as an observable: its name and description are held
/// here, since ObservableInfo only points at them.
struct SpeedMoment {
  std::string name, description;
  int k;
  explicit SpeedMoment(std::uint64_t index)
      : name(moment_name(static_cast<int>(index) + 1)),
        description("<|v - V|^" + std::to_string(2 * (index + 1)) +
                    ">: the central speed moment of order " + std::to_string(2 * (index + 1)) +
                    " (dsmc.moments)"),
        k(static_cast<int>(index)) {}
  ObservableInfo info() const { return {name.c_str(), k, 0, description.c_str()}; }
};

/// The speed moments moment_2 ... moment_2P, from sums laid out as [rows][P].
void write_speed_moments(Presenter& out, const std::string& prefix,
                         const std::vector<Moments2>& sums, std::uint64_t P, std::uint64_t rows,
                         std::uint64_t samples, bool scalar_rows) {
  for (std::uint64_t k = 0; k < P; ++k)
    write_observable(out, prefix, SpeedMoment(k).info(), sums, P, rows, samples, scalar_rows);
}

}  // namespace

namespace {

const char* const kA2Description =
    "a2 = 3/5 M4/M2^2 - 1, the second Sonine coefficient from the ensemble means of the speed "
    "moments (d = 3); ci by the delta method over the ensembles; bias: the ratio estimator's "
    "leading 1/N bias (second-order delta method), not subtracted from mean";
const char* const kA3Description =
    "a3 = 1 + 3 a2 - 9/35 M6/M2^3, the third Sonine coefficient from the ensemble means of the "
    "speed moments (d = 3); ci by the delta method over the ensembles; bias: the ratio "
    "estimator's leading 1/N bias (second-order delta method), not subtracted from mean";
const char* const kA2Description2 =
    "a2 = 1/2 M4/M2^2 - 1, the second Sonine coefficient from the ensemble means of the speed "
    "moments (d = 2); ci by the delta method over the ensembles; bias: the ratio estimator's "
    "leading 1/N bias (second-order delta method), not subtracted from mean";
const char* const kA3Description2 =
    "a3 = 1 + 3 a2 - 1/6 M6/M2^3, the third Sonine coefficient from the ensemble means of the "
    "speed moments (d = 2); ci by the delta method over the ensembles; bias: the ratio "
    "estimator's leading 1/N bias (second-order delta method), not subtracted from mean";

void write_sonine(Presenter& out, const DsmcRunConfig& config, const Record& record,
                  const RowSet& set) {
  const DsmcConfig& d = config.dsmc;
  const std::uint64_t P = set.P;
  const std::string& x = set.prefix;
  const std::uint64_t C = cross_pairs(P), N = record.ensembles();
  if (!C || N == 0) return;
  const std::string a2_text = d.dimension == 2 ? kA2Description2 : kA2Description;
  const std::string a3_text = d.dimension == 2 ? kA3Description2 : kA3Description;
  const std::uint64_t rows = d.observations() + 1;
  const auto& series = record.moments(x + "moment_series");
  const auto& cross = record.moments(x + "moment_cross");
  std::vector<double> a2(rows), a2ci(rows), a2bias(rows), a3(rows), a3ci(rows), a3bias(rows);
  for (std::uint64_t m = 0; m < rows; ++m) {
    const Sonine s = sonine(&series[m * P], &cross[m * C], P, N, false, d.dimension);
    a2[m] = s.a2;
    a2ci[m] = kLambdaP * std::sqrt(s.var_a2);
    a2bias[m] = s.bias_a2;
    a3[m] = s.a3;
    a3ci[m] = kLambdaP * std::sqrt(s.var_a3);
    a3bias[m] = s.bias_a3;
  }
  const std::string a2g = set.group + "/a2", a3g = set.group + "/a3";
  out.write(a2g + "/mean", a2, {rows}, a2_text + "; per row t_m: mean");
  out.write(a2g + "/ci", a2ci, {rows}, "confidence half-width of " + a2g + "/mean");
  out.write(a2g + "/bias", a2bias, {rows}, "the leading 1/N bias of " + a2g + "/mean");
  out.attr(a2g, "description", a2_text);
  if (P >= 3) {
    out.write(a3g + "/mean", a3, {rows}, a3_text + "; per row t_m: mean");
    out.write(a3g + "/ci", a3ci, {rows}, "confidence half-width of " + a3g + "/mean");
    out.write(a3g + "/bias", a3bias, {rows}, "the leading 1/N bias of " + a3g + "/mean");
    out.attr(a3g, "description", a3_text);
  }
  if (!d.steady) return;
  // Steady: each ensemble's time averages of M2, M4, M6 are one independent sample.
  const Sonine s = sonine(&record.moments(x + "steady_ensemble")[set.width],
                          record.moments(x + "steady_moment_cross").data(), P, N, true, d.dimension);
  const double factor = confidence_factor(static_cast<double>(N) - 1);
  for (int which = 2; which <= (P >= 3 ? 3 : 2); ++which) {
    const std::string g = "/steady" + set.group + "/a" + std::to_string(which);
    const double sigma = N >= 2 ? std::sqrt(which == 2 ? s.var_a2 : s.var_a3) : NAN;
    const std::string what = (which == 2 ? a2_text : a3_text) + "; steady, from the ensembles' time averages";
    out.write(g + "/mean", std::vector<double>{which == 2 ? s.a2 : s.a3}, {}, what + ": mean");
    out.write(g + "/sigma", std::vector<double>{sigma}, {}, "the standard error of " + g + "/mean");
    out.write(g + "/ci", std::vector<double>{factor * sigma}, {}, "confidence half-width of " + g + "/mean");
    out.write(g + "/bias", std::vector<double>{which == 2 ? s.bias_a2 : s.bias_a3}, {},
              "the leading 1/N bias of " + g + "/mean");
    out.attr(g, "description", which == 2 ? a2_text : a3_text);
    out.attr(g, "estimator", std::string("ensembles"));
    out.attr(g, "samples", record.total("steady_samples"));
    out.attr(g, "from", d.steady_from);
  }
}

}  // namespace

SteadyStats steady_stats(const DsmcRunConfig& config, const Record& record, std::uint64_t k,
                         bool batch) {
  const RowSet whole{"", "", kNumScalars, static_cast<std::uint64_t>(config.dsmc.moments)};
  return steady_stats(config, record, whole, k, batch);
}

SteadyStats steady_stats(const DsmcRunConfig& config, const Record& record, const RowSet& set,
                         std::uint64_t k, bool batch) {
  const DsmcConfig& d = config.dsmc;
  const std::uint64_t P = set.P, W = set.width;
  const std::string& x = set.prefix;
  const std::uint64_t S = record.total("steady_samples"), N = record.ensembles();
  const MeanCi all = k < W ? record.moments(x + "steady")[k].stats(S)
                           : record.moments(x + "moment_steady")[k - W].stats(S);
  const std::uint64_t K = W + P, L = steady_block_levels(d);
  // Blocking within the ensembles (Flyvbjerg & Petersen 1989) only where too few ensembles give
  // a spread of their own.
  const SteadyEstimator how = d.steady_ci_independent && !batch ? SteadyEstimator::kIndependent
                              : N >= kSteadyMinEnsembles || L == 0 ? SteadyEstimator::kEnsembles
                                                                   : SteadyEstimator::kBlocking;
  std::vector<double> blocked;
  if (how == SteadyEstimator::kBlocking)
    for (std::uint64_t l = 0; l < L; ++l)
      blocked.push_back(record.moments(x + "steady_blocks")[l * K + k].sum.value());
  return steady_interval(how, all, S, N, steady_rows(d), record.moments(x + "steady_ensemble")[k],
                         blocked);
}

namespace {
const ObservableInfo kRotational{"temperature_rotational", 0, 0,
                                 "T_rot = sum_j I_j |omega_j|^2 / (n d_rot), d_rot = 3 (d = 3) or 1 "
                                 "(d = 2): the rotational temperature of rough particles"};

/// The datasets of a row set beyond the first: a species' group /species/<name> (and under
/// /steady), or /temperature_rotational.
void present_row_set(Presenter& out, const DsmcRunConfig& config, const Record& record,
                     const RowSet& set) {
  const DsmcConfig& d = config.dsmc;
  const std::uint64_t rows = d.observations() + 1, N = record.ensembles();
  if (set.width == 1) {  // T_rot
    write_observable(out, "", kRotational, record.moments(set.prefix + "series"), 1, rows, N, false);
    if (d.steady) write_steady_observable(out, config, record, kRotational, 0, set);
    return;
  }
  write_moments(out, set.group, record.moments(set.prefix + "series"), rows, N, false);
  if (set.P)
    write_speed_moments(out, set.group, record.moments(set.prefix + "moment_series"), set.P, rows,
                        N, false);
  if (d.steady) {
    for (const auto& o : kObservables) write_steady_observable(out, config, record, o, 0, set);
    for (std::uint64_t k = 0; k < set.P; ++k)
      write_steady_observable(out, config, record, SpeedMoment(k).info(), kNumScalars, set);
  }
  write_sonine(out, config, record, set);
  for (const auto& sp : d.species)
    if (set.group == "/species/" + sp.name) {
      out.attr(set.group, "mass", sp.mass);
      out.attr(set.group, "diameter", sp.diameter);
      out.attr(set.group, "fraction", static_cast<double>(sp.count) / static_cast<double>(d.particles));
      out.attr(set.group, "particles", sp.count);
      if (d.roughness.on) out.attr(set.group, "inertia", sp.inertia);
    }
}

/// The datasets of one ratio (ratio_sets): <group>/{mean,ci,bias} [M+1] and with steady_from
/// /steady<group>/{mean,sigma,ci,bias}, as a2's.
void write_ratio(Presenter& out, const DsmcRunConfig& config, const Record& record,
                 const RatioSet& r) {
  const DsmcConfig& d = config.dsmc;
  const std::uint64_t rows = d.observations() + 1, N = record.ensembles();
  if (N == 0) return;
  std::vector<RowSet> sets{RowSet{"", "", kNumScalars, static_cast<std::uint64_t>(d.moments)}};
  for (const RowSet& s : extra_row_sets(d)) sets.push_back(s);
  const RowSet &X = sets[r.x_set], &Y = sets[r.y_set];
  const std::string what = r.group == "/theta" ? "theta = T_rot/T (T translational)"
                                               : "T_" + r.numerator + "/T_" + r.denominator +
                                                     ", the species' temperatures";
  const std::string bias_text =
      "; bias: the ratio estimator's leading 1/N bias (second-order delta method), not "
      "subtracted from mean";
  const std::string how = ": the ratio of the ensemble means; ci by the delta method with the "
                          "variances and the covariance of the two over the ensembles" + bias_text;
  const std::string steady_how =
      ": the ratio of the steady averages; ci by the delta method with the variances and the "
      "covariance of the ensembles' time averages over t_m > steady_from" + bias_text;
  const auto& sx = record.moments(X.prefix + "series");
  const auto& sy = record.moments(Y.prefix + "series");
  const auto& cross = record.moments(r.prefix + "cross");
  std::vector<double> mean(rows), ci(rows), bias(rows);
  for (std::uint64_t m = 0; m < rows; ++m) {
    const Moments2 &x = sx[m * X.width + r.x_k], &y = sy[m * Y.width + r.y_k];
    const RatioStats s = ratio_of_means(x.sum.value() / static_cast<double>(N),
                                        y.sum.value() / static_cast<double>(N), x, y, cross[m], N,
                                        false);
    mean[m] = s.mean;
    ci[m] = kLambdaP * std::sqrt(s.variance);
    bias[m] = s.bias;
  }
  auto attrs = [&](const std::string& g, const std::string& text) {
    out.attr(g, "description", what + text);
    out.attr(g, "numerator", r.numerator);
    out.attr(g, "denominator", r.denominator);
  };
  out.write(r.group + "/mean", mean, {rows}, what + "; per row t_m: the ratio of the means");
  out.write(r.group + "/ci", ci, {rows}, "confidence half-width of " + r.group + "/mean");
  out.write(r.group + "/bias", bias, {rows}, "the leading 1/N bias of " + r.group + "/mean");
  attrs(r.group, how);
  if (!d.steady) return;
  // Each ensemble's time averages over the steady rows are one independent sample (as /steady/a2,
  // whatever steady_ci says); the mean is the ratio of the steady means, as a user divides them.
  const std::uint64_t S = record.total("steady_samples");
  const Moments2& x = record.moments(X.prefix + "steady_ensemble")[r.x_k];
  const Moments2& y = record.moments(Y.prefix + "steady_ensemble")[r.y_k];
  const RatioStats s = ratio_of_means(record.moments(X.prefix + "steady")[r.x_k].stats(S).mean,
                                      record.moments(Y.prefix + "steady")[r.y_k].stats(S).mean, x,
                                      y, record.moments(r.prefix + "steady_cross")[0], N, true);
  const double sigma = N >= 2 ? std::sqrt(s.variance) : NAN;
  const std::string g = "/steady" + r.group;
  out.write(g + "/mean", std::vector<double>{s.mean}, {}, what + "; steady: the ratio of the steady means");
  out.write(g + "/sigma", std::vector<double>{sigma}, {}, "the standard error of " + g + "/mean");
  const double factor = confidence_factor(static_cast<double>(N) - 1);
  out.write(g + "/ci", std::vector<double>{factor * sigma}, {}, "confidence half-width of " + g + "/mean");
  out.write(g + "/bias", std::vector<double>{N >= 2 ? s.bias : NAN}, {},
            "the leading 1/N bias of " + g + "/mean");
  attrs(g, steady_how);
  out.attr(g, "estimator", std::string("ensembles"));
  out.attr(g, "samples", S);
  out.attr(g, "from", d.steady_from);
}
}  // namespace

void present_dsmc(H5Writer& file, const DsmcRunConfig& config, const Record& record) {
  const DsmcConfig& d = config.dsmc;
  const std::vector<double> times = dsmc_times(d);
  const std::uint64_t rows = times.size(), N = record.ensembles();
  const RowSet whole{"", "", kNumScalars, static_cast<std::uint64_t>(d.moments)};
  Presenter out(file);
  out.observer("time");
  out.write("/time", times, {rows}, "the observation times t_m, m = 0..M");
  out.observer("moments");
  write_moments(out, "", record.moments("series"), rows, N, false);
  const auto P = static_cast<std::uint64_t>(d.moments);
  if (P) write_speed_moments(out, "", record.moments("moment_series"), P, rows, N, false);
  out.attr("/", "confidence_lambda_p", kLambdaP);
  if (d.steady) {
    const std::uint64_t samples = record.total("steady_samples");
    for (const auto& o : kObservables) write_steady_observable(out, config, record, o, 0, whole);
    for (std::uint64_t k = 0; k < P; ++k)
      write_steady_observable(out, config, record, SpeedMoment(k).info(), kNumScalars, whole);
    out.attr("/steady", "estimator",
             std::string(d.steady_ci_independent ? "independent"
                         : record.ensembles() >= kSteadyMinEnsembles || !steady_block_levels(d)
                             ? "ensembles" : "blocking"));
    out.attr("/steady", "samples", samples);
    out.attr("/steady", "from", d.steady_from);
  }
  write_sonine(out, config, record, whole);
  for (const auto& o : make_observers(d)) {
    out.observer(o->name());
    o->present(out, record);
  }
  for (const RowSet& set : extra_row_sets(d)) {
    out.observer(set.width == 1 ? "rotation" : "species");
    present_row_set(out, config, record, set);
  }
  out.observer("ratios");
  for (const RatioSet& r : ratio_sets(d)) write_ratio(out, config, record, r);
  out.write_manifest();
}

}  // namespace granboltz
