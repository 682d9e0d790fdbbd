#include "granboltz/dsmc_run.hpp"

#include <algorithm>
#include <cmath>
#include <mutex>

#include "granboltz/dsmc_ensemble.hpp"

namespace granboltz {

DsmcResult run_dsmc(const Config& config, const DriverOptions& options) {
  const DsmcConfig& d = config.dsmc;
  const std::uint64_t M = d.observations();
  const std::uint64_t K1 = d.histogram.shells ? d.histogram.shells + 1 : 0;
  const std::uint64_t first = config.first_ensemble(), last = config.last_ensemble();

  DsmcResult r;
  r.times.resize(M + 1);
  for (std::uint64_t m = 0; m <= M; ++m)
    r.times[m] = m == M ? d.t_end : static_cast<double>(m) * d.observe_every;
  r.series.resize((M + 1) * kNumScalars);
  r.histogram.assign((M + 1) * K1, 0);
  r.histogram_sq.assign((M + 1) * K1, 0);
  r.steady.resize(kNumScalars);
  const std::uint64_t count = last - first;
  r.ensemble_index.resize(count);
  r.collisions.resize(count);
  r.fictitious.resize(count);
  r.kicks.resize(count);
  r.u_max_final.resize(count);
  const double steady_after = d.steady_from + 1e-9 * d.observe_every;

  std::mutex mutex;
  for_each_ensemble(first, last, options, [&](std::uint64_t e, ProgressSlot& slot) {
    DsmcEnsemble ensemble(d, config.seed, e, &slot);
    std::vector<Observation> obs(M + 1);
    std::vector<std::uint64_t> hist((M + 1) * K1, 0);
    for (std::uint64_t m = 0; m <= M; ++m) {
      if (m > 0) ensemble.advance_to(r.times[m]);
      obs[m] = measure(ensemble.particles());
      if (K1) radial_histogram(ensemble.particles(), d.histogram, &hist[m * K1]);
    }
    // Exact sums: the order in which ensembles arrive here does not matter.
    std::lock_guard<std::mutex> lock(mutex);
    for (std::uint64_t m = 0; m <= M; ++m) {
      for (int k = 0; k < kNumScalars; ++k) r.series[m * kNumScalars + k].add(obs[m][k]);
      if (d.steady && r.times[m] > steady_after) {
        for (int k = 0; k < kNumScalars; ++k) r.steady[k].add(obs[m][k]);
        ++r.steady_samples;
      }
    }
    for (std::size_t k = 0; k < hist.size(); ++k) {
      r.histogram[k] += hist[k];
      r.histogram_sq[k] += static_cast<uint128>(hist[k]) * hist[k];
    }
    const std::uint64_t i = e - first;
    r.ensemble_index[i] = e;
    r.collisions[i] = ensemble.counts().collisions;
    r.fictitious[i] = ensemble.counts().fictitious;
    r.kicks[i] = ensemble.counts().kicks;
    r.u_max_final[i] = ensemble.u_max();
  });
  r.ensembles = count;
  return r;
}

namespace {

Dims shape_of(const ObservableInfo& o, std::uint64_t rows) {
  if (o.rank == 0) return {rows};
  if (o.rank == 1) return {rows, 3};
  return {rows, 3, 3};
}

void write_moments(H5Writer& out, const std::string& prefix, const std::vector<Moments2>& sums,
                   std::uint64_t rows, std::uint64_t samples, bool scalar_rows) {
  for (const auto& o : kObservables) {
    const int size = observable_size(o);
    std::vector<double> mean, ci, var;
    for (std::uint64_t m = 0; m < rows; ++m)
      for (int k = 0; k < size; ++k) {
        const MeanCi s = sums[m * kNumScalars + o.offset + k].stats(samples);
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
}

std::vector<std::int64_t> digits_of(const std::vector<Moments2>& sums) {
  std::vector<std::int64_t> all;
  for (const auto& s : sums)
    for (const ExactSum* e : {&s.sum, &s.sum_sq}) {
      const auto d = e->digits();
      all.insert(all.end(), d.begin(), d.end());
    }
  return all;
}

}  // namespace

void write_dsmc(H5Writer& out, const Config& config, const DsmcResult& r) {
  const DsmcConfig& d = config.dsmc;
  const std::uint64_t rows = r.times.size();
  out.write("/time", r.times, {rows});
  write_moments(out, "", r.series, rows, r.ensembles, false);
  out.attr("/", "confidence_lambda_p", kLambdaP);

  if (d.histogram.shells) {
    const std::uint64_t K1 = d.histogram.shells + 1;
    std::vector<double> edges(K1), mean(rows * K1), ci(rows * K1);
    for (std::uint64_t k = 0; k < K1; ++k)
      edges[k] = d.histogram.radius * static_cast<double>(k) / static_cast<double>(K1 - 1);
    const double n = static_cast<double>(d.particles), N = static_cast<double>(r.ensembles);
    for (std::size_t k = 0; k < mean.size(); ++k) {
      const double f = static_cast<double>(r.histogram[k]) / (n * N);
      const double f2 = static_cast<double>(r.histogram_sq[k]) / (n * n * N);
      mean[k] = f;
      ci[k] = kLambdaP * std::sqrt(std::max(0.0, f2 - f * f) / N);
    }
    out.write("/histogram/edges", edges, {K1});
    out.write("/histogram/mean", mean, {rows, K1});
    out.write("/histogram/ci", ci, {rows, K1});
    out.write("/histogram/counts", r.histogram, {rows, K1});
    out.attr("/histogram", "description",
             std::string("f_k = fraction of particles with r_{k-1} <= |v| < r_k, r_k = k R/K "
                         "(GRW05 eq. 37); the last shell holds |v| >= R"));
    std::vector<std::uint64_t> sq(2 * r.histogram_sq.size());
    for (std::size_t k = 0; k < r.histogram_sq.size(); ++k) {
      sq[2 * k] = static_cast<std::uint64_t>(r.histogram_sq[k] >> 64);
      sq[2 * k + 1] = static_cast<std::uint64_t>(r.histogram_sq[k]);
    }
    out.write("/accumulators/histogram_sq", sq, {rows, K1, 2});
  }

  const std::uint64_t N = r.ensemble_index.size();
  out.write("/events/ensemble", r.ensemble_index, {N});
  out.write("/events/collisions", r.collisions, {N});
  out.write("/events/fictitious", r.fictitious, {N});
  out.write("/events/kicks", r.kicks, {N});
  out.write("/events/u_max_final", r.u_max_final, {N});

  if (d.steady) {
    write_moments(out, "/steady", r.steady, 1, r.steady_samples, true);
    out.attr("/steady", "samples", r.steady_samples);
    out.attr("/steady", "from", d.steady_from);
    out.write("/accumulators/steady", digits_of(r.steady),
              {kNumScalars, 2, static_cast<hsize_t>(ExactSum::kLimbs)});
    out.attr("/accumulators", "steady_samples", r.steady_samples);
  }
  out.write("/accumulators/series", digits_of(r.series),
            {rows, kNumScalars, 2, static_cast<hsize_t>(ExactSum::kLimbs)});
}

}  // namespace granboltz
