// Observation times other than the uniform grid (dsmc.observe: log or times): the grids as
// specified, stored as the actual times, the exact Maxwell cooling law at log-spaced times for
// no-splitting and splitting, and the bits: a list equal to the observe_every grid gives the bits
// of observe_every for every engine, and threads, shards and a resumed run give the same file.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "granboltz/dsmc/run.hpp"
#include "test_support.hpp"

using namespace granboltz;
using granboltz::test::MaxwellExact;

namespace {

constexpr int kTemperature = 4;

DsmcConfig dsmc_of(const std::vector<std::string>& sets) {
  std::vector<std::string> all = {
      "model=dsmc",     "seed=1",      "ensembles=2",          "dsmc.particles=64",
      "dsmc.alpha=0.5", "dsmc.beta=0", "dsmc.kernel.lambda=0", "dsmc.kernel.C=0.0795774715459477",
      "dsmc.t_end=100"};
  all.insert(all.end(), sets.begin(), sets.end());
  return parse_config("{}", "test", all).dsmc;
}

// The stored config of an output, and its times.
std::string stored_config(const std::string& file) {
  return H5Reader(file).attr_string("/", "config");
}
std::vector<double> stored_times(const std::string& file) {
  return H5Reader(file).read_double("/time");
}

// Every dataset of two outputs agrees byte for byte (their stored configs differ in the key).
void expect_same_datasets(const std::string& a, const std::string& b) {
  H5Reader ra(a), rb(b);
  const auto names = ra.datasets();
  ASSERT_EQ(names, rb.datasets());
  ASSERT_GT(names.size(), 5u);
  for (const auto& name : names) EXPECT_EQ(ra.read_bytes(name), rb.read_bytes(name)) << name;
}

}  // namespace

TEST(ObservationTimes, LogGridIsZeroThenT1TimesTenToTheJOverKThenTEnd) {
  // Five decades, 12 per decade: 60 times from 10^-3 below t_end = 100, then t_end, after t = 0.
  const DsmcConfig d = dsmc_of({"dsmc.observe.log.from=0.001", "dsmc.observe.log.per_decade=12"});
  const std::vector<double> t = dsmc_times(d);
  ASSERT_EQ(t.size(), 62u);
  EXPECT_EQ(d.observations(), 61u);
  EXPECT_EQ(t[0], 0.0);
  for (std::size_t j = 0; j < 60; ++j) EXPECT_EQ(t[j + 1], 0.001 * std::pow(10.0, j / 12.0)) << j;
  for (int q = 0; q < 5; ++q) EXPECT_EQ(t[1 + 12 * q], 0.001 * std::pow(10.0, q)) << "decade " << q;
  EXPECT_EQ(t[12], 0.001 * std::pow(10.0, 11 / 12.0));
  EXPECT_EQ(t.back(), 100.0);
  // from = t_end: t = 0 and t_end; a grid ending a hair below t_end ends at t_end only.
  EXPECT_EQ(dsmc_times(dsmc_of({"dsmc.observe.log.from=100", "dsmc.observe.log.per_decade=3"})),
            (std::vector<double>{0.0, 100.0}));
  EXPECT_EQ(dsmc_times(dsmc_of({"dsmc.observe.log.from=0.1", "dsmc.observe.log.per_decade=1"})),
            (std::vector<double>{0.0, 0.1, 1.0, 10.0, 100.0}));
  // The uniform grid is unchanged, and observe_every is 0 with dsmc.observe (the steady window is
  // then t > steady_from).
  EXPECT_EQ(dsmc_times(dsmc_of({"dsmc.observe_every=25"})),
            (std::vector<double>{0.0, 25.0, 50.0, 75.0, 100.0}));
  EXPECT_EQ(d.observe_every, 0.0);
}

TEST(ObservationTimes, SplittingRoundsTheLogGridToStepsAndRefusesListedTimesOffThem) {
  // dt = 0.05: 10^-3 ... 10^-1.5 round to 0 or to steps already taken and are dropped.
  const DsmcConfig d = dsmc_of({"dsmc.scheme=euler", "dsmc.steps=2000",
                                "dsmc.observe.log.from=0.001", "dsmc.observe.log.per_decade=12"});
  const std::vector<double> t = dsmc_times(d);
  const double dt = d.time_step();
  EXPECT_EQ(t[1], dt);
  EXPECT_EQ(t.back(), 100.0);
  // The steps of the grid's points below t_end, each once, and t_end.
  std::vector<double> expected{0.0};
  for (int j = 0; j < 60; ++j) {
    const auto k = std::llround(0.001 * std::pow(10.0, j / 12.0) / dt);
    if (k > 0 && static_cast<double>(k) * dt > expected.back())
      expected.push_back(static_cast<double>(k) * dt);
  }
  expected.push_back(100.0);
  EXPECT_EQ(t, expected);
  for (std::size_t m = 1; m < t.size(); ++m) {
    EXPECT_GT(t[m], t[m - 1]) << m;
    EXPECT_EQ(t[m], m + 1 == t.size() ? 100.0 : static_cast<double>(std::llround(t[m] / dt)) * dt)
        << m;
    // Within half a step of a point of the log grid.
    const double j = std::round(12.0 * std::log10(t[m] / 0.001));
    EXPECT_LE(std::fabs(t[m] - 0.001 * std::pow(10.0, j / 12.0)), 0.5 * dt * (1 + 1e-12)) << m;
  }
  EXPECT_EQ(test::config_error(
                "{}", {"model=dsmc", "seed=1", "ensembles=2", "dsmc.particles=64", "dsmc.alpha=0.5",
                       "dsmc.beta=0", "dsmc.kernel.lambda=0", "dsmc.kernel.C=1", "dsmc.t_end=1",
                       "dsmc.scheme=strang", "dsmc.steps=10", "dsmc.observe.times=[0.2, 0.25]"}),
            "dsmc.observe.times[1] = 0.25: must be a whole multiple of the time step t_end/steps = "
            "0.1 (scheme strang)");
}

TEST(ObservationTimes, ListedTimesAreStoredAsGivenWithTEndAppendedAndTheConfigRoundTrips) {
  test::TempDir dir;
  const std::string cfg = dir.write("c.yaml", test::base_config("dsmc_observe"));
  const std::string out = dir.file("out.h5");
  const auto r =
      test::run_granboltz("run " + cfg + " -q -o " + out +
                          " --set 'dsmc.observe={times: [0.1, 0.125, 0.30000000000000004]}'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(stored_times(out), (std::vector<double>{0.0, 0.1, 0.125, 0.30000000000000004, 0.5}));
  const std::string text = stored_config(out);
  EXPECT_NE(text.find("  observe: {times: [0.1, 0.125, 0.30000000000000004, 0.5]}\n"),
            std::string::npos)
      << text;
  EXPECT_EQ(text.find("observe_every"), std::string::npos) << text;
  // The stored config read again is the same config, written the same way.
  const Config again = parse_config(text, "stored", {});
  EXPECT_EQ(dsmc_times(again.dsmc), stored_times(out));
  EXPECT_EQ(again.to_yaml(true), text);
  // The log grid too.
  const Config log = parse_config(test::base_config("dsmc_observe"), "base",
                                  {"dsmc.observe={log: {from: 0.001, per_decade: 7}}"});
  const std::string log_text = log.to_yaml(true);
  EXPECT_NE(log_text.find("  observe: {log: {from: 0.001, per_decade: 7}}\n"), std::string::npos)
      << log_text;
  EXPECT_EQ(parse_config(log_text, "stored", {}).to_yaml(true), log_text);
}

TEST(ObservationTimes, MaxwellFreeCoolingAtLogTimesFollowsTheExactLawOverFiveDecades) {
  // E[T](t) = (1 - 1/n) T0 e^(-kappa t) for no-splitting, the two-term recurrence at t = k dt for
  // Euler splitting; every observation within its interval at family-wise level 0.999.
  const double n = 64, N = 2000;
  const MaxwellExact exact{0.5, 0.0, 1.0, 0.0795774715459477, 1.0};
  for (const bool split : {false, true}) {
    std::vector<std::string> sets = {"model=dsmc",
                                     "seed=41",
                                     "ensembles=2000",
                                     "dsmc.particles=64",
                                     "dsmc.alpha=0.5",
                                     "dsmc.thermostat=none",
                                     "dsmc.kernel.lambda=0",
                                     "dsmc.kernel.C=0.0795774715459477",
                                     "dsmc.t_end=100",
                                     "dsmc.observe.log.from=0.001",
                                     "dsmc.observe.log.per_decade=12",
                                     "dsmc.moments=0"};
    if (split) sets.insert(sets.end(), {"dsmc.scheme=euler", "dsmc.steps=2000"});
    const Config c = parse_config("{}", "test", sets);
    const test::DsmcRun r(c);
    EXPECT_EQ(r.times, dsmc_times(c.dsmc));
    if (!split) ASSERT_EQ(r.times.size(), 62u);
    const double z = test::family_z(static_cast<int>(r.times.size()) - 1);
    const double dt = c.dsmc.time_step();
    for (std::size_t m = 1; m < r.times.size(); ++m) {
      const double t = r.times[m];
      const MeanCi T = r.at(m, kTemperature);
      const double expected =
          split ? exact.centred_split(static_cast<int>(std::llround(t / dt)), dt, n, false)
                : exact.centred_nosplit(t, n);
      EXPECT_NEAR(T.mean, expected, z * std::sqrt(T.variance / N))
          << (split ? "euler" : "nosplit") << " t = " << t;
    }
  }
}

namespace {
// Configs of every engine, observed every 0.1 up to t_end = 1 (0.1 m is not 0.1 * m in decimal:
// the listed times below are the doubles m * 0.1, written so that they read back exactly).
const char* kEngines[] = {
    // one species, no splitting, white noise, steady window, histogram
    "dsmc.kernel.lambda=1 --set dsmc.kernel.C=0.25 --set dsmc.steady_from=0.35 "
    "--set 'dsmc.histogram={shells: 8, radius: 5, component: true}'",
    // one species, Strang splitting, Gaussian thermostat
    "dsmc.kernel.lambda=1 --set dsmc.kernel.C=0.25 --set dsmc.thermostat=gaussian "
    "--set dsmc.beta=0 --set dsmc.scheme=strang --set dsmc.steps=20 --set dsmc.steady_from=0",
    // the general gas: a rough binary mixture in d = 2
    "dsmc.dimension=2 --set dsmc.roughness.beta=0.2 --set dsmc.roughness.inertia=0.5 "
    "--set 'dsmc.species=[{name: a, fraction: 0.5}, {name: b, fraction: 0.5, mass: 3}]' "
    "--set dsmc.steady_from=0.5",
    // weighted particles (SWPM) under the Gaussian thermostat
    "dsmc.kernel.lambda=1 --set dsmc.kernel.C=0.25 --set dsmc.thermostat=gaussian "
    "--set dsmc.beta=0 --set dsmc.weights.method=swpm --set dsmc.weights.kappa=0.5 "
    "--set dsmc.weights.max_particles=200 --set dsmc.steady_from=0.2"};

std::string uniform_list(double every, int M) {
  std::string s = "[";
  for (int m = 1; m <= M; ++m) s += (m > 1 ? ", " : "") + format_real(m == M ? 1.0 : m * every);
  return s + "]";
}
}  // namespace

TEST(ObservationTimes, AListEqualToTheObserveEveryGridGivesItsBitsOnEveryEngine) {
  for (const char* engine : kEngines) {
    test::TempDir dir;
    const std::string cfg = dir.write("c.yaml", test::base_config("dsmc")) +
                            " -q --set dsmc.particles=100 --set dsmc.t_end=1 --set " + engine;
    const std::string every = dir.file("every.h5"), listed = dir.file("listed.h5");
    auto ok = [](const test::CommandResult& r) { ASSERT_EQ(r.exit_code, 0) << r.output; };
    ok(test::run_granboltz("run " + cfg + " --set dsmc.observe_every=0.1 -o " + every));
    // The base config has observe_every; --set cannot remove it, so a copy without it.
    std::string text = test::base_config("dsmc");
    text.replace(text.find("  observe_every: 0.25\n"), 21, "");
    const std::string cfg2 = dir.write("d.yaml", text) +
                             " -q --set dsmc.particles=100 --set dsmc.t_end=1 --set " + engine;
    ok(test::run_granboltz("run " + cfg2 + " --set 'dsmc.observe={times: " + uniform_list(0.1, 10) +
                           "}' -o " + listed));
    expect_same_datasets(every, listed);
    EXPECT_EQ(stored_times(listed),
              dsmc_times(parse_config(test::base_config("dsmc"), "b",
                                      {"dsmc.t_end=1", "dsmc.observe_every=0.1"})
                             .dsmc))
        << engine;
    EXPECT_NE(stored_config(listed).find("observe: {times: [0.1, 0.2, 0.30000000000000004"),
              std::string::npos)
        << stored_config(listed);
  }
}

TEST(ObservationTimes, ThreadsShardsAndResumeAreBitIdenticalOnALogGrid) {
  for (const std::string engine : {std::string("dsmc.beta=1"), std::string(kEngines[1]),
                                   std::string(kEngines[2]), std::string(kEngines[3])}) {
    test::TempDir dir;
    const std::string cfg = dir.write("c.yaml", test::base_config("dsmc_observe")) +
                            " --set dsmc.t_end=1 --set dsmc.particles=100 --set 'dsmc.observe="
                            "{log: {from: 0.01, per_decade: 5}}' --set " +
                            engine;
    const std::string one = test::expect_threads_and_shards_identical(dir, cfg);
    const std::vector<double> t = stored_times(one);
    EXPECT_GE(t.size(), 8u) << engine;
    EXPECT_EQ(t.back(), 1.0) << engine;
  }
  // A run stopped by SIGTERM (its ensembles saved in progress between two observations) resumes
  // to the file of the uninterrupted run.
  test::TempDir dir;
  std::string text = test::base_config("dsmc_observe");
  text.replace(text.find("particles: 64"), 13, "particles: 200000");
  text.replace(text.find("t_end: 0.5"), 10, "gamma: 40\n  t_end: 2");  // about 2 s on 2 threads
  text.replace(text.find("observe: {times: [0.25, 0.5]}"), 29,
               "observe: {log: {from: 0.001, per_decade: 4}}\n  steady_from: 0.5");
  text += "checkpoint: {every_seconds: 3600}\n";
  test::expect_sigterm_resumes_identically(dir, dir.write("c.yaml", text));
}
