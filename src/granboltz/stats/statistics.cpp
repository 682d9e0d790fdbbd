#include "granboltz/stats/statistics.hpp"

#include <gsl/gsl_cdf.h>

#include <algorithm>
#include <cmath>

namespace granboltz {

MeanCi Moments2::stats(std::uint64_t count) const {
  MeanCi r;
  if (count == 0) return r;
  const double n = static_cast<double>(count);
  r.mean = sum.value() / n;
  r.variance = std::max(0.0, sum_sq.value() / n - r.mean * r.mean);
  r.ci = kLambdaP * std::sqrt(r.variance / n);
  return r;
}

double confidence_factor(double dof) {
  if (!(dof >= 1 && dof < 30)) return kLambdaP;
  return gsl_cdf_tdist_Qinv(0.5 * std::erfc(kLambdaP / std::sqrt(2.0)), dof);
}

double variance_of_mean(const Moments2& e, std::uint64_t count) {
  if (count < 2) return NAN;
  const double Nd = static_cast<double>(count);
  const double m = e.sum.value() / Nd;
  const double s2 = std::max(0.0, (e.sum_sq.value() - Nd * m * m) / (Nd - 1));
  return s2 / Nd;
}

}  // namespace granboltz
