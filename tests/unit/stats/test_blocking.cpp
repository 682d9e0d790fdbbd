// Blocking and the steady-state interval (stats/blocking.hpp, stats/steady.hpp): small cases by
// hand, an AR(1) series of known tau_int, and the edge cases.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

#include "granboltz/stats/blocking.hpp"
#include "granboltz/stats/steady.hpp"

using namespace granboltz;

TEST(StatsBlocking, SmallCasesByHand) {
  const std::vector<double> x{1, 3, 2, 6};
  EXPECT_EQ(row_average(x.data(), 4), 3.0);
  EXPECT_DOUBLE_EQ(blocked_variance(x.data(), 4, 1), 7.0 / 6.0);  // ss 14, / 3, * 1/4
  EXPECT_DOUBLE_EQ(blocked_variance(x.data(), 4, 2), 1.0);        // blocks 2, 4: ss 2, / 1, * 2/4
  // Rows beyond the last full block are left out: blocks (1, 3) of 5 rows, B / R = 2/5.
  const std::vector<double> y{1, 1, 3, 3, 100};
  EXPECT_DOUBLE_EQ(blocked_variance(y.data(), 5, 2), 2.0 * 2.0 / 5.0);
  for (auto [R, L] : std::vector<std::pair<int, int>>{
           {0, 0}, {1, 0}, {2, 1}, {3, 1}, {4, 2}, {7, 2}, {8, 3}, {1024, 10}})
    EXPECT_EQ(block_levels(R), static_cast<std::uint64_t>(L)) << R;
}

TEST(StatsBlocking, RefusesNaNAndTooFewBlocks) {
  const std::vector<double> x{1, NAN, 2, 3};
  EXPECT_THROW(row_average(x.data(), 4), std::invalid_argument);
  EXPECT_THROW(blocked_variance(x.data(), 4, 1), std::invalid_argument);
  const std::vector<double> y{1, 2, 3};
  EXPECT_THROW(blocked_variance(y.data(), 3, 2), std::invalid_argument);
  EXPECT_THROW(blocked_variance(y.data(), 3, 0), std::invalid_argument);
  EXPECT_NO_THROW(blocked_variance(y.data(), 3, 1));
}

TEST(StatsBlocking, LevelChoiceAndIntegratedTime) {
  // Flat v: the first B with B^3 > 2 R; none: the longest blocks.
  const double flat[4] = {1, 1, 1, 1};
  EXPECT_EQ(chosen_block_level(flat, 4, 3), 1u);   // 8 > 6
  EXPECT_EQ(chosen_block_level(flat, 4, 40), 3u);  // 64 <= 80: none, the last
  const double zero[2] = {0, 5};
  EXPECT_EQ(chosen_block_level(zero, 2, 3), 1u);  // v0 = 0 counts as ratio 1
  const IntegratedTime t = integrated_time(2.0, 0.3, 100);
  EXPECT_DOUBLE_EQ(t.tau_int, 0.3 * 100 / 4.0);
  EXPECT_DOUBLE_EQ(t.effective_samples, 2.0 / 0.3);
  const IntegratedTime z = integrated_time(0.0, 0.0, 100);  // zero variance: independent
  EXPECT_EQ(z.tau_int, 0.5);
  EXPECT_EQ(z.effective_samples, 100.0);
  const IntegratedTime n = integrated_time(1.0, NAN, 100);
  EXPECT_TRUE(std::isnan(n.tau_int) && std::isnan(n.effective_samples));
}

namespace {
/// N stationary AR(1) series x_t = phi x_{t-1} + e_t of R rows, unit innovations, fixed seed.
std::vector<std::vector<double>> ar1(int N, std::uint64_t R, double phi) {
  std::mt19937_64 gen(20261204);
  std::normal_distribution<double> e;
  std::vector<std::vector<double>> out(N, std::vector<double>(R));
  for (auto& x : out) {
    x[0] = e(gen) / std::sqrt(1 - phi * phi);
    for (std::uint64_t t = 1; t < R; ++t) x[t] = phi * x[t - 1] + e(gen);
  }
  return out;
}
/// The sums steady_interval takes, from N series.
struct Sums {
  MeanCi all;
  std::uint64_t samples = 0;
  Moments2 averages;
  std::vector<double> blocked;
};
Sums sums_of(const std::vector<std::vector<double>>& xs) {
  Sums s;
  Moments2 each;
  const std::uint64_t R = xs[0].size(), L = block_levels(R);
  s.blocked.assign(L, 0.0);
  for (const auto& x : xs) {
    for (double v : x) each.add(v);
    s.averages.add(row_average(x.data(), R));
    for (std::uint64_t l = 0; l < L; ++l) s.blocked[l] += blocked_variance(x.data(), R, 1u << l);
  }
  s.samples = R * xs.size();
  s.all = each.stats(s.samples);
  return s;
}
}  // namespace

// AR(1): 2 tau_int = (1 + phi)/(1 - phi) (tau_int = sigma^2 S / (2 variance) in rows). At block
// length B the expected blocked variance times R / variance is (1 + phi)/(1 - phi) -
// 2 phi (1 - phi^B) / (B (1 - phi)^2) exactly (stationary start); its relative standard deviation
// is sqrt(2 / (blocks - N)) over the pooled blocks: the test allows 4 of them.
TEST(StatsBlocking, Ar1TauIntWithinItsInterval) {
  const double phi = 0.5;
  const int N = 4;
  const std::uint64_t R = 8192;
  const Sums s = sums_of(ar1(N, R, phi));
  const SteadyStats b =
      steady_interval(SteadyEstimator::kBlocking, s.all, s.samples, N, R, s.averages, s.blocked);
  EXPECT_STREQ(b.estimator, "blocking");
  const double B = static_cast<double>(b.block_rows);
  EXPECT_GE(B, 16);  // the criterion passes tau_int ~ 1.5 by a margin
  const double expected = 0.5 * ((1 + phi) / (1 - phi) -
                                 2 * phi * (1 - std::pow(phi, B)) / (B * (1 - phi) * (1 - phi)));
  const double rel = std::sqrt(2.0 / (N * (R / b.block_rows) - N));
  // all.variance is itself an estimate, of relative error ~ sqrt(2 * 2 tau / S): negligible here.
  EXPECT_NEAR(b.tau_int, expected, 4 * rel * expected) << "B = " << B;
  EXPECT_NEAR(b.effective_samples, s.samples / (2 * b.tau_int), 1e-9 * b.effective_samples);
  EXPECT_DOUBLE_EQ(b.dof, N * (static_cast<double>(R) / B - 1));
  EXPECT_DOUBLE_EQ(b.ci, confidence_factor(b.dof) * b.sigma);
  // Independent rows (phi = 0): tau_int = 1/2.
  const Sums w = sums_of(ar1(N, R, 0.0));
  const SteadyStats i =
      steady_interval(SteadyEstimator::kBlocking, w.all, w.samples, N, R, w.averages, w.blocked);
  EXPECT_NEAR(i.tau_int, 0.5, 4 * std::sqrt(2.0 / (N * (R / i.block_rows) - N)) * 0.5);
}

// Many ensembles: the spread of their averages; its sigma^2 estimates the same variance of the
// mean, with relative standard deviation sqrt(2 / (N - 1)).
TEST(StatsBlocking, Ar1EnsemblesEstimatorAgrees) {
  const double phi = 0.5;
  const int N = 64;
  const std::uint64_t R = 1024;
  const Sums s = sums_of(ar1(N, R, phi));
  const SteadyStats e =
      steady_interval(SteadyEstimator::kEnsembles, s.all, s.samples, N, R, s.averages, {});
  EXPECT_STREQ(e.estimator, "ensembles");
  EXPECT_EQ(e.dof, N - 1);
  EXPECT_DOUBLE_EQ(e.sigma, std::sqrt(variance_of_mean(s.averages, N)));
  const double expected = 0.5 * ((1 + phi) / (1 - phi) -
                                 2 * phi * (1 - std::pow(phi, R)) / (R * (1 - phi) * (1 - phi)));
  EXPECT_NEAR(e.tau_int, expected, 4 * std::sqrt(2.0 / (N - 1)) * expected);
  EXPECT_EQ(e.ci, kLambdaP * e.sigma);  // 63 degrees of freedom: lambda_p
}

TEST(StatsBlocking, SteadyIntervalEdgeCases) {
  Moments2 one;
  one.add(2.0);
  const MeanCi all{2.0, 0.25, kLambdaP * 0.05};
  // Independent: sigma from all samples, the ci as given.
  const SteadyStats i = steady_interval(SteadyEstimator::kIndependent, all, 100, 1, 100, one, {});
  EXPECT_STREQ(i.estimator, "independent");
  EXPECT_DOUBLE_EQ(i.sigma, 0.05);
  EXPECT_EQ(i.ci, all.ci);
  EXPECT_EQ(i.tau_int, 0.5);
  EXPECT_TRUE(std::isinf(i.dof));
  // No samples: independent whatever was asked, sigma 0.
  const SteadyStats none = steady_interval(SteadyEstimator::kEnsembles, MeanCi{}, 0, 0, 0, one, {});
  EXPECT_STREQ(none.estimator, "independent");
  EXPECT_EQ(none.sigma, 0.0);
  // One ensemble: no spread, sigma and tau_int NaN.
  const SteadyStats n1 = steady_interval(SteadyEstimator::kEnsembles, all, 100, 1, 100, one, {});
  EXPECT_TRUE(std::isnan(n1.sigma) && std::isnan(n1.ci) && std::isnan(n1.tau_int));
  EXPECT_EQ(n1.dof, 0.0);
  // Two ensembles: one degree of freedom, the Cauchy quantile.
  Moments2 two;
  two.add(1.0);
  two.add(3.0);
  const SteadyStats n2 = steady_interval(SteadyEstimator::kEnsembles, all, 100, 2, 50, two, {});
  EXPECT_DOUBLE_EQ(n2.sigma, 1.0);  // sample variance 2, / 2
  EXPECT_EQ(n2.dof, 1.0);
  EXPECT_EQ(n2.ci, confidence_factor(1) * 1.0);
  // Zero variance everywhere: sigma 0, tau_int 1/2, every sample effective.
  Moments2 flat;
  flat.add(2.0);
  flat.add(2.0);
  const SteadyStats z =
      steady_interval(SteadyEstimator::kEnsembles, MeanCi{2.0, 0.0, 0.0}, 100, 2, 50, flat, {});
  EXPECT_EQ(z.sigma, 0.0);
  EXPECT_EQ(z.tau_int, 0.5);
  EXPECT_EQ(z.effective_samples, 100.0);
  EXPECT_THROW(steady_interval(SteadyEstimator::kBlocking, all, 100, 2, 50, two, {}),
               std::invalid_argument);
}
