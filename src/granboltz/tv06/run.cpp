// TV06 runs: ensembles of intruder or needle simulations, combined exactly and written to HDF5.
#include "granboltz/tv06/run.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <string>
#include <vector>

#include "granboltz/core/gsl_errors.hpp"
#include "granboltz/stats/statistics.hpp"
#include "granboltz/tv06/intruder.hpp"
#include "granboltz/tv06/needle.hpp"

namespace granboltz {

namespace {

using tv06::Histogram;

struct ScalarSpec {
  const char* name;
  const char* description;
};

const ScalarSpec kIntruderScalars[] = {
    {"temperature_ratio", "T/T_B, T = M <v1^2> time-averaged over each ensemble"},
    {"mean_velocity", "<v1>, time-averaged over each ensemble"}};
const ScalarSpec kNeedleScalars[] = {
    {"translational_temperature_ratio",
     "T_trans/T_B, T_trans = M <|v1|^2> / 2 (per degree of freedom)"},
    {"rotational_temperature_ratio", "T_rot/T_B, T_rot = I <omega^2>"},
    {"R", "<v^2 omega^2> / (<v^2> <omega^2>) (TV06 eq. 30) per ensemble"}};

std::string per_ensemble(const char* name) {
  std::string path = "/";
  path += name;
  path += "/per_ensemble";
  return path;
}

void declare_histogram(Record& r, const std::string& name, const VelocityHistogramSpec& spec) {
  if (!spec.bins) return;
  r.declare_counts(name, spec.bins);
  for (const char* t : {"_below", "_above", "_samples"}) r.declare_total(name + t);
}

void add_histogram(Record& r, const std::string& name, const Histogram& h, std::uint64_t samples) {
  if (!h.enabled()) return;
  r.add_counts(name, h.counts());
  r.total(name + "_below") += h.below();
  r.total(name + "_above") += h.above();
  r.total(name + "_samples") += samples;
}

void write_scalar(H5Writer& out, const Record& r, const ScalarSpec& s) {
  const MeanCi m = r.moments(s.name)[0].stats(r.ensembles());
  const std::string g = std::string("/") + s.name;
  out.write(g + "/mean", std::vector<double>{m.mean}, {});
  out.write(g + "/variance", std::vector<double>{m.variance}, {});
  out.write(g + "/ci", std::vector<double>{m.ci}, {});
  out.attr(g, "description", std::string(s.description));
}

void write_histogram(H5Writer& out, const Record& r, const std::string& name,
                     const VelocityHistogramSpec& spec, const std::string& description) {
  if (!spec.bins) return;
  const auto& counts = r.counts(name);
  const auto& counts_sq = r.counts_sq(name);
  const std::size_t K = counts.size();
  const double width = 2.0 * spec.range / static_cast<double>(K);
  const std::uint64_t samples = r.total(name + "_samples");
  const double total = static_cast<double>(samples);
  const double N = static_cast<double>(r.ensembles()), per = total / N;
  std::vector<double> density(K), ci(K);
  for (std::size_t k = 0; k < K; ++k) {
    density[k] = static_cast<double>(counts[k]) / (total * width);
    // Spread of the per-ensemble fractions c_ek / n_e, with n_e taken as its mean (the sample
    // counts of the ensembles differ by O(sqrt n_e) only).
    const double m1 = static_cast<double>(counts[k]) / N / per;
    const double m2 = static_cast<double>(counts_sq[k]) / N / (per * per);
    ci[k] = kLambdaP * std::sqrt(std::max(0.0, m2 - m1 * m1) / N) / width;
  }
  const std::string g = "/" + name;
  out.write(g + "/edges", Histogram(spec).edges(), {K + 1});
  out.write(g + "/counts", counts, {K});
  out.write(g + "/overflow",
            std::vector<std::uint64_t>{r.total(name + "_below"), r.total(name + "_above")}, {2});
  out.write(g + "/density", density, {K});
  out.write(g + "/ci", ci, {K});
  out.attr(g, "description", description);
  out.attr(g, "samples", samples);
}

void write_scalar_dataset(H5Writer& out, const std::string& path, double value,
                          const std::string& description) {
  out.write(path, std::vector<double>{value}, {});
  out.attr(path, "description", description);
}

// Runs `simulate(e, slot)` for the ensembles of the shard missing from `record` and adds each
// result with `add(result, e)` under a lock.
template <class Simulate, class Add>
void run_missing(const Tv06RunConfig& config, const DriverOptions& options, Record& record,
                 Simulate simulate, Add add) {
  std::vector<std::uint64_t> todo;
  for (std::uint64_t e = config.first_ensemble(); e < config.last_ensemble(); ++e)
    if (!record.has_ensemble(e)) todo.push_back(e);
  std::mutex mutex;
  DriverOptions opts = options;
  if (options.checkpoint)
    opts.tick = [&] {
      std::lock_guard<std::mutex> lock(mutex);
      options.checkpoint(record, [](H5Writer&) {});  // TV06 ensembles are short: none in progress
    };
  for_each_ensemble(todo, opts, [&](std::uint64_t e, ProgressSlot& slot) {
    const auto result = simulate(e, slot);
    std::lock_guard<std::mutex> lock(mutex);
    add(result, e);
  });
}

}  // namespace

Record tv06_layout(const Tv06RunConfig& config) {
  Record r;
  if (config.model == Model::kIntruder) {
    const IntruderConfig& c = config.intruder;
    for (const auto& s : kIntruderScalars) r.declare_moments(s.name, 1);
    declare_histogram(r, "histogram", c.histogram);
    for (const auto& s : kIntruderScalars) r.declare_column(per_ensemble(s.name), true);
    r.declare_column("/events/collisions", false);
    r.declare_column("/events/samples", false);
    r.declare_column("/events/time", true);
    if (c.method == IntruderMethod::kDsmc) {
      r.declare_column("/events/fictitious", false);
      r.declare_column("/events/majorant_exceeded", false);
      r.declare_column("/events/omega_max_final", true);
    }
  } else {
    const NeedleConfig& c = config.needle;
    for (const auto& s : kNeedleScalars) r.declare_moments(s.name, 1);
    declare_histogram(r, "velocity_histogram", c.velocity_histogram);
    declare_histogram(r, "omega_histogram", c.omega_histogram);
    for (const auto& s : kNeedleScalars) r.declare_column(per_ensemble(s.name), true);
    r.declare_column("/events/collisions", false);
    r.declare_column("/events/samples", false);
    r.declare_column("/events/time", true);
    r.declare_column("/events/fictitious", false);
  }
  return r;
}

namespace {
// A result that overflowed, named, instead of the exact sums' bare refusal of a non-finite number.
void add_finite(Record& record, const std::string& name, double value, std::uint64_t e,
                const char* model) {
  if (!std::isfinite(value)) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", value);
    throw std::runtime_error(std::string(model) + ": " + name + " = " + text + " in ensemble " +
                             std::to_string(e) + ": the simulation overflowed; are the " + model +
                             " section's masses, densities or lengths extreme?");
  }
  record.moments(name)[0].add(value);
}
}  // namespace

void run_tv06(const Tv06RunConfig& config, const DriverOptions& options, Record& record) {
  install_gsl_error_handler();
  if (config.model == Model::kIntruder) {
    const IntruderConfig& c = config.intruder;
    const bool dsmc = c.method == IntruderMethod::kDsmc;
    run_missing(
        config, options, record,
        [&](std::uint64_t e, ProgressSlot& slot) {
          return tv06::simulate_intruder(c, config.seed, e, &slot);
        },
        [&](const tv06::IntruderEnsemble& r, std::uint64_t e) {
          add_finite(record, "temperature_ratio", r.temperature_ratio, e, "intruder");
          add_finite(record, "mean_velocity", r.mean_velocity, e, "intruder");
          add_histogram(record, "histogram", r.histogram, r.samples);
          std::vector<double> row = {r.temperature_ratio, r.mean_velocity,
                                     static_cast<double>(r.collisions),
                                     static_cast<double>(r.samples), r.time};
          if (dsmc) {
            row.push_back(static_cast<double>(r.fictitious));
            row.push_back(static_cast<double>(r.majorant_exceeded));
            row.push_back(r.omega_max);
          }
          record.add_ensemble(e, row);
        });
  } else {
    const NeedleConfig& c = config.needle;
    run_missing(
        config, options, record,
        [&](std::uint64_t e, ProgressSlot& slot) {
          return tv06::simulate_needle(c, config.seed, e, &slot);
        },
        [&](const tv06::NeedleEnsemble& r, std::uint64_t e) {
          add_finite(record, "translational_temperature_ratio", r.translational_ratio, e, "needle");
          add_finite(record, "rotational_temperature_ratio", r.rotational_ratio, e, "needle");
          add_finite(record, "R", r.R, e, "needle");
          add_histogram(record, "velocity_histogram", r.velocity_histogram, r.samples);
          add_histogram(record, "omega_histogram", r.omega_histogram, r.samples);
          record.add_ensemble(
              e, {r.translational_ratio, r.rotational_ratio, r.R, static_cast<double>(r.collisions),
                  static_cast<double>(r.samples), r.time, static_cast<double>(r.fictitious)});
        });
  }
}

void present_tv06(H5Writer& out, const Tv06RunConfig& config, const Record& record) {
  out.attr("/", "confidence_lambda_p", kLambdaP);
  if (config.model == Model::kIntruder) {
    const IntruderConfig& c = config.intruder;
    for (const auto& s : kIntruderScalars) write_scalar(out, record, s);
    double exact = 0.0;
    if (tv06::intruder_exact_temperature_ratio(c, &exact))
      write_scalar_dataset(out, "/exact/temperature_ratio", exact,
                           c.bath.kind == BathKind::kGaussian
                               ? "(1+alpha)/(2+(1-alpha)/M) (Martin and Piasecki; TV06 eq. 18)"
                               : "alpha: at M = alpha the intruder takes the bath's distribution");
    write_scalar_dataset(out, "/bath_temperature", tv06::intruder_bath_temperature(c),
                         "T_B = <v^2> of a bath particle (mass 1)");
    write_scalar_dataset(out, "/sample_interval", tv06::intruder_sample_interval(c),
                         "delta t between samples of the time averages");
    write_histogram(out, record, "histogram", c.histogram,
                    "intruder velocity v1 at the sample times: counts on [-range, range], "
                    "density = counts / (samples * bin width), overflow = [below, above]");
  } else {
    const NeedleConfig& c = config.needle;
    for (const auto& s : kNeedleScalars) write_scalar(out, record, s);
    if (c.alpha == 1.0) {
      const std::string eq = "1: equipartition with the bath and no correlation at alpha = 1";
      write_scalar_dataset(out, "/exact/translational_temperature_ratio", 1.0, eq);
      write_scalar_dataset(out, "/exact/rotational_temperature_ratio", 1.0, eq);
      write_scalar_dataset(out, "/exact/R", 1.0, eq);
    }
    write_scalar_dataset(out, "/bath_temperature", 0.5 / c.a, "T_B = 1/(2a)");
    write_scalar_dataset(out, "/sample_interval", tv06::needle_sample_interval(c),
                         "delta t between samples of the time averages");
    write_histogram(out, record, "velocity_histogram", c.velocity_histogram,
                    "needle velocity component v1x at the sample times: counts on [-range, "
                    "range], density = counts / (samples * bin width), overflow = [below, above]");
    write_histogram(out, record, "omega_histogram", c.omega_histogram,
                    "needle angular velocity omega at the sample times: counts on [-range, "
                    "range], density = counts / (samples * bin width), overflow = [below, above]");
  }
}

double tv06_memory_estimate(const Tv06RunConfig& config, unsigned threads) {
  const double t = threads;
  const double N = static_cast<double>(config.last_ensemble() - config.first_ensemble());
  double bins = 0.0, per_thread = 512.0 * 1024;  // event loop state, GSL workspaces
  if (config.model == Model::kIntruder) {
    bins = static_cast<double>(config.intruder.histogram.bins);
    if (config.intruder.method == IntruderMethod::kDsmc)
      per_thread += 8.0 * static_cast<double>(config.intruder.bath_particles);
  } else {
    bins = static_cast<double>(config.needle.velocity_histogram.bins +
                               config.needle.omega_histogram.bins);
  }
  // Per thread: an ensemble's histograms (and a moved copy); globally: counts, squared counts,
  // and the output's double copies (edges, density, ci) and split squares; per ensemble a row.
  return t * (per_thread + 16.0 * bins) + bins * (8.0 + 16.0 + 24.0 + 16.0) + N * 200.0;
}

}  // namespace granboltz
