// Free flights between collisions (physics/flight/): drag, uniform shear flow and their sums with
// white noise, against exact results.
//
// The propagator: v(s) = exp(-A s) v + Gaussian noise of covariance Sigma(s), A = gamma I +
// a e_x e_y^T; checked by its moments over many draws and by the semigroup identity
// Sigma(s1 + s2) = M(s2) Sigma(s1) M(s2)^T + Sigma(s2), M(s) = exp(-A s).
//
// The engine, lambda = 0 (docs/physics.md, "Shear flow and drag"): with e uniform on S^{d-1}
// every pair collides at the same rate, so the expectation of the centred second-moment tensor
// C = (1/n) sum (v - V)(v - V)^T of the n-particle system obeys, exactly for any n,
//   dE[C]/dt = (nu/2) [(4 p^2 - 1) C + (4 b^2/d) tr C I] - a (E C + C E^T) - 2 gamma C
//              + 2 beta (1 - 1/n) I,
// p = (1 - alpha)/4, b = (1 + alpha)/4, E = e_x e_y^T, nu = |S^{d-1}| gamma_B C = 1 here: the
// collision part is that of the prepared-state tests, the drift and drag act linearly on v - V,
// and the noise of the centred velocities has covariance (1 - 1/n) 2 beta I. E[C(0)] = (1 - 1/n)
// T0 I. Its steady solution at the shear rate a_s = nu (3 - alpha) sqrt(3 (1 - alpha^2))/8
// (d = 3; sqrt(2 (1 - alpha^2)) in d = 2) has T constant and P/p of shared/reference/transport.md
// §2, which the test checks of its own reference first. Under the Gaussian thermostat the stored
// velocities follow the unthermostatted equation and the true ones are scaled to T0, so
// E[P_ij] = T0 C_ij/(tr C/d) up to the O(1/n) bias of a ratio of sums.
//
// Drag with noise, lambda = 0, d = 3 (transport.md §4, exact): T_st = 2 beta/(zeta + 2 gamma),
// zeta = nu (1 - alpha^2)/4, and a2 = 2 (1-alpha)^2 (1+alpha)/[13 - 9 alpha + alpha^2 - alpha^3
// + 12 omega (1 - alpha)], omega = 2 gamma/zeta.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "granboltz/dsmc/run.hpp"
#include "granboltz/physics/flight/list.hpp"
#include "granboltz/random/rng.hpp"
#include "test_support.hpp"

using namespace granboltz;

namespace {

constexpr int kTemperature = 4, kPressure = 5;
using Matrix = std::array<double, 9>;

struct Flow {
  int d = 3;
  double alpha = 0.5;
  double shear = 0.0, drag = 0.0, beta = 0.0;
  std::string thermostat = "white_noise";  // beta = 0: free cooling
};

/// nu = 1: C = 1/|S^{d-1}|, gamma_B = 1.
double kernel_C(int d) { return d == 3 ? 1 / (4 * M_PI) : 1 / (2 * M_PI); }

Config flow_config(const Flow& f, std::uint64_t n, std::uint64_t N, std::uint64_t seed,
                   double t_end, double every, const std::vector<std::string>& extra = {}) {
  std::vector<std::string> sets = {"model=dsmc",
                                   "seed=" + std::to_string(seed),
                                   "ensembles=" + std::to_string(N),
                                   "dsmc.particles=" + std::to_string(n),
                                   "dsmc.dimension=" + std::to_string(f.d),
                                   "dsmc.geometry=uniform",
                                   "dsmc.alpha=" + format_real(f.alpha),
                                   "dsmc.beta=" + format_real(f.beta),
                                   "dsmc.thermostat=" + f.thermostat,
                                   "dsmc.gamma=1",
                                   "dsmc.kernel.lambda=0",
                                   "dsmc.kernel.C=" + format_real(kernel_C(f.d)),
                                   "dsmc.t_end=" + format_real(t_end),
                                   "dsmc.observe_every=" + format_real(every)};
  if (f.shear != 0) sets.push_back("dsmc.shear.rate=" + format_real(f.shear));
  if (f.drag != 0) sets.push_back("dsmc.drag.gamma=" + format_real(f.drag));
  sets.insert(sets.end(), extra.begin(), extra.end());
  return parse_config("{}", "test", sets);
}

/// dE[C]/dt of the header, row-major d x d in a 3 x 3 array.
Matrix rate(const Flow& f, double n, const Matrix& C) {
  const double nu = 1.0, p = (1 - f.alpha) / 4, b = (1 + f.alpha) / 4;
  double tr = 0;
  for (int i = 0; i < f.d; ++i) tr += C[4 * i];
  Matrix r{};
  for (int i = 0; i < f.d; ++i)
    for (int j = 0; j < f.d; ++j) {
      double x = 0.5 * nu * (4 * p * p - 1) * C[3 * i + j] - 2 * f.drag * C[3 * i + j];
      if (i == j) x += 0.5 * nu * 4 * b * b / f.d * tr + 2 * f.beta * (1 - 1 / n);
      // -(E C + C E^T)_ij, (E C)_ij = delta_ix C_yj
      if (i == 0) x -= f.shear * C[3 * 1 + j];
      if (j == 0) x -= f.shear * C[3 * i + 1];
      r[3 * i + j] = x;
    }
  return r;
}

/// E[C(t)] by RK4 in steps of at most 1e-3 (error far below 1e-10 here).
Matrix exact_second_moments(const Flow& f, double n, double T0, double t) {
  Matrix C{};
  for (int i = 0; i < f.d; ++i) C[4 * i] = (1 - 1 / n) * T0;
  const int steps = std::max(1, static_cast<int>(std::ceil(t / 1e-3)));
  const double h = t / steps;
  auto axpy = [](const Matrix& a, double s, const Matrix& b) {
    Matrix r;
    for (int k = 0; k < 9; ++k) r[k] = a[k] + s * b[k];
    return r;
  };
  for (int s = 0; s < steps; ++s) {
    const Matrix k1 = rate(f, n, C), k2 = rate(f, n, axpy(C, h / 2, k1));
    const Matrix k3 = rate(f, n, axpy(C, h / 2, k2)), k4 = rate(f, n, axpy(C, h, k3));
    for (int k = 0; k < 9; ++k) C[k] += h / 6 * (k1[k] + 2 * k2[k] + 2 * k3[k] + k4[k]);
  }
  return C;
}

double a_s(int d, double alpha) {
  return (3 - alpha) * std::sqrt((d == 3 ? 3 : 2) * (1 - alpha * alpha)) / 8;
}

/// Every P_ij(t_m) against the exact E[C(t_m)] (or, gaussian, T0 C/(tr C/d)).
void expect_exact_pressure(const Flow& f, std::uint64_t n, std::uint64_t N, std::uint64_t seed,
                           double t_end, double every, const std::vector<std::string>& extra = {}) {
  const test::DsmcRun r(flow_config(f, n, N, seed, t_end, every, extra));
  const int comps = f.d * (f.d + 1) / 2;
  const double z = test::family_z(static_cast<int>(r.times.size()) * comps);
  const bool gaussian = f.thermostat == "gaussian";
  const double nn = static_cast<double>(n);
  for (std::size_t m = 0; m < r.times.size(); ++m) {
    const Matrix C = exact_second_moments(f, nn, 1.0, r.times[m]);
    double tr = 0;
    for (int i = 0; i < f.d; ++i) tr += C[4 * i];
    for (int i = 0; i < f.d; ++i)
      for (int j = i; j < f.d; ++j) {
        const MeanCi P = r.at(m, kPressure + 3 * i + j);
        // The Gaussian fold divides by the sample's own trace: an O(1/n) bias of the ratio,
        // allowed as 2/n of the value (a tenth of the intervals here).
        const double expected = gaussian ? C[3 * i + j] / (tr / f.d) : C[3 * i + j];
        const double slack = gaussian ? 2 / nn * std::abs(expected) : 0.0;
        EXPECT_NEAR(P.mean, expected, z * std::sqrt(P.variance / static_cast<double>(N)) + slack)
            << "P_" << i << j << " t=" << r.times[m] << " d=" << f.d << " a=" << f.shear
            << " gamma_d=" << f.drag << " beta=" << f.beta << " " << f.thermostat;
      }
  }
}

}  // namespace

TEST(Flight, PropagatorCovarianceIsASemigroup) {
  for (const auto& fl : {LinearFlight{1.0, 0.0, 0.7}, LinearFlight{0.3, 0.9, -1.3},
                         LinearFlight{2.0, 1e-7, 0.2}, LinearFlight{0.5, 3.0, 0.0}}) {
    for (const auto& [s1, s2] : {std::pair{0.3, 0.5}, std::pair{1e-4, 2.0}, std::pair{1.7, 0.05}}) {
      // M(s2) Sigma(s1) M(s2)^T + Sigma(s2) in the xy block, zz separately.
      const auto c1 = fl.covariance(s1), c2 = fl.covariance(s2), c = fl.covariance(s1 + s2);
      const double e = std::exp(-fl.gamma * s2), k = -fl.shear * s2;
      // M = e [[1, k], [0, 1]] on (x, y).
      const double xx = e * e * (c1.xx + 2 * k * c1.xy + k * k * c1.yy) + c2.xx;
      const double xy = e * e * (c1.xy + k * c1.yy) + c2.xy;
      const double yy = e * e * c1.yy + c2.yy;
      EXPECT_NEAR(c.xx, xx, 1e-13 * (1 + std::abs(xx)));
      EXPECT_NEAR(c.xy, xy, 1e-13 * (1 + std::abs(xy)));
      EXPECT_NEAR(c.yy, yy, 1e-13 * (1 + std::abs(yy)));
    }
  }
  // The series and the closed form of int_0^1 u^m e^{-xu} du meet at x = 1/2.
  for (int m = 0; m < 3; ++m)
    EXPECT_NEAR(exp_moment(m, std::nextafter(0.5, 0.0)), exp_moment(m, 0.5), 1e-15);
}

TEST(Flight, PropagatorDrawsTheExactMeanAndCovariance) {
  // 400,000 draws from one start velocity: sample mean and covariance within 4.4 sigma
  // (family-wise 0.999 over the 9 checks per case; the covariance's variance is that of a
  // product of Gaussians).
  Engine eng = make_stream(11, 0, Consumer::kSweep);
  const Vec3 v{0.8, -1.1, 0.4};
  const double z = test::family_z(9);
  for (const auto& fl :
       {LinearFlight{1.0, 0.0, 0.7}, LinearFlight{0.3, 0.9, -1.3}, LinearFlight{0.0, 0.5, 1.0}}) {
    const double s = 0.8;
    const int K = 400000;
    double m[3] = {}, q[6] = {};
    std::vector<Vec3> draws(K);
    for (auto& w : draws) w = fl.propagate<3>(v, s, eng);
    for (const auto& w : draws) m[0] += w.x / K, m[1] += w.y / K, m[2] += w.z / K;
    const Vec3 mu = fl.mean(v, s);
    const auto c = fl.covariance(s);
    for (const auto& w : draws) {
      const double dx = w.x - mu.x, dy = w.y - mu.y, dz = w.z - mu.z;
      q[0] += dx * dx / K, q[1] += dx * dy / K, q[2] += dy * dy / K, q[3] += dz * dz / K;
      q[4] += dx * dz / K, q[5] += dy * dz / K;
    }
    if (fl.beta == 0) {  // deterministic: the mean map itself
      EXPECT_EQ(draws[0].x, mu.x);
      EXPECT_EQ(draws[0].y, mu.y);
      continue;
    }
    EXPECT_NEAR(m[0], mu.x, z * std::sqrt(c.xx / K));
    EXPECT_NEAR(m[1], mu.y, z * std::sqrt(c.yy / K));
    EXPECT_NEAR(m[2], mu.z, z * std::sqrt(c.yy / K));
    EXPECT_NEAR(q[0], c.xx, z * std::sqrt(2.0 / K) * c.xx);
    EXPECT_NEAR(q[1], c.xy, z * std::sqrt((c.xx * c.yy + c.xy * c.xy) / K));
    EXPECT_NEAR(q[2], c.yy, z * std::sqrt(2.0 / K) * c.yy);
    EXPECT_NEAR(q[3], c.yy, z * std::sqrt(2.0 / K) * c.yy);
    EXPECT_NEAR(q[4], 0.0, z * std::sqrt(c.xx * c.yy / K));
    EXPECT_NEAR(q[5], 0.0, z * std::sqrt(c.yy * c.yy / K));
  }
  // In the plane z stays 0.
  EXPECT_EQ((LinearFlight{1.0, 0.2, 0.5}.propagate<2>(Vec3{1, 2, 0}, 0.3, eng).z), 0.0);
}

TEST(Flight, SteadyShearOfTheReferenceIsTransportsExactState) {
  // The test's own reference: at a_s the late solution has dT/dt = 0 and P/p of transport.md.
  for (const int d : {3, 2}) {
    const double al = 0.5;
    const Flow f{d, al, a_s(d, al)};
    const Matrix C = exact_second_moments(f, 1e12, 1.0, 60.0),
                 C2 = exact_second_moments(f, 1e12, 1.0, 61.0);
    double tr = 0, tr2 = 0;
    for (int i = 0; i < d; ++i) tr += C[4 * i], tr2 += C2[4 * i];
    const double p = tr / d;
    EXPECT_NEAR(tr2 / tr, 1.0, 1e-9) << "T constant at a_s, d=" << d;
    EXPECT_NEAR(C[4] / p, (1 + al) / (3 - al), 1e-9);
    EXPECT_NEAR(-C[1] / p, std::sqrt((d == 3 ? 3 : 2) * (1 - al * al)) / (3 - al), 1e-9);
    if (d == 3) {
      EXPECT_NEAR(C[8] / p, (1 + al) / (3 - al), 1e-9);
      EXPECT_NEAR(C[0] / p, 3 - 2 * (1 + al) / (3 - al), 1e-9);
    }
  }
}

TEST(Flight, ShearFlowOfMaxwellMoleculesFollowsTheExactSecondMoments) {
  // No thermostat: at the steady shear rate (T constant) in d = 3 and d = 2, and at twice it
  // (the gas heats exponentially).
  expect_exact_pressure({3, 0.5, a_s(3, 0.5)}, 1000, 200, 1, 8, 0.5);
  expect_exact_pressure({2, 0.5, a_s(2, 0.5)}, 1000, 200, 2, 8, 0.5);
  expect_exact_pressure({3, 0.7, 2 * a_s(3, 0.7)}, 1000, 200, 3, 5, 0.5);
}

TEST(Flight, DragNoiseAndShearTogetherFollowTheExactSecondMoments) {
  expect_exact_pressure({3, 0.6, 0.4, 0.3, 0.5}, 1000, 200, 4, 6, 0.5);
  expect_exact_pressure({2, 0.8, -0.7, 0.2, 1.0}, 1000, 200, 5, 6, 0.5);
  // Drag alone cools the gas faster: dT/dt = -(zeta + 2 gamma_d) T.
  expect_exact_pressure({3, 0.5, 0.0, 0.4, 0.0}, 1000, 200, 6, 4, 0.5);
}

TEST(Flight, ShearUnderTheGaussianThermostatHasTheExactRatiosAtT0) {
  // The thermostat frees the shear rate: any a has a steady P/p (the dominant eigenvector of the
  // unthermostatted equation), reached from the Maxwellian as computed.
  expect_exact_pressure({3, 0.5, 1.0, 0.0, 0.0, "gaussian"}, 2000, 200, 7, 6, 0.5);
  expect_exact_pressure({2, 0.9, 0.3, 0.0, 0.0, "gaussian"}, 2000, 200, 8, 6, 0.5);
}

TEST(Flight, SplittingSchemesRunTheExactFlightBetweenCollisionSteps) {
  // Strang splitting with the exact flight: the splitting error is O(dt^2) (here dt = 0.01, a
  // relative error about 1e-5, far below the intervals) in both the flight and the thermostat.
  expect_exact_pressure({3, 0.5, a_s(3, 0.5), 0.2, 0.5}, 1000, 100, 9, 4, 0.5,
                        {"dsmc.scheme=strang", "dsmc.steps=400"});
  expect_exact_pressure({3, 0.5, 1.0, 0.0, 0.0, "gaussian"}, 2000, 100, 10, 4, 0.5,
                        {"dsmc.scheme=strang", "dsmc.steps=400"});
}

TEST(Flight, DragWithNoiseHasTheExactSteadyTemperatureAndA2) {
  const double alpha = 0.5, gd = 0.5, beta = 1.0, nu = 1.0;
  const double zeta = nu * (1 - alpha * alpha) / 4, omega = 2 * gd / zeta;
  const double T = 2 * beta / (zeta + 2 * gd);
  const double a2 =
      2 * (1 - alpha) * (1 - alpha) * (1 + alpha) /
      (13 - 9 * alpha + alpha * alpha - alpha * alpha * alpha + 12 * omega * (1 - alpha));
  test::TempDir dir;
  const Config c =
      flow_config({3, alpha, 0.0, gd, beta}, 2000, 32, 12, 40, 1, {"dsmc.steady_from=10"});
  const std::string cfg = dir.write("c.yaml", c.to_yaml(true)), out = dir.file("o.h5");
  const auto r = test::run_granboltz("run " + cfg + " -q -o " + out);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  H5Reader h(out);
  const double n = 2000;
  // The centred temperature carries (1 - 1/n); a2, a ratio, an O(1/n) bias allowed as 2/n.
  EXPECT_NEAR(h.read_double("/steady/temperature/mean")[0], (1 - 1 / n) * T,
              h.read_double("/steady/temperature/ci")[0]);
  EXPECT_NEAR(h.read_double("/steady/a2/mean")[0], a2, h.read_double("/steady/a2/ci")[0] + 2 / n);
}

TEST(Flight, ShearRunsAreIdenticalOnThreadsShardsAndAfterACheckpoint) {
  test::TempDir dir;
  // Hard spheres: the majorant's windows are part of the state (a window ends at 0.45/a).
  const Config c =
      flow_config({3, 0.7, 0.9, 0.0, 0.3}, 300, 4, 13, 3, 0.5, {"dsmc.kernel.lambda=1"});
  const std::string cfg = dir.write("c.yaml", c.to_yaml(true));
  test::expect_threads_and_shards_identical(dir, cfg);
  // Saved mid-window and restored: the same particles, collisions and draws.
  test::expect_restored_ensemble_continues_identically(c.dsmc, 13, 1, 1.3, 3.0);
  const Config g = flow_config({3, 0.7, 0.9, 0.2, 0.0, "none"}, 300, 4, 14, 3, 0.5,
                               {"dsmc.scheme=strang", "dsmc.steps=30"});
  test::expect_restored_ensemble_continues_identically(g.dsmc, 14, 0, 1.0, 3.0);
}

TEST(Flight, ConfigKeysAreCheckedAndWrittenOnlyWhenGiven) {
  const std::vector<std::string> base = {"model=dsmc",           "seed=1",          "ensembles=1",
                                         "dsmc.particles=10",    "dsmc.alpha=0.5",  "dsmc.beta=0",
                                         "dsmc.kernel.lambda=1", "dsmc.kernel.C=1", "dsmc.t_end=1"};
  auto parse = [&](std::vector<std::string> extra) {
    auto sets = base;
    sets.insert(sets.end(), extra.begin(), extra.end());
    return parse_config("{}", "t", sets);
  };
  const Config plain = parse({});
  EXPECT_EQ(plain.to_yaml(true).find("shear"), std::string::npos);
  EXPECT_EQ(plain.to_yaml(true).find("drag"), std::string::npos);
  const Config sheared = parse({"dsmc.shear.rate=0.5", "dsmc.drag.gamma=0.25"});
  EXPECT_EQ(sheared.dsmc.shear_rate(), 0.5);
  EXPECT_EQ(sheared.dsmc.drag_gamma(), 0.25);
  EXPECT_EQ(sheared.dsmc.majorant,
            MajorantKind::kGlobal);  // auto: pairwise cannot follow the drift
  const Config again = parse_config(sheared.to_yaml(true), "t", {});
  EXPECT_EQ(again.dsmc.shear_rate(), 0.5);
  EXPECT_EQ(again.dsmc.drag_gamma(), 0.25);
  auto refused = [&](std::vector<std::string> extra, const std::string& part) {
    try {
      parse(extra);
      ADD_FAILURE() << extra.back() << " accepted";
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
    }
  };
  refused({"dsmc.drag.gamma=-1"}, "dsmc.drag.gamma");
  refused({"dsmc.shear.rate=.inf"}, "dsmc.shear.rate");
  refused({"dsmc.shear.rat=1"}, "rat");
  refused({"dsmc.shear.rate=1", "dsmc.majorant=pairwise"}, "dsmc.majorant");
  refused({"dsmc.drag.gamma=1", "dsmc.thermostat=gaussian"}, "dsmc.drag");
  refused({"dsmc.shear.rate=1", "dsmc.thermostat=gaussian"}, "dsmc.shear");  // lambda = 1, nosplit
  refused({"dsmc.drag.gamma={a: 1}"}, "per species needs dsmc.species");
  refused({"dsmc.shear.rate=1", "dsmc.weights.method=swpm", "dsmc.weights.kappa=0",
           "dsmc.weights.max_particles=20"},
          "dsmc.shear: not available with dsmc.weights");
  refused({"dsmc.shear.rate=1", "dsmc.species=[{name: a, fraction: 1}]"}, "dsmc.shear");
}

TEST(Flight, ShearMajorantBoundsEverySpeedOfItsWindow) {
  // Hard spheres, no splitting: U_max >= 2 g max|v| (g = 1.25, the growth of a speed over a
  // window) at every stop, so that no pair within the window can outrun it. Without the factor
  // g the drift would carry relative speeds beyond U_max between stops.
  const Config c =
      flow_config({3, 0.7, 2.0, 0.0, 0.0}, 500, 1, 15, 6, 0.5, {"dsmc.kernel.lambda=1"});
  DsmcEnsemble e(c.dsmc, 15, 0);
  const double g = flight::Shear::growth(0.45);
  for (double t = 0.05; t <= 6.0; t += 0.05) {
    e.advance_to(t);
    double r = 0;
    for (const auto& q : e.particles()) r = std::max(r, std::sqrt(norm2(q.v)));
    ASSERT_GE(e.u_max(), 2 * g * r * (1 - 1e-12)) << "t = " << t;
  }
}
