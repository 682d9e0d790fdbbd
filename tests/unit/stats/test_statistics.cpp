// The Student factor and the variance of a mean (stats/statistics.hpp) against GSL's quantiles and
// closed forms.
#include <gsl/gsl_cdf.h>
#include <gtest/gtest.h>

#include <cmath>

#include "granboltz/stats/statistics.hpp"

using namespace granboltz;

// The two-sided level of lambda_p = 3.2 for a normal: P = Phi(3.2).
TEST(StatsConfidence, StudentFactorIsGslsQuantileBelowThirtyDegrees) {
  const double P = gsl_cdf_ugaussian_P(kLambdaP);
  for (int dof = 1; dof < 30; ++dof)
    EXPECT_NEAR(confidence_factor(dof), gsl_cdf_tdist_Pinv(P, dof),
                1e-9 * gsl_cdf_tdist_Pinv(P, dof))
        << dof;
  // Closed forms: nu = 1 (Cauchy) tan(pi (P - 1/2)); nu = 2 (2P - 1) / sqrt(2 P (1 - P)).
  EXPECT_NEAR(confidence_factor(1), std::tan(M_PI * (P - 0.5)), 1e-9 * confidence_factor(1));
  EXPECT_NEAR(confidence_factor(2), (2 * P - 1) / std::sqrt(2 * P * (1 - P)),
              1e-9 * confidence_factor(2));
  // Fractional degrees of freedom (blocking: N (R/B - 1)) are allowed.
  EXPECT_NEAR(confidence_factor(2.5), gsl_cdf_tdist_Pinv(P, 2.5), 1e-9 * confidence_factor(2.5));
}

TEST(StatsConfidence, StudentFactorFallsToLambdaP) {
  double last = INFINITY;
  for (int dof = 1; dof < 30; ++dof) {
    EXPECT_LT(confidence_factor(dof), last);
    EXPECT_GT(confidence_factor(dof), kLambdaP);
    last = confidence_factor(dof);
  }
  for (double dof :
       {30.0, 1e6, static_cast<double>(INFINITY), 0.0, 0.5, -1.0, static_cast<double>(NAN)})
    EXPECT_EQ(confidence_factor(dof), kLambdaP) << dof;
}

TEST(StatsConfidence, VarianceOfTheMeanIsTheSampleVarianceOverN) {
  Moments2 m;
  for (double x : {1.0, 2.0, 3.0}) m.add(x);
  EXPECT_DOUBLE_EQ(variance_of_mean(m, 3), 1.0 / 3.0);
  Moments2 two;
  for (double x : {1.0, 4.0}) two.add(x);
  EXPECT_DOUBLE_EQ(variance_of_mean(two, 2), 4.5 / 2.0);
  Moments2 same;
  for (int i = 0; i < 4; ++i) same.add(0.1);
  EXPECT_GE(variance_of_mean(same, 4), 0.0);  // rounding never makes it negative
  EXPECT_LT(variance_of_mean(same, 4), 1e-17);
  Moments2 one;
  one.add(5.0);
  EXPECT_TRUE(std::isnan(variance_of_mean(one, 1)));
  EXPECT_TRUE(std::isnan(variance_of_mean(Moments2{}, 0)));
}
