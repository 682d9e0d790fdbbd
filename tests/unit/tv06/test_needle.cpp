// The needle of TV06 §3.2: total rate against quadrature and against the paper's eq. 22, the
// collision rule's conservation laws, the impact point and waiting-time samplers against their
// exact laws, and equipartition (T_trans = T_rot = T_B, R = 1) at alpha = 1.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "granboltz/random/rng.hpp"
#include "granboltz/tv06/needle.hpp"
#include "tv06_support.hpp"

using namespace granboltz;
using namespace granboltz::tv06;
using namespace granboltz::tv06test;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// TV06 eq. 22 as printed (a = 1, L = 1).
double paper_eq22(double rho, double v, double w) {
  const double pre = std::exp(-v * v - w * w / 4) / (4 * std::sqrt(M_PI));
  return rho * (v * v / (2 * w) + w / 8 + v / 2 + 1 / (4 * w)) * std::erf(v + w / 2) +
         rho * (v * v / (2 * w) + w / 8 - v / 2 + 1 / (4 * w)) * std::erf(-v + w / 2) +
         rho * pre * (std::exp(v * w) * (1 - 2 * v / w) + std::exp(-v * w) * (1 + 2 * v / w));
}

/// Lambda(t) = ∫_0^t Phi at the sorted times, by quadrature between consecutive ones.
std::vector<double> cumulative_rate(const NeedleRate& rate, const NeedleState& s,
                                    const std::vector<double>& sorted_t) {
  auto phi = [&](double t) {
    const double angle = s.theta + s.omega * t;
    return rate(s.vy * std::cos(angle) - s.vx * std::sin(angle), s.omega);
  };
  std::vector<double> out(sorted_t.size());
  double acc = 0, prev = 0;
  for (std::size_t i = 0; i < sorted_t.size(); ++i) {
    if (sorted_t[i] > prev) acc += integrate(phi, prev, sorted_t[i], 1e-11);
    prev = std::max(prev, sorted_t[i]);
    out[i] = acc;
  }
  return out;
}

double ks_waiting_times(std::vector<double> t, const NeedleRate& rate, const NeedleState& s) {
  std::sort(t.begin(), t.end());
  const auto lambda = cumulative_rate(rate, s, t);
  const double n = static_cast<double>(t.size());
  double d = 0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    const double F = -std::expm1(-lambda[i]);
    d = std::max({d, F - static_cast<double>(i) / n, static_cast<double>(i + 1) / n - F});
  }
  return std::sqrt(n) * d;
}

NeedleConfig needle(double M, double alpha, std::uint64_t collisions) {
  NeedleConfig c;
  c.mass = M;
  c.alpha = alpha;
  c.collisions = collisions;
  c.warmup = collisions / 10;
  return c;
}

struct NeedleSeries {
  std::vector<double> trans, rot, R;
};
NeedleSeries run(const NeedleConfig& c, std::uint64_t seed, int ensembles,
                 std::vector<NeedleEnsemble>* all = nullptr) {
  NeedleSeries s;
  for (int e = 0; e < ensembles; ++e) {
    NeedleEnsemble r = simulate_needle(c, seed, e);
    s.trans.push_back(r.translational_ratio);
    s.rot.push_back(r.rotational_ratio);
    s.R.push_back(r.R);
    if (all) all->push_back(std::move(r));
  }
  return s;
}

}  // namespace

TEST(TV06Needle, TotalRateMatchesQuadratureAlongTheNeedle) {
  // Including omega -> 0 (series branch), both signs, and the switch between the branches.
  for (double a : {0.5, 1.0, 3.0})
    for (double L : {0.3, 1.0, 2.5})
      for (double rho : {1.0, 2.0}) {
        const NeedleRate rate(gaussian_bath(a, rho), L);
        for (double vn : {-4.0, -1.0, -0.1, 0.0, 0.2, 1.5, 5.0})
          for (double w : {0.0, 1e-14, 1e-9, 1e-5, 1e-2, 0.1, 0.3, 0.7, 2.0, 20.0, 200.0})
            for (double sign : {1.0, -1.0}) {
              const double omega = sign * w;
              // phi(vn + omega x) bends sharply where the contact velocity vanishes: split there.
              auto f = [&](double x) { return rate.per_length(vn + omega * x); };
              const double x0 = omega != 0 ? -vn / omega : 0.0;
              const double q = std::fabs(x0) < L / 2 ? integrate(f, -L / 2, x0, 1e-13) +
                                                           integrate(f, x0, L / 2, 1e-13)
                                                     : integrate(f, -L / 2, L / 2, 1e-13);
              EXPECT_NEAR(rate(vn, omega), q, 2e-13 * q)
                  << "a=" << a << " L=" << L << " vn=" << vn << " omega=" << omega;
            }
      }
}

TEST(TV06Needle, TotalRateAgreesWithThePapersEquation22) {
  const NeedleRate rate(gaussian_bath(1.0, 1.3), 1.0);
  for (double vn : {-2.0, -0.3, 0.0, 0.8, 3.0})
    for (double omega : {-10.0, -1.0, -0.1, 0.1, 0.5, 4.0}) {
      const double mine = rate(vn, omega);
      EXPECT_NEAR(mine, paper_eq22(1.3, vn, omega), 1e-13 * mine) << vn << " " << omega;
    }
  // At omega = 0 the rate is L phi(v_n) (eq. 16).
  EXPECT_NEAR(rate(0.4, 0.0), rate.per_length(0.4), 1e-15);
}

TEST(TV06Needle, RateBoundsHoldAlongFreeRotations) {
  const NeedleRate rate(gaussian_bath(1.0, 1.0), 1.0);
  Engine e = make_stream(3, 0, Consumer::kNeedle);
  for (int i = 0; i < 20000; ++i) {
    NeedleState s{3 * normal(e), 3 * normal(e), 10 * normal(e), 6 * uniform01(e)};
    const double t = 5 * uniform01(e);
    s.theta += s.omega * t;
    const double phi = rate(normal_velocity(s), s.omega);
    ASSERT_LE(phi, rate.upper_bound(std::hypot(s.vx, s.vy), s.omega));
    ASSERT_GE(phi, rate.lower_bound(s.omega));
  }
}

TEST(TV06Needle, CollisionConservesEnergyAndMomentaAndRestitutesAlpha) {
  Engine e = make_stream(11, 0, Consumer::kNeedle);
  for (int i = 0; i < 10000; ++i) {
    const double alpha = i % 2 ? 1.0 : uniform01(e);
    const NeedleBody b = uniform_rod(0.05 + 3 * uniform01(e), 0.2 + 2 * uniform01(e));
    NeedleState s{normal(e), normal(e), 5 * normal(e), 7 * uniform01(e)};
    const double x = b.length * (uniform01(e) - 0.5);
    const double nx = -std::sin(s.theta), ny = std::cos(s.theta);
    const double ex = std::cos(s.theta), ey = std::sin(s.theta);
    const double w = normal_velocity(s) + s.omega * x;
    // A bath particle approaching the contact point: normal component on the right side.
    const double vnorm = w + (i % 3 ? -1 : 1) * std::fabs(normal(e)) - 1e-3;
    const double vtan = normal(e);
    const double ux = vnorm * nx + vtan * ex, uy = vnorm * ny + vtan * ey;

    auto energy = [&](const NeedleState& q, double px, double py) {
      return 0.5 * b.mass * (q.vx * q.vx + q.vy * q.vy) + 0.5 * b.inertia * q.omega * q.omega +
             0.5 * (px * px + py * py);
    };
    const double E0 = energy(s, ux, uy);
    const double Px0 = b.mass * s.vx + ux, Py0 = b.mass * s.vy + uy;
    const double L0 = b.inertia * s.omega + x * (ex * uy - ey * ux);  // about the needle centre
    const double g0 = w - vnorm;

    const double dp = needle_impulse(b, alpha, x, w, vnorm);
    NeedleState t = s;
    apply_needle_impulse(t, b, x, dp);
    const double ux1 = ux - nx * dp, uy1 = uy - ny * dp;  // the bath particle (mass 1)
    const double g1 = normal_velocity(t) + t.omega * x - (ux1 * nx + uy1 * ny);

    EXPECT_NEAR(g1, -alpha * g0, 1e-12 * (1 + std::fabs(g0)));
    EXPECT_NEAR(b.mass * t.vx + ux1, Px0, 1e-12 * (1 + std::fabs(Px0)));
    EXPECT_NEAR(b.mass * t.vy + uy1, Py0, 1e-12 * (1 + std::fabs(Py0)));
    EXPECT_NEAR(b.inertia * t.omega + x * (ex * uy1 - ey * ux1), L0, 1e-12 * (1 + std::fabs(L0)));
    const double E1 = energy(t, ux1, uy1);
    if (alpha == 1.0) {
      EXPECT_NEAR(E1, E0, 1e-13 * E0);
    } else {
      EXPECT_LE(E1, E0 * (1 + 1e-14));
    }
    // The impulse pushes the needle away from the particle: the normal relative speed drops.
    EXPECT_LT(dp * g0, 0.0);
  }
}

TEST(TV06Needle, ImpactPointFollowsTheRateAlongTheNeedle) {
  const int n = 20000, checks = 5;
  const NeedleRate rate(gaussian_bath(1.0, 1.0), 1.5);
  int k = 0;
  for (auto [vn, omega] :
       {std::pair{0.5, 3.0}, {-2.0, 0.1}, {0.0, 10.0}, {1.0, -6.0}, {4.0, 0.0}}) {
    Engine e = make_stream(21, static_cast<std::uint64_t>(k++), Consumer::kNeedle);
    std::vector<double> x(n);
    Fluxes f;
    for (auto& xi : x) {
      xi = sample_impact_point(rate, vn, omega, e, &f);
      ASSERT_EQ(f.total(), rate.bath().fluxes(vn + omega * xi).total());
    }
    EXPECT_LT(ks_statistic(
                  x, [&](double y) { return rate.per_length(vn + omega * y); }, -0.75, 0.75),
              ks_critical(checks))
        << "vn=" << vn << " omega=" << omega;
  }
}

TEST(TV06Needle, WaitingTimesFollowTheExactLawByThinningAndByInversion) {
  struct Case {
    double a, L;
    NeedleState s;
  };
  const Case cases[] = {{1.0, 1.0, {0.3, -1.2, 2.5, 0.4}},
                        {1.0, 1.0, {3.0, 0.0, 0.05, 0.0}},
                        {1.0, 1.0, {0.0, 0.0, 8.0, 1.0}},
                        {2.0, 1.5, {-2.0, 1.0, -15.0, 2.0}},
                        {0.5, 0.7, {1.0, 4.0, 1e-9, -1.0}}};
  const int checks = 10;
  int k = 0;
  for (const Case& c : cases) {
    const NeedleRate rate(gaussian_bath(c.a, 1.0), c.L);
    Engine e = make_stream(31, static_cast<std::uint64_t>(k++), Consumer::kNeedle);
    std::vector<double> thin(20000), inv(1500);
    std::uint64_t rejected = 0;
    for (auto& t : thin) t = waiting_time_by_thinning(rate, c.s, e, &rejected);
    WaitingTimeSolver solver(rate);
    for (auto& t : inv) t = solver.sample(c.s, e);
    EXPECT_LT(ks_waiting_times(thin, rate, c.s), ks_critical(checks)) << "thinning, case " << k;
    EXPECT_LT(ks_waiting_times(inv, rate, c.s), ks_critical(checks)) << "inversion, case " << k;
    // The solver's root satisfies its equation.
    const double target = 0.7;
    const double t = solver.solve(c.s, target);
    EXPECT_NEAR(solver.integral(c.s, t), target, 1e-9 * target) << "case " << k;
  }
}

TEST(TV06Needle, ElasticNeedleIsInEquipartitionWithoutCorrelation) {
  // At alpha = 1 the stationary state is Gibbs: T_trans = T_rot = T_B, v and omega independent
  // (R = 1), omega Gaussian with variance T_B / I.
  struct Case {
    double a, L, rho, M;
  };
  const Case cases[] = {{1.0, 1.0, 1.0, 0.1}, {1.0, 1.0, 1.0, 1.0}, {2.0, 1.5, 2.0, 0.5}};
  const int N = 16, checks = 3 * 3 + 1;
  std::uint64_t seed = 50;
  for (const Case& k : cases) {
    NeedleConfig c = needle(k.M, 1.0, 40000);
    c.a = k.a;
    c.length = k.L;
    c.density = k.rho;
    const NeedleSeries s = run(c, seed++, N);
    for (const auto* v : {&s.trans, &s.rot, &s.R}) {
      const Interval t = t_interval(*v, checks);
      EXPECT_TRUE(t.contains(1.0))
          << "M=" << k.M << " a=" << k.a << ": " << t.mean << " +- " << t.half_width;
    }
  }
  // The omega histogram of M = 1 (sigma_omega^2 = T_B/I = 6): Hotelling's test of 8 bins on
  // [-3 sigma, 3 sigma] and the lower overflow against the Gaussian masses.
  NeedleConfig c = needle(1.0, 1.0, 20000);
  const double sigma = std::sqrt(6.0);
  c.omega_histogram.bins = 8;
  c.omega_histogram.range = 3 * sigma;
  std::vector<NeedleEnsemble> all;
  run(c, 60, 40, &all);
  std::vector<double> mu{gsl_cdf_gaussian_P(-3 * sigma, sigma)};
  for (int b = 0; b < 8; ++b)
    mu.push_back(gsl_cdf_gaussian_P(sigma * (-3 + 0.75 * (b + 1)), sigma) -
                 gsl_cdf_gaussian_P(sigma * (-3 + 0.75 * b), sigma));
  std::vector<std::vector<double>> rows;
  for (const auto& e : all) {
    const double n = static_cast<double>(e.samples);
    std::vector<double> row{static_cast<double>(e.omega_histogram.below()) / n};
    for (auto count : e.omega_histogram.counts()) row.push_back(static_cast<double>(count) / n);
    rows.push_back(row);
  }
  EXPECT_GT(hotelling_p_value(rows, mu), kLevel / checks);
}

TEST(TV06Needle, InelasticNeedleIsColderThanTheBathAndRotationColderStill) {
  // TV06 §3.2 (and Viot and Talbot 2004): T_B > T_trans > T_rot for alpha < 1.
  const NeedleSeries s = run(needle(0.5, 0.5, 30000), 70, 12);
  const Interval trans = t_interval(s.trans, 2), rot = t_interval(s.rot, 2);
  EXPECT_LT(trans.mean + trans.half_width, 1.0);
  EXPECT_LT(rot.mean + rot.half_width, trans.mean - trans.half_width);
}

TEST(TV06Needle, InversionAndThinningGiveTheSameStationaryState) {
  NeedleConfig thin = needle(0.5, 0.3, 4000);
  NeedleConfig inv = thin;
  inv.waiting_time = NeedleWaitingTime::kInversion;
  const NeedleSeries a = run(thin, 80, 12), b = run(inv, 81, 12);
  const int checks = 3;
  double z = 0;
  EXPECT_TRUE(same_mean(a.trans, b.trans, checks, &z)) << "T_trans: Welch t = " << z;
  EXPECT_TRUE(same_mean(a.rot, b.rot, checks, &z)) << "T_rot: Welch t = " << z;
  EXPECT_TRUE(same_mean(a.R, b.R, checks, &z)) << "R: Welch t = " << z;
}
