// Moments and histograms of a known particle system (GRW05 eqs. 9-13, 37; RW05 eq. 29).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

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

TEST(Observables, SpeedMomentsOfAHandComputedSystemAreExact) {
  // c = v - V in {(3,0,0), (-1,2,0), (-2,-2,0), 0}: |c|^2 = 9, 5, 8, 0 and sum c = 0, so
  // <|c|^{2p}> = (9^p + 5^p + 8^p) / 4, every term an integer below 2^53 up to p = 16.
  const Vec3 V{0.5, -1, 2};
  const Vec3 c[4] = {{3, 0, 0}, {-1, 2, 0}, {-2, -2, 0}, {0, 0, 0}};
  Particles p(4);
  for (int j = 0; j < 4; ++j) p[j].v = c[j] + V;
  double moments[kMaxMoments];
  const Observation o = measure(p, moments);
  double a = 1, b = 1, d = 1;
  for (int k = 0; k < kMaxMoments; ++k) {
    a *= 9, b *= 5, d *= 8;
    EXPECT_EQ(moments[k], (a + b + d) / 4) << moment_name(k + 1);
  }
  EXPECT_EQ(moment_name(16), "moment_32");
  // p = 1 and 2 are the temperature and the fourth moment of the fixed observables.
  EXPECT_EQ(moments[0], 3 * o[4]);
  EXPECT_DOUBLE_EQ(moments[1], o[17] + 15 * o[4] * o[4]);
  // Asking for the speed moments leaves every other observable bit for bit as it was.
  const Observation plain = measure(p);
  for (int k = 0; k < kNumScalars; ++k) EXPECT_EQ(o[k], plain[k]) << k;
  double fewer[3];
  measure(p, fewer);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(fewer[k], moments[k]);
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
  radial_histogram(p, HistogramSpec{3, 3.0}, Vec3{}, counts);
  EXPECT_EQ(counts[0], 1u);
  EXPECT_EQ(counts[1], 1u);
  EXPECT_EQ(counts[2], 1u);
  EXPECT_EQ(counts[3], 2u);
}

TEST(Observables, RadialHistogramAboutTheBulkVelocityOrTheOrigin) {
  Particles p(3);
  const Vec3 V{0.5, -2.0, 1.0};
  p[0].v = V + Vec3{0.1, 0, 0};  // |v - V| in shell 0, |v| = 2.3 in shell 2
  p[1].v = V + Vec3{0, 1.5, 0};  // |v - V| in shell 1, |v| = 1.1 in shell 1
  p[2].v = V + Vec3{0, 0, 2.5};  // |v - V| in shell 2, |v| = 3.8: overflow
  std::uint64_t bulk[4] = {0, 0, 0, 0}, origin[4] = {0, 0, 0, 0};
  HistogramSpec spec{3, 3.0};
  radial_histogram(p, spec, V, bulk);
  spec.bulk = false;
  radial_histogram(p, spec, V, origin);
  EXPECT_EQ(std::vector<std::uint64_t>(bulk, bulk + 4), (std::vector<std::uint64_t>{1, 1, 1, 0}));
  EXPECT_EQ(std::vector<std::uint64_t>(origin, origin + 4),
            (std::vector<std::uint64_t>{0, 1, 1, 1}));
}

TEST(Observables, ComponentHistogramBinsAndOverflow) {
  const HistogramSpec spec{4, 2.0};  // bins of width 1 over (-2, 2); |x| >= 2 overflows
  EXPECT_EQ(component_bin(-2.0, spec), 4u);
  EXPECT_EQ(component_bin(std::nextafter(-2.0, 0.0), spec), 0u);
  EXPECT_EQ(component_bin(-1.5, spec), 0u);
  EXPECT_EQ(component_bin(-0.0, spec), 2u);
  EXPECT_EQ(component_bin(0.999, spec), 2u);
  EXPECT_EQ(component_bin(1.0, spec), 3u);
  EXPECT_EQ(component_bin(std::nextafter(2.0, 0.0), spec), 3u);
  EXPECT_EQ(component_bin(2.0, spec), 4u);
  EXPECT_EQ(component_bin(-7.0, spec), 4u);
  EXPECT_EQ(component_bin(std::nan(""), spec), 4u);
  Particles p(2);
  const Vec3 V{1.0, 5.0, 5.0};
  p[0].v = {0.5, 0, 0};  // x - V_x = -0.5: bin 1
  p[1].v = {3.5, 0, 0};  // 2.5: overflow
  std::uint64_t counts[5] = {0, 0, 0, 0, 0};
  component_histogram(p, spec, V, counts);
  EXPECT_EQ(std::vector<std::uint64_t>(counts, counts + 5),
            (std::vector<std::uint64_t>{0, 1, 0, 0, 1}));
}
