// Dimension 2 and the collision geometry (dsmc.dimension, dsmc.geometry). Exact results first:
// every collision in the plane (and in space), the law of the impact normal and of the elastic
// deflection of hard disks and of the uniform-direction model, free cooling and white-noise
// states of Maxwell molecules in d = 2 (closed moment equations). Then hard disks against the
// Sonine approximations (a2, Haff's law, the steady temperature) with stated allowances, and
// bit-reproducible d = 2 runs and the config.
//
// The d = 2 formulas used here (checked with exact symbolic Gaussian moments of the collision
// integrals in tests/sonine_moments.py, which reproduces every d = 3 entry of beyond.md §1-2):
// with u = v - w, mu = u^.e and the normal n = (u^ - e)/|u^ - e|, (u.n)^2 = |u|^2 (1 - mu)/2.
// - uniform: e uniform on S^1, so the impact angle theta (between u^ and n) is uniform on
//   (-pi/2, pi/2), <1 - mu> = 1; impact (hard disks): sin(theta) uniform on (-1, 1),
//   1 - mu = 2 cos^2(theta), <1 - mu> = 4/3. The elastic deflection is |chi| = pi - 2|theta|:
//   P(|chi| <= x) = x/pi (uniform) and 1 - cos(x/2) (hard disks; quartiles of |chi|/pi 0.460,
//   0.667, 0.839).
// - lambda = 0: sum |v|^2 loses (area/4) gamma C (1 - alpha^2) <1 - mu> sum |v - V|^2 per unit
//   time (sum over pairs |v_i - v_j|^2 = n sum |v_i - V|^2), exactly, at any n.
// - Hard disks: a pair collides at rate 2 pi gamma C |u| / n, so with the Maxwellian
//   E|u|^3 = 6 sqrt(pi) T^{3/2} (1 + 3a2/16 + a3/64): dT/dt = 2 beta - K T^{3/2},
//   K = pi^{3/2} gamma C (1 - alpha^2) (1 + 3a2/16 + a3/64).
#include <gsl/gsl_cdf.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "configs.hpp"
#include "granboltz/app/config.hpp"
#include "granboltz/dsmc/ensemble.hpp"
#include "granboltz/h5/hdf5_io.hpp"
#include "granboltz/physics/collision.hpp"
#include "granboltz/physics/geometry.hpp"
#include "granboltz/physics/restitution/collide.hpp"
#include "granboltz/random/rng.hpp"
#include "granboltz/random/samplers.hpp"
#include "test_support.hpp"

using namespace granboltz;
using granboltz::test::run_granboltz;
using granboltz::test::TempDir;

namespace {

constexpr int kTemperature = 4;
const double kGC = 1 / (4 * M_PI);  // GRW05's normalisation of hard spheres, kept for disks

// Heated hard disks with every output that has state of its own (histogram and its components,
// moments, steady averages); an odd n for the unpaired kick.
const std::string kHeated = std::string(R"(model: dsmc
seed: 12
ensembles: 7
dsmc:
  particles: 201
  dimension: 2
  alpha: 0.6
)") + test::kHeatedStatefulOutputs;

Config make(const std::vector<std::string>& sets, std::uint64_t seed, std::uint64_t ensembles) {
  std::vector<std::string> all = {"model=dsmc", "seed=" + std::to_string(seed),
                                  "ensembles=" + std::to_string(ensembles), "dsmc.dimension=2",
                                  "dsmc.gamma=1"};
  all.insert(all.end(), sets.begin(), sets.end());
  return parse_config("{}", "test", all);
}

Vec3 unit(Vec3 x) { return (1.0 / norm(x)) * x; }
double cross_z(Vec3 a, Vec3 b) { return a.x * b.y - a.y * b.x; }

// van Noije & Ernst's first Sonine a2 in d dimensions (beyond.md §1).
double vne_a2(double a, int d, bool white_noise) {
  const double num = 16 * (1 - a) * (1 - 2 * a * a);
  return white_noise ? num / (73 + 56 * d - 3 * a * (35 + 8 * d) + 30 * a * a * (1 - a))
                     : num / (9 + 24 * d - a * (41 - 8 * d) + 30 * a * a * (1 - a));
}

// Second Sonine (a2, a3 with their products dropped) for hard disks, derived as described at
// the top; d = 3 analogues in beyond.md's table.
struct Sonine2 {
  double a2, a3;
};
constexpr Sonine2 kWhiteNoise05{0.03452, -0.00550};  // alpha = 0.5 (vNE 0.03563)
constexpr Sonine2 kHcs08{-0.02551, -0.01036};        // alpha = 0.8 (vNE -0.02194)
constexpr Sonine2 kHcs09{-0.02967, -0.00937};        // alpha = 0.9 (vNE -0.02686)

// Exact steady a2 and a3 of Maxwell molecules (lambda = 0) under white noise in d = 2: the
// moment equations close (derived as above; the d = 3 case gives beyond.md §2).
double maxwell_wn_a2(double a, Geometry g) {
  return g == Geometry::kImpact
             ? 2 * std::pow(1 - a, 2) * (1 + a) / (10 - 8 * a + a * a - a * a * a)
             : 6 * std::pow(1 - a, 2) * (1 + a) / (33 - 25 * a + 3 * a * a - 3 * a * a * a);
}
double maxwell_wn_a3(double a, Geometry g) {
  const double a2 = a * a, a3 = a2 * a, a4 = a3 * a, a5 = a4 * a,
               q = std::pow(1 - a, 3) * (1 + a) * (1 + a);
  return g == Geometry::kImpact
             ? -4 * q * (17 - 15 * a + 2 * a2 - 2 * a3) /
                   ((10 - 8 * a + a2 - a3) * (55 - 45 * a + 21 * a2 - 17 * a3 + a4 - a5))
             : -8 * q * (129 - 113 * a + 15 * a2 - 15 * a3) /
                   ((33 - 25 * a + 3 * a2 - 3 * a3) *
                    (317 - 245 * a + 110 * a2 - 86 * a3 + 5 * a4 - 5 * a5));
}

// <1 - mu> of the geometry in d = 2.
double one_minus_mu(Geometry g) { return g == Geometry::kImpact ? 4.0 / 3.0 : 1.0; }

void expect_ok(const test::CommandResult& r) { ASSERT_EQ(r.exit_code, 0) << r.output; }

struct Steady {
  double a2, a2_ci, a3, a3_ci, T, T_ci;
  std::vector<double> T_rows, T_variance;  // every observation: ensemble mean and variance of T
};

// A CLI run with `sets` on `text`; the steady a2, a3 and T with their intervals.
Steady run_steady(const std::string& text, const std::vector<std::string>& sets) {
  TempDir dir;
  const std::string cfg = dir.write("c.yaml", text), out = dir.file("out.h5");
  std::string args = "run " + cfg + " -q -o " + out;
  for (const auto& s : sets) args += " --set " + s;
  const auto r = run_granboltz(args);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  H5Reader f(out);
  // In the plane nothing may leave it: the z parts of the outputs are exactly 0.
  EXPECT_EQ(f.read_double("/steady/bulk_velocity/mean")[2], 0.0);
  EXPECT_EQ(f.read_double("/steady/heat_flux/mean")[2], 0.0);
  const auto P = f.read_double("/steady/pressure_tensor/mean");
  EXPECT_TRUE(P[2] == 0.0 && P[5] == 0.0 && P[6] == 0.0 && P[7] == 0.0 && P[8] == 0.0);
  return {f.read_double("/steady/a2/mean")[0],          f.read_double("/steady/a2/ci")[0],
          f.read_double("/steady/a3/mean")[0],          f.read_double("/steady/a3/ci")[0],
          f.read_double("/steady/temperature/mean")[0], f.read_double("/steady/temperature/ci")[0],
          f.read_double("/temperature/mean"),           f.read_double("/temperature/variance")};
}

// Every collision of geometry G (the engine's direction law) with the four restitution cases.
template <class G>
void expect_exact_collisions(std::uint64_t seed) {
  Engine rng = make_stream(seed, 0, Consumer::kEvents);
  const ViscoelasticRestitution visco{0.3};
  for (int i = 0; i < 40000; ++i) {
    const double scale = std::exp(6.0 * uniform01(rng) - 3.0);  // speeds over 2.6 decades
    Vec3 v, w;
    if constexpr (G::kDim == 2) {
      v = {scale * normal(rng), scale * normal(rng), 0.0};
      w = {scale * normal(rng), scale * normal(rng), 0.0};
    } else {
      v = scale * normal3(rng);
      w = scale * normal3(rng);
    }
    const Vec3 v0 = v, w0 = w, u = v - w;
    const Vec3 e = G::direction(u, rng);
    if constexpr (G::kDim == 2) ASSERT_EQ(e.z, 0.0);
    ASSERT_NEAR(norm(e), 1.0, 4 * DBL_EPSILON);
    const Vec3 n = unit(unit(u) - e);
    const double gn = dot(u, n);
    ASSERT_GE(gn, 0.0);
    const double size = norm(v) + norm(w), e2 = norm2(v) + norm2(w);
    double eps = 0.0;
    switch (i % 4) {
      case 0:
        collide(v, w, e, eps = 0.3);
        break;
      case 1:
        collide(v, w, e, eps = 1.0);
        break;
      case 2:
        eps = collide_law(v, w, e, RestitutionLaw{ConstantRestitution{0.7}}, 1.0);
        break;
      default:
        eps = collide_law(v, w, e, visco, 1.0);
        ASSERT_EQ(eps, visco.eps_of_g2(normal_speed2(v0, w0, e)));
        ASSERT_NEAR(normal_speed2(v0, w0, e), gn * gn, 64 * DBL_EPSILON * norm2(u));
    }
    if constexpr (G::kDim == 2) ASSERT_TRUE(v.z == 0.0 && w.z == 0.0) << i;  // exactly
    ASSERT_LE(norm((v + w) - (v0 + w0)), 8 * DBL_EPSILON * size) << i;
    // The impact map with the normal n. n carries the round-off of 1/|u^ - e| (its direction is
    // off by about DBL_EPSILON / |u^ - e|, large for grazing impacts, frequent for uniform e in
    // the plane), and so does the reference jump.
    const Vec3 jump = (0.5 * (1.0 + eps) * gn) * n;
    const double tol_n = 16 * DBL_EPSILON * (size + norm(u) / norm(unit(u) - e));
    ASSERT_LE(norm(v - (v0 - jump)) + norm(w - (w0 + jump)), tol_n) << i;
    // |v|^2 + |w|^2 changes by -(1 - eps^2)/2 (u.n)^2: kinetic energy (m = 1) by -(1 - eps^2)/4.
    const double change = norm2(v) + norm2(w) - e2;
    ASSERT_NEAR(change, -0.5 * (1.0 - eps * eps) * gn * gn, 64 * DBL_EPSILON * e2) << i;
    ASSERT_NEAR(change, energy_change(v0, w0, e, eps), 64 * DBL_EPSILON * e2) << i;
    if (eps == 1.0) ASSERT_NEAR(change, 0.0, 16 * DBL_EPSILON * e2) << i;
  }
}

// Chi-square statistic of `x` (values of a CDF, in [0, 1]) against K equiprobable bins.
double chi_square(const std::vector<double>& x, int K) {
  std::vector<double> counts(K, 0.0);
  for (double p : x) counts[std::min(K - 1, static_cast<int>(p * K))] += 1.0;
  const double expected = static_cast<double>(x.size()) / K;
  double s = 0.0;
  for (double c : counts) s += (c - expected) * (c - expected) / expected;
  return s;
}

}  // namespace

TEST(Dimension, EveryCollisionKeepsMomentumAndThePlaneAndLosesTheNormalEnergy) {
  expect_exact_collisions<CircleImpact>(31);
  expect_exact_collisions<CircleUniform>(32);
  expect_exact_collisions<Sphere3>(33);  // d = 3, for comparison
  // u = 0: the direction is arbitrary but a unit vector of the plane, and nothing moves.
  Engine rng = make_stream(34, 0, Consumer::kEvents);
  Vec3 v{0.5, -1.5, 0.0}, w = v;
  const Vec3 e = disk_impact_direction(v - w, rng);
  EXPECT_EQ(norm(e), 1.0);
  collide(v, w, e, 0.5);
  EXPECT_TRUE(v.x == 0.5 && v.y == -1.5 && v.z == 0.0 && w.x == 0.5 && w.y == -1.5 && w.z == 0.0);
}

TEST(Dimension, ImpactAngleAndDeflectionFollowTheExactLawOfEachGeometry) {
  // The impact angle theta, read off the collision's velocity change (v' - v is along -n), for a
  // constant alpha, the elastic case and the viscoelastic law; and the elastic deflection |chi|
  // between u and u'. Each sample is binned by its law's exact CDF into K equiprobable bins: the
  // chi-square statistic must lie below the 99.9 % point (Bonferroni over the 8 checks; fixed
  // streams: a deterministic outcome), and above it for the other geometry's law.
  const int K = 40, m = 200000;
  const double critical = gsl_cdf_chisq_Qinv(0.001 / 8, K - 1);
  const auto F_theta = [](double theta, Geometry g) {
    return g == Geometry::kImpact ? 0.5 * (1.0 + std::sin(theta)) : theta / M_PI + 0.5;
  };
  const auto F_chi = [](double chi, Geometry g) {
    return g == Geometry::kImpact ? 1.0 - std::cos(0.5 * chi) : chi / M_PI;
  };
  const ViscoelasticRestitution visco{0.4};
  std::uint64_t seed = 40;
  for (Geometry g : {Geometry::kImpact, Geometry::kUniform}) {
    const Geometry other = g == Geometry::kImpact ? Geometry::kUniform : Geometry::kImpact;
    const char* name = geometry_name(g);
    for (int law = 0; law < 3; ++law) {
      Engine rng = make_stream(++seed, 0, Consumer::kEvents);
      std::vector<double> own, wrong, own_chi, wrong_chi;
      for (int i = 0; i < m; ++i) {
        Vec3 v{normal(rng), normal(rng), 0.0}, w{normal(rng), normal(rng), 0.0};
        const Vec3 v0 = v, u = v - w;
        const Vec3 e = g == Geometry::kImpact ? disk_impact_direction(u, rng) : unit_circle(rng);
        if (law == 0)
          collide(v, w, e, 0.5);
        else if (law == 1)
          collide(v, w, e, 1.0);
        else
          collide_law(v, w, e, visco, 1.0);
        const Vec3 dv = v0 - v;  // (1 + eps)/2 (u.n) n
        ASSERT_GT(norm(dv), 0.0);
        const Vec3 nh = unit(dv), uh = unit(u);
        const double theta = std::atan2(cross_z(uh, nh), dot(uh, nh));
        ASSERT_LE(std::fabs(theta), 0.5 * M_PI + 1e-12);
        own.push_back(std::clamp(F_theta(theta, g), 0.0, 1.0));
        wrong.push_back(std::clamp(F_theta(theta, other), 0.0, 1.0));
        if (law == 1) {
          const Vec3 uh1 = unit(v - w);
          const double chi = std::fabs(std::atan2(cross_z(uh, uh1), dot(uh, uh1)));
          own_chi.push_back(std::clamp(F_chi(chi, g), 0.0, 1.0));
          wrong_chi.push_back(std::clamp(F_chi(chi, other), 0.0, 1.0));
        }
      }
      const double s = chi_square(own, K), s_other = chi_square(wrong, K);
      std::printf("%s, law %d: impact angle chi2 %.1f (other law's %.0f), critical %.1f\n", name,
                  law, s, s_other, critical);
      EXPECT_LT(s, critical) << name << " law " << law;
      EXPECT_GT(s_other, critical) << name << " law " << law << ": the laws are not told apart";
      if (law == 1) {
        const double c = chi_square(own_chi, K), c_other = chi_square(wrong_chi, K);
        std::printf("%s: deflection chi2 %.1f (other law's %.0f)\n", name, c, c_other);
        EXPECT_LT(c, critical) << name << " deflection";
        EXPECT_GT(c_other, critical) << name << " deflection: the laws are not told apart";
      }
    }
  }
}

TEST(Dimension, MaxwellFreeCoolingIsExactlyExponentialAtTheRateOfTheGeometry) {
  // lambda = 0: E[T(t)] = (1 - 1/n) T0 exp(-k t) exactly (T centred on the empirical V of n
  // independent Maxwellian velocities), k = (2 pi / 4) gamma C (1 - alpha^2) <1 - mu>. With
  // 2 pi gamma C = 1 and alpha = 1/2: k = 3/16 (uniform), 1/4 (impact). Every observation row
  // within the interval (family-wise 0.999), and the other geometry's rate rejected.
  const double n = 1000, N = 100, alpha = 0.5;
  const int rows = 13;
  const double z = test::family_z(2 * rows);
  std::uint64_t seed = 50;
  for (Geometry g : {Geometry::kImpact, Geometry::kUniform}) {
    const Geometry other = g == Geometry::kImpact ? Geometry::kUniform : Geometry::kImpact;
    const auto k = [&](Geometry h) { return 0.25 * (1 - alpha * alpha) * one_minus_mu(h); };
    const test::DsmcRun r(
        make({"dsmc.particles=1000", "dsmc.alpha=0.5", "dsmc.thermostat=none",
              "dsmc.geometry=" + std::string(geometry_name(g)), "dsmc.kernel.lambda=0",
              "dsmc.kernel.C=" + format_real(0.5 / M_PI), "dsmc.t_end=12", "dsmc.observe_every=1"},
             ++seed, static_cast<std::uint64_t>(N)));
    ASSERT_EQ(r.times.size(), static_cast<std::size_t>(rows));
    double worst = 0.0, worst_other = 1e300;
    for (std::size_t m = 0; m < r.times.size(); ++m) {
      const double t = r.times[m];
      const MeanCi T = r.at(m, kTemperature);
      const double ci = z * std::sqrt(T.variance / N);
      EXPECT_NEAR(T.mean, (1 - 1 / n) * std::exp(-k(g) * t), ci) << geometry_name(g) << " t=" << t;
      worst = std::max(worst, std::fabs(T.mean - (1 - 1 / n) * std::exp(-k(g) * t)) / ci);
      if (m + 1 == r.times.size())
        worst_other = std::fabs(T.mean - (1 - 1 / n) * std::exp(-k(other) * t)) / ci;
    }
    std::printf("%s: worst |T - exact| / interval %.3f; the other rate at t = 12: %.1f\n",
                geometry_name(g), worst, worst_other);
    EXPECT_GT(worst_other, 1.0) << geometry_name(g) << ": the two rates are not told apart";
  }
}

TEST(Dimension, MaxwellMoleculesUnderWhiteNoiseHaveTheExactA2A3AndTemperatureOfEachGeometry) {
  // lambda = 0 in d = 2, white noise: E[T] = (1 - 1/n) 2 beta / k at all times when started at
  // T0 = 2 beta / k (k as in the free cooling test: the kicks add 2 beta d (n - 1) to
  // sum |v - V|^2 per unit time), checked at every row (family-wise 0.999) and on the steady
  // average; and the steady a2, a3 are exact (top of file). Tolerance: the run's interval (3.2
  // sigma over the ensembles) plus 2/n (1 + |a|) for the finite-n bias of the moments, as in
  // SonineExact. The two geometries' exact a2 differ by 0.015, several intervals: each run must
  // reject the other's value.
  const double alpha = 0.5, beta = 0.125, n = 2000;
  const char* text = R"(model: dsmc
seed: 9
ensembles: 120
dsmc:
  particles: 2000
  dimension: 2
  alpha: 0.5
  beta: 0.125
  gamma: 1
  kernel: {lambda: 0, C: 0.15915494309189535}
  t_end: 80
  observe_every: 0.5
  moments: 3
  steady_from: 20
)";
  for (Geometry g : {Geometry::kImpact, Geometry::kUniform}) {
    const Geometry other = g == Geometry::kImpact ? Geometry::kUniform : Geometry::kImpact;
    const double k = 0.25 * (1 - alpha * alpha) * one_minus_mu(g), T_inf = 2 * beta / k;
    const Steady s = run_steady(text, {"dsmc.geometry=" + std::string(geometry_name(g)),
                                       "dsmc.initial.temperature=" + format_real(T_inf)});
    const double a2 = maxwell_wn_a2(alpha, g), a3 = maxwell_wn_a3(alpha, g);
    std::printf(
        "%s: a2 %.5f +- %.5f (exact %.5f), a3 %.5f +- %.5f (exact %.5f), "
        "T %.5f +- %.5f (exact %.5f)\n",
        geometry_name(g), s.a2, s.a2_ci, a2, s.a3, s.a3_ci, a3, s.T, s.T_ci, (1 - 1 / n) * T_inf);
    EXPECT_NEAR(s.a2, a2, s.a2_ci + 2 / n * (1 + std::fabs(a2))) << geometry_name(g);
    EXPECT_NEAR(s.a3, a3, s.a3_ci + 2 / n * (1 + std::fabs(a3))) << geometry_name(g);
    EXPECT_NEAR(s.T, (1 - 1 / n) * T_inf, s.T_ci) << geometry_name(g);
    ASSERT_EQ(s.T_rows.size(), 161u);
    const double z = test::family_z(2 * 161), N = 120;
    for (std::size_t m = 0; m < s.T_rows.size(); ++m)
      EXPECT_NEAR(s.T_rows[m], (1 - 1 / n) * T_inf, z * std::sqrt(s.T_variance[m] / N))
          << geometry_name(g) << " row " << m;
    const double a2_other = maxwell_wn_a2(alpha, other);
    EXPECT_GT(std::fabs(s.a2 - a2_other), s.a2_ci + 2 / n * (1 + std::fabs(a2_other)))
        << geometry_name(g) << ": the geometries' a2 are not told apart";
  }
}

TEST(Dimension, HardDisksUnderWhiteNoiseHaveFirstSonineA2AndTheSteadyTemperature) {
  // alpha = 0.5, beta = K0/2 (K0: K without the Sonine factor) so that the Maxwellian steady
  // T is 1, started there.
  // a2 against van Noije-Ernst in d = 2 (0.03563). Second Sonine gives 0.03452: the
  // approximation's error is allowed as twice that difference (the next terms no larger than
  // the last), besides the run's interval and 2/n (1 + |a2|) for the finite-n bias. The window
  // excludes the d = 3 value (0.0256) and the uniform geometry's first Sonine (0.0273).
  // T_st: the n-particle energy balance, 2 beta d (n - 1) = (2 pi/3) gamma C (1 - alpha^2)
  // (1/n) E sum_pairs |u|^3, fixes the pairs' mean |u|^3 independently of n, and their mean
  // |u|^2 is 2d E[T] n/(n - 1): E[T_st] = (1 - 1/n) (2 beta / K)^{2/3}, K's Sonine factor from
  // vNE's a2. Allowance: 2/3 of 3/16 of the a2 error above and of a3/64 (second Sonine's a3),
  // and 1/n for the finite-n correlations. The Maxwellian T_st (a2 = 0) is 0.44 % higher: the
  // run must resolve that.
  const double alpha = 0.5, n = 2000;
  const double K0 = std::pow(M_PI, 1.5) * kGC * (1 - alpha * alpha), beta = 0.5 * K0;
  const std::string text = std::string(R"(model: dsmc
seed: 13
ensembles: 40
dsmc:
  particles: 2000
  dimension: 2
  alpha: 0.5
  beta: )") + format_real(beta) +
                           R"(
  gamma: 1
  kernel: {lambda: 1, C: 0.0795774715459477}
  t_end: 400
  observe_every: 1
  moments: 3
  steady_from: 20
)";
  const Steady s = run_steady(text, {});
  const double first = vne_a2(alpha, 2, true), delta = std::fabs(first - kWhiteNoise05.a2);
  EXPECT_NEAR(first, 0.03563, 5e-6);  // beyond.md's d = 2 value
  std::printf(
      "a2 %.5f +- %.5f (vNE %.5f, second Sonine %.5f); a3 %.5f +- %.5f (second Sonine "
      "%.5f)\n",
      s.a2, s.a2_ci, first, kWhiteNoise05.a2, s.a3, s.a3_ci, kWhiteNoise05.a3);
  EXPECT_NEAR(s.a2, first, s.a2_ci + 2 * delta + 2 / n * (1 + first));
  const double T_vne = (1 - 1 / n) * std::pow(2 * beta / (K0 * (1 + 3 * first / 16)), 2.0 / 3);
  const double T_plain = (1 - 1 / n) * std::pow(2 * beta / K0, 2.0 / 3);
  const double allowance =
      T_vne * (2.0 / 3 * (3.0 / 16 * 2 * delta + std::fabs(kWhiteNoise05.a3) / 64) + 1 / n);
  std::printf("T_st %.5f +- %.5f (with vNE's a2 %.5f, allowance %.5f; Maxwellian %.5f)\n", s.T,
              s.T_ci, T_vne, allowance, T_plain);
  EXPECT_NEAR(s.T, T_vne, s.T_ci + allowance);
  EXPECT_GT(std::fabs(s.T - T_plain), s.T_ci + allowance) << "the a2 term is not resolved";
}

TEST(Dimension, HardDisksInTheHomogeneousCoolingStateHaveFirstSonineA2) {
  // The Gaussian thermostat gives the HCS's scaled state. alpha = 0.8, away from the strong
  // dissipation where the HCS's Sonine approximations part (at alpha = 0.5 in d = 2: vNE 0.0829,
  // second Sonine 0.0655) and from a2's zero near 0.7: vNE -0.02194, second Sonine -0.02551.
  // Tolerance as for white noise: twice their difference, the run's interval and 2/n (1 + |a2|).
  const double alpha = 0.8, n = 2000;
  const char* text = R"(model: dsmc
seed: 14
ensembles: 40
dsmc:
  particles: 2000
  dimension: 2
  alpha: 0.8
  beta: 0
  thermostat: gaussian
  gamma: 1
  kernel: {lambda: 1, C: 0.0795774715459477}
  t_end: 400
  observe_every: 1
  moments: 3
  steady_from: 20
)";
  const Steady s = run_steady(text, {});
  const double first = vne_a2(alpha, 2, false), delta = std::fabs(first - kHcs08.a2);
  EXPECT_NEAR(first, -0.02194, 5e-6);  // beyond.md's d = 2 value
  std::printf(
      "a2 %.5f +- %.5f (vNE %.5f, second Sonine %.5f); a3 %.5f +- %.5f (second Sonine "
      "%.5f)\n",
      s.a2, s.a2_ci, first, kHcs08.a2, s.a3, s.a3_ci, kHcs08.a3);
  EXPECT_NEAR(s.a2, first, s.a2_ci + 2 * delta + 2 / n * (1 + std::fabs(first)));
  EXPECT_NEAR(s.T, 1.0, 1e-12);  // held at T0 to round-off
}

TEST(Dimension, HardDisksFollowHaffsLawWithinTheSonineBand) {
  // dT/dt = -K T^{3/2}: T = T(0) / (1 + t/t0)^2, t0 = 2 / (K sqrt(T(0))), E[T(0)] = (1 - 1/n) T0,
  // K carrying (n/(n-1))^{1/2} (the pairs' E|u|^3 at finite n, as in FreeCooling). alpha = 0.9.
  // The Sonine factor of K goes from 1 (the Maxwellian start) towards its HCS value as a2
  // relaxes, so T lies between Haff's law without it (the lower edge) and with the HCS's (the
  // upper): that one is taken with a2 = vNE - 2 |vNE - second Sonine| (-0.0325, the a2
  // allowance of the HCS test) and second Sonine's a3/64. Every row within the band widened by
  // its interval (family-wise 0.999), and the lower edge rejected at late times.
  const double alpha = 0.9, n = 10000, N = 120;
  const double first = vne_a2(alpha, 2, false);
  const double a2_far = first - 2 * std::fabs(first - kHcs09.a2);
  const double K0 = std::pow(M_PI, 1.5) * kGC * (1 - alpha * alpha) * std::sqrt(n / (n - 1));
  const double T0 = 1 - 1 / n;
  const auto haff = [&](double t, double factor) {
    const double t0 = 2 / (K0 * factor * std::sqrt(T0));
    return T0 / ((1 + t / t0) * (1 + t / t0));
  };
  const double far = 1 + 3 * a2_far / 16 + kHcs09.a3 / 64;
  const test::DsmcRun r(make(
      {"dsmc.particles=10000", "dsmc.alpha=0.9", "dsmc.thermostat=none", "dsmc.kernel.lambda=1",
       "dsmc.kernel.C=" + format_real(kGC), "dsmc.t_end=96", "dsmc.observe_every=8"},
      15, static_cast<std::uint64_t>(N)));
  const double z = test::family_z(2 * 13);
  const std::size_t last = r.times.size() - 1;
  EXPECT_LT(r.at(last, kTemperature).mean, 0.05);  // T falls by a factor 25
  for (std::size_t m = 1; m < r.times.size(); ++m) {
    const double t = r.times[m];
    const MeanCi T = r.at(m, kTemperature);
    const double ci = z * std::sqrt(T.variance / N), lo = haff(t, 1.0), hi = haff(t, far);
    if (m == last || m == 1)
      std::printf("t %.0f: T (1 + t/t0)^2 %.5f +- %.5f, band [1, %.5f] (vNE %.5f)\n", t,
                  T.mean / lo, ci / lo, hi / lo, haff(t, 1 + 3 * first / 16) / lo);
    EXPECT_GT(T.mean, lo - ci) << "t=" << t;
    EXPECT_LT(T.mean, hi + ci) << "t=" << t;
    if (m == last) EXPECT_GT(T.mean, lo + ci) << "the Sonine correction is not resolved";
  }
}

TEST(Dimension, PlaneRunsKeepEveryVelocityInThePlaneAndConserveMomentum) {
  // Every scheme and thermostat, both geometries, hard disks and Maxwell molecules, odd n (the
  // unpaired kick): v_z is exactly 0 after the run, and without heating the momentum is kept.
  const std::vector<std::vector<std::string>> variants = {
      {"dsmc.beta=0.5"},
      {"dsmc.beta=0.5", "dsmc.scheme=euler", "dsmc.steps=8"},
      {"dsmc.beta=0.5", "dsmc.scheme=strang", "dsmc.steps=8", "dsmc.majorant=pairwise"},
      {"dsmc.thermostat=gaussian", "dsmc.beta=0"},
      {"dsmc.thermostat=gaussian", "dsmc.beta=0", "dsmc.scheme=strang", "dsmc.steps=8"},
      {"dsmc.thermostat=none", "dsmc.beta=0", "dsmc.majorant=global"},
      {"dsmc.thermostat=none", "dsmc.beta=0", "dsmc.kernel.lambda=0"},
  };
  for (const char* geometry : {"impact", "uniform"})
    for (const auto& variant : variants) {
      std::vector<std::string> sets = {"dsmc.particles=301",
                                       "dsmc.alpha=0.6",
                                       "dsmc.kernel.lambda=1",
                                       "dsmc.kernel.C=0.1",
                                       "dsmc.t_end=16",
                                       "dsmc.observe_every=16",
                                       "dsmc.geometry=" + std::string(geometry)};
      sets.insert(sets.end(), variant.begin(), variant.end());
      const Config c = make(sets, 3, 1);
      DsmcEnsemble e(c.dsmc, 3, 0);
      Vec3 p0;
      for (const auto& q : e.particles()) p0 += q.v;
      ASSERT_TRUE(e.advance_to(16.0));
      EXPECT_GT(e.counts().collisions, 1000u) << geometry << " " << variant[0];
      Vec3 p1;
      for (const auto& q : e.particles()) {
        ASSERT_EQ(q.v.z, 0.0) << geometry << " " << variant[0];
        p1 += q.v;
      }
      if (c.dsmc.beta == 0.0)
        EXPECT_LE(norm(p1 - p0), 1e-11 * 301) << geometry << " " << variant[0];
    }
}

TEST(Dimension, ThreadsShardsAndCheckpointsGiveTheSameBits) {
  for (const std::vector<std::string> sets :
       {std::vector<std::string>{},
        std::vector<std::string>{"dsmc.thermostat=gaussian", "dsmc.beta=0", "dsmc.scheme=strang",
                                 "dsmc.steps=16"},
        std::vector<std::string>{"dsmc.geometry=uniform", "dsmc.scheme=euler", "dsmc.steps=16"}}) {
    TempDir dir;
    std::string args;
    for (const auto& s : sets) args += " --set " + s;
    const std::string cfg = dir.write("c.yaml", kHeated) + args;
    const std::string one = test::expect_threads_and_shards_identical(dir, cfg);
    H5Reader f(one);
    EXPECT_NE(f.attr_string("/", "config").find("dimension: 2"), std::string::npos);
  }
  // An ensemble saved mid-run and restored continues bit for bit.
  for (const std::vector<std::string> sets :
       {std::vector<std::string>{},
        std::vector<std::string>{"dsmc.thermostat=gaussian", "dsmc.beta=0"},
        std::vector<std::string>{"dsmc.geometry=uniform", "dsmc.scheme=strang", "dsmc.steps=16"}}) {
    const Config c = parse_config(kHeated, "c.yaml", sets);
    test::expect_restored_ensemble_continues_identically(c.dsmc, 12, 3, 1.0, 2.0);
  }
  // A state from space is no state of the plane.
  {
    const Config space = parse_config(kHeated, "c.yaml", {"dsmc.dimension=3"});
    const Config plane = parse_config(kHeated, "c.yaml");
    TempDir dir;
    DsmcEnsemble a(space.dsmc, 12, 0);
    a.advance_to(0.5);
    {
      H5Writer w(dir.file("state.h5"));
      a.save(w, "/e");
      w.commit();
    }
    H5Reader r(dir.file("state.h5"));
    try {
      DsmcEnsemble b(plane.dsmc, r, "/e");
      ADD_FAILURE() << "a d = 3 state restored into d = 2";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(", not 0 in dimension 2"), std::string::npos)
          << e.what();
    }
  }
}

TEST(Dimension, RunKilledBySigtermResumesToTheUninterruptedOutput) {
  // White noise with a histogram (nosplit), and Strang splitting with the Gaussian thermostat.
  // Each lasts about 2 s here, long enough to be signalled mid-run.
  for (const char* extra :
       {"  particles: 60000\n  t_end: 10\n  beta: 1\n"
        "  histogram: {shells: 8, radius: 8, component: true}\n",
        "  particles: 100000\n  t_end: 20\n  beta: 0\n  thermostat: gaussian\n"
        "  scheme: strang\n  steps: 200\n  histogram: {shells: 8, radius: 8}\n"}) {
    TempDir dir;
    const std::string cfg = dir.write("c.yaml", std::string(R"(model: dsmc
seed: 42
ensembles: 3
checkpoint: {every_seconds: 3600}
dsmc:
  dimension: 2
  alpha: 0.5
  gamma: 4
  kernel: {lambda: 1, C: 0.0795774715459477}
  observe_every: 0.5
  moments: 3
)") + extra);
    test::expect_sigterm_resumes_identically(dir, cfg);
  }
}

TEST(Dimension, ThreeDimensionalImpactIsTheUniformRunBitForBit) {
  // In d = 3 the impact law is GRW05's uniform e: every dataset agrees, only the stored config
  // text says impact.
  TempDir dir;
  const std::string cfg = dir.write("c.yaml", kHeated), a = dir.file("a.h5"), b = dir.file("b.h5");
  expect_ok(run_granboltz("run " + cfg +
                          " -q --set dsmc.dimension=3 --set dsmc.geometry=uniform -o " + a));
  expect_ok(run_granboltz("run " + cfg +
                          " -q --set dsmc.dimension=3 --set dsmc.geometry=impact -o " + b));
  H5Reader ra(a), rb(b);
  const auto names = ra.datasets();
  ASSERT_EQ(names, rb.datasets());
  for (const auto& name : names)
    if (name.rfind("/provenance", 0) != 0)
      EXPECT_EQ(ra.read_bytes(name), rb.read_bytes(name)) << name;
  EXPECT_EQ(ra.attr_string("/", "config").find("geometry"), std::string::npos);
  EXPECT_NE(rb.attr_string("/", "config").find("geometry: impact"), std::string::npos);
}

TEST(Dimension, ConfigWritesDimensionAndGeometryOnlyOffTheDefault) {
  const auto text_of = [](const std::vector<std::string>& sets) {
    return parse_config(kHeated, "c.yaml", sets).to_yaml(true);
  };
  // d = 2: impact by default; both keys written, and the text reads back to itself.
  const Config c = parse_config(kHeated, "c.yaml");
  EXPECT_EQ(c.dsmc.dimension, 2);
  EXPECT_EQ(c.dsmc.geometry, Geometry::kImpact);
  EXPECT_EQ(c.dsmc.kernel.area, 2 * M_PI);
  for (const auto& [sets, geometry] : std::vector<std::pair<std::vector<std::string>, std::string>>{
           {{}, "impact"},
           {{"dsmc.geometry=uniform"}, "uniform"},
           {{"dsmc.dimension=3", "dsmc.geometry=impact"}, "impact"}}) {
    const std::string text = text_of(sets);
    EXPECT_NE(text.find("geometry: " + geometry), std::string::npos) << text;
    EXPECT_NE(text.find("dimension: "), std::string::npos) << text;
    EXPECT_EQ(parse_config(text, "stored").to_yaml(true), text);
    const Config back = parse_config(text, "stored");
    const Config orig = parse_config(kHeated, "c.yaml", sets);
    EXPECT_EQ(back.dsmc.dimension, orig.dsmc.dimension);
    EXPECT_EQ(back.dsmc.geometry, orig.dsmc.geometry);
  }
  EXPECT_NE(text_of({}).find("dimension: 2"), std::string::npos);
  // d = 3 uniform, the default (given or not): no key, the text of every older config.
  for (const auto& sets : {std::vector<std::string>{"dsmc.dimension=3"},
                           std::vector<std::string>{"dsmc.dimension=3", "dsmc.geometry=uniform"}}) {
    const std::string text = text_of(sets);
    EXPECT_EQ(text.find("dimension"), std::string::npos) << text;
    EXPECT_EQ(text.find("geometry"), std::string::npos) << text;
    EXPECT_EQ(parse_config(text, "stored").dsmc.dimension, 3);
    EXPECT_EQ(parse_config(text, "stored").dsmc.kernel.area, 4 * M_PI);
  }
  std::string old = kHeated;
  old.erase(old.find("  dimension: 2\n"), std::string("  dimension: 2\n").size());
  const std::string text3 = parse_config(old, "c.yaml").to_yaml(true);
  EXPECT_EQ(text3.find("dimension"), std::string::npos) << text3;
  EXPECT_EQ(parse_config(old, "c.yaml").dsmc.geometry, Geometry::kUniform);
}

TEST(Dimension, BadDimensionOrGeometryGivesOneLineErrors) {
  const auto error = [](const std::vector<std::string>& sets) {
    return test::config_error(kHeated, sets);
  };
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"dsmc.dimension=4"}, "dsmc.dimension = 4: must be one of 2, 3"},
      {{"dsmc.dimension=1"}, "dsmc.dimension = 1: must be one of 2, 3"},
      // An integer key like every other: 2.0 is 2, a fraction or a string is refused.
      {{"dsmc.dimension=2.5"}, "dsmc.dimension = 2.5: not an integer"},
      {{"dsmc.dimension='2'"}, "dsmc.dimension = \"2\": must be an integer, not a quoted string"},
      {{"dsmc.dimension=!!str 2"},
       "dsmc.dimension = !!str 2: must be an integer, not a value tagged !!str"},
      {{"dsmc.geometry=bogus"}, "dsmc.geometry = bogus: must be one of impact, uniform"},
      {{"dsmc.geometry=[1]"}, "dsmc.geometry = [...]: must be one of impact, uniform"},
  };
  for (const auto& [sets, message] : cases) {
    const std::string e = error(sets);
    EXPECT_EQ(e, message) << sets[0];
    EXPECT_EQ(e.find('\n'), std::string::npos) << sets[0];
  }
  // Weighted particles run in either dimension.
  for (const char* d : {"dsmc.dimension=2", "dsmc.dimension=3"})
    EXPECT_EQ(error({d, "dsmc.weights={method: swpm, kappa: 0, max_particles: 1000}"}), "");
}
