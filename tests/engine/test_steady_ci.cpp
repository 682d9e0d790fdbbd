// The steady-state interval (dsmc.steady_ci): consecutive observation rows of one ensemble are
// correlated, so an interval counting every (ensemble, t_m) sample as independent is too narrow.
// Replicas with other seeds measure the real spread of the steady means; the default estimator's
// sigma must match it, for both its branches, and the independent one must not.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "granboltz/app/config.hpp"
#include "granboltz/dsmc/run.hpp"
#include "test_support.hpp"

using namespace granboltz;

namespace {

// Heated hard spheres; rows every 0.2 are several rows apart from independent for T and M4.
const char* kHeated = R"(model: dsmc
seed: 1
ensembles: 12
dsmc:
  particles: 200
  alpha: 0.7
  beta: 1
  gamma: 4
  kernel: {lambda: 1, C: 0.07957747154594767}
  t_end: 30
  observe_every: 0.2
  moments: 2
  steady_from: 5
)";

constexpr std::uint64_t kT = 4;                 // temperature in an Observation
constexpr std::uint64_t kM4 = kNumScalars + 1;  // <|v - V|^4>

struct Coverage {
  double batch_T, batch_M4, independent_T, independent_M4;
  std::string estimator;
};

double spread_over_sigma(const std::vector<double>& means, const std::vector<double>& sigmas) {
  double m = 0, s = 0, v = 0;
  for (double x : means) m += x;
  m /= static_cast<double>(means.size());
  for (double x : means) v += (x - m) * (x - m);
  v /= static_cast<double>(means.size() - 1);
  for (double x : sigmas) s += x;
  s /= static_cast<double>(sigmas.size());
  return std::sqrt(v) / s;
}

/// Replicas with seeds 1..replicas: the spread of their steady means over the mean reported sigma.
Coverage coverage(std::uint64_t ensembles, int replicas) {
  std::vector<double> T, M4, sT, sM4, iT, iM4;
  Coverage c;
  for (int seed = 1; seed <= replicas; ++seed) {
    const Config config =
        parse_config(kHeated, "test.yaml",
                     {"seed=" + std::to_string(seed), "ensembles=" + std::to_string(ensembles)});
    Config independent = config;
    independent.dsmc.steady_ci_independent = true;
    test::DsmcRun run(config);
    const SteadyStats t = steady_stats(config, run.record, kT);
    const SteadyStats m = steady_stats(config, run.record, kM4);
    c.estimator = t.estimator;
    T.push_back(t.mean);
    M4.push_back(m.mean);
    sT.push_back(t.sigma);
    sM4.push_back(m.sigma);
    // The same record read as independent samples: the same means, today's sigma.
    const SteadyStats ti = steady_stats(independent, run.record, kT);
    const SteadyStats mi = steady_stats(independent, run.record, kM4);
    EXPECT_EQ(ti.mean, t.mean);
    EXPECT_EQ(std::string(ti.estimator), "independent");
    iT.push_back(ti.sigma);
    iM4.push_back(mi.sigma);
  }
  c.batch_T = spread_over_sigma(T, sT);
  c.batch_M4 = spread_over_sigma(M4, sM4);
  c.independent_T = spread_over_sigma(T, iT);
  c.independent_M4 = spread_over_sigma(M4, iM4);
  return c;
}

void expect_covers(const Coverage& c, const std::string& estimator) {
  EXPECT_EQ(c.estimator, estimator);
  EXPECT_GE(c.batch_T, 0.75) << estimator;
  EXPECT_LE(c.batch_T, 1.33) << estimator;
  EXPECT_GE(c.batch_M4, 0.75) << estimator;
  EXPECT_LE(c.batch_M4, 1.33) << estimator;
  EXPECT_GT(c.independent_T, 1.33) << "the rows should be correlated enough to show the bias";
  EXPECT_GT(c.independent_M4, 1.33) << "the rows should be correlated enough to show the bias";
  std::printf("%s: spread / sigma  T %.2f  M4 %.2f  (independent: T %.2f  M4 %.2f)\n",
              estimator.c_str(), c.batch_T, c.batch_M4, c.independent_T, c.independent_M4);
}

}  // namespace

TEST(SteadyCi, EnsemblesEstimatorCoversTheSpreadOfReplicas) {
  expect_covers(coverage(kSteadyMinEnsembles + 2, 60), "ensembles");
}

TEST(SteadyCi, BlockingEstimatorCoversTheSpreadOfReplicas) {
  expect_covers(coverage(4, 60), "blocking");
}

TEST(SteadyCi, OutputsCarrySigmaAndTheEstimatorAndIndependentKeepsTheOtherDatasets) {
  test::TempDir dir;
  const std::string cfg = dir.write("c.yaml", kHeated);
  const std::string batch = dir.file("batch.h5"), ind = dir.file("independent.h5");
  ASSERT_EQ(test::run_granboltz("run " + cfg + " -q --set ensembles=3 -o " + batch).exit_code, 0);
  ASSERT_EQ(test::run_granboltz("run " + cfg +
                                " -q --set ensembles=3 --set dsmc.steady_ci=independent -o " + ind)
                .exit_code,
            0);
  H5Reader b(batch), i(ind);
  EXPECT_EQ(b.attr_string("/steady/temperature", "estimator"), "blocking");
  EXPECT_EQ(i.attr_string("/steady/temperature", "estimator"), "independent");
  EXPECT_EQ(b.dims("/steady/bulk_velocity/sigma"), (Dims{3}));
  EXPECT_EQ(b.dims("/steady/pressure_tensor/sigma"), (Dims{3, 3}));
  EXPECT_EQ(b.attr_uint64("/steady/moment_4", "samples"), 3u * 125u);
  EXPECT_GT(b.read_double("/steady/temperature/ci")[0], i.read_double("/steady/temperature/ci")[0]);
  // independent: sigma = sqrt(variance / samples), and beside it the batch estimator's interval,
  // equal to the batch run's.
  const double var = i.read_double("/steady/temperature/variance")[0];
  EXPECT_DOUBLE_EQ(i.read_double("/steady/temperature/sigma")[0], std::sqrt(var / 375.0));
  EXPECT_EQ(i.attr_string("/steady/temperature/batch", "estimator"), "blocking");
  EXPECT_FALSE(b.exists("/steady/temperature/batch"));
  for (const char* obs : {"temperature", "pressure_tensor", "moment_4"})
    for (const char* what : {"/sigma", "/ci"})
      EXPECT_EQ(i.read_bytes(std::string("/steady/") + obs + "/batch" + what),
                b.read_bytes(std::string("/steady/") + obs + what))
          << obs << what;
  EXPECT_TRUE(b.exists("/accumulators/steady_ensemble"));
  EXPECT_TRUE(b.exists("/accumulators/steady_blocks"));
  for (const std::string& name : i.datasets()) {
    const bool estimator_only = name.rfind("/steady/", 0) == 0 &&
                                (name.size() > 3 && (name.substr(name.size() - 3) == "/ci" ||
                                                     name.substr(name.size() - 6) == "/sigma"));
    // The manifest lists what each output presents: the independent one its batch subgroups too.
    if (estimator_only || name.rfind("/manifest/", 0) == 0) continue;
    EXPECT_EQ(b.read_bytes(name), i.read_bytes(name)) << name;
  }
}

TEST(SteadyCi, MergedShardsGiveTheSameSteadyIntervals) {
  test::TempDir dir;
  const std::string cfg = dir.write("c.yaml", kHeated);
  for (const std::string n : {"4", "12"}) {  // blocking and ensembles
    const std::string one = dir.file("one" + n + ".h5");
    ASSERT_EQ(
        test::run_granboltz("run " + cfg + " -q --set ensembles=" + n + " -o " + one).exit_code, 0);
    std::string shards;
    for (int s = 0; s < 3; ++s) {
      const std::string path = dir.file("s" + n + "_" + std::to_string(s) + ".h5");
      ASSERT_EQ(test::run_granboltz("run " + cfg + " -q --set ensembles=" + n +
                                    " --set shard.count=3 --set shard.index=" + std::to_string(s) +
                                    " -o " + path)
                    .exit_code,
                0);
      shards += path + " ";
    }
    const std::string merged = dir.file("merged" + n + ".h5");
    ASSERT_EQ(test::run_granboltz("merge " + shards + "-o " + merged).exit_code, 0);
    test::expect_identical_outputs(one, merged);
    H5Reader m(merged);
    EXPECT_EQ(m.attr_string("/steady/temperature", "estimator"),
              n == "4" ? "blocking" : "ensembles");
  }
}

TEST(SteadyCi, ConfigWithoutSteadyFromIsUnchangedAndSteadyCiNeedsIt) {
  const std::string base =
      "model: dsmc\nseed: 1\ndsmc: {particles: 10, alpha: 0.5, beta: 1, kernel: {lambda: 1, C: "
      "0.1}, t_end: 1";
  const Config plain = parse_config(base + "}\n", "test.yaml");
  EXPECT_FALSE(plain.dsmc.steady);
  EXPECT_EQ(plain.to_yaml(true).find("steady"), std::string::npos);
  const Record r = dsmc_layout(plain);
  EXPECT_THROW(r.moments("steady_ensemble"), std::out_of_range);
  EXPECT_THROW(r.moments("steady"), std::out_of_range);
  EXPECT_EQ(test::config_error(base + ", steady_ci: batch}\n"),
            "dsmc.steady_ci: needs dsmc.steady_from (the steady-state window)");
  EXPECT_NE(test::config_error(base + ", steady_from: 0.5, steady_ci: pooled}\n")
                .find("dsmc.steady_ci = pooled: must be one of batch, independent"),
            std::string::npos);
  const Config batch = parse_config(base + ", steady_from: 0.5}\n", "test.yaml");
  EXPECT_FALSE(batch.dsmc.steady_ci_independent);  // the honest interval by default
  EXPECT_NE(batch.to_yaml(true).find("steady_ci: batch"), std::string::npos);
  const Config once =
      parse_config(base + ", steady_from: 0.5, steady_ci: independent}\n", "test.yaml");
  const Config ind = parse_config(once.to_yaml(true), "again.yaml");
  EXPECT_TRUE(ind.dsmc.steady_ci_independent);
}

TEST(SonineCoefficients, A2AndA3FollowTheMomentsAndTheirIntervalsCoverReplicas) {
  // The delta method over ensembles: the spread of replicas' a2, a3 (last row and steady) over
  // their mean reported sigma.
  test::TempDir dir;
  const std::string cfg = dir.write("c.yaml", kHeated);
  std::vector<double> a2, a3, s2, s3, sa2, sa3, ss2, ss3;
  for (int seed = 1; seed <= 40; ++seed) {
    const std::string out = dir.file("r" + std::to_string(seed) + ".h5");
    ASSERT_EQ(test::run_granboltz("run " + cfg + " -q --set dsmc.moments=3 --set seed=" +
                                  std::to_string(seed) + " -o " + out)
                  .exit_code,
              0);
    H5Reader f(out);
    const auto m2 = f.read_double("/moment_2/mean"), m4 = f.read_double("/moment_4/mean"),
               m6 = f.read_double("/moment_6/mean");
    const auto A2 = f.read_double("/a2/mean"), A3 = f.read_double("/a3/mean");
    ASSERT_EQ(A2.size(), m2.size());
    for (std::size_t m = 0; m < m2.size(); m += 37) {
      const double x2 = 0.6 * m4[m] / (m2[m] * m2[m]) - 1;
      EXPECT_NEAR(A2[m], x2, 1e-12);
      EXPECT_NEAR(A3[m], 1 + 3 * x2 - 9.0 / 35.0 * m6[m] / (m2[m] * m2[m] * m2[m]), 1e-12);
    }
    a2.push_back(A2.back());
    a3.push_back(A3.back());
    s2.push_back(f.read_double("/a2/ci").back() / kLambdaP);
    s3.push_back(f.read_double("/a3/ci").back() / kLambdaP);
    sa2.push_back(f.read_double("/steady/a2/mean")[0]);
    sa3.push_back(f.read_double("/steady/a3/mean")[0]);
    ss2.push_back(f.read_double("/steady/a2/sigma")[0]);
    ss3.push_back(f.read_double("/steady/a3/sigma")[0]);
    EXPECT_EQ(f.attr_string("/steady/a2", "estimator"), "ensembles");
    // The ratio estimator's 1/N bias is far inside the interval at every row and in the steady
    // state (it is O(1/N) against a sigma of O(1/sqrt(N))), so it is reported, not subtracted.
    for (const char* g : {"/a2", "/a3", "/steady/a2", "/steady/a3"}) {
      const auto bias = f.read_double(std::string(g) + "/bias");
      const auto ci = f.read_double(std::string(g) + "/ci");
      ASSERT_EQ(bias.size(), ci.size()) << g;
      for (std::size_t k = 0; k < bias.size(); ++k)
        EXPECT_LT(std::fabs(bias[k]), 0.1 * ci[k]) << g << " row " << k;
    }
  }
  const double r[] = {spread_over_sigma(a2, s2), spread_over_sigma(a3, s3),
                      spread_over_sigma(sa2, ss2), spread_over_sigma(sa3, ss3)};
  std::printf("a2, a3 spread / sigma: last row %.2f %.2f, steady %.2f %.2f\n", r[0], r[1], r[2],
              r[3]);
  for (double x : r) {
    EXPECT_GE(x, 0.75);
    EXPECT_LE(x, 1.33);
  }
  // White-noise heated hard spheres at alpha = 0.7: a2 ~ 1e-3 (van Noije & Ernst 1998), plus a
  // finite-n bias of order 1/n; far below 0.05 either way.
  double mean = 0;
  for (double x : sa2) mean += x / static_cast<double>(sa2.size());
  EXPECT_LT(std::fabs(mean), 0.05);
}

TEST(SonineCoefficients, AbsentWithoutEnoughMomentsAndFromEnsemblesWhateverSteadyCi) {
  test::TempDir dir;
  const std::string cfg = dir.write("c.yaml", kHeated);
  const std::string one = dir.file("one.h5"), two = dir.file("two.h5"), ind = dir.file("i.h5");
  ASSERT_EQ(
      test::run_granboltz("run " + cfg + " -q --set ensembles=2 --set dsmc.moments=1 -o " + one)
          .exit_code,
      0);
  ASSERT_EQ(test::run_granboltz("run " + cfg + " -q --set ensembles=2 -o " + two).exit_code, 0);
  ASSERT_EQ(test::run_granboltz("run " + cfg +
                                " -q --set ensembles=2 --set dsmc.steady_ci=independent -o " + ind)
                .exit_code,
            0);
  H5Reader a(one), b(two), i(ind);
  EXPECT_FALSE(a.exists("/a2/mean"));
  EXPECT_FALSE(a.exists("/accumulators/moment_cross"));
  EXPECT_TRUE(b.exists("/a2/mean"));
  EXPECT_FALSE(b.exists("/a3/mean"));  // moments: 2 gives M2 and M4 only
  EXPECT_TRUE(b.exists("/steady/a2/ci"));
  EXPECT_TRUE(i.exists("/a2/mean"));
  // The steady a2 has one estimator, the spread of the ensembles' averages.
  EXPECT_EQ(i.attr_string("/steady/a2", "estimator"), "ensembles");
  EXPECT_EQ(i.read_bytes("/steady/a2/ci"), b.read_bytes("/steady/a2/ci"));
}
