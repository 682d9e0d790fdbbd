#include "granboltz/dsmc/run.hpp"

#include <algorithm>
#include <cmath>
#include <condition_variable>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>

#include "granboltz/dsmc/ensemble.hpp"
#include "granboltz/dsmc/observables.hpp"
#include "granboltz/dsmc/weighted.hpp"

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
  const std::uint64_t M = d.observations();
  std::vector<double> t(M + 1);
  for (std::uint64_t m = 0; m <= M; ++m)
    t[m] = m == M ? d.t_end : static_cast<double>(m) * d.observe_every;
  return t;
}

Record dsmc_layout(const Config& config) {
  const DsmcConfig& d = config.dsmc;
  const std::uint64_t rows = d.observations() + 1;
  Record r;
  r.declare_moments("series", rows * kNumScalars);
  if (d.histogram.shells) r.declare_counts("histogram", rows * (d.histogram.shells + 1));
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
  if (d.steady && d.histogram.shells) r.declare_moments("histogram_steady", d.histogram.shells + 1);
  if (d.weights.swpm) {
    // SWPM: the histogram's weight per shell (f_k itself), beside the particle numbers above.
    if (d.histogram.shells) r.declare_moments("histogram_weight", rows * (d.histogram.shells + 1));
    r.declare_column("/events/reductions", false);
    r.declare_column("/events/particles_final", false);
  }
  return r;
}

namespace {

/// An ensemble under way: the particle system and what has been observed so far.
struct InProgress {
  std::unique_ptr<DsmcEnsemble> ensemble;
  std::unique_ptr<WeightedEnsemble> weighted;  // dsmc.weights: swpm (then `ensemble` is empty)
  std::uint64_t next = 0;              // the next observation index m
  std::vector<Observation> obs;        // [rows]
  std::vector<double> moments;         // [rows * P]: <|v - V|^{2p}>, p = 1..P
  std::vector<std::uint64_t> hist;     // [rows * K1]: particles per shell
  std::vector<double> whist;           // swpm: [rows * K1] weight per shell
};

// An observable that overflowed: named with the values that make a run overflow, instead of
// the exact sums' bare refusal of a non-finite number.
[[noreturn]] void throw_not_finite(int k, double value, double t, std::uint64_t e) {
  const char* name = "an observable";
  for (const auto& o : kObservables) {
    const int width = o.rank == 0 ? 1 : o.rank == 1 ? 3 : 9;
    if (k >= o.offset && k < o.offset + width) name = o.name;
  }
  throw std::runtime_error(std::string("dsmc: ") + name + " = " + format_real(value) +
                           " at t = " + format_real(t) + " in ensemble " + std::to_string(e) +
                           ": the simulation overflowed; are dsmc.beta, dsmc.initial_temperature "
                           "or dsmc.kernel.C far too large?");
}

std::string in_progress_group(std::uint64_t e) { return "/in_progress/" + std::to_string(e); }

void save_in_progress(H5Writer& out, std::uint64_t e, const InProgress& w) {
  const std::string g = in_progress_group(e);
  if (w.weighted) {
    w.weighted->save(out, g);
    out.write(g + "/histogram_weight", w.whist, {w.whist.size()});
  } else {
    w.ensemble->save(out, g);
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
  out.attr(g, "next_observation", w.next);
}

InProgress load_in_progress(const DsmcConfig& d, const H5Reader& in, std::uint64_t e,
                            std::uint64_t rows, std::uint64_t K1, ProgressSlot* slot) {
  const std::string g = in_progress_group(e);
  InProgress w;
  if (d.weights.swpm) {
    w.weighted = std::make_unique<WeightedEnsemble>(d, in, g, slot);
    w.whist = in.read_double(g + "/histogram_weight");
    if (w.whist.size() != rows * K1)
      throw std::runtime_error(in.path() + ": malformed ensemble state " + g);
  } else {
    w.ensemble = std::make_unique<DsmcEnsemble>(d, in, g, slot);
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
  return w;
}

}  // namespace

void run_dsmc(const Config& config, const DriverOptions& options, Record& record) {
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
  std::mutex mutex;
  std::condition_variable changed;
  std::atomic<bool> pause{false};
  int active = 0;
  std::map<std::uint64_t, const InProgress*> parked;

  DriverOptions opts = options;
  if (options.checkpoint)
    opts.tick = [&] {
      std::unique_lock<std::mutex> lock(mutex);
      pause = true;
      changed.wait(lock, [&] { return static_cast<int>(parked.size()) == active; });
      try {
        options.checkpoint(record, [&](H5Writer& out) {
          for (const auto& [e, w] : parked) save_in_progress(out, e, *w);
        });
      } catch (...) {
        pause = false;
        changed.notify_all();
        throw;
      }
      pause = false;
      changed.notify_all();
    };

  for_each_ensemble(todo, opts, [&](std::uint64_t e, ProgressSlot& slot) {
    InProgress w;
    {
      std::unique_lock<std::mutex> lock(mutex);
      ++active;
    }
    // However this ensemble ends (an exception included), it stops counting as under way, so that
    // a checkpoint never waits for it.
    struct Leave {
      std::mutex& mutex;
      std::condition_variable& changed;
      int& active;
      bool done = false;
      void now() {  // with the lock held
        if (!done) --active, changed.notify_all(), done = true;
      }
      ~Leave() {
        if (done) return;
        std::lock_guard<std::mutex> lock(mutex);
        now();
      }
    } leave{mutex, changed, active};
    if (checkpoint_has(resumed, e)) {
      std::unique_lock<std::mutex> lock(mutex);  // HDF5 (serial build) is not thread-safe
      w = load_in_progress(d, *checkpoint, e, rows, K1, &slot);
    } else {
      if (d.weights.swpm) {
        w.weighted = std::make_unique<WeightedEnsemble>(d, config.seed, e, &slot);
        w.whist.assign(rows * K1, 0.0);
      } else {
        w.ensemble = std::make_unique<DsmcEnsemble>(d, config.seed, e, &slot);
      }
      w.obs.resize(rows);
      w.moments.assign(rows * P, 0.0);
      w.hist.assign(rows * K1, 0);
    }
    auto advance = [&](double s) {
      return w.weighted ? w.weighted->advance_to(s, &pause) : w.ensemble->advance_to(s, &pause);
    };
    for (; w.next < rows; ++w.next) {
      const std::uint64_t m = w.next;
      if (m > 0)
        while (!advance(times[m])) {
          std::unique_lock<std::mutex> lock(mutex);
          parked[e] = &w;
          changed.notify_all();
          changed.wait(lock, [&] { return !pause.load(); });
          parked.erase(e);
        }
      if (w.weighted) {
        const WeightedEnsemble& we = *w.weighted;
        w.obs[m] = measure_weighted(we.particles(), we.weights(), {w.moments.data() + m * P, P});
        if (K1)
          radial_histogram_weighted(we.particles(), we.weights(), d.histogram,
                                    &w.whist[m * K1], &w.hist[m * K1]);
      } else {
        w.obs[m] = measure(w.ensemble->particles(), {w.moments.data() + m * P, P});
        if (K1) radial_histogram(w.ensemble->particles(), d.histogram, &w.hist[m * K1]);
      }
    }
    // Exact sums: the order in which ensembles arrive here does not matter.
    std::lock_guard<std::mutex> lock(mutex);
    leave.now();
    auto& series = record.moments("series");
    for (std::uint64_t m = 0; m < rows; ++m) {
      for (int k = 0; k < kNumScalars; ++k)
        if (!std::isfinite(w.obs[m][k])) throw_not_finite(k, w.obs[m][k], times[m], e);
      for (int k = 0; k < kNumScalars; ++k) series[m * kNumScalars + k].add(w.obs[m][k]);
      const double* moments = w.moments.data() + m * P;
      if (P) {
        // After the other observables, so that a run overflowing anyway fails as before.
        for (std::uint64_t k = 0; k < P; ++k)
          if (!(std::fabs(moments[k]) <= kMomentLimit))
            throw std::runtime_error(
                "dsmc.moments = " + std::to_string(P) + ": " +
                moment_name(static_cast<int>(k) + 1) + " = " + format_real(moments[k]) +
                " at t = " + format_real(times[m]) + " in ensemble " + std::to_string(e) +
                " exceeds 1e150 (its square would overflow); ask for fewer moments");
        auto& mseries = record.moments("moment_series");
        for (std::uint64_t k = 0; k < P; ++k) mseries[m * P + k].add(moments[k]);
      }
      if (d.steady && times[m] > steady_after) {
        auto& steady = record.moments("steady");
        for (int k = 0; k < kNumScalars; ++k) steady[k].add(w.obs[m][k]);
        if (P) {
          auto& msteady = record.moments("moment_steady");
          for (std::uint64_t k = 0; k < P; ++k) msteady[k].add(moments[k]);
        }
        ++record.total("steady_samples");
      }
    }
    if (K1) record.add_counts("histogram", w.hist);
    if (K1 && d.steady) {
      std::vector<double> avg(K1, 0.0);
      double steady_rows = 0.0;
      for (std::uint64_t m = 0; m < rows; ++m) {
        if (!(times[m] > steady_after)) continue;
        steady_rows += 1.0;
        for (std::uint64_t k = 0; k < K1; ++k)
          avg[k] += w.weighted ? w.whist[m * K1 + k]
                               : static_cast<double>(w.hist[m * K1 + k]) /
                                     static_cast<double>(d.particles);
      }
      auto& hs = record.moments("histogram_steady");
      for (std::uint64_t k = 0; k < K1; ++k) hs[k].add(avg[k] / steady_rows);
    }
    if (w.weighted) {
      const WeightedEnsemble& we = *w.weighted;
      if (K1) {
        auto& hw = record.moments("histogram_weight");
        for (std::size_t k = 0; k < w.whist.size(); ++k) hw[k].add(w.whist[k]);
      }
      const EventCounts& c = we.counts();
      record.add_ensemble(e, {static_cast<double>(c.collisions), static_cast<double>(c.fictitious),
                              static_cast<double>(c.kicks), we.u_max(),
                              static_cast<double>(we.reductions()),
                              static_cast<double>(we.particles().size())});
      return;
    }
    const EventCounts& c = w.ensemble->counts();
    record.add_ensemble(e, {static_cast<double>(c.collisions), static_cast<double>(c.fictitious),
                            static_cast<double>(c.kicks), w.ensemble->u_max()});
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

void write_moments(H5Writer& out, const std::string& prefix, const std::vector<Moments2>& sums,
                   std::uint64_t rows, std::uint64_t samples, bool scalar_rows) {
  for (const auto& o : kObservables)
    write_observable(out, prefix, o, sums, kNumScalars, rows, samples, scalar_rows);
}

/// The speed moments moment_2 ... moment_2P, from sums laid out as [rows][P].
void write_speed_moments(H5Writer& out, const std::string& prefix,
                         const std::vector<Moments2>& sums, std::uint64_t P, std::uint64_t rows,
                         std::uint64_t samples, bool scalar_rows) {
  for (std::uint64_t k = 0; k < P; ++k) {
    const int p = static_cast<int>(k) + 1;
    const std::string name = moment_name(p);
    const std::string description = "<|v - V|^" + std::to_string(2 * p) +
                                    ">: the central speed moment of order " +
                                    std::to_string(2 * p) + " (dsmc.moments)";
    const ObservableInfo o{name.c_str(), static_cast<int>(k), 0, description.c_str()};
    write_observable(out, prefix, o, sums, P, rows, samples, scalar_rows);
  }
}

}  // namespace

void present_dsmc(H5Writer& out, const Config& config, const Record& record) {
  const DsmcConfig& d = config.dsmc;
  const std::vector<double> times = dsmc_times(d);
  const std::uint64_t rows = times.size(), N = record.ensembles();
  out.write("/time", times, {rows});
  write_moments(out, "", record.moments("series"), rows, N, false);
  const auto P = static_cast<std::uint64_t>(d.moments);
  if (P) write_speed_moments(out, "", record.moments("moment_series"), P, rows, N, false);
  out.attr("/", "confidence_lambda_p", kLambdaP);

  if (d.histogram.shells) {
    const std::uint64_t K1 = d.histogram.shells + 1;
    const auto& counts = record.counts("histogram");
    const auto& counts_sq = record.counts_sq("histogram");
    std::vector<double> edges(K1), mean(rows * K1), ci(rows * K1);
    for (std::uint64_t k = 0; k < K1; ++k)
      edges[k] = d.histogram.radius * static_cast<double>(k) / static_cast<double>(K1 - 1);
    const double n = static_cast<double>(d.particles), Nd = static_cast<double>(N);
    if (d.weights.swpm) {  // f_k = the weight in shell k, from exact sums over ensembles
      const auto& hw = record.moments("histogram_weight");
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
    out.write("/histogram/edges", edges, {K1});
    out.write("/histogram/mean", mean, {rows, K1});
    out.write("/histogram/ci", ci, {rows, K1});
    out.write("/histogram/counts", counts, {rows, K1});
    out.attr("/histogram", "description",
             std::string("f_k = fraction of particles with r_k <= |v| < r_{k+1}, r_k = k R/K "
                         "(GRW05 eq. 37); the last shell holds |v| >= R"));
  }
  if (d.steady && d.histogram.shells) {
    const auto& hs = record.moments("histogram_steady");
    std::vector<double> mean(hs.size()), ci(hs.size());
    for (std::size_t k = 0; k < hs.size(); ++k) {
      const MeanCi s = hs[k].stats(N);
      mean[k] = s.mean;
      ci[k] = s.ci;
    }
    std::uint64_t steady_rows = 0;
    for (double t : times) steady_rows += t > d.steady_from + 1e-9 * d.observe_every;
    out.write("/steady/histogram/mean", mean, {mean.size()});
    out.write("/steady/histogram/ci", ci, {ci.size()});
    out.attr("/steady/histogram", "rows", steady_rows);
    out.attr("/steady/histogram", "description",
             std::string("f_k averaged over the observation times t_m > steady_from in each "
                         "ensemble; mean and confidence half-width over the ensembles (edges: "
                         "/histogram/edges)"));
  }
  if (d.steady) {
    const std::uint64_t samples = record.total("steady_samples");
    write_moments(out, "/steady", record.moments("steady"), 1, samples, true);
    if (P)
      write_speed_moments(out, "/steady", record.moments("moment_steady"), P, 1, samples, true);
    out.attr("/steady", "samples", samples);
    out.attr("/steady", "from", d.steady_from);
  }
}

}  // namespace granboltz
