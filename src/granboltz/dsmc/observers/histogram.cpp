#include "granboltz/dsmc/observers/histogram.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "granboltz/dsmc/observers/row_set.hpp"  // steady_rows
#include "granboltz/dsmc/weighted.hpp"
#include "granboltz/stats/statistics.hpp"

namespace granboltz {

HistogramObserver::HistogramObserver(const DsmcConfig& d, Kind kind)
    : d_(d),
      kind_(kind),
      name_(kind == kRadial ? "histogram" : "histogram_component"),
      rows_(d.observations() + 1),
      K1_(d.histogram.shells + 1) {}

void HistogramObserver::declare(Record& r, LayoutPhase phase) const {
  // The radial histogram's sums sit where they always have, between the whole gas's; the
  // component histogram came later and has its three together.
  const bool radial = kind_ == kRadial;
  if (phase == (radial ? LayoutPhase::kRows : LayoutPhase::kComponent))
    r.declare_counts(name_, rows_ * K1_);
  // The steady-state histogram: per ensemble the time average of f_k over the steady rows, so
  // that its confidence interval comes from independent ensembles, not from correlated rows.
  if (d_.steady && phase == (radial ? LayoutPhase::kSteadyAverages : LayoutPhase::kComponent))
    r.declare_moments(name_ + "_steady", K1_);
  // SWPM: the weight per shell (f_k itself), beside the particle numbers.
  if (d_.weights.swpm && phase == (radial ? LayoutPhase::kWeights : LayoutPhase::kComponent))
    r.declare_moments(name_ + "_weight", rows_ * K1_);
}

ObserverRows HistogramObserver::start(bool weighted) const {
  ObserverRows w;
  w.counts.assign(rows_ * K1_, 0);
  if (weighted) w.values.assign(rows_ * K1_, 0.0);
  return w;
}

void HistogramObserver::observe(const ObservedRow& row, ObserverRows& w) const {
  const Vec3 V{row.whole[1], row.whole[2], row.whole[3]};  // bulk_velocity
  const ParticleView& v = row.view;
  std::uint64_t* count = &w.counts[row.m * K1_];
  if (!v.weights.empty()) {
    double* weight = &w.values[row.m * K1_];
    if (kind_ == kRadial)
      radial_histogram_weighted(v.particles, v.weights, d_.histogram, V, weight, count);
    else
      component_histogram_weighted(v.particles, v.weights, d_.histogram, V, weight, count);
  } else if (kind_ == kRadial) {
    radial_histogram(v.particles, d_.histogram, V, count);
  } else {
    component_histogram(v.particles, d_.histogram, V, count);
  }
}

void HistogramObserver::save(H5Writer& out, const std::string& g, const ObserverRows& w,
                             std::uint64_t) const {
  out.write(g + "/" + name_, w.counts, {w.counts.size()});
  if (!w.values.empty()) out.write(g + "/" + name_ + "_weight", w.values, {w.values.size()});
}

ObserverRows HistogramObserver::load(const H5Reader& in, const std::string& g, bool weighted,
                                     std::uint64_t) const {
  ObserverRows w;
  w.counts = in.read_uint64(g + "/" + name_);
  if (weighted) w.values = in.read_double(g + "/" + name_ + "_weight");
  if (w.counts.size() != rows_ * K1_ || (weighted && w.values.size() != rows_ * K1_))
    throw std::runtime_error(in.path() + ": malformed ensemble state " + g);
  return w;
}

void HistogramObserver::accumulate(const FinishedEnsemble& f, const ObserverRows& w,
                                   Record& record) const {
  const RunRows& run = f.run;
  const bool weighted = f.ensemble.weighted();
  record.add_counts(name_, w.counts);
  if (d_.steady) {
    std::vector<double> avg(K1_, 0.0);
    double steady_rows = 0.0;
    for (std::uint64_t m = 0; m < rows_; ++m) {
      if (!(run.times[m] > run.steady_after)) continue;
      steady_rows += 1.0;
      for (std::uint64_t k = 0; k < K1_; ++k)
        avg[k] += weighted ? w.values[m * K1_ + k]
                           : static_cast<double>(w.counts[m * K1_ + k]) /
                                 static_cast<double>(d_.particles);
    }
    auto& hs = record.moments(name_ + "_steady");
    for (std::uint64_t k = 0; k < K1_; ++k) hs[k].add(avg[k] / steady_rows);
  }
  if (weighted) {
    auto& hw = record.moments(name_ + "_weight");
    for (std::size_t k = 0; k < w.values.size(); ++k) hw[k].add(w.values[k]);
  }
}

void HistogramObserver::present(Presenter& out, const Record& record) const {
  const std::uint64_t rows = rows_, N = record.ensembles(), K1 = K1_;
  const double R = d_.histogram.radius, K = static_cast<double>(K1 - 1);
  std::vector<double> edges(K1);
  // The radial shells 0..R; the component's K + 1 edges -R .. R of its K bins.
  for (std::uint64_t k = 0; k < K1; ++k)
    edges[k] = kind_ == kRadial ? R * static_cast<double>(k) / K
                                : R * (2.0 * static_cast<double>(k) / K - 1.0);
  const std::string description =
      kind_ == kComponent
          ? "f_k = fraction of particles with x_k <= (v - V(t))_x < x_{k+1}, x_k = -R + 2 k R/K "
            "(dsmc.histogram.component); the last bin holds |(v - V)_x| >= R"
      : d_.histogram.bulk
          ? "f_k = fraction of particles with r_k <= |v - V(t)| < r_{k+1}, r_k = k R/K, V(t) the "
            "ensemble's bulk velocity (dsmc.histogram.center: bulk); the last shell holds |v - V| "
            ">= R"
          : "f_k = fraction of particles with r_k <= |v| < r_{k+1}, r_k = k R/K (GRW05 eq. 37); "
            "the "
            "last shell holds |v| >= R";
  const auto& counts = record.counts(name_);
  const auto& counts_sq = record.counts_sq(name_);
  std::vector<double> mean(rows * K1), ci(rows * K1);
  const double n = static_cast<double>(d_.particles), Nd = static_cast<double>(N);
  if (d_.weights.swpm) {  // f_k = the weight in shell k, from exact sums over ensembles
    const auto& hw = record.moments(name_ + "_weight");
    for (std::size_t k = 0; k < mean.size(); ++k) {
      const MeanCi s = hw[k].stats(N);
      mean[k] = s.mean;
      ci[k] = s.ci;
    }
  }
  for (std::size_t k = 0; k < mean.size() && !d_.weights.swpm; ++k) {
    const double f = static_cast<double>(counts[k]) / (n * Nd);
    const double f2 = static_cast<double>(counts_sq[k]) / (n * n * Nd);
    mean[k] = f;
    ci[k] = kLambdaP * std::sqrt(std::max(0.0, f2 - f * f) / Nd);
  }
  const std::string g = "/" + name_;
  out.write(g + "/edges", edges, {K1}, "the K + 1 edges of the bins of " + g + "/mean");
  out.write(g + "/mean", mean, {rows, K1}, description + "; per row t_m, mean over the ensembles");
  out.write(g + "/ci", ci, {rows, K1}, "confidence half-width of " + g + "/mean");
  out.write(g + "/counts", counts, {rows, K1},
            "particles per bin and row, summed over the ensembles");
  out.attr(g, "description", description);
  out.attr(g, "center", std::string(d_.histogram.bulk || kind_ == kComponent ? "bulk" : "origin"));
  if (!d_.steady) return;
  const auto& hs = record.moments(name_ + "_steady");
  std::vector<double> smean(hs.size()), sci(hs.size());
  for (std::size_t k = 0; k < hs.size(); ++k) {
    const MeanCi s = hs[k].stats(N);
    smean[k] = s.mean;
    sci[k] = s.ci;
  }
  const std::string steady_text =
      "f_k averaged over the observation times t_m > steady_from in each ensemble; mean and "
      "confidence half-width over the ensembles (edges: " +
      g + "/edges)";
  out.write("/steady" + g + "/mean", smean, {smean.size()}, steady_text + ": mean");
  out.write("/steady" + g + "/ci", sci, {sci.size()}, steady_text + ": confidence half-width");
  out.attr("/steady" + g, "rows", steady_rows(d_));
  out.attr("/steady" + g, "description", steady_text);
}

}  // namespace granboltz
