// The collision map (GRW05 eq. 4) and the white-noise kick (eq. 23).
#include <gsl/gsl_cdf.h>
#include <gtest/gtest.h>

#include <cfloat>

#include "granboltz/physics/collision.hpp"
#include "granboltz/physics/heating.hpp"
#include "granboltz/random/rng.hpp"
#include "granboltz/random/samplers.hpp"
#include "test_support.hpp"

using namespace granboltz;

TEST(CollisionMap, ConservesMomentumToRoundOffInEveryCollision) {
  Engine e = make_stream(11, 0, Consumer::kEvents);
  for (double alpha : {0.1, 0.5, 0.9, 1.0}) {
    for (int i = 0; i < 100000; ++i) {
      Vec3 v = 3.0 * normal3(e), w = 3.0 * normal3(e);
      const Vec3 before = v + w;
      const double scale = norm(v) + norm(w);
      collide(v, w, unit_vector(e), alpha);
      const Vec3 d = (v + w) - before;
      ASSERT_LE(norm(d), 8 * DBL_EPSILON * scale) << "alpha = " << alpha;
    }
  }
}

TEST(CollisionMap, ChangesEnergyByExactlyTheInelasticLoss) {
  // |v'|^2 + |w'|^2 - |v|^2 - |w|^2 = -(1 - alpha^2)/4 (1 - mu) |u|^2 (GRW05 §2).
  Engine e = make_stream(12, 0, Consumer::kEvents);
  for (double alpha : {0.1, 0.5, 0.9, 1.0}) {
    for (int i = 0; i < 100000; ++i) {
      Vec3 v = normal3(e), w = 2.0 * normal3(e);
      const Vec3 dir = unit_vector(e);
      const double expected = energy_change(v, w, dir, alpha);
      const double before = norm2(v) + norm2(w);
      collide(v, w, dir, alpha);
      const double change = norm2(v) + norm2(w) - before;
      ASSERT_NEAR(change, expected, 16 * DBL_EPSILON * before) << "alpha = " << alpha;
    }
  }
}

TEST(CollisionMap, ElasticCollisionKeepsTheRelativeSpeed) {
  Engine e = make_stream(13, 0, Consumer::kEvents);
  Vec3 v = normal3(e), w = normal3(e);
  const double u = norm(v - w);
  collide(v, w, unit_vector(e), 1.0);
  EXPECT_NEAR(norm(v - w), u, 1e-14);
}

TEST(WhiteNoiseKick, PairedKicksHaveVariance2BetaSAndAreUncorrelated) {
  Engine e = make_stream(15, 0, Consumer::kSweep);
  const double beta = 0.8, sa = 0.5, sb = 2.0;
  const int n = 200000;
  double saa = 0, sbb = 0, sab = 0;
  for (int i = 0; i < n; ++i) {
    Vec3 a{0, 0, 0}, b{1, 1, 1};
    white_noise_kick2(a, sa, b, sb, beta, e);
    b = b - Vec3{1, 1, 1};
    saa += norm2(a);
    sbb += norm2(b);
    sab += dot(a, b);
  }
  // Sums of 3n squared normals: relative sd sqrt(2 / (3n)).
  const double z = test::family_z(3), rel = std::sqrt(2.0 / (3 * n));
  EXPECT_NEAR(saa / (3 * n), 2 * beta * sa, z * rel * 2 * beta * sa);
  EXPECT_NEAR(sbb / (3 * n), 2 * beta * sb, z * rel * 2 * beta * sb);
  EXPECT_NEAR(sab / (3 * n), 0.0, z * 2 * beta * std::sqrt(sa * sb / (3.0 * n)));
}

TEST(WhiteNoiseKick, HasVariance2BetaSPerComponent) {
  // The sample variance of n kicks: (n-1) S^2 / sigma^2 ~ chi^2_{n-1}.
  Engine e = make_stream(14, 0, Consumer::kSweep);
  const double beta = 1.7, s = 0.3, sigma2 = 2 * beta * s;
  const int n = 200000;
  double sum[3] = {0, 0, 0}, sum2[3] = {0, 0, 0};
  for (int i = 0; i < n; ++i) {
    const Vec3 k = white_noise_kick(Vec3{1, -2, 3}, beta, s, e) - Vec3{1, -2, 3};
    const double c[3] = {k.x, k.y, k.z};
    for (int a = 0; a < 3; ++a) {
      sum[a] += c[a];
      sum2[a] += c[a] * c[a];
    }
  }
  for (int a = 0; a < 3; ++a) {
    const double mean = sum[a] / n;
    const double var = (sum2[a] - n * mean * mean) / (n - 1);
    const double stat = (n - 1) * var / sigma2;
    EXPECT_GT(stat, gsl_cdf_chisq_Pinv(0.0005 / 3, n - 1)) << "component " << a;
    EXPECT_LT(stat, gsl_cdf_chisq_Qinv(0.0005 / 3, n - 1)) << "component " << a;
    EXPECT_LT(std::fabs(mean), test::family_z(3) * std::sqrt(sigma2 / n));
  }
}
