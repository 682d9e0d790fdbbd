#include "granboltz/stats/steady.hpp"

#include <cmath>
#include <stdexcept>

#include "granboltz/stats/blocking.hpp"

namespace granboltz {

SteadyStats steady_interval(SteadyEstimator how, const MeanCi& all, std::uint64_t samples,
                            std::uint64_t N, std::uint64_t R, const Moments2& averages,
                            const std::vector<double>& blocked) {
  const std::uint64_t S = samples;
  SteadyStats r;
  r.mean = all.mean;
  r.variance = all.variance;
  r.effective_samples = static_cast<double>(S);
  r.dof = INFINITY;
  if (how == SteadyEstimator::kIndependent ||
      S == 0) {  // every (ensemble, t_m) sample counted independent
    r.sigma = S ? std::sqrt(all.variance / static_cast<double>(S)) : 0.0;
    r.ci = all.ci;
    return r;
  }
  const double Nd = static_cast<double>(N);
  double var_mean = NAN;
  if (how == SteadyEstimator::kEnsembles) {
    // Independent ensembles by construction: the spread of their time averages is honest.
    r.estimator = "ensembles";
    var_mean = variance_of_mean(averages, N);
    r.dof = Nd - 1;
  } else {
    // Pooled blocking: each level's variance of the mean is the sum of the ensembles' over N^2.
    if (blocked.empty()) throw std::invalid_argument("steady_interval: blocking without levels");
    r.estimator = "blocking";
    std::vector<double> v(blocked.size());
    for (std::size_t l = 0; l < v.size(); ++l) v[l] = blocked[l] / (Nd * Nd);
    const std::uint64_t chosen = chosen_block_level(v.data(), v.size(), R);
    var_mean = v[chosen];
    r.block_rows = std::uint64_t{1} << chosen;
    r.dof = Nd * static_cast<double>(R / r.block_rows - 1);
  }
  r.sigma = std::sqrt(var_mean);
  const IntegratedTime t = integrated_time(all.variance, var_mean, S);
  r.tau_int = t.tau_int;
  r.effective_samples = t.effective_samples;
  r.ci = confidence_factor(r.dof) * r.sigma;
  return r;
}

}  // namespace granboltz
