// Exact, order-independent summation: the basis of thread- and shard-independent statistics.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "granboltz/stats/exact_sum.hpp"

using granboltz::ExactSum;

TEST(ExactSum, KeepsWhatNaiveSummationLoses) {
  ExactSum s;
  for (double x : {1e16, 1.0, -1e16, 1e-300, 3.0}) s.add(x);
  EXPECT_EQ(s.value(), 4.0);  // 1e-300 is below half an ulp of 4
  ExactSum t;
  t.add(1e308);
  t.add(1e308);
  t.add(-1e308);
  EXPECT_EQ(t.value(), 1e308);  // the intermediate 2e308 would overflow a double
}

TEST(ExactSum, GivesBitIdenticalResultsInAnyOrder) {
  std::mt19937_64 g(1);
  std::vector<double> x(100000);
  std::lognormal_distribution<double> d(0, 8);
  for (auto& v : x) v = (g() & 1 ? -1 : 1) * d(g);
  ExactSum a;
  for (double v : x) a.add(v);
  std::shuffle(x.begin(), x.end(), g);
  ExactSum b, c;  // and split into two partial sums merged afterwards
  for (std::size_t i = 0; i < x.size(); ++i) (i % 3 ? b : c).add(x[i]);
  b.merge(c);
  EXPECT_EQ(a.value(), b.value());
  EXPECT_EQ(a.digits(), b.digits());
}

TEST(ExactSum, MatchesLongDoubleOnWellConditionedSums) {
  ExactSum s;
  long double ref = 0;
  for (int i = 1; i <= 10000; ++i) {
    const double v = 1.0 / i;
    s.add(v);
    ref += v;
  }
  EXPECT_NEAR(s.value(), static_cast<double>(ref), 1e-15);
}

TEST(ExactSum, RoundTripsThroughItsDigits) {
  ExactSum s;
  s.add(-3.25);
  s.add(1e-200);
  const ExactSum t = ExactSum::from_digits(s.digits());
  EXPECT_EQ(t.value(), s.value());
  EXPECT_EQ(t.digits(), s.digits());
}

TEST(ExactSum, RejectsNonFiniteValues) {
  ExactSum s;
  EXPECT_THROW(s.add(std::nan("")), std::domain_error);
  EXPECT_THROW(s.add(INFINITY), std::domain_error);
}
