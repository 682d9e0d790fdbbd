#pragma once
// Ensemble statistics of GRW05 §5.1: empirical mean, variance and confidence half-width.
#include <cstdint>
#include <vector>

#include "granboltz/stats/exact_sum.hpp"

namespace granboltz {

/// lambda_p for the confidence level p = 0.999 used by GRW05 and RW05.
inline constexpr double kLambdaP = 3.2;

struct MeanCi {
  double mean = 0.0;
  double variance = 0.0;  ///< eta_2 - eta_1^2 (GRW05 §5.1)
  double ci = 0.0;        ///< lambda_p sqrt(variance / N)
};

/// Running sums of x and x^2 over independent samples, exact and order-independent.
struct Moments2 {
  ExactSum sum, sum_sq;
  void add(double x) {
    sum.add(x);
    sum_sq.add(x * x);
  }
  void merge(const Moments2& o) {
    sum.merge(o.sum);
    sum_sq.merge(o.sum_sq);
  }
  MeanCi stats(std::uint64_t count) const;
};

/// The factor of the confidence half-width for a sigma with `dof` degrees of freedom: GRW05's
/// lambda_p = 3.2 from 30 on (and for a dof that is not a number >= 1), below the Student-t
/// quantile of the same two-sided level, since sigma is then itself uncertain.
double confidence_factor(double dof);

/// The variance of the mean of `count` independent samples from their sums: the sample variance
/// (count - 1) over count; NaN below 2 samples.
double variance_of_mean(const Moments2& m, std::uint64_t count);

}  // namespace granboltz
