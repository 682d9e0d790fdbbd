#pragma once
// Blocking (Flyvbjerg & Petersen 1989): the variance of a time average of correlated rows from
// the spread of the averages of blocks of 2^l rows, and tau_int from it.
#include <cstdint>

namespace granboltz {

/// The average of x[0..R), summed in row order (so the same rows always give the same double).
/// Throws std::invalid_argument on a NaN row.
double row_average(const double* x, std::uint64_t R);

/// The variance of the average of x[0..R) if blocks of B rows were independent: var(block mean)
/// B / R over the n = R / B full blocks (leaving out the last R - n B rows). Throws
/// std::invalid_argument for n < 2 or a NaN row.
double blocked_variance(const double* x, std::uint64_t R, std::uint64_t B);

/// Blocking levels l = 0..L-1 (blocks of 2^l rows) with at least 2 full blocks in R rows.
std::uint64_t block_levels(std::uint64_t R);

/// The level whose blocks are long enough to be independent: the smallest l with
/// B^3 > 2 R (v_l / v_0)^2, B = 2^l (Lee, Needs & Drummond 2011), else the longest (L - 1).
/// v[0..L): the blocked variance at each level, L >= 1.
std::uint64_t chosen_block_level(const double* v, std::uint64_t L, std::uint64_t R);

/// tau_int = var_mean samples / (2 variance) in rows and N_eff = variance / var_mean, from the
/// variance of one sample and that of the mean; tau_int = 1/2 and N_eff = samples (independent
/// samples) where either variance is 0, NaN both where var_mean is NaN.
struct IntegratedTime {
  double tau_int = 0.5;
  double effective_samples = 0.0;
};
IntegratedTime integrated_time(double variance, double var_mean, std::uint64_t samples);

}  // namespace granboltz
