// The delta method of stats/delta_method.hpp against closed forms computed by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "granboltz/stats/delta_method.hpp"

using namespace granboltz;

namespace {
Moments2 sums(const std::vector<double>& v) {
  Moments2 m;
  for (double x : v) m.add(x);
  return m;
}
Moments2 cross_sum(const std::vector<double>& x, const std::vector<double>& y) {
  Moments2 m;
  for (std::size_t i = 0; i < x.size(); ++i) m.sum.add(x[i] * y[i]);
  return m;
}
}  // namespace

// x = (1, 2, 3), y = (2, 2, 5): means 2, 3; population V_x = 2/3, V_y = 2, C_xy = 1; r = 2/3.
TEST(StatsDelta, RatioOfMeansIsTheClosedForm) {
  const std::vector<double> x{1, 2, 3}, y{2, 2, 5};
  const RatioStats p = ratio_of_means(2.0, 3.0, sums(x), sums(y), cross_sum(x, y), 3, false);
  EXPECT_DOUBLE_EQ(p.mean, 2.0 / 3.0);
  // Rounding of the cancelling terms: a few ulps of the largest.
  EXPECT_NEAR(p.variance, 2.0 / 243.0, 1e-15);  // (2/3 - 4/3 + 8/9) / (9 * 3)
  EXPECT_NEAR(p.bias, 1.0 / 81.0, 1e-15);       // (4/3 - 1) / 27
  // Sample (co)variances, times 3/2: V_x = 1, V_y = 3, C_xy = 3/2.
  const RatioStats s = ratio_of_means(2.0, 3.0, sums(x), sums(y), cross_sum(x, y), 3, true);
  EXPECT_NEAR(s.variance, 1.0 / 81.0, 1e-15);  // (1 - 2 + 4/3) / 27
  EXPECT_NEAR(s.bias, 1.0 / 54.0, 1e-15);      // (2 - 3/2) / 27
}

TEST(StatsDelta, RatioWithAZeroNumeratorIsZeroNotNaN) {
  const std::vector<double> x{0, 0, 0}, y{1, 2, 3};
  const RatioStats r = ratio_of_means(0.0, 2.0, sums(x), sums(y), cross_sum(x, y), 3, true);
  EXPECT_EQ(r.mean, 0.0);
  EXPECT_EQ(r.variance, 0.0);
  EXPECT_EQ(r.bias, 0.0);
}

TEST(StatsDelta, CrossPairsOfTheSpeedMoments) {
  EXPECT_EQ(cross_pairs(0), 0u);
  EXPECT_EQ(cross_pairs(1), 0u);
  EXPECT_EQ(cross_pairs(2), 1u);
  EXPECT_EQ(cross_pairs(3), 3u);
  EXPECT_EQ(cross_pairs(5), 3u);
  Moments2 out[3];
  const double M[3] = {2, 3, 5};
  add_cross(out, M, 3);
  EXPECT_EQ(out[0].sum.value(), 6.0);
  EXPECT_EQ(out[1].sum.value(), 10.0);
  EXPECT_EQ(out[2].sum.value(), 15.0);
  EXPECT_EQ(out[0].sum_sq.value(), 0.0);  // only `sum` is used
}

// A Maxwellian has a2 = a3 = 0: M2 = d T, M4 = d (d + 2) T^2, M6 = d (d + 2) (d + 4) T^3. With
// every sample equal, the variances and biases vanish.
TEST(StatsDelta, SonineOfAMaxwellianIsZeroInBothDimensions) {
  for (int d : {2, 3}) {
    const double T = 1.7, M[3] = {d * T, d * (d + 2) * T * T, d * (d + 2) * (d + 4) * T * T * T};
    Moments2 m[3], c[3];
    for (int i = 0; i < 4; ++i) {
      for (int p = 0; p < 3; ++p) m[p].add(M[p]);
      add_cross(c, M, 3);
    }
    const Sonine s = sonine(m, c, 3, 4, true, d);
    EXPECT_NEAR(s.a2, 0.0, 1e-14) << d;
    EXPECT_NEAR(s.a3, 0.0, 1e-14) << d;
    EXPECT_NEAR(s.var_a2, 0.0, 1e-24) << d;
    EXPECT_NEAR(s.var_a3, 0.0, 1e-24) << d;
    EXPECT_NEAR(s.bias_a2, 0.0, 1e-14) << d;
    EXPECT_NEAR(s.bias_a3, 0.0, 1e-14) << d;
  }
}

// For samples close to a point the map (M2, M4, M6) -> a2, a3 is linear, so the delta-method
// variance must be the variance of the samples' own a2, a3 over N, to relative O(epsilon).
TEST(StatsDelta, SonineVarianceIsThatOfTheLinearisedMap) {
  const int d = 3, N = 5;
  const double eps = 1e-6;
  const double e2[N] = {1, -2, 0.5, 0.3, 0.2}, e4[N] = {-1, 0.4, 2, -0.7, 0.1},
               e6[N] = {0.3, 1, -1.5, 0.2, 0.9};
  Moments2 m[3], c[3];
  std::vector<double> a2, a3;
  for (int i = 0; i < N; ++i) {
    const double M[3] = {3 + eps * e2[i], 15 + eps * e4[i], 105 + eps * e6[i]};
    for (int p = 0; p < 3; ++p) m[p].add(M[p]);
    add_cross(c, M, 3);
    const double x2 = 3.0 / 5.0 * M[1] / (M[0] * M[0]) - 1;
    a2.push_back(x2);
    a3.push_back(1 + 3 * x2 - 9.0 / 35.0 * M[2] / (M[0] * M[0] * M[0]));
  }
  auto var_of_mean = [&](const std::vector<double>& a) {  // sample variance / N
    double mu = 0, ss = 0;
    for (double v : a) mu += v / N;
    for (double v : a) ss += (v - mu) * (v - mu);
    return ss / (N - 1) / N;
  };
  const Sonine s = sonine(m, c, 3, N, true, d);
  // The sums' cancellation leaves ~1e-16 / eps^2 relative noise in the covariance.
  EXPECT_NEAR(s.var_a2 / var_of_mean(a2), 1.0, 1e-3);
  EXPECT_NEAR(s.var_a3 / var_of_mean(a3), 1.0, 1e-3);
  const Sonine p = sonine(m, c, 3, N, false, d);
  EXPECT_NEAR(p.var_a2 / s.var_a2, (N - 1.0) / N, 1e-12);  // population against sample covariance
}

// Two moments only (P = 2): a3 stays 0 and cross sums of one pair are enough.
TEST(StatsDelta, SonineWithTwoMomentsHasNoA3) {
  Moments2 m[2], c[1];
  for (double T : {1.0, 2.0}) {
    const double M[2] = {3 * T, 15 * T * T * 1.1};
    m[0].add(M[0]);
    m[1].add(M[1]);
    add_cross(c, M, 2);
  }
  const Sonine s = sonine(m, c, 2, 2, true, 3);
  // Means M2 = 4.5, M4 = 15 * 1.1 * 2.5 = 41.25: a2 = 3/5 * 41.25 / 20.25 - 1.
  EXPECT_NEAR(s.a2, 0.6 * 41.25 / 20.25 - 1, 1e-15);
  EXPECT_EQ(s.a3, 0.0);
  EXPECT_EQ(s.var_a3, 0.0);
  EXPECT_GT(s.var_a2, 0.0);
}
