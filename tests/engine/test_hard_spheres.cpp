// Variable hard spheres (lambda > 0): fictitious collisions must give the exact collision rate.
//
// For the elastic, unheated gas started from independent Maxwellian velocities, the law of the
// particle system is invariant (the Gaussian product measure restricted to each energy-momentum
// shell is uniform, and elastic collisions preserve it), so at all times the rate of real
// collisions has expectation (n-1)/2 * 4 pi gamma C E|u|^lambda with u the difference of two
// independent Maxwellian velocities: E|u|^lambda = (4 T)^(lambda/2) Gamma((3+lambda)/2)/Gamma(3/2).
#include <gsl/gsl_sf_gamma.h>
#include <gtest/gtest.h>

#include <cmath>

#include "granboltz/dsmc/run.hpp"
#include "test_support.hpp"

using namespace granboltz;

namespace {

test::DsmcRun run_elastic(double lambda, const std::string& update, std::uint64_t seed,
                          const std::string& majorant = "global") {
  const Config c = parse_config(
      "{}", "test",
      {"model=dsmc", "seed=" + std::to_string(seed), "ensembles=400", "dsmc.particles=200",
       "dsmc.alpha=1", "dsmc.beta=0", "dsmc.gamma=2", "dsmc.kernel.lambda=" + format_real(lambda),
       "dsmc.kernel.C=0.05", "dsmc.initial.temperature=1.5", "dsmc.t_end=2",
       "dsmc.observe_every=0.5", "dsmc.majorant_update=" + update, "dsmc.majorant=" + majorant});
  return test::DsmcRun(c);
}

double expected_collisions(double lambda, double n, double T, double gamma, double C, double t) {
  const double mean_u =
      std::pow(4 * T, lambda / 2) * gsl_sf_gamma((3 + lambda) / 2) / gsl_sf_gamma(1.5);
  return (n - 1) / 2 * 4 * M_PI * gamma * C * mean_u * t;
}

}  // namespace

TEST(HardSpheres, RealCollisionRateMatchesTheKernelForEveryLambdaAndMajorantRule) {
  const double z = test::family_z(3 * 2);
  std::uint64_t seed = 500;
  for (double lambda : {1.0, 0.5, 0.25}) {
    for (const char* update : {"paper", "strict"}) {
      const test::DsmcRun r = run_elastic(lambda, update, ++seed);
      double sum = 0, sum2 = 0;
      for (double c : r.collisions) {
        sum += c;
        sum2 += c * c;
      }
      const double N = static_cast<double>(r.collisions.size());
      const double mean = sum / N, var = sum2 / N - mean * mean;
      EXPECT_NEAR(mean, expected_collisions(lambda, 200, 1.5, 2, 0.05, 2), z * std::sqrt(var / N))
          << "lambda=" << lambda << " majorant_update=" << update;
      // Fictitious collisions happen for lambda > 0, and never outnumber what U_max implies.
      EXPECT_GT(r.fictitious[0], 0.0);
    }
  }
}

TEST(HardSpheres, PairwiseMajorantGivesTheExactRateWithFewerEvents) {
  // Without heating the pairwise bound w_i + w_j >= |u|^lambda is exact: the same real-collision
  // rate as the kernel. For hard spheres it also wastes fewer fictitious collisions than the
  // global majorant; for small lambda the bound (a+b)^l <= a^l + b^l is loose by up to 2^(1-l).
  const double z = test::family_z(3);
  std::uint64_t seed = 700;
  for (double lambda : {1.0, 0.5, 0.25}) {
    const test::DsmcRun r = run_elastic(lambda, "paper", ++seed, "pairwise");
    const test::DsmcRun g = run_elastic(lambda, "paper", seed, "global");
    double sum = 0, sum2 = 0, fict = 0, gfict = 0;
    for (std::size_t e = 0; e < r.collisions.size(); ++e) {
      const double c = static_cast<double>(r.collisions[e]);
      sum += c;
      sum2 += c * c;
      fict += static_cast<double>(r.fictitious[e]);
      gfict += static_cast<double>(g.fictitious[e]);
    }
    const double N = static_cast<double>(r.collisions.size());
    const double mean = sum / N, var = sum2 / N - mean * mean;
    EXPECT_NEAR(mean, expected_collisions(lambda, 200, 1.5, 2, 0.05, 2), z * std::sqrt(var / N))
        << "lambda=" << lambda;
    if (lambda == 1.0) EXPECT_LT(3 * fict, gfict) << "lambda=" << lambda;
  }
}

TEST(HardSpheres, PairwiseAndGlobalMajorantsAgreeOnTheHeatedGas) {
  // GRW05 Example 5 (heated inelastic hard spheres) at n = 256 with Strang splitting: temperature
  // and fourth moment of the two majorants agree within their joint confidence interval at every
  // observation time.
  auto run = [](const std::string& majorant, std::uint64_t seed) {
    const Config c =
        parse_config("{}", "test",
                     {"model=dsmc", "seed=" + std::to_string(seed), "ensembles=1500",
                      "dsmc.particles=256", "dsmc.alpha=0.5", "dsmc.beta=0.125", "dsmc.gamma=4",
                      "dsmc.kernel.lambda=1", "dsmc.kernel.C=0.0795774715459477", "dsmc.t_end=2",
                      "dsmc.observe_every=0.25", "dsmc.scheme=strang", "dsmc.steps=16",
                      "dsmc.majorant_update=strict", "dsmc.majorant=" + majorant});
    return test::DsmcRun(c);
  };
  const test::DsmcRun g = run("global", 801), p = run("pairwise", 802);
  const double z = test::family_z(2 * 8);
  for (std::size_t m = 1; m < g.times.size(); ++m)
    for (int k : {4, 17}) {  // temperature, fourth moment
      const MeanCi a = g.at(m, k);
      const MeanCi b = p.at(m, k);
      EXPECT_NEAR(a.mean, b.mean,
                  z * std::sqrt(a.variance / g.ensembles + b.variance / p.ensembles))
          << "scalar " << k << " t=" << g.times[m];
    }
  double ge = 0, pe = 0;
  for (std::size_t e = 0; e < g.collisions.size(); ++e) {
    ge += g.collisions[e] + g.fictitious[e];
    pe += p.collisions[e] + p.fictitious[e];
  }
  EXPECT_LT(pe, ge);  // the point of the pairwise majorant
}

TEST(HardSpheres, ElasticCollisionsConserveEnergyAndMomentumInEveryEnsemble) {
  const test::DsmcRun r = run_elastic(1.0, "paper", 600);
  // Variance over ensembles of T(t) - T(0) is round-off only when every ensemble conserves
  // energy; compare each time's ensemble mean and variance with t = 0.
  const MeanCi T0 = r.at(0, 4);
  for (std::size_t m = 1; m < r.times.size(); ++m) {
    const MeanCi T = r.at(m, 4);
    EXPECT_NEAR(T.mean, T0.mean, 1e-12);
    EXPECT_NEAR(T.variance, T0.variance, 1e-12);
    for (int a = 1; a <= 3; ++a) {
      const MeanCi V = r.at(m, a);
      const MeanCi V0 = r.at(0, a);
      EXPECT_NEAR(V.mean, V0.mean, 1e-14);
    }
  }
}
