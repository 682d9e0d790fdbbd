// The thermostats of dsmc.thermostat: free cooling (none) and the Gaussian thermostat against
// exact results and the kinetic theory of the homogeneous cooling state (HCS).
//
// Maxwell molecules (lambda = 0, B = C0, isotropic scattering): the moments close. With
// nu = 4 pi gamma C0 and M_2p = <|v - V|^2p>,
//   dM2/dt = -nu (1 - alpha^2)/4 M2                          (GRW05 eq. 16 with beta = 0),
//   dM4/dt = nu (A M2^2 - B M4),  A = 5 (1+alpha)^2 (3 - 2 alpha + alpha^2)/72,
//                                 B = (1+alpha)(13 - 9 alpha + alpha^2 - alpha^3)/24
// (45/128 and 69/128 at alpha = 1/2, as in shared/reference/tails.md). The scaled ratio
// R = M4/M2^2 then obeys dR/dt = nu (A - k R), k = B - (1 - alpha^2)/2
// = (1+alpha)^2 (1 + 2 alpha - alpha^2)/24, exactly, so the HCS has
// a2 = 3 R/5 - 1 = 2 (1 - alpha)^2/(1 + 2 alpha - alpha^2), approached like e^{-nu k t}.
//
// Hard spheres (lambda = 1): the energy loss is pi gamma C (1 - alpha^2)/2 <|u|^3> per particle,
// so dT/dt = -K T^{3/2}, K = (16/3) sqrt(pi) gamma C (1 - alpha^2)(1 + 3 a2/16) with the first
// Sonine correction, a2 of van Noije & Ernst (Granular Matter 1, 57 (1998)) for the HCS:
// a2 = 16 (1 - alpha)(1 - 2 alpha^2)/(81 - 17 alpha + 30 alpha^2 (1 - alpha)). Haff's law:
// T = T0/(1 + t/t0)^2, t0 = 2/(K sqrt(T0)).
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <thread>

#include "granboltz/dsmc/ensemble.hpp"
#include "granboltz/dsmc/observables.hpp"
#include "test_support.hpp"

using namespace granboltz;

namespace {

constexpr int kTemperature = 4, kFourth = 17;

Config make(const std::vector<std::string>& extra, std::uint64_t seed, std::uint64_t N) {
  std::vector<std::string> sets = {"model=dsmc", "seed=" + std::to_string(seed),
                                   "ensembles=" + std::to_string(N)};
  sets.insert(sets.end(), extra.begin(), extra.end());
  return parse_config("{}", "test", sets);
}

double vne_a2(double a) {  // van Noije-Ernst first Sonine a2 of the hard-sphere HCS, d = 3
  return 16 * (1 - a) * (1 - 2 * a * a) / (81 - 17 * a + 30 * a * a * (1 - a));
}

}  // namespace

TEST(GaussianThermostat, HoldsTheTemperatureAtT0ToRoundOffAtEveryObservation) {
  struct Case {
    const char *lambda, *majorant, *scheme;
  };
  const Case cases[] = {{"0", "global", "nosplit"},    {"1", "global", "nosplit"},
                        {"1", "pairwise", "nosplit"},  {"0.5", "pairwise", "strang"},
                        {"0.3", "global", "euler"},    {"1", "global", "strang"},
                        {"0.3", "pairwise", "nosplit"}};
  for (const Case& k : cases) {
    const Config c =
        make({"dsmc.particles=300", "dsmc.alpha=0.3", "dsmc.thermostat=gaussian", "dsmc.gamma=1",
              "dsmc.kernel.lambda=" + std::string(k.lambda), "dsmc.kernel.C=0.2",
              "dsmc.initial.temperature=2.5", "dsmc.t_end=30", "dsmc.observe_every=2.5",
              "dsmc.steps=120", "dsmc.majorant=" + std::string(k.majorant),
              "dsmc.scheme=" + std::string(k.scheme)},
             1, 1);
    for (std::uint64_t e = 0; e < 3; ++e) {
      DsmcEnsemble ens(c.dsmc, 77, e);
      const Observation start = measure(ens.particles());
      for (const double t : dsmc_times(c.dsmc)) {
        if (t > 0) ASSERT_TRUE(ens.advance_to(t));
        const Observation o = measure(ens.particles());
        EXPECT_NEAR(o[kTemperature], 2.5, 1e-13 * 2.5)
            << "lambda=" << k.lambda << " " << k.majorant << " " << k.scheme << " t=" << t;
        // The thermostat scales peculiar velocities only: the bulk velocity stays put, through
        // the many folds of the scale factor (s^2 > 2^8) that a run this long needs.
        for (int a = 1; a <= 3; ++a)
          EXPECT_NEAR(o[a], start[a], 1e-14) << "lambda=" << k.lambda << " t=" << t;
      }
      // The gas did cool: without the thermostat T would have fallen by orders of magnitude.
      EXPECT_GT(ens.counts().collisions, 300u * 3) << "lambda=" << k.lambda;
    }
  }
}

TEST(FreeCooling, NoneIsWhiteNoiseWithBetaZeroBitForBit) {
  for (const char* lambda : {"0", "1"}) {
    const std::vector<std::string> common = {
        "dsmc.particles=100",    "dsmc.alpha=0.6",
        "dsmc.gamma=2",          "dsmc.kernel.lambda=" + std::string(lambda),
        "dsmc.kernel.C=0.1",     "dsmc.t_end=2",
        "dsmc.observe_every=0.5"};
    auto a = common, b = common;
    a.push_back("dsmc.beta=0");
    b.push_back("dsmc.thermostat=none");
    const test::DsmcRun ra(make(a, 5, 20)), rb(make(b, 5, 20));
    EXPECT_EQ(ra.collisions, rb.collisions);
    EXPECT_EQ(ra.fictitious, rb.fictitious);
    for (std::size_t m = 0; m < ra.times.size(); ++m)
      for (int k = 0; k < kNumScalars; ++k) {
        EXPECT_EQ(ra.at(m, k).mean, rb.at(m, k).mean);
        EXPECT_EQ(ra.at(m, k).variance, rb.at(m, k).variance);
      }
  }
}

TEST(FreeCooling, MaxwellMoleculesCoolExponentiallyInEveryScheme) {
  // E[T](t) = (1 - 1/n) T0 exp(-gamma pi C0 (1 - alpha^2) t) exactly for the particle system
  // (test_support.hpp, MaxwellExact with beta = 0); the splitting schemes have the same law.
  const double n = 64, N = 2000;
  const double z = test::family_z(2 * 3 * 16);
  std::uint64_t seed = 900;
  for (const double alpha : {0.5, 0.2}) {
    const test::MaxwellExact exact{alpha, 0.0, 4.0, 1 / (4 * M_PI), 1.5};
    for (const char* scheme : {"nosplit", "euler", "strang"}) {
      const test::DsmcRun r(make(
          {"dsmc.particles=64", "dsmc.alpha=" + format_real(alpha), "dsmc.thermostat=none",
           "dsmc.gamma=4", "dsmc.kernel.lambda=0", "dsmc.kernel.C=" + format_real(1 / (4 * M_PI)),
           "dsmc.initial.temperature=1.5", "dsmc.t_end=4", "dsmc.observe_every=0.25",
           "dsmc.steps=16", "dsmc.scheme=" + std::string(scheme)},
          ++seed, static_cast<std::uint64_t>(N)));
      for (std::size_t m = 1; m < r.times.size(); ++m) {
        const MeanCi T = r.at(m, kTemperature);
        EXPECT_NEAR(T.mean, exact.centred_nosplit(r.times[m], n), z * std::sqrt(T.variance / N))
            << scheme << " alpha=" << alpha << " t=" << r.times[m];
      }
    }
  }
}

TEST(GaussianThermostat, MaxwellHcsFourthMomentFollowsTheExactMomentHierarchy) {
  // a2(t) = 3 R(t)/5 - 1 with R(t) = R* + (5/3 - R*) e^{-nu k t}, R* = A/k: the transient from
  // the Maxwellian and the HCS value 2 (1-alpha)^2/(1 + 2 alpha - alpha^2) (2/7 at alpha = 1/2).
  // Each observation is compared across independent ensembles; n = 2000 keeps the O(1/n) bias
  // (about 2/(3n) in a2) a tenth of the interval.
  const double N = 600, nu = 4.0;
  const double z = test::family_z(2 * 10);
  std::uint64_t seed = 950;
  for (const double alpha : {0.5, 0.8}) {
    const double ap = 1 + alpha;
    const double A = 5 * ap * ap * (3 - 2 * alpha + alpha * alpha) / 72;
    const double k = ap * ap * (1 + 2 * alpha - alpha * alpha) / 24;
    const double Rs = A / k;
    EXPECT_NEAR(3 * Rs / 5 - 1, 2 * (1 - alpha) * (1 - alpha) / (1 + 2 * alpha - alpha * alpha),
                1e-14);
    const test::DsmcRun r(
        make({"dsmc.particles=2000", "dsmc.alpha=" + format_real(alpha), "dsmc.thermostat=gaussian",
              "dsmc.gamma=1", "dsmc.kernel.lambda=0", "dsmc.kernel.C=" + format_real(1 / M_PI),
              "dsmc.t_end=10", "dsmc.observe_every=1"},
             ++seed, static_cast<std::uint64_t>(N)));
    for (std::size_t m = 1; m < r.times.size(); ++m) {
      const double t = r.times[m];
      const double a2 = 3 * (Rs + (5.0 / 3 - Rs) * std::exp(-nu * k * t)) / 5 - 1;
      const MeanCi g = r.at(m, kFourth);  // <|c|^4> - 15 T^2 with T = T0 = 1
      EXPECT_NEAR(g.mean / 15, a2, z * std::sqrt(g.variance / N) / 15)
          << "alpha=" << alpha << " t=" << t;
    }
  }
}

TEST(FreeCooling, HardSpheresFollowHaffsLawWithTheSonineCorrection) {
  // alpha = 0.9, where the first Sonine a2 (-0.0146) is accurate to about 10^-3 (Santos &
  // Montanero, Granular Matter 11, 157 (2009)), over two decades of T. Leading finite-n terms:
  // E[T(0)] = (1 - 1/n) T0, and the pairs' E|u|^3 is (n/(n-1))^{3/2} times the Maxwellian's
  // while there are (n-1)/n pairs per particle, so K carries (n/(n-1))^{1/2}.
  const double alpha = 0.9, n = 2000, N = 300, gC = 1 / (4 * M_PI);
  const double a2 = vne_a2(alpha);
  const double K = 16.0 / 3 * std::sqrt(M_PI) * gC * (1 - alpha * alpha) * (1 + 3 * a2 / 16) *
                   std::sqrt(n / (n - 1));
  const double T0 = 1 - 1 / n, t0 = 2 / (K * std::sqrt(T0));
  const double t_end = 130;  // 1 + t/t0 = 10.3: T falls to 0.0094
  const double z = test::family_z(13);
  const test::DsmcRun r(
      make({"dsmc.particles=2000", "dsmc.alpha=0.9", "dsmc.thermostat=none", "dsmc.gamma=1",
            "dsmc.kernel.lambda=1", "dsmc.kernel.C=" + format_real(gC), "dsmc.majorant=pairwise",
            "dsmc.t_end=" + format_real(t_end), "dsmc.observe_every=10"},
           31, static_cast<std::uint64_t>(N)));
  EXPECT_LT(r.at(r.times.size() - 1, kTemperature).mean, 0.01);
  double worst_plain = 0;  // the same law without the Sonine correction must be rejected
  const double t0_plain = t0 * (1 + 3 * a2 / 16);
  for (std::size_t m = 1; m < r.times.size(); ++m) {
    const double t = r.times[m];
    const MeanCi T = r.at(m, kTemperature);
    const double haff = T0 / ((1 + t / t0) * (1 + t / t0));
    const double ci = z * std::sqrt(T.variance / N);
    EXPECT_NEAR(T.mean, haff, ci) << "t=" << t;
    const double plain = T0 / ((1 + t / t0_plain) * (1 + t / t0_plain));
    worst_plain = std::max(worst_plain, std::fabs(T.mean - plain) / ci);
  }
  EXPECT_GT(worst_plain, 1.0) << "the run cannot resolve the Sonine correction";
}

TEST(GaussianThermostat, HardSpheresCollideAtTheRateOfAGasAtT0) {
  // The clock runs in true velocities: real collisions per unit time are (n-1)/2 4 pi gamma C
  // E|u| with E|u| = 4 sqrt(T0/pi) (n/(n-1))^{1/2} (1 - a2/16) at every time, although the stored
  // velocities cool by Haff's law (which would slow a clock run in them several-fold).
  // t = 60 with a single observation: the stored velocities cool by ~10^4 and the scale is
  // folded in mid-run.
  const double alpha = 0.9, n = 500, N = 150, gC = 1 / (4 * M_PI), t = 60;
  const double mean_u = 4 * std::sqrt(1 / M_PI) * std::sqrt(n / (n - 1)) * (1 - vne_a2(alpha) / 16);
  const double expected = (n - 1) / 2 * 4 * M_PI * gC * mean_u * t;
  const double z = test::family_z(3);
  std::uint64_t seed = 60;
  for (const char* variant : {"global nosplit", "pairwise nosplit", "global strang"}) {
    const std::string v(variant);
    const test::DsmcRun r(
        make({"dsmc.particles=500", "dsmc.alpha=0.9", "dsmc.thermostat=gaussian", "dsmc.gamma=1",
              "dsmc.kernel.lambda=1", "dsmc.kernel.C=" + format_real(gC), "dsmc.t_end=60",
              "dsmc.steps=120", "dsmc.majorant=" + v.substr(0, v.find(' ')),
              "dsmc.scheme=" + v.substr(v.find(' ') + 1)},
             ++seed, static_cast<std::uint64_t>(N)));
    double sum = 0, sum2 = 0;
    for (double c : r.collisions) sum += c, sum2 += c * c;
    const double mean = sum / N, var = sum2 / N - mean * mean;
    EXPECT_NEAR(mean, expected, z * std::sqrt(var / N)) << variant;
  }
}

TEST(GaussianThermostat, PausedSavedAndRestoredEnsembleContinuesBitForBit) {
  // A pause lands between two events, with the scale factor not folded in: the checkpoint must
  // carry the stored velocities and the running energies. The runs are long enough (about
  // 2.5 10^6 events) for the scale to be folded in mid-run as well (s^2 > 2^64).
  for (const char* majorant : {"global", "pairwise"}) {
    const std::string t_end = std::string(majorant) == "global" ? "250" : "600";
    const Config c = make({"dsmc.particles=2000", "dsmc.alpha=0.5", "dsmc.thermostat=gaussian",
                           "dsmc.gamma=1", "dsmc.kernel.lambda=1", "dsmc.kernel.C=0.1",
                           "dsmc.t_end=" + t_end, "dsmc.majorant=" + std::string(majorant)},
                          1, 1);
    const double end = c.dsmc.t_end;
    DsmcEnsemble reference(c.dsmc, 3, 0);
    ASSERT_TRUE(reference.advance_to(end));

    // Progress is published every 2^20 events; the pause is noticed within 2^14 more.
    ProgressSlot slot{0.0};
    DsmcEnsemble paused(c.dsmc, 3, 0, &slot);
    std::atomic<bool> pause{false};
    std::thread stopper([&] {
      while (slot.load() == 0.0) std::this_thread::yield();
      pause = true;
    });
    const bool reached = paused.advance_to(end, &pause);
    stopper.join();
    ASSERT_FALSE(reached) << majorant << ": the run ended before the pause; make it longer";
    EXPECT_GT(paused.time(), 0.0);
    test::TempDir dir;
    const std::string file = dir.file("state.h5");
    {
      H5Writer out(file);
      paused.save(out, "/e");
      out.commit();
    }
    H5Reader in(file);
    DsmcEnsemble restored(c.dsmc, in, "/e");
    ASSERT_TRUE(restored.advance_to(end));
    pause = false;
    ASSERT_TRUE(paused.advance_to(end, &pause));
    for (const DsmcEnsemble* e : {&paused, &restored}) {
      EXPECT_EQ(e->counts().collisions, reference.counts().collisions) << majorant;
      EXPECT_EQ(e->u_max(), reference.u_max()) << majorant;
      for (std::size_t i = 0; i < reference.particles().size(); ++i) {
        const Vec3 a = e->particles()[i].v, b = reference.particles()[i].v;
        ASSERT_TRUE(a.x == b.x && a.y == b.y && a.z == b.z) << majorant << " particle " << i;
      }
    }
  }
}

TEST(GaussianThermostat, ThreadsAndShardsGiveTheSameOutput) {
  test::TempDir dir;
  const std::string cfg = dir.write("c.yaml", R"(model: dsmc
seed: 8
ensembles: 6
dsmc:
  particles: 300
  alpha: 0.4
  thermostat: gaussian
  kernel: {lambda: 1, C: 0.08}
  t_end: 3
  observe_every: 0.5
  histogram: {shells: 10, radius: 5}
  steady_from: 1
)");
  const std::string one = dir.file("one.h5"), two = dir.file("two.h5");
  ASSERT_EQ(test::run_granboltz("run " + cfg + " -q --threads 1 -o " + one).exit_code, 0);
  ASSERT_EQ(test::run_granboltz("run " + cfg + " -q --threads 2 -o " + two).exit_code, 0);
  test::expect_identical_outputs(one, two);
  std::string shards;
  for (int i = 0; i < 2; ++i) {
    const std::string s = dir.file("s" + std::to_string(i) + ".h5");
    ASSERT_EQ(test::run_granboltz("run " + cfg + " -q --set shard.count=2 --set shard.index=" +
                                  std::to_string(i) + " -o " + s)
                  .exit_code,
              0);
    shards += s + " ";
  }
  const std::string merged = dir.file("merged.h5");
  ASSERT_EQ(test::run_granboltz("merge " + shards + "-o " + merged).exit_code, 0);
  test::expect_identical_outputs(one, merged);
}

TEST(ThermostatConfig, BadThermostatSettingsGiveOneLineErrors) {
  const std::string base =
      "model: dsmc\nseed: 1\ndsmc: {particles: 10, alpha: 0.5, kernel: {lambda: 1, C: 0.1}, "
      "t_end: 1";
  auto error = [&](const std::string& extra) { return test::config_error(base + extra + "}\n"); };
  EXPECT_EQ(error(", thermostat: gaussian, beta: 0.5"),
            "dsmc.beta = 0.5: must be 0 with thermostat gaussian (only white_noise heats)");
  EXPECT_EQ(error(", thermostat: none, beta: 1"),
            "dsmc.beta = 1: must be 0 with thermostat none (only white_noise heats)");
  EXPECT_NE(error(", thermostat: nose_hoover")
                .find("dsmc.thermostat = nose_hoover: must be one of white_noise, gaussian, none"),
            std::string::npos)
      << error(", thermostat: nose_hoover");
  EXPECT_NE(error("").find("dsmc.beta"), std::string::npos);  // white_noise still needs beta
  EXPECT_EQ(error(", thermostat: gaussian"), "");
  EXPECT_EQ(error(", thermostat: none, beta: 0"), "");
  for (const std::string& e :
       {error(", thermostat: gaussian, beta: 0.5"), error(", thermostat: 3")})
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
}
