// The general gas (dsmc/gas.hpp): mixtures and rough particles. Exact results first: two species
// that are the same gas, an elastic mixture at equipartition, energy exchange of perfectly rough
// elastic spheres (T + T_rot conserved per ensemble, relaxing to T_rot = T), the smooth limit
// beta = -1 (spins untouched, the smooth run's bits), Martin-Piasecki's tracer in an elastic bath
// and the reproducibility of threads, shards, checkpoints and signals. Then the Maxwellian
// approximations with stated allowances: Garzo-Dufty's HCS temperature ratio and the rough-sphere
// theta of Huthmann-Zippelius/Luding, in the HCS and under white noise (beyond.md §4-5).
//
// Each comparison is |x - y| < z sigma (+ an allowance where the reference is approximate), sigma
// the steady intervals' standard errors (batch estimator) combined, z the two-sided family-wise
// 0.1 % quantile over the checks of a test (test::family_z). A ratio (theta, T_a/T_b) is the one
// the simulator stores, /steady/theta and /steady/temperature_ratio/<a>_over_<b>, whose sigma
// includes the covariance of the two temperatures over the ensembles: leaving it out would make
// the sigma too small where a thermostat holds their sum (correlation near -1), too large where
// they move together.
#include <gsl/gsl_cdf.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "granboltz/app/config.hpp"
#include "granboltz/dsmc/gas.hpp"
#include "granboltz/h5/hdf5_io.hpp"
#include "test_support.hpp"

using namespace granboltz;
using granboltz::test::run_granboltz;
using granboltz::test::TempDir;

namespace {

constexpr const char* kHardSpheres = "  kernel: {lambda: 1, C: 0.0795774715459477}\n";

struct Steady {
  double mean, sigma;
};

Steady steady(const H5Reader& f, const std::string& group) {
  return {f.read_double("/steady" + group + "/mean")[0],
          f.read_double("/steady" + group + "/sigma")[0]};
}

std::string run(const TempDir& dir, const std::string& name, const std::string& text) {
  const std::string cfg = dir.write(name + ".yaml", text), out = dir.file(name + ".h5");
  const auto r = run_granboltz("run " + cfg + " -q -o " + out);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  return out;
}

std::string header(int seed, int ensembles, int particles) {
  return "model: dsmc\nseed: " + std::to_string(seed) +
         "\nensembles: " + std::to_string(ensembles) +
         "\ndsmc:\n  particles: " + std::to_string(particles) + "\n";
}

const std::string kTwoEqual =
    "  species:\n"
    "    - {name: a, fraction: 0.5, mass: 1.0, diameter: 1.0}\n"
    "    - {name: b, fraction: 0.5, mass: 1.0, diameter: 1.0}\n";

}  // namespace

// Two species of equal mass, size and alpha are one gas: T_a = T_b, and the mixture's T and a2
// are the one-species run's (the papers' engine), within the statistics.
TEST(Gas, EqualSpeciesAreOneGas) {
  TempDir dir;
  const std::string body = "  alpha: 0.7\n  beta: 0.5\n" + std::string(kHardSpheres) +
                           "  initial: {temperature: 1.5}\n  t_end: 30\n  observe_every: 0.25\n"
                           "  steady_from: 5\n";
  const std::string mix = run(dir, "mix", header(3, 20, 800) + kTwoEqual + body);
  const std::string one = run(dir, "one", header(4, 20, 800) + body + "  majorant: global\n");
  H5Reader m(mix), o(one);
  const double z = test::family_z(4);
  const Steady Ta = steady(m, "/species/a/temperature"), Tb = steady(m, "/species/b/temperature");
  EXPECT_LT(std::fabs(Ta.mean - Tb.mean), z * std::hypot(Ta.sigma, Tb.sigma))
      << Ta.mean << " " << Tb.mean;
  const Steady T = steady(m, "/temperature"), T1 = steady(o, "/temperature");
  EXPECT_LT(std::fabs(T.mean - T1.mean), z * std::hypot(T.sigma, T1.sigma))
      << T.mean << " " << T1.mean;
  const Steady a2 = steady(m, "/a2"), a21 = steady(o, "/a2");
  EXPECT_LT(std::fabs(a2.mean - a21.mean), z * std::hypot(a2.sigma, a21.sigma))
      << a2.mean << " " << a21.mean;
  // The species' temperatures average to the mixture's exactly (x_a = x_b = 1/2).
  const auto ta = m.read_double("/species/a/temperature/mean"),
             tb = m.read_double("/species/b/temperature/mean");
  const auto t = m.read_double("/temperature/mean");
  for (std::size_t k = 0; k < t.size(); ++k) EXPECT_NEAR(0.5 * (ta[k] + tb[k]), t[k], 1e-12 * t[k]);
  EXPECT_EQ(m.read_double("/species/a/density/mean")[0], 0.5);
}

// alpha = 1: the Maxwellian at equipartition is stationary, whatever the masses and sizes, so
// every species keeps T_a = T0 at every time (and the mixture's energy is conserved exactly).
TEST(Gas, ElasticMixtureStaysAtEquipartition) {
  TempDir dir;
  const std::string out = run(dir, "elastic",
                              header(5, 20, 400) +
                                  "  species:\n"
                                  "    - {name: heavy, fraction: 0.25, mass: 10.0, diameter: 2.0}\n"
                                  "    - {name: light, fraction: 0.75, mass: 1.0, diameter: 1.0}\n"
                                  "  alpha: 1\n  thermostat: none\n" +
                                  kHardSpheres + "  t_end: 10\n  observe_every: 1\n");
  H5Reader f(out);
  const auto T = f.read_double("/temperature/mean");
  const double z = test::family_z(2 * 10);
  for (const char* s : {"heavy", "light"}) {
    const std::string g = std::string("/species/") + s + "/temperature";
    const auto mean = f.read_double(g + "/mean"), var = f.read_double(g + "/variance");
    for (std::size_t k = 1; k < mean.size(); ++k)
      EXPECT_LT(std::fabs(mean[k] - mean[0]), z * std::sqrt(2 * var[k] / 20)) << s << " row " << k;
  }
  for (std::size_t k = 1; k < T.size(); ++k) EXPECT_NEAR(T[k], T[0], 1e-12);
}

// Perfectly rough elastic spheres (alpha = beta = 1) conserve T + T_rot (d = d_rot = 3) in every
// ensemble, and relax from T_rot(0) = T0/4 to equipartition T = T_rot = 5/8 T0.
TEST(Gas, RoughElasticRelaxesToEquipartition) {
  TempDir dir;
  const std::string out =
      run(dir, "rough",
          header(6, 10, 1000) + "  alpha: 1\n  thermostat: none\n" + kHardSpheres +
              "  roughness: {beta: 1, inertia: 0.4}\n"
              "  initial: {temperature: 1, rotational_temperature: 0.25}\n"
              "  t_end: 20\n  observe_every: 1\n  steady_from: 10\n");
  H5Reader f(out);
  const auto T = f.read_double("/temperature/mean"),
             R = f.read_double("/temperature_rotational/mean");
  for (std::size_t k = 1; k < T.size(); ++k) EXPECT_NEAR(T[k] + R[k], T[0] + R[0], 1e-12);
  const double z = test::family_z(2);
  const double expected = 0.5 * (T[0] + R[0]);  // this run's own initial energy
  const Steady t = steady(f, "/temperature"), r = steady(f, "/temperature_rotational");
  EXPECT_LT(std::fabs(t.mean - expected), z * t.sigma + 1e-3) << t.mean << " " << expected;
  EXPECT_LT(std::fabs(r.mean - expected), z * r.sigma + 1e-3) << r.mean << " " << expected;
}

// beta = -1 is the smooth gas: spins untouched (T_rot the same at every time, bit for bit) and
// the translational outputs the bits of the smooth run (the spins have a stream of their own).
TEST(Gas, SmoothLimitLeavesSpinsUntouched) {
  TempDir dir;
  const std::string body = "  alpha: 0.8\n  thermostat: none\n" + std::string(kHardSpheres) +
                           "  t_end: 2\n  observe_every: 0.5\n";
  const std::string rough =
      run(dir, "rough", header(7, 3, 300) + body + "  roughness: {beta: -1, inertia: 0.4}\n");
  const std::string smooth =
      run(dir, "smooth", header(7, 3, 300) + "  species:\n    - {name: gas, fraction: 1}\n" + body);
  H5Reader r(rough), s(smooth);
  const auto R = r.read_double("/temperature_rotational/mean");
  for (double x : R) EXPECT_EQ(x, R[0]);
  for (const char* g : {"/temperature/mean", "/moment_4/mean", "/events/collisions"})
    EXPECT_EQ(r.read_bytes(g), s.read_bytes(g)) << g;
  EXPECT_LT(r.read_double("/temperature/mean").back(), 0.8);  // it did cool
}

// Martin-Piasecki: a tracer (1 % of the particles) of mass m0 and restitution alpha0 in an elastic
// bath of mass m has T0/T = (1 + alpha0)/(2 + (1 - alpha0) m/m0) exactly in the tracer limit. At
// x = 0.01 the bath's own cooling by the tracer shifts the ratio by at most 0.4 % (Garzo-Dufty's
// cooling rates at x = 0.01 against x -> 0, for these cases): allowance 1 %.
TEST(Gas, MartinPiaseckiTracer) {
  struct Case {
    double alpha0, m0;
  };
  const double z = test::family_z(2);
  int seed = 8;
  for (const Case c : {Case{0.5, 1.0}, Case{0.8, 4.0}}) {
    TempDir dir;
    const std::string a = std::to_string(c.alpha0);
    const std::string out =
        run(dir, "tracer",
            header(seed++, 12, 10000) + "  species:\n    - {name: tracer, fraction: 0.01, mass: " +
                std::to_string(c.m0) + "}\n    - {name: bath, fraction: 0.99, mass: 1}\n" +
                "  alpha: [[" + a + ", " + a + "], [" + a + ", 1]]\n  thermostat: gaussian\n" +
                kHardSpheres + "  t_end: 40\n  observe_every: 0.5\n  steady_from: 5\n");
    H5Reader f(out);
    const Steady r = steady(f, "/temperature_ratio/tracer_over_bath");
    const double mp = (1 + c.alpha0) / (2 + (1 - c.alpha0) * 1.0 / c.m0);
    EXPECT_LT(std::fabs(r.mean - mp), z * r.sigma + 0.01 * mp)
        << "alpha0 " << c.alpha0 << ": " << r.mean << " +- " << r.sigma << " vs " << mp;
  }
}

// Garzo-Dufty (Maxwellian, beyond.md §4): HCS T1/T2 of equal-size hard spheres, x1 = 1/2. The
// approximation neglects each species' a2 (measured |a2| <= 0.03 here), which changes a cooling
// rate by about 3 a2/16 <= 0.6 %, so the ratio of rates by <= 1.2 %: allowance 2 %.
TEST(Gas, GarzoDuftyTemperatureRatio) {
  struct Case {
    double mass_ratio, alpha, reference;
  };
  const Case cases[] = {{2, 0.9, 1.0596}, {4, 0.8, 1.3412}, {4, 0.9, 1.1566}};
  const double z = test::family_z(3);
  int seed = 20;
  for (const Case& c : cases) {
    TempDir dir;
    const std::string out =
        run(dir, "gd",
            header(seed++, 10, 2000) + "  species:\n    - {name: one, fraction: 0.5, mass: " +
                std::to_string(c.mass_ratio) + "}\n    - {name: two, fraction: 0.5, mass: 1}\n" +
                "  alpha: " + std::to_string(c.alpha) + "\n  thermostat: gaussian\n" +
                kHardSpheres + "  t_end: 25\n  observe_every: 0.25\n  steady_from: 5\n");
    H5Reader f(out);
    const Steady r = steady(f, "/temperature_ratio/one_over_two");
    EXPECT_LT(std::fabs(r.mean - c.reference), z * r.sigma + 0.02 * c.reference)
        << c.mass_ratio << " " << c.alpha << ": " << r.mean << " +- " << r.sigma;
  }
}

// Rough spheres at kappa = 2/5 against the Maxwellian theta (beyond.md §5). White noise on the
// translational velocities: a public DSMC agrees within 1 %: allowance 1.5 %. HCS: the public
// DSMC puts theta 4-5 % below the formula at alpha = 0.8-0.9: allowance 7 % below, 2 % above.
TEST(Gas, RoughSpheresTheta) {
  struct Case {
    const char* thermostat;
    double alpha, beta, reference, below, above;
  };
  const Case cases[] = {{"white_noise", 0.9, 0.5, 0.4615, 0.015, 0.015},
                        {"gaussian", 0.9, 0.5, 0.8671, 0.07, 0.02}};
  const double z = test::family_z(2);
  int seed = 30;
  for (const Case& c : cases) {
    TempDir dir;
    const bool noise = std::string(c.thermostat) == "white_noise";
    const std::string out = run(
        dir, "theta",
        header(seed++, 10, 2000) + "  alpha: " + std::to_string(c.alpha) +
            "\n  thermostat: " + c.thermostat + "\n" + (noise ? "  beta: 1\n" : "") + kHardSpheres +
            "  roughness: {beta: " + std::to_string(c.beta) + ", inertia: 0.4}\n" +
            (noise ? "  initial: {temperature: 8, rotational_temperature: 4}\n" : "") +
            "  t_end: 25\n  observe_every: 0.25\n  steady_from: 8\n");
    H5Reader f(out);
    const Steady th = steady(f, "/theta");
    EXPECT_GT(th.mean, c.reference * (1 - c.below) - z * th.sigma)
        << c.thermostat << ": " << th.mean << " +- " << th.sigma;
    EXPECT_LT(th.mean, c.reference * (1 + c.above) + z * th.sigma)
        << c.thermostat << ": " << th.mean << " +- " << th.sigma;
  }
}

// The stored ratios are the ratios of the stored means, row by row and in the steady state, and
// their intervals are the delta method's. The Gaussian thermostat holds d T + d_rot T_rot in every
// ensemble, so T and T_rot move exactly against each other: the interval must then equal
// theta (s_rot/T_rot + s/T) (correlation -1), in d = 3 and d = 2. A mixture under it holds
// x_1 T_1 + x_2 T_2, so T_1/T_2 has the same structure.
TEST(Gas, StoredRatiosAreTheDeltaMethods) {
  const std::string body = "  alpha: 0.8\n  thermostat: gaussian\n" + std::string(kHardSpheres) +
                           "  t_end: 6\n  observe_every: 0.5\n  steady_from: 2\n";
  for (const char* geometry : {"", "  dimension: 2\n"}) {
    TempDir dir;
    const bool plane = *geometry != 0;
    const std::string out =
        run(dir, "g",
            header(50, 12, 400) + body + geometry +
                "  roughness: {beta: 0.4, inertia: " + (plane ? "0.5" : "0.4") + "}\n");
    H5Reader f(out);
    const auto rot = f.read_double("/temperature_rotational/mean"),
               T = f.read_double("/temperature/mean");
    const auto th = f.read_double("/theta/mean"), ci = f.read_double("/theta/ci");
    const auto rot_ci = f.read_double("/temperature_rotational/ci"),
               T_ci = f.read_double("/temperature/ci");
    for (std::size_t m = 0; m < T.size(); ++m) {
      EXPECT_EQ(th[m], rot[m] / T[m]) << m;
      EXPECT_NEAR(ci[m], th[m] * (rot_ci[m] / rot[m] + T_ci[m] / T[m]), 1e-6 * ci[m] + 1e-15) << m;
    }
    const Steady s = steady(f, "/theta"), r = steady(f, "/temperature_rotational"),
                 t = steady(f, "/temperature");
    EXPECT_EQ(s.mean, r.mean / t.mean);
    EXPECT_NEAR(s.sigma, s.mean * (r.sigma / r.mean + t.sigma / t.mean), 1e-6 * s.sigma)
        << (plane ? "d = 2" : "d = 3");
  }
  TempDir dir;
  const std::string out = run(dir, "m",
                              header(51, 12, 400) +
                                  "  species:\n    - {name: heavy, fraction: 0.5, mass: 3}\n"
                                  "    - {name: light, fraction: 0.5, mass: 1}\n" +
                                  body);
  H5Reader f(out);
  const Steady s = steady(f, "/temperature_ratio/heavy_over_light");
  const Steady a = steady(f, "/species/heavy/temperature"),
               b = steady(f, "/species/light/temperature");
  EXPECT_EQ(s.mean, a.mean / b.mean);
  EXPECT_NEAR(s.sigma, s.mean * (a.sigma / a.mean + b.sigma / b.mean), 1e-6 * s.sigma);
  EXPECT_FALSE(
      f.exists("/temperature_ratio/light_over_heavy"));  // one ratio per pair, in species order
  EXPECT_FALSE(f.exists("/theta"));                      // smooth particles: no theta
}

// The splitting schemes give the no-splitting scheme's steady state (Strang's error is O(dt^2),
// below the statistics at dt = 0.05 for this gas).
TEST(Gas, SplittingSchemesAgree) {
  TempDir dir;
  const std::string body =
      "  species:\n    - {name: heavy, fraction: 0.5, mass: 4}\n"
      "    - {name: light, fraction: 0.5, mass: 1}\n"
      "  alpha: 0.8\n  beta: 1\n" +
      std::string(kHardSpheres) +
      "  roughness: {beta: 0.5, inertia: 0.4}\n"
      "  initial: {temperature: 8, rotational_temperature: 4}\n"
      "  t_end: 20\n  observe_every: 0.5\n  steady_from: 6\n";
  const std::string a = run(dir, "nosplit", header(40, 10, 1000) + body);
  const std::string b =
      run(dir, "strang", header(41, 10, 1000) + body + "  scheme: strang\n  steps: 400\n");
  H5Reader fa(a), fb(b);
  const double z = test::family_z(3);
  for (const char* g :
       {"/species/heavy/temperature", "/species/light/temperature", "/temperature_rotational"}) {
    const Steady x = steady(fa, g), y = steady(fb, g);
    EXPECT_LT(std::fabs(x.mean - y.mean), z * std::hypot(x.sigma, y.sigma))
        << g << ": " << x.mean << " " << y.mean;
  }
}

namespace {
// A rough binary mixture with every output that has state: heated, histograms, moments, steady.
const char* kRoughMixture = R"(model: dsmc
seed: 12
ensembles: 5
dsmc:
  particles: 301
  species:
    - {name: heavy, fraction: 0.3, mass: 3.0, diameter: 1.5}
    - {name: light, fraction: 0.7, mass: 1.0, diameter: 1.0}
  alpha: [[0.9, 0.8], [0.8, 0.7]]
  roughness: {beta: 0.3, inertia: {heavy: 0.4, light: 0.5}}
  beta: 0.5
  kernel: {lambda: 1, C: 0.0795774715459477}
  t_end: 4
  observe_every: 0.5
  histogram: {shells: 20, radius: 6, component: true}
  moments: 3
  steady_from: 1
)";
}  // namespace

TEST(Gas, ThreadsShardsAndSignalsAreBitIdentical) {
  for (const std::string extra :
       {"", " --set dsmc.scheme=euler --set dsmc.steps=40",
        " --set dsmc.thermostat=gaussian --set dsmc.beta=0 --set dsmc.dimension=2 "
        "--set dsmc.roughness.inertia=0.5"}) {
    TempDir dir;
    const std::string cfg = dir.write("c.yaml", kRoughMixture) + extra;
    H5Reader f(test::expect_threads_and_shards_identical(dir, cfg));
    for (const char* g : {"/theta", "/steady/theta", "/temperature_ratio/heavy_over_light",
                          "/steady/temperature_ratio/heavy_over_light"})
      EXPECT_TRUE(f.exists(std::string(g) + "/ci")) << g << ": the identities above cover it";
  }
  // Long enough to be under way when the signal comes.
  std::string longer = kRoughMixture;
  longer.replace(longer.find("ensembles: 5"), 12, "ensembles: 4");
  longer.replace(longer.find("particles: 301"), 14, "particles: 300000");
  longer.replace(longer.find("t_end: 4"), 8, "t_end: 8");
  longer += "checkpoint: {every_seconds: 3600}\n";
  TempDir dir;
  test::expect_sigterm_resumes_identically(dir, dir.write("c.yaml", longer));
}

TEST(Gas, RestoredEnsembleContinuesIdentically) {
  for (const char* sets : {"", "dsmc.thermostat=gaussian"}) {
    std::vector<std::string> s;
    if (*sets) s = {sets, "dsmc.beta=0"};
    const Config config = parse_config(kRoughMixture, "c.yaml", s);
    const DsmcConfig& d = config.dsmc;
    TempDir dir;
    GasEnsemble a(d, 3, 1);
    a.advance_to(1.5);
    {
      H5Writer w(dir.file("state.h5"));
      a.save(w, "/e");
      w.commit();
    }
    H5Reader r(dir.file("state.h5"));
    GasEnsemble b(d, r, "/e");
    a.advance_to(4);
    b.advance_to(4);
    for (std::size_t i = 0; i < a.particles().size(); ++i) {
      const Particle &p = a.particles()[i], &q = b.particles()[i];
      ASSERT_TRUE(p.v.x == q.v.x && p.v.y == q.v.y && p.v.z == q.v.z && p.t == q.t) << i;
      const Vec3 &u = a.spins()[i], &w = b.spins()[i];
      ASSERT_TRUE(u.x == w.x && u.y == w.y && u.z == w.z) << i;
    }
    EXPECT_EQ(a.counts().collisions, b.counts().collisions);
    EXPECT_EQ(a.species_collisions(), b.species_collisions());
  }
}

// Without species and roughness nothing of the general gas is in the stored config (its text is
// what checkpoints and merge compare), and with them every key is written out.
TEST(Gas, StoredConfigRoundTrips) {
  const Config c = parse_config(kRoughMixture, "c.yaml", {});
  const std::string text = c.to_yaml(true);
  EXPECT_NE(text.find("species"), std::string::npos);
  EXPECT_NE(text.find("rotational_temperature"), std::string::npos);
  EXPECT_EQ(parse_config(text, "again.yaml", {}).to_yaml(true), text);
  const Config plain = parse_config(
      header(1, 1, 10) + "  alpha: 0.5\n  beta: 1\n" + kHardSpheres + "  t_end: 1\n", "p.yaml", {});
  const std::string p = plain.to_yaml(true);
  for (const char* key : {"species", "roughness", "rotational_temperature"})
    EXPECT_EQ(p.find(key), std::string::npos) << key;
}

// The species' steady intervals cover: over independent replicas of a heated binary mixture the
// spread of T_heavy and T_light about their grand means, in units of each replica's sigma, is 1
// within the chi-square bounds of its own family-wise level.
TEST(Gas, SpeciesIntervalsCover) {
  const int R = 30;
  std::vector<double> heavy_mean, heavy_sigma, light_mean, light_sigma;
  for (int k = 0; k < R; ++k) {
    TempDir dir;
    const std::string out =
        run(dir, "replica",
            header(100 + k, 10, 200) +
                "  species:\n    - {name: heavy, fraction: 0.4, mass: 5}\n"
                "    - {name: light, fraction: 0.6, mass: 1}\n"
                "  alpha: 0.7\n  beta: 1\n" +
                kHardSpheres +
                "  initial: {temperature: 6}\n  t_end: 12\n  observe_every: 0.25\n"
                "  steady_from: 4\n");
    H5Reader f(out);
    const Steady h = steady(f, "/species/heavy/temperature"),
                 l = steady(f, "/species/light/temperature");
    heavy_mean.push_back(h.mean), heavy_sigma.push_back(h.sigma);
    light_mean.push_back(l.mean), light_sigma.push_back(l.sigma);
  }
  for (const auto& [mean, sigma] :
       {std::pair{heavy_mean, heavy_sigma}, std::pair{light_mean, light_sigma}}) {
    double grand = 0.0;
    for (double m : mean) grand += m / R;
    double ss = 0.0;
    for (int k = 0; k < R; ++k) ss += std::pow((mean[k] - grand) / sigma[k], 2);
    const double spread = std::sqrt(ss / (R - 1));
    // (R - 1) spread^2 is about chi-square with R - 1 dof; each sigma has 9 dof (10 ensembles), so
    // a deviation over it is Student t with sd sqrt(9/7) = 1.13: the upper bound carries 1.25.
    EXPECT_GT(spread, std::sqrt(gsl_cdf_chisq_Pinv(0.0005, R - 1) / (R - 1))) << spread;
    EXPECT_LT(spread, 1.25 * std::sqrt(gsl_cdf_chisq_Qinv(0.0005, R - 1) / (R - 1))) << spread;
  }
}

// The rates at t = 0 are exact: the initial state is Maxwellian in v and in omega, independent,
// and for such a state the two-temperature equations of Huthmann-Zippelius / Luding et al. hold
// with no approximation (the approximation is that the state stays so). Hard spheres at unit
// density with gamma C = 1/(4 pi) collide at nu = <|u|> = 4 sqrt(T/pi) per particle, and
// dT/dt = -(4 nu/3)(A T - B T_rot), dT_rot/dt = (4 nu/3)(B T - C T_rot), eta = kappa(1+beta)/
// (2(1+kappa)), A = (1-alpha^2)/4 + eta(1-eta), B = eta^2/kappa, C = (eta/kappa)(1 - eta/kappa).
// From T_rot(0) = 0 the slope at 0 by Richardson extrapolation of the rows at delta and 2 delta,
// 2 x(delta)/delta - x(2 delta)/(2 delta) (its O(delta^2) error below 0.1 % here); its sigma
// bounds the rows' covariance by the product of their sigmas. Measured: dT_rot/dt within 1 % of
// exact with a sigma of 2.5 %; the translational slope is a coarse check (its sigma, from the
// sampled T(0), is some 40 % of it).
TEST(Gas, RoughInitialRatesAreExact) {
  const double kappa = 0.4, alpha = 0.9;
  const double z = test::family_z(4), delta = 0.01;
  int seed = 60;
  for (const double beta : {0.0, 0.5}) {
    TempDir dir;
    const std::string out =
        run(dir, "rates",
            header(seed++, 20, 100000) + "  alpha: 0.9\n  thermostat: none\n" + kHardSpheres +
                "  roughness: {beta: " + std::to_string(beta) +
                ", inertia: 0.4}\n  initial: {temperature: 1, rotational_temperature: 0}\n"
                "  t_end: 0.02\n  observe_every: 0.01\n");
    H5Reader f(out);
    const double eta = kappa * (1 + beta) / (2 * (1 + kappa));
    const double A = (1 - alpha * alpha) / 4 + eta * (1 - eta), B = eta * eta / kappa;
    for (const char* g : {"/temperature", "/temperature_rotational"}) {
      const auto mean = f.read_double(std::string(g) + "/mean");
      const auto var = f.read_double(std::string(g) + "/variance");
      const double T0 = f.read_double("/temperature/mean")[0];
      const double nu = 4 * std::sqrt(T0 / M_PI);
      const bool rot = std::string(g) == "/temperature_rotational";
      const double exact = rot ? 4 * nu / 3 * B * T0 : -4 * nu / 3 * A * T0;
      const double d1 = mean[1] - mean[0], d2 = mean[2] - mean[0];
      const double slope = 2 * d1 / delta - d2 / (2 * delta);
      // T(0) is random too (the sampled Maxwellian); T_rot(0) = 0 exactly.
      const double s0 = std::sqrt(var[0] / 20), s1 = std::sqrt(var[1] / 20),
                   s2 = std::sqrt(var[2] / 20);
      const double sigma =
          rot ? 2 * s1 / delta + s2 / (2 * delta) : 2 * (s1 + s0) / delta + (s2 + s0) / (2 * delta);
      EXPECT_LT(std::fabs(slope - exact), z * sigma + 1e-3 * std::fabs(exact))
          << g << " beta " << beta << ": " << slope << " +- " << sigma << " vs " << exact;
    }
  }
}
