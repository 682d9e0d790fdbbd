// TV06 runs: ensembles of intruder or needle simulations, combined exactly and written to HDF5.
#include "granboltz/tv06_run.hpp"

#include <cmath>
#include <mutex>
#include <string>
#include <vector>

#include "granboltz/exact_sum.hpp"
#include "granboltz/int128.hpp"
#include "granboltz/statistics.hpp"
#include "granboltz/tv06_intruder.hpp"
#include "granboltz/tv06_needle.hpp"

namespace granboltz {

namespace {

using tv06::Histogram;

/// One per-ensemble observable: exact sums over ensembles plus the values in ensemble order.
struct Scalar {
  std::string name, description;
  Moments2 sums;
  std::vector<double> values;
};

/// Sums of histograms over ensembles, and of their squared counts (for a confidence band).
struct HistogramSum {
  std::vector<std::uint64_t> counts;
  std::vector<uint128> counts_sq;
  std::uint64_t below = 0, above = 0, samples = 0;
  std::vector<double> edges;
  double range = 0.0;

  void add(const Histogram& h, std::uint64_t samples_of_ensemble) {
    if (!h.enabled()) return;
    if (counts.empty()) {
      counts.assign(h.counts().size(), 0);
      counts_sq.assign(h.counts().size(), 0);
      edges = h.edges();
      range = h.range();
    }
    for (std::size_t k = 0; k < counts.size(); ++k) {
      counts[k] += h.counts()[k];
      counts_sq[k] += static_cast<uint128>(h.counts()[k]) * h.counts()[k];
    }
    below += h.below();
    above += h.above();
    samples += samples_of_ensemble;
  }
};

void write_scalar(H5Writer& out, Scalar& s, std::uint64_t ensembles) {
  const MeanCi m = s.sums.stats(ensembles);
  const std::string g = "/" + s.name;
  out.write(g + "/mean", std::vector<double>{m.mean}, {});
  out.write(g + "/variance", std::vector<double>{m.variance}, {});
  out.write(g + "/ci", std::vector<double>{m.ci}, {});
  out.write(g + "/per_ensemble", s.values, {s.values.size()});
  out.attr(g, "description", s.description);
  std::vector<std::int64_t> digits = s.sums.sum.digits();
  const auto sq = s.sums.sum_sq.digits();
  digits.insert(digits.end(), sq.begin(), sq.end());
  out.write("/accumulators/" + s.name, digits, {2, static_cast<hsize_t>(ExactSum::kLimbs)});
}

void write_histogram(H5Writer& out, const std::string& name, const HistogramSum& h,
                     std::uint64_t ensembles, const std::string& description) {
  if (h.counts.empty()) return;
  const std::size_t K = h.counts.size();
  const double width = 2.0 * h.range / static_cast<double>(K);
  const double total = static_cast<double>(h.samples);
  const double N = static_cast<double>(ensembles), per = total / N;
  std::vector<double> density(K), ci(K);
  for (std::size_t k = 0; k < K; ++k) {
    density[k] = static_cast<double>(h.counts[k]) / (total * width);
    // Spread of the per-ensemble fractions c_ek / n_e, with n_e taken as its mean (the sample
    // counts of the ensembles differ by O(sqrt n_e) only).
    const double m1 = static_cast<double>(h.counts[k]) / N / per;
    const double m2 = static_cast<double>(h.counts_sq[k]) / N / (per * per);
    ci[k] = kLambdaP * std::sqrt(std::max(0.0, m2 - m1 * m1) / N) / width;
  }
  const std::string g = "/" + name;
  out.write(g + "/edges", h.edges, {K + 1});
  out.write(g + "/counts", h.counts, {K});
  out.write(g + "/overflow", std::vector<std::uint64_t>{h.below, h.above}, {2});
  out.write(g + "/density", density, {K});
  out.write(g + "/ci", ci, {K});
  out.attr(g, "description", description);
  out.attr(g, "samples", h.samples);
  std::vector<std::uint64_t> sq(2 * K);
  for (std::size_t k = 0; k < K; ++k) {
    sq[2 * k] = static_cast<std::uint64_t>(h.counts_sq[k] >> 64);
    sq[2 * k + 1] = static_cast<std::uint64_t>(h.counts_sq[k]);
  }
  out.write("/accumulators/" + name + "_counts_sq", sq, {K, 2});
}

void write_scalar_dataset(H5Writer& out, const std::string& path, double value,
                          const std::string& description) {
  out.write(path, std::vector<double>{value}, {});
  out.attr(path, "description", description);
}

void run_intruder(H5Writer& out, const Config& config, const DriverOptions& options) {
  const IntruderConfig& c = config.intruder;
  const std::uint64_t first = config.first_ensemble(), last = config.last_ensemble();
  const std::uint64_t N = last - first;
  const bool dsmc = c.method == IntruderMethod::kDsmc;

  Scalar ratio{"temperature_ratio",
               "T/T_B, T = M <v1^2> time-averaged over each ensemble",
               {},
               std::vector<double>(N)};
  Scalar velocity{
      "mean_velocity", "<v1>, time-averaged over each ensemble", {}, std::vector<double>(N)};
  HistogramSum hist;
  std::vector<std::uint64_t> index(N), collisions(N), samples(N), fictitious(N), exceeded(N);
  std::vector<double> time(N), omega_max(N);

  std::mutex mutex;
  for_each_ensemble(first, last, options, [&](std::uint64_t e, ProgressSlot& slot) {
    const tv06::IntruderEnsemble r = tv06::simulate_intruder(c, config.seed, e, &slot);
    std::lock_guard<std::mutex> lock(mutex);
    const std::uint64_t i = e - first;
    ratio.sums.add(r.temperature_ratio);
    ratio.values[i] = r.temperature_ratio;
    velocity.sums.add(r.mean_velocity);
    velocity.values[i] = r.mean_velocity;
    hist.add(r.histogram, r.samples);
    index[i] = e;
    collisions[i] = r.collisions;
    samples[i] = r.samples;
    fictitious[i] = r.fictitious;
    exceeded[i] = r.majorant_exceeded;
    time[i] = r.time;
    omega_max[i] = r.omega_max;
  });

  out.attr("/", "confidence_lambda_p", kLambdaP);
  write_scalar(out, ratio, N);
  write_scalar(out, velocity, N);
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
  write_histogram(out, "histogram", hist, N,
                  "intruder velocity v1 at the sample times: counts on [-range, range], "
                  "density = counts / (samples * bin width), overflow = [below, above]");
  out.write("/events/ensemble", index, {N});
  out.write("/events/collisions", collisions, {N});
  out.write("/events/samples", samples, {N});
  out.write("/events/time", time, {N});
  if (dsmc) {
    out.write("/events/fictitious", fictitious, {N});
    out.write("/events/majorant_exceeded", exceeded, {N});
    out.write("/events/omega_max_final", omega_max, {N});
  }
}

void run_needle(H5Writer& out, const Config& config, const DriverOptions& options) {
  const NeedleConfig& c = config.needle;
  const std::uint64_t first = config.first_ensemble(), last = config.last_ensemble();
  const std::uint64_t N = last - first;

  Scalar trans{"translational_temperature_ratio",
               "T_trans/T_B, T_trans = M <|v1|^2> / 2 (per degree of freedom)",
               {},
               std::vector<double>(N)};
  Scalar rot{
      "rotational_temperature_ratio", "T_rot/T_B, T_rot = I <omega^2>", {}, std::vector<double>(N)};
  Scalar corr{"R",
              "<v^2 omega^2> / (<v^2> <omega^2>) (TV06 eq. 30) per ensemble",
              {},
              std::vector<double>(N)};
  HistogramSum vel, omega;
  std::vector<std::uint64_t> index(N), collisions(N), samples(N), fictitious(N);
  std::vector<double> time(N);

  std::mutex mutex;
  for_each_ensemble(first, last, options, [&](std::uint64_t e, ProgressSlot& slot) {
    const tv06::NeedleEnsemble r = tv06::simulate_needle(c, config.seed, e, &slot);
    std::lock_guard<std::mutex> lock(mutex);
    const std::uint64_t i = e - first;
    trans.sums.add(r.translational_ratio);
    trans.values[i] = r.translational_ratio;
    rot.sums.add(r.rotational_ratio);
    rot.values[i] = r.rotational_ratio;
    corr.sums.add(r.R);
    corr.values[i] = r.R;
    vel.add(r.velocity_histogram, r.samples);
    omega.add(r.omega_histogram, r.samples);
    index[i] = e;
    collisions[i] = r.collisions;
    samples[i] = r.samples;
    fictitious[i] = r.fictitious;
    time[i] = r.time;
  });

  out.attr("/", "confidence_lambda_p", kLambdaP);
  write_scalar(out, trans, N);
  write_scalar(out, rot, N);
  write_scalar(out, corr, N);
  if (c.alpha == 1.0) {
    const std::string eq = "1: equipartition with the bath and no correlation at alpha = 1";
    write_scalar_dataset(out, "/exact/translational_temperature_ratio", 1.0, eq);
    write_scalar_dataset(out, "/exact/rotational_temperature_ratio", 1.0, eq);
    write_scalar_dataset(out, "/exact/R", 1.0, eq);
  }
  write_scalar_dataset(out, "/bath_temperature", 0.5 / c.a, "T_B = 1/(2a)");
  write_scalar_dataset(out, "/sample_interval", tv06::needle_sample_interval(c),
                       "delta t between samples of the time averages");
  write_histogram(out, "velocity_histogram", vel, N,
                  "needle velocity component v1x at the sample times: counts on [-range, range], "
                  "density = counts / (samples * bin width), overflow = [below, above]");
  write_histogram(out, "omega_histogram", omega, N,
                  "needle angular velocity omega at the sample times: counts on [-range, range], "
                  "density = counts / (samples * bin width), overflow = [below, above]");
  out.write("/events/ensemble", index, {N});
  out.write("/events/collisions", collisions, {N});
  out.write("/events/samples", samples, {N});
  out.write("/events/time", time, {N});
  out.write("/events/fictitious", fictitious, {N});
}

}  // namespace

void run_tv06(H5Writer& out, const Config& config, const DriverOptions& options) {
  if (config.model == Model::kIntruder)
    run_intruder(out, config, options);
  else if (config.model == Model::kNeedle)
    run_needle(out, config, options);
  else
    throw ConfigError("run_tv06: model " + model_name(config.model) + " is not a TV06 model");
}

double tv06_memory_estimate(const Config& config, unsigned threads) {
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
  // and the output's double copies (edges, density, ci) and split squares.
  return t * (per_thread + 16.0 * bins) + bins * (8.0 + 16.0 + 24.0 + 16.0) + N * 80.0;
}

}  // namespace granboltz
