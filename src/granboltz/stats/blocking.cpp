#include "granboltz/stats/blocking.hpp"

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace granboltz {

double row_average(const double* x, std::uint64_t R) {
  double sum = 0.0;
  for (std::uint64_t i = 0; i < R; ++i) {
    if (std::isnan(x[i]))
      throw std::invalid_argument("row_average: row " + std::to_string(i) + " is NaN");
    sum += x[i];
  }
  return sum / static_cast<double>(R);
}

double blocked_variance(const double* x, std::uint64_t R, std::uint64_t B) {
  const std::uint64_t n = B ? R / B : 0;
  if (n < 2)
    throw std::invalid_argument("blocked_variance: " + std::to_string(R) +
                                " rows hold fewer than 2 blocks of " + std::to_string(B));
  for (std::uint64_t i = 0; i < n * B; ++i)
    if (std::isnan(x[i]))
      throw std::invalid_argument("blocked_variance: row " + std::to_string(i) + " is NaN");
  std::vector<double> b(n, 0.0);
  double bsum = 0.0;
  for (std::uint64_t j = 0; j < n; ++j) {
    for (std::uint64_t i = 0; i < B; ++i) b[j] += x[j * B + i];
    b[j] /= static_cast<double>(B);
    bsum += b[j];
  }
  const double bmean = bsum / static_cast<double>(n);
  double ss = 0.0;
  for (double v : b) ss += (v - bmean) * (v - bmean);
  return ss / static_cast<double>(n - 1) * static_cast<double>(B) / static_cast<double>(R);
}

std::uint64_t block_levels(std::uint64_t R) {
  std::uint64_t L = 0;
  while (L < 63 && (R >> L) >= 2) ++L;
  return L;
}

std::uint64_t chosen_block_level(const double* v, std::uint64_t L, std::uint64_t R) {
  const double v0 = v[0];
  for (std::uint64_t l = 0; l < L; ++l) {
    const double B = std::ldexp(1.0, static_cast<int>(l));
    const double ratio = v0 > 0 ? v[l] / v0 : 1.0;
    if (B * B * B > 2.0 * static_cast<double>(R) * ratio * ratio) return l;
  }
  return L - 1;
}

IntegratedTime integrated_time(double variance, double var_mean, std::uint64_t samples) {
  IntegratedTime r;
  r.effective_samples = static_cast<double>(samples);
  if (variance > 0 && var_mean > 0) {
    r.tau_int = var_mean * static_cast<double>(samples) / (2.0 * variance);
    r.effective_samples = variance / var_mean;
  } else if (!(var_mean >= 0)) {
    r.tau_int = r.effective_samples = NAN;
  }
  return r;
}

}  // namespace granboltz
