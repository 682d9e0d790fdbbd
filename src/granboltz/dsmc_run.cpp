#include "granboltz/dsmc_run.hpp"

#include <algorithm>
#include <cmath>
#include <mutex>

#include "granboltz/dsmc_ensemble.hpp"
#include "granboltz/observables.hpp"

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
  for (const ColumnSpec& c : kColumns) r.declare_column(c.path, c.floating);
  return r;
}

void run_dsmc(const Config& config, const DriverOptions& options, Record& record) {
  const DsmcConfig& d = config.dsmc;
  const std::vector<double> times = dsmc_times(d);
  const std::uint64_t rows = times.size();
  const std::uint64_t K1 = d.histogram.shells ? d.histogram.shells + 1 : 0;
  const double steady_after = d.steady_from + 1e-9 * d.observe_every;

  std::vector<std::uint64_t> todo;
  for (std::uint64_t e = config.first_ensemble(); e < config.last_ensemble(); ++e)
    if (!record.has_ensemble(e)) todo.push_back(e);

  std::mutex mutex;
  DriverOptions opts = options;
  if (options.checkpoint)
    opts.tick = [&] {
      std::lock_guard<std::mutex> lock(mutex);
      options.checkpoint(record);
    };
  for_each_ensemble(todo, opts, [&](std::uint64_t e, ProgressSlot& slot) {
    DsmcEnsemble ensemble(d, config.seed, e, &slot);
    std::vector<Observation> obs(rows);
    std::vector<std::uint64_t> hist(rows * K1, 0);
    for (std::uint64_t m = 0; m < rows; ++m) {
      if (m > 0) ensemble.advance_to(times[m]);
      obs[m] = measure(ensemble.particles());
      if (K1) radial_histogram(ensemble.particles(), d.histogram, &hist[m * K1]);
    }
    // Exact sums: the order in which ensembles arrive here does not matter.
    std::lock_guard<std::mutex> lock(mutex);
    auto& series = record.moments("series");
    for (std::uint64_t m = 0; m < rows; ++m) {
      for (int k = 0; k < kNumScalars; ++k) series[m * kNumScalars + k].add(obs[m][k]);
      if (d.steady && times[m] > steady_after) {
        auto& steady = record.moments("steady");
        for (int k = 0; k < kNumScalars; ++k) steady[k].add(obs[m][k]);
        ++record.total("steady_samples");
      }
    }
    if (K1) record.add_counts("histogram", hist);
    const EventCounts& c = ensemble.counts();
    record.add_ensemble(e, {static_cast<double>(c.collisions), static_cast<double>(c.fictitious),
                            static_cast<double>(c.kicks), ensemble.u_max()});
  });
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

}  // namespace

void present_dsmc(H5Writer& out, const Config& config, const Record& record) {
  const DsmcConfig& d = config.dsmc;
  const std::vector<double> times = dsmc_times(d);
  const std::uint64_t rows = times.size(), N = record.ensembles();
  out.write("/time", times, {rows});
  write_moments(out, "", record.moments("series"), rows, N, false);
  out.attr("/", "confidence_lambda_p", kLambdaP);

  if (d.histogram.shells) {
    const std::uint64_t K1 = d.histogram.shells + 1;
    const auto& counts = record.counts("histogram");
    const auto& counts_sq = record.counts_sq("histogram");
    std::vector<double> edges(K1), mean(rows * K1), ci(rows * K1);
    for (std::uint64_t k = 0; k < K1; ++k)
      edges[k] = d.histogram.radius * static_cast<double>(k) / static_cast<double>(K1 - 1);
    const double n = static_cast<double>(d.particles), Nd = static_cast<double>(N);
    for (std::size_t k = 0; k < mean.size(); ++k) {
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
  if (d.steady) {
    const std::uint64_t samples = record.total("steady_samples");
    write_moments(out, "/steady", record.moments("steady"), 1, samples, true);
    out.attr("/steady", "samples", samples);
    out.attr("/steady", "from", d.steady_from);
  }
}

}  // namespace granboltz
