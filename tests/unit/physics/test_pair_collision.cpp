// The collision of two particles with masses and rough surfaces (physics/pair_collision.hpp):
// every conservation law and restitution relation checked exactly, collision by collision, in
// d = 3 and d = 2, on random pairs of species.
#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <cstring>
#include <random>

#include "granboltz/physics/collision.hpp"
#include "granboltz/physics/pair_collision.hpp"

using namespace granboltz;

namespace {

constexpr double kTol = 1e-12;  // relative, at round-off for a handful of operations

struct Species {
  double m, sigma, kappa;
  double r() const { return 0.5 * sigma; }
  double inertia() const { return kappa * m * r() * r(); }
};

/// One random pair with its state before the collision.
struct Case {
  Species a, b;
  double eps, beta;
  PairTerms p;
  Vec3 va, wa, vb, wb, n;
};

class Draw {
 public:
  explicit Draw(std::uint64_t seed) : rng_(seed) {}
  double uniform(double lo, double hi) { return lo + (hi - lo) * u01_(rng_); }
  double gauss() { return gauss_(rng_); }
  Vec3 gauss_vec(int dim) { return {gauss(), gauss(), dim == 3 ? gauss() : 0.0}; }
  Vec3 unit(int dim) {
    for (;;) {
      const Vec3 x = gauss_vec(dim);
      const double r = norm(x);
      if (r > 1e-3) return (1.0 / r) * x;
    }
  }
  Species species() {
    // Masses log-uniform in [0.1, 10], so that mass ratios up to 100 occur; kappa in (0, 2/3].
    return {std::exp(uniform(std::log(0.1), std::log(10.0))), uniform(0.5, 2.0),
            (2.0 / 3.0) * (1.0 - u01_(rng_))};
  }
  /// An angular velocity of the size that gives I w^2 ~ m v^2 ~ 1: (0, 0, omega) in d = 2.
  Vec3 spin(const Species& s, int dim) {
    const double scale = 1.0 / (s.r() * std::sqrt(s.m * s.kappa));
    if (dim == 2) return {0.0, 0.0, scale * gauss()};
    return scale * gauss_vec(3);
  }
  /// A pair with eps in (0, 1] and beta in [-1, 1] unless given; n from impact_normal as in the
  /// engine (drawn again in the measure-zero case where it declines).
  Case pair(int dim, double eps = -2, double beta = -2) {
    Case c;
    c.a = species();
    c.b = species();
    c.eps = eps > -2 ? eps : 1.0 - u01_(rng_);
    c.beta = beta > -2 ? beta : uniform(-1.0, 1.0);
    c.p = pair_terms(c.a.m, c.b.m, c.a.sigma, c.b.sigma, c.beta, c.a.kappa, c.b.kappa);
    do {
      c.va = (1.0 / std::sqrt(c.a.m)) * gauss_vec(dim);
      c.vb = (1.0 / std::sqrt(c.b.m)) * gauss_vec(dim);
    } while (!impact_normal(c.va - c.vb, unit(dim), c.n));
    c.wa = spin(c.a, dim);
    c.wb = spin(c.b, dim);
    return c;
  }

 private:
  std::mt19937_64 rng_;
  std::uniform_real_distribution<double> u01_{0.0, 1.0};
  std::normal_distribution<double> gauss_{0.0, 1.0};
};

/// The velocity of a's surface minus b's at the contact point x_c = x_a + r_a n = x_b - r_b n,
/// from the rigid-body velocity v + w x (x_c - x), independently of the header's expression.
Vec3 contact_velocity(Vec3 va, Vec3 wa, Vec3 vb, Vec3 wb, Vec3 n, double r_a, double r_b) {
  return (va + cross(wa, r_a * n)) - (vb + cross(wb, (-r_b) * n));
}

double energy(const Case& c, Vec3 va, Vec3 wa, Vec3 vb, Vec3 wb) {
  return pair_energy(c.a.m, c.a.inertia(), va, wa, c.b.m, c.b.inertia(), vb, wb);
}

/// The k of 1/k = m_ab (r_a^2/I_a + r_b^2/I_b), from the moments of inertia themselves.
double k_of(const Case& c) {
  const double m_ab = c.a.m * c.b.m / (c.a.m + c.b.m);
  return 1.0 / (m_ab * (c.a.r() * c.a.r() / c.a.inertia() + c.b.r() * c.b.r() / c.b.inertia()));
}

/// The size of the velocities of a collision, before and after, for relative tolerances.
double speed_scale(const Case& c, const Case& after) {
  auto s = [](const Case& x) {
    return norm(x.va) + norm(x.vb) + x.a.r() * norm(x.wa) + x.b.r() * norm(x.wb);
  };
  return s(c) + s(after);
}

Case collided(const Case& c) {
  Case x = c;
  collide_rough(x.va, x.wa, x.vb, x.wb, x.n, x.eps, x.p);
  return x;
}

constexpr int kPairs = 4000;

/// The rounding of n near grazing impacts (u^ close to e): u^ - e is rounded by about
/// DBL_EPSILON, which turns n by DBL_EPSILON/|u^ - e|, and u.n, with u nearly normal to n, moves
/// by |u| times that. Inherent in taking n from e (the GRW05 map is as inexact there).
double grazing_error(Vec3 u, Vec3 e) {
  return 4 * DBL_EPSILON * norm(u) / norm((1.0 / norm(u)) * u - e);
}

}  // namespace

TEST(PairCollision, PairTermsFollowFromTheMomentsOfInertia) {
  Draw draw(1);
  for (int i = 0; i < kPairs; ++i) {
    const Case c = draw.pair(3);
    const double m_ab = c.a.m * c.b.m / (c.a.m + c.b.m), k = k_of(c);
    EXPECT_NEAR(c.p.mu_a, c.a.m / (c.a.m + c.b.m), 1e-15);
    EXPECT_NEAR(c.p.mu_a + c.p.mu_b, 1.0, 1e-15);
    EXPECT_EQ(c.p.r_a, 0.5 * c.a.sigma);
    EXPECT_EQ(c.p.r_b, 0.5 * c.b.sigma);
    EXPECT_NEAR(c.p.tangential, (1 + c.beta) * k / (1 + k), 1e-14);
    const double spin_a = m_ab * c.a.r() / c.a.inertia(), spin_b = m_ab * c.b.r() / c.b.inertia();
    EXPECT_NEAR(c.p.spin_a, spin_a, 1e-14 * spin_a);
    EXPECT_NEAR(c.p.spin_b, spin_b, 1e-14 * spin_b);
  }
  // Equal spheres: k = kappa, so t = (1+beta) kappa/(1+kappa) and spin = 1/(kappa sigma).
  const PairTerms eq = pair_terms(2.5, 2.5, 1.5, 1.5, 0.3, 0.4, 0.4);
  EXPECT_EQ(eq.mu_a, 0.5);
  EXPECT_EQ(eq.mu_b, 0.5);
  EXPECT_NEAR(eq.tangential, 1.3 * 0.4 / 1.4, 1e-15);
  EXPECT_NEAR(eq.spin_a, 1.0 / (0.4 * 1.5), 1e-14);
  EXPECT_NEAR(eq.spin_b, 1.0 / (0.4 * 1.5), 1e-14);
  // kappa <= 0 on either side: smooth.
  for (const PairTerms s :
       {pair_terms(1, 2, 1, 1, 0.5, 0.0, 0.4), pair_terms(1, 2, 1, 1, 0.5, 0.4, -1),
        pair_terms(1, 2, 1, 1, -1.0, 0.4, 0.4)}) {
    EXPECT_EQ(s.tangential, 0.0);
  }
}

TEST(PairCollision, ImpactNormalIsAUnitVectorFacingTheRelativeVelocity) {
  Draw draw(2);
  for (int dim : {3, 2}) {
    for (int i = 0; i < kPairs; ++i) {
      const Vec3 u = draw.uniform(0.01, 5.0) * draw.unit(dim), e = draw.unit(dim);
      Vec3 n;
      ASSERT_TRUE(impact_normal(u, e, n));
      EXPECT_GE(dot(u, n), 0.0);
      EXPECT_NEAR(norm(n), 1.0, 4e-16);
      // (u.n) n = (u - |u| e)/2: the normal GRW05's e stands for.
      const Vec3 d = dot(u, n) * n - 0.5 * (u - norm(u) * e);
      EXPECT_LE(norm(d), kTol * norm(u) + grazing_error(u, e));
      if (dim == 2) {
        EXPECT_EQ(n.z, 0.0);
      }
    }
  }
  // Nearly grazing, |u^ - e| ~ 1e-14 (n would be mostly rounding): declined. Just above the
  // threshold, 1e-7: taken, with u.n >= 0 and (u.n) n still (u - |u| e)/2.
  int taken = 0;
  for (int i = 0; i < kPairs; ++i) {
    const Vec3 u = draw.uniform(0.01, 5.0) * draw.unit(3), r = draw.unit(3);
    const Vec3 x = (1.0 / norm(u)) * u + 1e-14 * r, e = (1.0 / norm(x)) * x;
    const Vec3 y = (1.0 / norm(u)) * u + 1e-7 * r, e1 = (1.0 / norm(y)) * y;
    Vec3 n;
    ASSERT_FALSE(impact_normal(u, e, n));
    if (!impact_normal(u, e1, n)) continue;
    ++taken;
    ASSERT_GE(dot(u, n), 0.0);
    ASSERT_NEAR(norm(n), 1.0, 4e-16);
    const Vec3 d = dot(u, n) * n - 0.5 * (u - norm(u) * e1);
    ASSERT_LE(norm(d), kTol * norm(u) + grazing_error(u, e1));
  }
  EXPECT_GT(taken, kPairs / 2);
  Vec3 n{7, 7, 7};
  EXPECT_FALSE(impact_normal({0, 0, 0}, {1, 0, 0}, n));
  EXPECT_FALSE(impact_normal({3, 0, 0}, {1, 0, 0}, n));  // e = u^: no impact
  EXPECT_FALSE(impact_normal({0, 0.25, 0}, {0, 1, 0}, n));
  EXPECT_EQ(n.x, 7.0);
  EXPECT_EQ(n.y, 7.0);
  EXPECT_EQ(n.z, 7.0);
}

TEST(PairCollision, ConservesMomentumInEveryCollision) {
  Draw draw(3);
  for (int dim : {3, 2}) {
    for (int i = 0; i < kPairs; ++i) {
      const Case c = draw.pair(dim), x = collided(c);
      const Vec3 before = c.a.m * c.va + c.b.m * c.vb, after = x.a.m * x.va + x.b.m * x.vb;
      const double scale = c.a.m * (norm(c.va) + norm(x.va)) + c.b.m * (norm(c.vb) + norm(x.vb));
      ASSERT_LE(norm(after - before), kTol * scale) << "d = " << dim << ", pair " << i;
    }
  }
}

TEST(PairCollision, ConservesAngularMomentumAboutTheContactPoint) {
  // a at the origin, b at (r_a + r_b) n, contact point x_c = r_a n: the impulse acts at x_c.
  auto L = [](const Case& c) {
    const Vec3 terms[4] = {c.a.m * cross((-c.a.r()) * c.n, c.va), c.a.inertia() * c.wa,
                           c.b.m * cross(c.b.r() * c.n, c.vb), c.b.inertia() * c.wb};
    Vec3 sum;
    double scale = 0;
    for (const Vec3& t : terms) {
      sum += t;
      scale += norm(t);
    }
    return std::pair{sum, scale};
  };
  Draw draw(4);
  for (int dim : {3, 2}) {
    for (int i = 0; i < kPairs; ++i) {
      const Case c = draw.pair(dim), x = collided(c);
      const auto [before, s0] = L(c);
      const auto [after, s1] = L(x);
      ASSERT_LE(norm(after - before), kTol * (s0 + s1)) << "d = " << dim << ", pair " << i;
    }
  }
}

TEST(PairCollision, ReversesTheContactVelocityByEpsNormallyAndBetaTangentially) {
  Draw draw(5);
  for (int dim : {3, 2}) {
    for (int i = 0; i < kPairs; ++i) {
      const Case c = draw.pair(dim), x = collided(c);
      const Vec3 g = contact_velocity(c.va, c.wa, c.vb, c.wb, c.n, c.a.r(), c.b.r());
      const Vec3 g1 = contact_velocity(x.va, x.wa, x.vb, x.wb, x.n, x.a.r(), x.b.r());
      const double gn = dot(g, c.n), gn1 = dot(g1, c.n);
      const Vec3 gt = g - gn * c.n, gt1 = g1 - gn1 * c.n;
      const double tol = kTol * speed_scale(c, x);
      ASSERT_GT(gn, 0.0);
      ASSERT_NEAR(gn1, -c.eps * gn, tol) << "d = " << dim << ", pair " << i;
      ASSERT_LE(norm(gt1 + c.beta * gt), tol) << "d = " << dim << ", pair " << i;
    }
  }
}

TEST(PairCollision, ReturnsTheNormalRelativeSpeedBeforeTheCollision) {
  Draw draw(6);
  for (int i = 0; i < 100; ++i) {
    Case c = draw.pair(3);
    const double gn = dot(c.va - c.vb, c.n);
    Vec3 va = c.va, vb = c.vb;
    EXPECT_EQ(collide_smooth(va, vb, c.n, c.eps, c.p), gn);
    EXPECT_EQ(collide_rough(c.va, c.wa, c.vb, c.wb, c.n, c.eps, c.p), gn);
  }
}

TEST(PairCollision, ChangesEnergyByTheNormalAndTangentialLosses) {
  // dE = -(m_ab/2) [(1 - eps^2) g_n^2 + k/(1+k) (1 - beta^2) |g_t|^2].
  Draw draw(7);
  for (int dim : {3, 2}) {
    for (int i = 0; i < kPairs; ++i) {
      const Case c = draw.pair(dim), x = collided(c);
      const Vec3 g = contact_velocity(c.va, c.wa, c.vb, c.wb, c.n, c.a.r(), c.b.r());
      const double gn = dot(g, c.n), gt2 = norm2(g - gn * c.n), k = k_of(c);
      const double m_ab = c.a.m * c.b.m / (c.a.m + c.b.m);
      const double expected =
          -0.5 * m_ab * ((1 - c.eps * c.eps) * gn * gn + k / (1 + k) * (1 - c.beta * c.beta) * gt2);
      const double e0 = energy(c, c.va, c.wa, c.vb, c.wb), e1 = energy(x, x.va, x.wa, x.vb, x.wb);
      ASSERT_NEAR(e1 - e0, expected, kTol * e0) << "d = " << dim << ", pair " << i;
    }
  }
}

TEST(PairCollision, ConservesEnergyWhenPerfectlyElasticAndRough) {
  Draw draw(8);
  for (int dim : {3, 2}) {
    for (int i = 0; i < kPairs; ++i) {
      const Case c = draw.pair(dim, 1.0, 1.0), x = collided(c);
      const double e0 = energy(c, c.va, c.wa, c.vb, c.wb), e1 = energy(x, x.va, x.wa, x.vb, x.wb);
      ASSERT_NEAR(e1, e0, kTol * e0) << "d = " << dim << ", pair " << i;
      ASSERT_GT(norm(x.wa - c.wa), 0.0);  // the spins took part
    }
  }
}

TEST(PairCollision, BetaMinusOneLeavesSpinsAndEqualsTheSmoothCollisionBitForBit) {
  Draw draw(9);
  for (int dim : {3, 2}) {
    for (int i = 0; i < kPairs; ++i) {
      const Case c = draw.pair(dim, -2, -1.0);
      ASSERT_EQ(c.p.tangential, 0.0);
      const Case x = collided(c);
      Vec3 va = c.va, vb = c.vb;
      collide_smooth(va, vb, c.n, c.eps, c.p);
      ASSERT_EQ(std::memcmp(&x.va, &va, sizeof va), 0) << "d = " << dim << ", pair " << i;
      ASSERT_EQ(std::memcmp(&x.vb, &vb, sizeof vb), 0) << "d = " << dim << ", pair " << i;
      ASSERT_EQ(std::memcmp(&x.wa, &c.wa, sizeof c.wa), 0) << "d = " << dim << ", pair " << i;
      ASSERT_EQ(std::memcmp(&x.wb, &c.wb, sizeof c.wb), 0) << "d = " << dim << ", pair " << i;
    }
  }
}

TEST(PairCollision, InTwoDimensionsStaysInThePlaneWithSpinsAlongZ) {
  Draw draw(10);
  for (int i = 0; i < kPairs; ++i) {
    const Case c = draw.pair(2), x = collided(c);
    ASSERT_EQ(x.va.z, 0.0);
    ASSERT_EQ(x.vb.z, 0.0);
    ASSERT_EQ(x.wa.x, 0.0);
    ASSERT_EQ(x.wa.y, 0.0);
    ASSERT_EQ(x.wb.x, 0.0);
    ASSERT_EQ(x.wb.y, 0.0);
    ASSERT_NE(x.wa.z, c.wa.z);
  }
}

TEST(PairCollision, EqualSpheresFollowTheEqualSphereMap) {
  // Equal spheres (mass m, diameter sigma, kappa), n from 1 to 2:
  //   w = g - (g.n) n - n x (sigma/2)(w1 + w2),  g = v1 - v2,
  //   dv1 = -(1+alpha)/2 (g.n) n - kappa/(1+kappa) (1+beta)/2 w = -dv2,
  //   dw1 = dw2 = -(1+beta)/(sigma (1+kappa)) n x w.
  Draw draw(11);
  for (int dim : {3, 2}) {
    for (int i = 0; i < kPairs; ++i) {
      Case c = draw.pair(dim);
      c.b = c.a;
      c.p = pair_terms(c.a.m, c.a.m, c.a.sigma, c.a.sigma, c.beta, c.a.kappa, c.a.kappa);
      const Case x = collided(c);
      const double s = c.a.sigma, kap = c.a.kappa;
      const Vec3 g = c.va - c.vb;
      const Vec3 w = g - dot(g, c.n) * c.n - cross(c.n, (0.5 * s) * (c.wa + c.wb));
      const Vec3 dv1 =
          (-0.5 * (1 + c.eps) * dot(g, c.n)) * c.n - (kap / (1 + kap) * 0.5 * (1 + c.beta)) * w;
      const Vec3 dw = (-(1 + c.beta) / (s * (1 + kap))) * cross(c.n, w);
      const double tol = kTol * speed_scale(c, x);
      ASSERT_LE(norm(x.va - (c.va + dv1)), tol) << "d = " << dim << ", pair " << i;
      ASSERT_LE(norm(x.vb - (c.vb - dv1)), tol) << "d = " << dim << ", pair " << i;
      ASSERT_LE(0.5 * s * norm(x.wa - (c.wa + dw)), tol) << "d = " << dim << ", pair " << i;
      ASSERT_LE(0.5 * s * norm(x.wb - (c.wb + dw)), tol) << "d = " << dim << ", pair " << i;
    }
  }
}

TEST(PairCollision, EqualSmoothMassesGiveGrw05sCollisionMap) {
  Draw draw(12);
  for (int dim : {3, 2}) {
    for (int i = 0; i < kPairs; ++i) {
      const double m = draw.uniform(0.1, 10.0), alpha = 1.0 - draw.uniform(0.0, 1.0);
      const PairTerms p = pair_terms(m, m, 1.0, 1.0, 0.5, 0.0, 0.0);
      Vec3 v = draw.gauss_vec(dim), w = 2.0 * draw.gauss_vec(dim), n;
      const Vec3 e = draw.unit(dim);
      if (!impact_normal(v - w, e, n)) continue;
      const double tol = 1e-14 * (norm(v) + norm(w)) + grazing_error(v - w, e);
      Vec3 v1 = v, w1 = w;
      collide_smooth(v1, w1, n, alpha, p);
      collide(v, w, e, alpha);
      ASSERT_LE(norm(v1 - v), tol) << "d = " << dim << ", pair " << i;
      ASSERT_LE(norm(w1 - w), tol) << "d = " << dim << ", pair " << i;
    }
  }
}
