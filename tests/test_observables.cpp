// Moments and histograms of a known particle system (GRW05 eqs. 9-13, 37; RW05 eq. 29).
#include <gtest/gtest.h>

#include <cmath>

#include "granboltz/dsmc/observables.hpp"
#include "granboltz/random/rng.hpp"
#include "granboltz/random/samplers.hpp"

using namespace granboltz;

TEST(Observables, MomentsOfTwoParticlesAreExact) {
  // v = +-(1, 0, 0) + V: T = 1/3, P = diag(1, 0, 0), q = 0, int |c|^4 = 1.
  Particles p(2);
  p[0].v = {3, 1, 1};
  p[1].v = {1, 1, 1};
  const Observation o = measure(p);
  EXPECT_DOUBLE_EQ(o[0], 1.0);
  EXPECT_DOUBLE_EQ(o[1], 2.0);
  EXPECT_DOUBLE_EQ(o[2], 1.0);
  EXPECT_DOUBLE_EQ(o[4], 1.0 / 3.0);
  EXPECT_DOUBLE_EQ(o[5], 1.0);  // P_xx
  EXPECT_DOUBLE_EQ(o[9], 0.0);  // P_yy
  EXPECT_DOUBLE_EQ(o[14], 0.0);
  EXPECT_DOUBLE_EQ(o[17], 1.0 - 15.0 / 9.0);
  EXPECT_DOUBLE_EQ(o[19], 1.0 / 3.0 + (4.0 + 1.0 + 1.0) / 3.0);
}

TEST(Observables, CritIsZeroForAMaxwellianAndPositiveOtherwise) {
  const double P[9] = {2, 0, 0, 0, 2, 0, 0, 0, 2}, q[3] = {0, 0, 0};
  EXPECT_DOUBLE_EQ(crit(2.0, P, q, 0.0), 0.0);
  // Anisotropic pressure: ||P - pI||_F^2 = 2 (diag(3, 1, 2) - 2), Crit = sqrt(1)/2.
  const double A[9] = {3, 0, 0, 0, 1, 0, 0, 0, 2};
  EXPECT_DOUBLE_EQ(crit(2.0, A, q, 0.0), 0.5);
}

TEST(Observables, LargeMaxwellianSampleHasMaxwellianMoments) {
  Engine e = make_stream(21, 0, Consumer::kInitial);
  Particles p(400000);
  for (auto& q : p) q.v = std::sqrt(2.0) * normal3(e);
  const Observation o = measure(p);
  const double n = static_cast<double>(p.size());
  EXPECT_NEAR(o[4], 2.0, 4 * 2.0 * std::sqrt(2.0 / (3 * n)));  // Var T = 2 T^2 / (3 n)
  // int |c|^4 has variance E|c|^8 - (15 T^2)^2 = (945 - 225) T^4 per particle.
  EXPECT_NEAR(o[17], 0.0, 5 * std::sqrt(720.0 * 16 / n));
  EXPECT_LT(o[18], 0.02);
}

TEST(Observables, RadialHistogramCountsShellsAndOverflow) {
  Particles p(5);
  p[0].v = {0.1, 0, 0};   // shell 0 of [0, 1)
  p[1].v = {0, 1.0, 0};   // r = 1 starts shell 1
  p[2].v = {0, 0, 2.5};   // shell 2
  p[3].v = {3, 0, 0};     // r = R: overflow
  p[4].v = {10, 10, 10};  // overflow
  std::uint64_t counts[4] = {0, 0, 0, 0};
  radial_histogram(p, HistogramSpec{3, 3.0}, counts);
  EXPECT_EQ(counts[0], 1u);
  EXPECT_EQ(counts[1], 1u);
  EXPECT_EQ(counts[2], 1u);
  EXPECT_EQ(counts[3], 2u);
}
