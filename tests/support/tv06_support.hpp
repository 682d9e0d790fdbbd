#pragma once
// Statistics for the TV06 tests: Kolmogorov-Smirnov against a density integrated by GSL
// quadrature, Student-t intervals over ensembles, Welch comparisons and Hotelling's T^2 test of a
// histogram. Every threshold comes from a stated family-wise level (0.001), never from tuning.
#include <gsl/gsl_cdf.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_integration.h>
#include <gsl/gsl_linalg.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>
#include <vector>

namespace granboltz::tv06test {

/// The family-wise level of each test (split over its checks by Bonferroni).
inline constexpr double kLevel = 0.001;

/// GSL reports errors through codes while this guard lives (the tests check them).
struct GslErrorsAsCodes {
  gsl_error_handler_t* previous;
  GslErrorsAsCodes() : previous(gsl_set_error_handler_off()) {}
  ~GslErrorsAsCodes() { gsl_set_error_handler(previous); }
};

/// ∫_a^b f by adaptive quadrature; a = -inf and/or b = +inf allowed.
inline double integrate(const std::function<double(double)>& f, double a, double b,
                        double epsrel = 1e-12) {
  GslErrorsAsCodes guard;
  gsl_integration_workspace* w = gsl_integration_workspace_alloc(2000);
  gsl_function F;
  F.function = [](double x, void* p) {
    return (*static_cast<const std::function<double(double)>*>(p))(x);
  };
  F.params = const_cast<std::function<double(double)>*>(&f);
  double result = 0, error = 0;
  int status;
  const double inf = std::numeric_limits<double>::infinity();
  if (a == -inf && b == inf)
    status = gsl_integration_qagi(&F, 0, epsrel, 2000, w, &result, &error);
  else if (a == -inf)
    status = gsl_integration_qagil(&F, b, 0, epsrel, 2000, w, &result, &error);
  else if (b == inf)
    status = gsl_integration_qagiu(&F, a, 0, epsrel, 2000, w, &result, &error);
  else
    status = gsl_integration_qags(&F, a, b, 0, epsrel, 2000, w, &result, &error);
  gsl_integration_workspace_free(w);
  // Round-off limits are reported but the result is still accurate to ~1e-14 of its scale.
  if (status != GSL_SUCCESS && status != GSL_EROUND)
    throw std::runtime_error(std::string("quadrature failed: ") + gsl_strerror(status));
  return result;
}

/// sqrt(n) D_n of a sample against the law with (unnormalized) density `pdf` on (lo, hi).
/// The CDF at the sorted samples is accumulated by quadrature between consecutive samples and
/// normalized by the quadrature of the whole support.
inline double ks_statistic(std::vector<double> x, const std::function<double(double)>& pdf,
                           double lo, double hi) {
  std::sort(x.begin(), x.end());
  const std::size_t n = x.size();
  std::vector<double> cdf(n);
  double acc = integrate(pdf, lo, x[0]);
  cdf[0] = acc;
  for (std::size_t i = 1; i < n; ++i) {
    if (x[i] > x[i - 1]) acc += integrate(pdf, x[i - 1], x[i], 1e-10);
    cdf[i] = acc;
  }
  const double total = acc + integrate(pdf, x[n - 1], hi);
  double d = 0;
  const double N = static_cast<double>(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double F = cdf[i] / total;
    d = std::max({d, F - static_cast<double>(i) / N, static_cast<double>(i + 1) / N - F});
  }
  return std::sqrt(N) * d;
}

/// The asymptotic Kolmogorov critical value of sqrt(n) D_n at level kLevel/checks:
/// P(K > c) = 2 sum_k (-1)^(k-1) exp(-2 k^2 c^2) ~ 2 exp(-2 c^2) for these small levels.
inline double ks_critical(int checks) { return std::sqrt(-0.5 * std::log(0.5 * kLevel / checks)); }

/// Mean of per-ensemble values and the half-width of its Student-t interval at level
/// kLevel/checks (two-sided).
struct Interval {
  double mean = 0, half_width = 0, standard_error = 0;
  bool contains(double x) const { return std::fabs(x - mean) <= half_width; }
};
inline Interval t_interval(const std::vector<double>& v, int checks) {
  const double n = static_cast<double>(v.size());
  double m = 0;
  for (double x : v) m += x;
  m /= n;
  double s2 = 0;
  for (double x : v) s2 += (x - m) * (x - m);
  s2 /= n - 1;
  Interval r;
  r.mean = m;
  r.standard_error = std::sqrt(s2 / n);
  r.half_width = gsl_cdf_tdist_Qinv(0.5 * kLevel / checks, n - 1) * r.standard_error;
  return r;
}

/// Welch's test that two sets of per-ensemble values have the same mean: true if consistent.
inline bool same_mean(const std::vector<double>& a, const std::vector<double>& b, int checks,
                      double* z = nullptr) {
  const Interval ia = t_interval(a, 1), ib = t_interval(b, 1);
  const double se2a = ia.standard_error * ia.standard_error;
  const double se2b = ib.standard_error * ib.standard_error;
  const double se = std::sqrt(se2a + se2b);
  const double na = static_cast<double>(a.size()), nb = static_cast<double>(b.size());
  const double dof =
      (se2a + se2b) * (se2a + se2b) / (se2a * se2a / (na - 1) + se2b * se2b / (nb - 1));
  const double t = std::fabs(ia.mean - ib.mean) / se;
  if (z) *z = t;
  return t <= gsl_cdf_tdist_Qinv(0.5 * kLevel / checks, dof);
}

/// Hotelling's T^2 test that the mean of N independent k-vectors (rows of `x`) is `mu`:
/// F = (N - k) / (k (N - 1)) T^2 ~ F(k, N - k). Returns the p-value.
inline double hotelling_p_value(const std::vector<std::vector<double>>& x,
                                const std::vector<double>& mu) {
  const std::size_t N = x.size(), k = mu.size();
  std::vector<double> mean(k, 0.0);
  for (const auto& row : x)
    for (std::size_t j = 0; j < k; ++j) mean[j] += row[j] / static_cast<double>(N);
  gsl_matrix* S = gsl_matrix_calloc(k, k);
  for (const auto& row : x)
    for (std::size_t i = 0; i < k; ++i)
      for (std::size_t j = 0; j < k; ++j)
        *gsl_matrix_ptr(S, i, j) +=
            (row[i] - mean[i]) * (row[j] - mean[j]) / static_cast<double>(N - 1);
  gsl_vector* d = gsl_vector_alloc(k);
  for (std::size_t j = 0; j < k; ++j) gsl_vector_set(d, j, mean[j] - mu[j]);
  gsl_vector* y = gsl_vector_alloc(k);
  GslErrorsAsCodes guard;
  if (gsl_linalg_cholesky_decomp1(S) != GSL_SUCCESS)
    throw std::runtime_error("singular covariance");
  gsl_linalg_cholesky_solve(S, d, y);
  double t2 = 0;
  for (std::size_t j = 0; j < k; ++j) t2 += gsl_vector_get(d, j) * gsl_vector_get(y, j);
  t2 *= static_cast<double>(N);
  gsl_vector_free(y);
  gsl_vector_free(d);
  gsl_matrix_free(S);
  const double f =
      static_cast<double>(N - k) / (static_cast<double>(k) * static_cast<double>(N - 1)) * t2;
  return gsl_cdf_fdist_Q(f, static_cast<double>(k), static_cast<double>(N - k));
}

}  // namespace granboltz::tv06test
