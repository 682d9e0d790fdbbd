#pragma once
// The interval of a steady-state average over N ensembles of R correlated rows each: from the
// spread of the ensembles' time averages, from blocking within them, or counting every
// (ensemble, row) sample independent.
#include <cstdint>
#include <vector>

#include "granboltz/stats/statistics.hpp"

namespace granboltz {

struct SteadyStats {
  double mean = 0.0;
  double variance = 0.0;                  ///< over all (ensemble, t_m) samples, as before
  double sigma = 0.0;                     ///< standard error of the mean
  double ci = 0.0;                        ///< confidence half-width from sigma
  double tau_int = 0.5;                   ///< sigma^2 samples / (2 variance), in observation rows
  double effective_samples = 0.0;         ///< samples / (2 tau_int)
  double dof = 0.0;                       ///< degrees of freedom of sigma (inf: independent)
  std::uint64_t block_rows = 1;           ///< blocking: the block length chosen, in rows
  const char* estimator = "independent";  ///< "ensembles" | "blocking" | "independent"
};

enum class SteadyEstimator { kIndependent, kEnsembles, kBlocking };

/// all: the mean and variance of the `samples` (ensemble, row) samples; averages: the sums of the
/// N ensembles' time averages over their R rows; blocked[l]: the sum over the ensembles of each
/// one's blocked_variance at level l (kBlocking only, at least one level). With no samples the
/// estimator is kIndependent whatever `how` says.
SteadyStats steady_interval(SteadyEstimator how, const MeanCi& all, std::uint64_t samples,
                            std::uint64_t N, std::uint64_t R, const Moments2& averages,
                            const std::vector<double>& blocked);

}  // namespace granboltz
