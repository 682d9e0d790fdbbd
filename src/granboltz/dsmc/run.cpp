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
  r.declare_moments("series", rows * kNumScalars);
  const std::uint64_t K1 = d.histogram.shells ? d.histogram.shells + 1 : 0;
  const bool component = K1 && d.histogram.component;
  if (K1) r.declare_counts("histogram", rows * K1);
  if (d.steady) {
    r.declare_moments("steady", kNumScalars);
    r.declare_total("steady_samples");
  }
  // The speed moments have sums of their own, so that the other sums keep their layout.
  const auto P = static_cast<std::uint64_t>(d.moments);
  if (P) r.declare_moments("moment_series", rows * P);
  if (P && d.steady) r.declare_moments("moment_steady", P);
  for (const ColumnSpec& c : kColumns) r.declare_column(c.path, c.floating);
  // The steady-state histogram: per ensemble the time average of f_k over the steady rows, so
  // that its confidence interval comes from independent ensembles, not from correlated rows.
  if (d.steady && K1) r.declare_moments("histogram_steady", K1);
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
  if (d.weights.swpm) {
    // SWPM: the histogram's weight per shell (f_k itself), beside the particle numbers above.
    if (K1) r.declare_moments("histogram_weight", rows * K1);
    r.declare_column("/events/reductions", false);
    r.declare_column("/events/particles_final", false);
    // The Gaussian thermostat: per ensemble the mean cooling rate over the steady window (or the
    // whole run), and its sums over the ensembles for /steady/cooling_rate.
    if (d.thermostat == Thermostat::kGaussian) {
      r.declare_column("/events/cooling_rate", true);
      r.declare_moments("cooling_rate", 1);
    }
  }
  // The histogram of (v - V)_x: after the others, so that their layout stays.
  if (component) {
    r.declare_counts("histogram_component", rows * K1);
    if (d.steady) r.declare_moments("histogram_component_steady", K1);
    if (d.weights.swpm) r.declare_moments("histogram_component_weight", rows * K1);
  }
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
  return r;
}

namespace {

/// An ensemble under way: the particle system and what has been observed so far.
struct InProgress {
  std::unique_ptr<Ensemble> ensemble;
  std::uint64_t next = 0;              // the next observation index m
  std::vector<Observation> obs;        // [rows]
  std::vector<double> moments;         // [rows * P]: <|v - V|^{2p}>, p = 1..P
  std::vector<std::uint64_t> hist;     // [rows * K1]: particles per shell
  std::vector<double> whist;           // weighted: [rows * K1] weight per shell
  std::vector<std::uint64_t> comp;     // histogram.component: [rows * K1] particles per bin
  std::vector<double> wcomp;           // weighted, histogram.component: [rows * K1] weight per bin
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

void save_in_progress(H5Writer& out, std::uint64_t e, const InProgress& w) {
  const std::string g = in_progress_group(e);
  w.ensemble->save(out, g);
  if (w.ensemble->weighted()) {
    out.write(g + "/histogram_weight", w.whist, {w.whist.size()});
    if (!w.wcomp.empty()) out.write(g + "/histogram_component_weight", w.wcomp, {w.wcomp.size()});
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
  out.write(g + "/histogram", w.hist, {w.hist.size()});
  if (!w.comp.empty()) out.write(g + "/histogram_component", w.comp, {w.comp.size()});
  out.attr(g, "next_observation", w.next);
}

InProgress load_in_progress(const DsmcConfig& d, const H5Reader& in, std::uint64_t e,
                            std::uint64_t rows, std::uint64_t K1, ProgressSlot* slot) {
  const std::string g = in_progress_group(e);
  InProgress w;
  w.ensemble = restore_ensemble(d, in, g, slot);
  if (w.ensemble->weighted()) {
    w.whist = in.read_double(g + "/histogram_weight");
    if (w.whist.size() != rows * K1)
      throw std::runtime_error(in.path() + ": malformed ensemble state " + g);
  }
  w.next = in.attr_uint64(g, "next_observation");
  const auto obs = in.read_double(g + "/observations");
  w.hist = in.read_uint64(g + "/histogram");
  if (w.next == 0 || w.next > rows || obs.size() != w.next * kNumScalars ||
      w.hist.size() != rows * K1)
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
  if (K1 && d.histogram.component) {
    w.comp = in.read_uint64(g + "/histogram_component");
    const bool weighted = w.ensemble->weighted();
    if (weighted) w.wcomp = in.read_double(g + "/histogram_component_weight");
    if (w.comp.size() != rows * K1 || (weighted && w.wcomp.size() != rows * K1))
      throw std::runtime_error(in.path() + ": malformed ensemble state " + g);
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
  const std::uint64_t K1 = d.histogram.shells ? d.histogram.shells + 1 : 0;
  const double steady_after = d.steady_from + 1e-9 * d.observe_every;
  const auto P = static_cast<std::uint64_t>(d.moments);

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
          for (const auto& [e, w] : parked) save_in_progress(out, e, *w);
        });
      });

  for_each_ensemble(todo, opts, [&](std::uint64_t e, ProgressSlot& slot) {
    InProgress w;
    SafePoints<InProgress>::Member member(safe);
    if (checkpoint_has(resumed, e)) {
      std::lock_guard<std::mutex> lock(safe.mutex());  // HDF5 (serial build) is not thread-safe
      w = load_in_progress(d, *checkpoint, e, rows, K1, &slot);
    } else {
      w.ensemble = make_ensemble(d, config.seed, e, &slot);
      if (w.ensemble->weighted()) w.whist.assign(rows * K1, 0.0);
      for (const RowSet& x : extra_row_sets(d)) {
        w.xobs.emplace_back(rows * x.width, 0.0);
        w.xmoments.emplace_back(rows * x.P, 0.0);
      }
      w.obs.resize(rows);
      w.moments.assign(rows * P, 0.0);
      w.hist.assign(rows * K1, 0);
      if (K1 && d.histogram.component) {
        w.comp.assign(rows * K1, 0);
        if (w.ensemble->weighted()) w.wcomp.assign(rows * K1, 0.0);
      }
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
      if (K1) {
        row.histogram = &w.hist[m * K1];
        if (!w.whist.empty()) row.histogram_weight = &w.whist[m * K1];
      }
      if (!w.comp.empty()) {
        row.component = &w.comp[m * K1];
        if (!w.wcomp.empty()) row.component_weight = &w.wcomp[m * K1];
      }
      w.obs[m] = ens.observe(d, row);
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
    // A histogram's per-ensemble steady average of f_k and, for SWPM, its weights per row.
    const bool weighted = ens.weighted();
    auto add_histogram = [&](const std::string& name, const std::vector<std::uint64_t>& hist,
                             const std::vector<double>& whist) {
      record.add_counts(name, hist);
      if (d.steady) {
        std::vector<double> avg(K1, 0.0);
        double steady_rows = 0.0;
        for (std::uint64_t m = 0; m < rows; ++m) {
          if (!(times[m] > steady_after)) continue;
          steady_rows += 1.0;
          for (std::uint64_t k = 0; k < K1; ++k)
            avg[k] += weighted ? whist[m * K1 + k]
                                 : static_cast<double>(hist[m * K1 + k]) /
                                       static_cast<double>(d.particles);
        }
        auto& hs = record.moments(name + "_steady");
        for (std::uint64_t k = 0; k < K1; ++k) hs[k].add(avg[k] / steady_rows);
      }
      if (weighted) {
        auto& hw = record.moments(name + "_weight");
        for (std::size_t k = 0; k < whist.size(); ++k) hw[k].add(whist[k]);
      }
    };
    if (K1) add_histogram("histogram", w.hist, w.whist);
    if (!w.comp.empty()) add_histogram("histogram_component", w.comp, w.wcomp);
    // The cooling rate's sums are declared with the weighted engine's Gaussian column.
    if (weighted && d.thermostat == Thermostat::kGaussian)
      record.moments("cooling_rate")[0].add(ens.mean_cooling_rate());
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
void write_observable(H5Writer& out, const std::string& prefix, const ObservableInfo& o,
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
  out.write(g + "/mean", mean, dims);
  out.write(g + "/ci", ci, dims);
  out.write(g + "/variance", var, dims);
  out.attr(g, "description", std::string(o.description));
}

/// The /steady group of one observable: mean, ci, variance as write_observable, plus sigma and
/// the estimator's attributes (the largest tau_int over the components, the smallest N_eff).
/// With steady_ci: independent the batch estimator's sigma and ci follow in a `batch` subgroup.
void write_steady_observable(H5Writer& out, const DsmcRunConfig& config, const Record& record,
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
      out.write(g + "/mean", mean, dims);
      out.write(g + "/ci", ci, dims);
      out.write(g + "/variance", var, dims);
      out.attr(g, "description", std::string(o.description));
    } else {
      out.write(group + "/ci", ci, dims);
      out.attr(group, "description",
               std::string("the batch estimator's interval (dsmc.steady_ci: batch), which "
                           "accounts for the correlation of consecutive rows"));
    }
    out.write(group + "/sigma", sigma, dims);
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

void write_moments(H5Writer& out, const std::string& prefix, const std::vector<Moments2>& sums,
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
void write_speed_moments(H5Writer& out, const std::string& prefix,
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

void write_sonine(H5Writer& out, const DsmcRunConfig& config, const Record& record,
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
  out.write(a2g + "/mean", a2, {rows});
  out.write(a2g + "/ci", a2ci, {rows});
  out.write(a2g + "/bias", a2bias, {rows});
  out.attr(a2g, "description", a2_text);
  if (P >= 3) {
    out.write(a3g + "/mean", a3, {rows});
    out.write(a3g + "/ci", a3ci, {rows});
    out.write(a3g + "/bias", a3bias, {rows});
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
    out.write(g + "/mean", std::vector<double>{which == 2 ? s.a2 : s.a3}, {});
    out.write(g + "/sigma", std::vector<double>{sigma}, {});
    out.write(g + "/ci", std::vector<double>{factor * sigma}, {});
    out.write(g + "/bias", std::vector<double>{which == 2 ? s.bias_a2 : s.bias_a3}, {});
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

/// A histogram's /<name> group (edges, mean, ci, counts per row) and, with steady_from, its
/// /steady/<name> group, from the accumulators <name>, <name>_steady and, for SWPM, <name>_weight.
void write_histogram(H5Writer& out, const DsmcRunConfig& config, const Record& record,
                     const std::string& name, const std::vector<double>& edges,
                     const char* description) {
  const DsmcConfig& d = config.dsmc;
  const std::uint64_t rows = d.observations() + 1, N = record.ensembles(), K1 = edges.size();
  const auto& counts = record.counts(name);
  const auto& counts_sq = record.counts_sq(name);
  std::vector<double> mean(rows * K1), ci(rows * K1);
  const double n = static_cast<double>(d.particles), Nd = static_cast<double>(N);
  if (d.weights.swpm) {  // f_k = the weight in shell k, from exact sums over ensembles
    const auto& hw = record.moments(name + "_weight");
    for (std::size_t k = 0; k < mean.size(); ++k) {
      const MeanCi s = hw[k].stats(N);
      mean[k] = s.mean;
      ci[k] = s.ci;
    }
  }
  for (std::size_t k = 0; k < mean.size() && !d.weights.swpm; ++k) {
    const double f = static_cast<double>(counts[k]) / (n * Nd);
    const double f2 = static_cast<double>(counts_sq[k]) / (n * n * Nd);
    mean[k] = f;
    ci[k] = kLambdaP * std::sqrt(std::max(0.0, f2 - f * f) / Nd);
  }
  const std::string g = "/" + name;
  out.write(g + "/edges", edges, {K1});
  out.write(g + "/mean", mean, {rows, K1});
  out.write(g + "/ci", ci, {rows, K1});
  out.write(g + "/counts", counts, {rows, K1});
  out.attr(g, "description", std::string(description));
  out.attr(g, "center", std::string(d.histogram.bulk || name != "histogram" ? "bulk" : "origin"));
  if (!d.steady) return;
  const auto& hs = record.moments(name + "_steady");
  std::vector<double> smean(hs.size()), sci(hs.size());
  for (std::size_t k = 0; k < hs.size(); ++k) {
    const MeanCi s = hs[k].stats(N);
    smean[k] = s.mean;
    sci[k] = s.ci;
  }
  std::uint64_t steady_rows = 0;
  for (double t : dsmc_times(d)) steady_rows += t > d.steady_from + 1e-9 * d.observe_every;
  out.write("/steady" + g + "/mean", smean, {smean.size()});
  out.write("/steady" + g + "/ci", sci, {sci.size()});
  out.attr("/steady" + g, "rows", steady_rows);
  out.attr("/steady" + g, "description",
           std::string("f_k averaged over the observation times t_m > steady_from in each "
                       "ensemble; mean and confidence half-width over the ensembles (edges: ") +
               g + "/edges)");
}

}  // namespace

namespace {
const ObservableInfo kRotational{"temperature_rotational", 0, 0,
                                 "T_rot = sum_j I_j |omega_j|^2 / (n d_rot), d_rot = 3 (d = 3) or 1 "
                                 "(d = 2): the rotational temperature of rough particles"};

/// The datasets of a row set beyond the first: a species' group /species/<name> (and under
/// /steady), or /temperature_rotational.
void present_row_set(H5Writer& out, const DsmcRunConfig& config, const Record& record,
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
void write_ratio(H5Writer& out, const DsmcRunConfig& config, const Record& record,
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
  out.write(r.group + "/mean", mean, {rows});
  out.write(r.group + "/ci", ci, {rows});
  out.write(r.group + "/bias", bias, {rows});
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
  out.write(g + "/mean", std::vector<double>{s.mean}, {});
  out.write(g + "/sigma", std::vector<double>{sigma}, {});
  const double factor = confidence_factor(static_cast<double>(N) - 1);
  out.write(g + "/ci", std::vector<double>{factor * sigma}, {});
  out.write(g + "/bias", std::vector<double>{N >= 2 ? s.bias : NAN}, {});
  attrs(g, steady_how);
  out.attr(g, "estimator", std::string("ensembles"));
  out.attr(g, "samples", S);
  out.attr(g, "from", d.steady_from);
}
}  // namespace

void present_dsmc(H5Writer& out, const DsmcRunConfig& config, const Record& record) {
  const DsmcConfig& d = config.dsmc;
  const std::vector<double> times = dsmc_times(d);
  const std::uint64_t rows = times.size(), N = record.ensembles();
  const RowSet whole{"", "", kNumScalars, static_cast<std::uint64_t>(d.moments)};
  out.write("/time", times, {rows});
  write_moments(out, "", record.moments("series"), rows, N, false);
  const auto P = static_cast<std::uint64_t>(d.moments);
  if (P) write_speed_moments(out, "", record.moments("moment_series"), P, rows, N, false);
  out.attr("/", "confidence_lambda_p", kLambdaP);

  if (d.histogram.shells) {
    const std::uint64_t K1 = d.histogram.shells + 1;
    std::vector<double> edges(K1);
    for (std::uint64_t k = 0; k < K1; ++k)
      edges[k] = d.histogram.radius * static_cast<double>(k) / static_cast<double>(K1 - 1);
    write_histogram(out, config, record, "histogram", edges,
                    d.histogram.bulk
                        ? "f_k = fraction of particles with r_k <= |v - V(t)| < r_{k+1}, r_k = k R/K, "
                          "V(t) the ensemble's bulk velocity (dsmc.histogram.center: bulk); the "
                          "last shell holds |v - V| >= R"
                        : "f_k = fraction of particles with r_k <= |v| < r_{k+1}, r_k = k R/K "
                          "(GRW05 eq. 37); the last shell holds |v| >= R");
    if (d.histogram.component) {
      // K + 1 edges -R .. R of the K bins; the last bin of mean holds |(v - V)_x| >= R.
      for (std::uint64_t k = 0; k < K1; ++k)
        edges[k] = d.histogram.radius * (2.0 * static_cast<double>(k) / static_cast<double>(K1 - 1) - 1.0);
      write_histogram(out, config, record, "histogram_component", edges,
                      "f_k = fraction of particles with x_k <= (v - V(t))_x < x_{k+1}, x_k = -R + "
                      "2 k R/K (dsmc.histogram.component); the last bin holds |(v - V)_x| >= R");
    }
  }
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
  if (d.weights.swpm && d.thermostat == Thermostat::kGaussian) {
    // zeta = -d ln T/dt of the collisions alone, which the thermostat undoes: per ensemble the
    // mean over its steady window, here its mean and interval over the ensembles.
    const std::string g = d.steady ? "/steady/cooling_rate" : "/cooling_rate";
    const MeanCi z = record.moments("cooling_rate")[0].stats(N);
    out.write(g + "/mean", std::vector<double>{z.mean}, {});
    out.write(g + "/ci", std::vector<double>{z.ci}, {});
    out.write(g + "/variance", std::vector<double>{z.variance}, {});
    out.attr(g, "description",
             std::string("zeta = -d ln T/dt: the rate at which inelastic collisions remove the "
                         "energy E = sum g |v - V|^2 that the Gaussian thermostat restores, "
                         "(energy lost per unit time)/E, averaged over (steady_from, t_end] in "
                         "each ensemble; mean and ci over the ensembles"));
  }
  write_sonine(out, config, record, whole);
  for (const RowSet& set : extra_row_sets(d)) present_row_set(out, config, record, set);
  for (const RatioSet& r : ratio_sets(d)) write_ratio(out, config, record, r);
}

}  // namespace granboltz
