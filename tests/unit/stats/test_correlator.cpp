// The multiple-tau correlator (stats/correlator.hpp): level 0 against the brute-force correlation
// bit for bit, the higher levels against the brute-force correlation of the block-averaged
// signal bit for bit, an AR(1) signal against its exact block-averaged correlation within the
// replicas' interval, and save/restore.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <stdexcept>
#include <vector>

#include "granboltz/stats/correlator.hpp"

namespace granboltz {
namespace {

using Series = std::vector<std::vector<double>>;  // [t][c]

Series random_series(std::uint64_t T, std::uint64_t C, unsigned seed) {
  std::mt19937_64 g(seed);
  std::normal_distribution<double> z;
  Series x(T, std::vector<double>(C));
  for (auto& row : x)
    for (auto& v : row) v = z(g);
  return x;
}

MultipleTauCorrelator feed(const Series& x, MultipleTauCorrelator::Resolution r) {
  MultipleTauCorrelator c(x[0].size(), r);
  for (const auto& row : x) c.add(row);
  return c;
}

// Every m values of one level averaged into the next, as the correlator does it.
Series coarsen(const Series& y, unsigned m) {
  Series out;
  const std::size_t C = y[0].size();
  for (std::size_t b = 0; (b + 1) * m <= y.size(); ++b) {
    std::vector<double> s(C, 0.0);
    for (unsigned a = 0; a < m; ++a)
      for (std::size_t c = 0; c < C; ++c) s[c] += y[b * m + a][c];
    for (double& v : s) v /= static_cast<double>(m);
    out.push_back(s);
  }
  return out;
}

TEST(Correlator, EveryLevelIsTheBruteForceCorrelationOfItsBlockAveragesBitForBit) {
  const MultipleTauCorrelator::Resolution r{8, 2, 5};
  // Seven channels: four partial sums over the first four, the rest into the first (the
  // correlator's fixed order of the products, checked here bit for bit).
  const std::size_t C = 7;
  const Series x = random_series(1001, C, 7);
  const auto c = feed(x, r);
  const auto lags = c.lags();
  const auto corr = c.correlation();
  const auto origins = c.origins();
  ASSERT_EQ(lags.size(), MultipleTauCorrelator::lag_count(r));
  std::size_t i = 0;
  Series y = x;
  std::uint64_t unit = 1;
  for (unsigned k = 0; k < r.levels; ++k, unit *= r.averaging) {
    if (k > 0) y = coarsen(y, r.averaging);
    for (unsigned j = k == 0 ? 0 : r.points / r.averaging; j < r.points; ++j, ++i) {
      ASSERT_EQ(lags[i], j * unit);
      double sum = 0.0;
      std::uint64_t n = 0;
      for (std::size_t t = j; t < y.size(); ++t) {
        double part[4] = {0.0, 0.0, 0.0, 0.0};
        for (std::size_t ch = 0; ch < C; ++ch) part[ch < 4 ? ch : 0] += y[t][ch] * y[t - j][ch];
        sum += (part[0] + part[1]) + (part[2] + part[3]);
        ++n;
      }
      ASSERT_EQ(origins[i], n) << "level " << k << " lag " << j;
      if (n == 0) {
        EXPECT_TRUE(std::isnan(corr[i]));
        continue;
      }
      EXPECT_EQ(corr[i], sum / (static_cast<double>(n) * static_cast<double>(C)))
          << "level " << k << " lag " << j;
    }
  }
  EXPECT_EQ(i, lags.size());
  EXPECT_EQ(lags.back(), 7u * 16u);
  EXPECT_EQ(MultipleTauCorrelator::longest_lag(r), 7.0 * 16.0);
}

// x_{t+1} = phi x_t + sqrt(1 - phi^2) xi: <x_0 x_tau> = phi^|tau|. The block means of B samples
// correlate at block lag j as (1/B^2) sum_{a,a'} phi^|j B + a - a'|: what level k estimates.
double ar1_block_correlation(double phi, std::uint64_t B, std::uint64_t j) {
  double s = 0.0;
  for (std::uint64_t a = 0; a < B; ++a)
    for (std::uint64_t b = 0; b < B; ++b)
      s += std::pow(phi, std::fabs(static_cast<double>(j * B + a) - static_cast<double>(b)));
  return s / static_cast<double>(B * B);
}

TEST(Correlator, AnAr1SignalMatchesItsExactBlockCorrelationWithinTheReplicasInterval) {
  const double phi = 0.9;
  const MultipleTauCorrelator::Resolution r{16, 2, 8};
  const int replicas = 24;
  const std::uint64_t T = 1 << 14, C = 4;
  const std::size_t L = MultipleTauCorrelator::lag_count(r);
  std::vector<double> s1(L, 0.0), s2(L, 0.0);
  std::mt19937_64 g(2024);
  std::normal_distribution<double> z;
  for (int rep = 0; rep < replicas; ++rep) {
    MultipleTauCorrelator c(C, r);
    std::vector<double> x(C);
    for (auto& v : x) v = z(g);  // stationary from the start
    for (std::uint64_t t = 0; t < T; ++t) {
      c.add(x);
      for (auto& v : x) v = phi * v + std::sqrt(1 - phi * phi) * z(g);
    }
    const auto corr = c.correlation();
    for (std::size_t i = 0; i < L; ++i) s1[i] += corr[i], s2[i] += corr[i] * corr[i];
  }
  // Family-wise level 0.999 over the lags (Bonferroni): |z| < 4.5 for 112 lags.
  const auto lags = MultipleTauCorrelator(C, r).lags();
  std::size_t i = 0;
  std::uint64_t unit = 1;
  for (unsigned k = 0; k < r.levels; ++k, unit *= r.averaging)
    for (unsigned j = k == 0 ? 0 : r.points / r.averaging; j < r.points; ++j, ++i) {
      const double mean = s1[i] / replicas;
      const double se = std::sqrt((s2[i] / replicas - mean * mean) / (replicas - 1));
      const double exact = ar1_block_correlation(phi, unit, j);
      EXPECT_LT(std::fabs(mean - exact), 4.5 * se + 1e-15)
          << "lag " << lags[i] << ": " << mean << " +- " << se << " against " << exact;
    }
}

TEST(Correlator, ARestoredStateContinuesBitForBit) {
  const MultipleTauCorrelator::Resolution r{8, 4, 4};
  const Series x = random_series(700, 2, 11);
  const auto whole = feed(x, r);
  MultipleTauCorrelator first(2, r);
  for (std::size_t t = 0; t < 333; ++t) first.add(x[t]);
  MultipleTauCorrelator second(2, r, first.state());
  for (std::size_t t = 333; t < x.size(); ++t) second.add(x[t]);
  const auto a = whole.correlation(), b = second.correlation();
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i)
    if (!std::isnan(a[i])) EXPECT_EQ(a[i], b[i]) << "lag " << i;
  EXPECT_EQ(whole.origins(), second.origins());
}

TEST(Correlator, RefusesABadResolutionSampleOrStateNamingIt) {
  auto message = [](auto f) {
    try {
      f();
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message([] {
              MultipleTauCorrelator(1, {7, 2, 3});
            }).find("points = 7"),
            std::string::npos);
  EXPECT_NE(message([] {
              MultipleTauCorrelator(1, {8, 3, 3});
            }).find("averaging = 3"),
            std::string::npos);
  EXPECT_NE(message([] {
              MultipleTauCorrelator(1, {8, 2, 0});
            }).find("levels = 0"),
            std::string::npos);
  EXPECT_NE(message([] {
              MultipleTauCorrelator(1, {8, 2, 70});
            }).find("levels = 70"),
            std::string::npos);
  EXPECT_NE(message([] {
              MultipleTauCorrelator(0, {8, 2, 3});
            }).find("channel"),
            std::string::npos);
  EXPECT_NE(message([] {
              MultipleTauCorrelator c(3, {8, 2, 3});
              c.add(std::vector<double>(2));
            }).find("a sample of 2 values"),
            std::string::npos);
  const MultipleTauCorrelator::Resolution r{8, 2, 3};
  const auto good = feed(random_series(50, 2, 3), r).state();
  auto bad = good;
  bad.fill[1] = 9;
  EXPECT_NE(message([&] { MultipleTauCorrelator(2, r, bad); }).find("filled beyond"),
            std::string::npos);
  bad = good;
  bad.in_block[0] = 2;
  EXPECT_NE(message([&] { MultipleTauCorrelator(2, r, bad); }).find("block"), std::string::npos);
  bad = good;
  bad.shift[4] = std::nan("");
  EXPECT_NE(message([&] { MultipleTauCorrelator(2, r, bad); }).find("non-finite"),
            std::string::npos);
  bad = good;
  bad.sum.pop_back();
  EXPECT_NE(message([&] { MultipleTauCorrelator(2, r, bad); }).find("wrong size"),
            std::string::npos);
  EXPECT_NO_THROW(MultipleTauCorrelator(2, r, good));
}

}  // namespace
}  // namespace granboltz
