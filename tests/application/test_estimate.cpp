// The cost estimate (granboltz estimate, and the line `run` prints) against the events counted by
// real runs: real collisions, fictitious candidates and kicks, each within 10 %, for the DSMC
// schemes and majorants and for the TV06 intruder and needle.
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "granboltz/app/estimate.hpp"
#include "granboltz/app/run.hpp"
#include "granboltz/h5/hdf5_io.hpp"
#include "test_support.hpp"

using granboltz::test::run_granboltz;
using granboltz::test::TempDir;

namespace {

const char* kHardSpheres = R"(model: dsmc
seed: 3
ensembles: 4
dsmc:
  particles: 2048
  alpha: 0.5
  beta: 0.125
  gamma: 4
  kernel: {lambda: 1, C: 0.0795774715459477}
  t_end: 2
  observe_every: 0.25
)";

// GRW05 Ex. 7 with weighted particles (SWPM, importance splitting), scaled down: the pilot
// (10^5 candidates) sees about a quarter of ensemble 0.
const char* kWeighted = R"(model: dsmc
seed: 7
ensembles: 4
dsmc:
  particles: 500
  alpha: 0.1
  beta: 30
  gamma: 16
  kernel: {lambda: 0, C: 0.07957747154594767}
  t_end: 20
  observe_every: 0.5
  weights:
    method: swpm
    kappa: 0.25
    max_particles: 1000
    split: {radius: 16, rate: 0.73, interval: 0.0625, max_radius: 130}
)";

const char* kIntruder = R"(model: intruder
seed: 12
ensembles: 4
intruder:
  bath: {kind: gaussian, a: 1}
  mass: 0.5
  alpha: 0.3
  collisions: 20000
)";

const char* kNeedle = R"(model: needle
seed: 13
ensembles: 4
needle:
  mass: 0.5
  alpha: 0.4
  collisions: 20000
)";

double total(const granboltz::H5Reader& in, const std::string& column) {
  if (!in.exists(column)) return 0.0;
  double s = 0.0;
  for (auto v : in.read_uint64(column)) s += static_cast<double>(v);
  return s;
}

// Runs `text` with `sets`, and compares the estimate with the counted events. The TV06 columns
// count the events after the warm-up; the estimate is of the whole run, so it is scaled back.
void expect_estimate_matches(const char* text, const std::vector<std::string>& sets,
                             double tolerance = 0.10) {
  TempDir dir;
  const std::string cfg = dir.write("c.yaml", text), out = dir.file("out.h5");
  std::string args;
  for (const auto& s : sets) args += " --set '" + s + "'";  // YAML values with spaces
  const auto r = run_granboltz("run " + cfg + args + " -q -o " + out);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const granboltz::Config config = granboltz::parse_config(text, "c.yaml", sets);
  const granboltz::RunEstimate e = granboltz::estimate_run(config, 1);
  double counted_fraction = 1.0;  // of the estimated events that the columns count
  if (config.model == granboltz::Model::kIntruder)
    counted_fraction = static_cast<double>(config.intruder.collisions) /
                       static_cast<double>(config.intruder.collisions + config.intruder.warmup);
  if (config.model == granboltz::Model::kNeedle)
    counted_fraction = static_cast<double>(config.needle.collisions) /
                       static_cast<double>(config.needle.collisions + config.needle.warmup);
  granboltz::H5Reader in(out);
  const struct {
    const char* name;
    double estimated, counted;
  } checks[] = {{"collisions", e.collisions * counted_fraction, total(in, "/events/collisions")},
                {"fictitious", e.fictitious * counted_fraction, total(in, "/events/fictitious")},
                {"kicks", e.kicks, total(in, "/events/kicks")}};
  std::string label;
  for (const auto& s : sets) label += s + " ";
  for (const auto& c : checks) {
    if (std::getenv("GRANBOLTZ_PRINT_RATIOS") && c.counted > 0)
      std::printf("estimate/counted %-10s %.4f  %s\n", c.name, c.estimated / c.counted,
                  label.c_str());
    if (c.counted == 0) {
      EXPECT_EQ(c.estimated, 0.0) << label << c.name;
      continue;
    }
    EXPECT_NEAR(c.estimated / c.counted, 1.0, tolerance)
        << label << c.name << ": estimated " << c.estimated << ", counted " << c.counted;
  }
}

}  // namespace

TEST(Estimate, DsmcEventsAreWithinTenPercentOfCountedForEverySchemeAndMajorant) {
  expect_estimate_matches(kHardSpheres, {});  // GRW05 Ex. 5, paper majorant update
  expect_estimate_matches(kHardSpheres, {"dsmc.majorant_update=strict"});
  expect_estimate_matches(kHardSpheres, {"dsmc.scheme=strang", "dsmc.steps=32"});
  expect_estimate_matches(kHardSpheres, {"dsmc.scheme=euler", "dsmc.steps=16"});
  expect_estimate_matches(kHardSpheres, {"dsmc.beta=0", "dsmc.alpha=1", "dsmc.majorant=pairwise"});
  // RW05 Maxwell molecules (heated, T_inf = 8/3) and a strongly heated GRW05 Ex. 8 start.
  expect_estimate_matches(kHardSpheres, {"dsmc.kernel.lambda=0", "dsmc.kernel.C=0.3183098861837907",
                                         "dsmc.gamma=1", "dsmc.beta=1", "dsmc.t_end=8"});
  expect_estimate_matches(kHardSpheres, {"dsmc.alpha=0.1", "dsmc.beta=30", "dsmc.gamma=16",
                                         "dsmc.t_end=0.1", "dsmc.observe_every=0.05"});
}

TEST(Estimate, SplittingWithManyStepsAndTheGaussianThermostatMatchCounted) {
  // Many steps: n kicks per step, and U_max sees them all.
  expect_estimate_matches(kHardSpheres, {"dsmc.scheme=euler", "dsmc.steps=4000"});
  expect_estimate_matches(kHardSpheres, {"dsmc.scheme=strang", "dsmc.steps=2000"});
  expect_estimate_matches(kHardSpheres,
                          {"dsmc.scheme=euler", "dsmc.steps=2000", "dsmc.majorant=pairwise"});
  // The Gaussian thermostat holds T at T0: hard spheres collide at the rate of T0 all along (an
  // estimate that let T cool as if unheated was 3.4 times low).
  expect_estimate_matches(kHardSpheres, {"dsmc.thermostat=gaussian", "dsmc.beta=0"});
  expect_estimate_matches(kHardSpheres,
                          {"dsmc.thermostat=gaussian", "dsmc.beta=0", "dsmc.majorant=pairwise"});
  expect_estimate_matches(kHardSpheres, {"dsmc.thermostat=gaussian", "dsmc.beta=0",
                                         "dsmc.scheme=strang", "dsmc.steps=64"});
  // Free cooling (Haff's law): the majorant stays, the real collisions slow down.
  expect_estimate_matches(kHardSpheres, {"dsmc.thermostat=none", "dsmc.beta=0", "dsmc.t_end=8",
                                         "dsmc.observe_every=1"});
}

TEST(Estimate, WeightedParticleEventsFromThePilotMatchCounted) {
  expect_estimate_matches(kWeighted, {});
  // Hard spheres (GRW05 Ex. 8's importance function): the pilot sees the start of the
  // temperature's rise (the real-collision rate grows as sqrt(T)) and of the majorant's growth as
  // the tail fills, so it underestimates; the promise for lambda > 0 is a factor 1.5
  // (docs/output.md; here 0.71, on the papers' weighted runs 0.8-1.1 in time).
  expect_estimate_matches(kWeighted,
                          {"dsmc.kernel.lambda=1", "dsmc.t_end=0.5", "dsmc.observe_every=0.05",
                           "dsmc.weights.kappa=1", "dsmc.weights.split.radius=7.5",
                           "dsmc.weights.split.rate=0.49", "dsmc.weights.split.power=1.5",
                           "dsmc.weights.split.interval=0.01", "dsmc.weights.split.max_radius=34"},
                          0.5);
}

TEST(Estimate, WeightedParticleMemoryFollowsMaxParticles) {
  granboltz::Config small = granboltz::parse_config(kWeighted, "c.yaml", {});
  granboltz::Config large =
      granboltz::parse_config(kWeighted, "c.yaml", {"dsmc.weights.max_particles=1000000"});
  // A million weighted particles per thread take well over 32 bytes each (positions, weights,
  // the sum tree): the estimate must grow with N_max, not stay with the initial n = 500.
  EXPECT_GT(granboltz::estimate_memory(large, 2) - granboltz::estimate_memory(small, 2),
            2u * 1000000u * 100u);
}

TEST(Estimate, Tv06EventsAreWithinTenPercentOfCounted) {
  expect_estimate_matches(kIntruder, {});
  expect_estimate_matches(kIntruder, {"intruder.method=dsmc"});
  expect_estimate_matches(kIntruder,
                          {"intruder.method=dsmc", "intruder.mass=5", "intruder.alpha=0.9"});
  expect_estimate_matches(kNeedle, {});
  expect_estimate_matches(kNeedle, {"needle.mass=5", "needle.alpha=0.9"});
  expect_estimate_matches(kNeedle, {"needle.length=3", "seed=5"});
}

TEST(Estimate, CommandPrintsOneLineAndRunPrintsItUnlessQuiet) {
  TempDir dir;
  const std::string cfg = dir.write("c.yaml", kHardSpheres);
  auto r = run_granboltz("estimate " + cfg);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output.rfind("4 ensembles: ", 0), 0u) << r.output;
  EXPECT_NE(r.output.find(" collisions, "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(" fictitious, "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(" kicks; peak memory "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("; wall time about "), std::string::npos) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  r = run_granboltz("run " + cfg + " -o " + dir.file("a.h5"));
  EXPECT_NE(r.output.find("[granboltz] estimate: 4 ensembles: "), std::string::npos) << r.output;
  r = run_granboltz("run " + cfg + " -q -o " + dir.file("b.h5"));
  EXPECT_EQ(r.output, "");
  r = run_granboltz("run " + cfg + " -q --max-hours 1e-9 -o " + dir.file("c.h5"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("the run would take longer: 4 ensembles: "), std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(dir.file("c.h5")));
}

namespace {

// Seconds that estimate_run takes for `text` with `sets`.
double estimate_seconds(const std::string& text, const std::vector<std::string>& sets) {
  const granboltz::Config config = granboltz::parse_config(text, "c.yaml", sets);
  const auto start = std::chrono::steady_clock::now();
  const granboltz::RunEstimate e = granboltz::estimate_run(config, 1);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_TRUE(std::isfinite(e.seconds) && e.seconds > 0) << e.seconds;
  return s;
}

const std::string kTiny = granboltz::test::base_config("dsmc");

}  // namespace

TEST(Estimate, TakesUnderASecondWhateverTheLengthOfTheRun) {
  // The estimate used to step the temperature ODE with h <= t_end/2000 and 0.02/relaxation:
  // t_end = 1e8 took over 30 s, gamma = 1e12 did not end.
  for (const char* lambda :
       {"dsmc.kernel.lambda=0", "dsmc.kernel.lambda=1", "dsmc.kernel.lambda=0.5"}) {
    EXPECT_LT(estimate_seconds(kTiny, {lambda, "dsmc.t_end=1e8", "dsmc.observe_every=1e8"}), 2.0);
    EXPECT_LT(estimate_seconds(kTiny, {lambda, "dsmc.gamma=1e12"}), 2.0);
    EXPECT_LT(estimate_seconds(
                  kTiny, {lambda, "dsmc.beta=0", "dsmc.t_end=1e15", "dsmc.observe_every=1e15"}),
              2.0);
    EXPECT_LT(estimate_seconds(kTiny, {lambda, "dsmc.thermostat=gaussian", "dsmc.beta=0",
                                       "dsmc.t_end=1e15", "dsmc.observe_every=1e15"}),
              2.0);
  }
  EXPECT_LT(estimate_seconds(kTiny, {"dsmc.kernel.lambda=1", "dsmc.scheme=euler", "dsmc.steps=1e15",
                                     "dsmc.majorant=pairwise"}),
            2.0);
  // TV06: the most collisions a config takes (2^53), and the DSMC intruder's record quantiles.
  EXPECT_LT(estimate_seconds(kIntruder, {"intruder.collisions=9e15", "intruder.method=dsmc"}), 2.0);
  EXPECT_LT(estimate_seconds(kNeedle, {"needle.collisions=9e15"}), 2.0);
}

TEST(Estimate, MaxHoursRefusesWhatTheEngineWouldTakeDaysFor) {
  TempDir dir;
  const std::string cfg = dir.write("c.yaml", kTiny), out = dir.file("out.h5");
  auto refused = [&](const std::string& args, const std::string& expect) {
    const auto r = run_granboltz("run " + cfg + " " + args + " -q -o " + out);
    EXPECT_EQ(r.exit_code, 2) << args << ": " << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    EXPECT_NE(r.output.find(expect), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("nan days"), std::string::npos) << r.output;
    EXPECT_FALSE(std::filesystem::exists(out)) << args;
  };
  // 1e15 Euler steps of 64 kicks each: the steps used not to be costed (a few microseconds).
  refused("--set dsmc.scheme=euler --set dsmc.steps=1e15 --max-hours 0.01",
          "the run would take longer");
  // 2^63 samples and more: the sample clock's arithmetic overflows and the run never ends.
  const std::string icfg = dir.write("i.yaml", kIntruder), ncfg = dir.write("n.yaml", kNeedle);
  for (const auto& [c, key] :
       {std::pair{icfg, "intruder.sample_every"}, std::pair{ncfg, "needle.sample_every"}}) {
    const auto r =
        run_granboltz("run " + c + " --set " + key + "=1e-20 --max-hours 0.01 -q -o " + out);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_EQ(r.output.rfind(std::string("granboltz: error: ") + key + " = 1e-20: ", 0), 0u)
        << r.output;
    EXPECT_FALSE(std::filesystem::exists(out));
  }
  // An estimate that overflows is refused with the key that made it, not "about -nan days".
  refused("--set dsmc.beta=1.7976931348623157e308 --max-hours 1",
          "dsmc.beta = 1.7976931348623157e+308: the run's cost cannot be estimated");
  for (const char* bad : {"nan", "inf", "-1", "0", "1e400"})
    refused(std::string("--max-hours ") + bad, std::string(bad) + ": must be a finite number > 0");
  // A generous limit lets the run go.
  const auto r = run_granboltz("run " + cfg + " --max-hours 1 -q -o " + out);
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

TEST(Estimate, HugeValuesPrintShort) {
  granboltz::RunEstimate e;
  e.ensembles = 1;
  e.collisions = 1e300;
  e.seconds = 1e300;
  const std::string line = granboltz::describe(e);
  EXPECT_LT(line.size(), 200u) << line;
  EXPECT_NE(line.find("wall time about 1.2e+295 days"), std::string::npos) << line;
}

// ---- The general gas (mixtures, rough particles, disks) ----

namespace {

const char* kMixture = R"(model: dsmc
seed: 5
ensembles: 2
dsmc:
  particles: 1000
  species:
    - {name: heavy, fraction: 0.3, mass: 3.0, diameter: 1.5}
    - {name: light, fraction: 0.7, mass: 1.0, diameter: 1.0}
  alpha: [[0.8, 0.7], [0.7, 0.9]]
  beta: 1
  gamma: 4
  kernel: {lambda: 1, C: 0.0795774715459477}
  t_end: 4
  observe_every: 0.5
)";

const char* kRough = R"(model: dsmc
seed: 5
ensembles: 2
dsmc:
  particles: 1000
  roughness: {beta: 0.5, inertia: 0.4}
  restitution: {law: constant, alpha: 0.8}
  beta: 1
  gamma: 4
  kernel: {lambda: 1, C: 0.0795774715459477}
  t_end: 4
  observe_every: 0.5
)";

}  // namespace

TEST(Estimate, GeneralGasEventsFollowTheSpeciesAndTheSpins) {
  // The estimate used the one-species model for the general gas: it ignored the species'
  // masses and diameters and the spins (collisions 0.74-0.87 of those counted on these configs,
  // and 10^-5 of them where the spins' energy heats the gas).
  expect_estimate_matches(kMixture, {}, 0.15);
  expect_estimate_matches(kMixture, {"dsmc.thermostat=none", "dsmc.beta=0"}, 0.15);
  expect_estimate_matches(kMixture, {"dsmc.thermostat=gaussian", "dsmc.beta=0"}, 0.15);
  expect_estimate_matches(kMixture, {"dsmc.scheme=strang", "dsmc.steps=64"}, 0.15);
  expect_estimate_matches(kMixture, {"dsmc.dimension=2", "dsmc.kernel.lambda=0.5"}, 0.15);
  // Masses far apart: the heavy species heats as m beta under white noise.
  expect_estimate_matches(kMixture,
                          {"dsmc.species=[{name: a, fraction: 0.5}, {name: b, "
                           "fraction: 0.5, mass: 1e6}]",
                           "dsmc.alpha=0.9", "dsmc.t_end=100", "dsmc.observe_every=100"},
                          0.15);
  // Many observations: the bounds are reset at each (followed on average, not one by one).
  expect_estimate_matches(kMixture, {"dsmc.t_end=1.2", "dsmc.observe_every=0.001"}, 0.15);
  expect_estimate_matches(kRough, {}, 0.15);
  expect_estimate_matches(kRough, {"dsmc.initial.rotational_temperature=0"}, 0.15);
  // The spins' energy flows into translation: T rises from 1 towards 10^5 within a few
  // collisions, and the bounds hold the peak until the next observation.
  expect_estimate_matches(
      kRough, {"dsmc.thermostat=none", "dsmc.beta=0", "dsmc.initial.rotational_temperature=1e6"},
      0.15);
  expect_estimate_matches(
      kRough, {"dsmc.thermostat=gaussian", "dsmc.beta=0", "dsmc.initial.rotational_temperature=10"},
      0.15);
  expect_estimate_matches(kRough,
                          {"dsmc.dimension=2", "dsmc.roughness.inertia=0.5",
                           "dsmc.restitution={law: viscoelastic, delta: 0.2}"},
                          0.15);
}

namespace {
// A config text without its observe_every line, for dsmc.observe (both keys are refused).
std::string without_observe_every(std::string text) {
  const auto at = text.find("  observe_every:");
  return text.erase(at, text.find('\n', at) + 1 - at);
}
}  // namespace

TEST(Estimate, LogAndListedObservationTimesAreCounted) {
  // n kicks per observation (no splitting, beta > 0): 1 000 of them over 3.3 decades, most of
  // the kicks counted.
  const std::string hs = without_observe_every(kHardSpheres), mix = without_observe_every(kMixture);
  expect_estimate_matches(hs.c_str(), {"dsmc.observe={log: {from: 0.001, per_decade: 300}}"});
  // The general gas resets its bounds at every observation: under the Gaussian thermostat they
  // grow between two by e^(lambda zeta gap/2), so the gaps of the grid, not their mean, set the
  // fictitious candidates (one by one up to 1000 resets, by the gap around each time beyond).
  const std::string gauss[] = {"dsmc.thermostat=gaussian", "dsmc.beta=0"};
  for (const char* observe :
       {"dsmc.observe={times: [0.05, 0.1]}", "dsmc.observe={log: {from: 0.001, per_decade: 4}}"}) {
    expect_estimate_matches(mix.c_str(), {observe}, 0.15);
    expect_estimate_matches(mix.c_str(), {gauss[0], gauss[1], observe}, 0.15);
  }
  expect_estimate_matches(
      mix.c_str(),
      {gauss[0], gauss[1], "dsmc.t_end=1", "dsmc.observe={log: {from: 0.0001, per_decade: 251}}"},
      0.15);
}

// ---- Wall time against the CPU time measured, every engine ----

namespace {

// CPU seconds (user + system) of `granboltz run` on one thread, the least of `repeats` runs
// (other jobs on a shared machine only ever add to it).
double measured_cpu(const std::string& text, const std::vector<std::string>& sets, int repeats) {
  TempDir dir;
  const std::string cfg = dir.write("c.yaml", text);
  std::string args;
  for (const auto& s : sets) args += " --set '" + s + "'";
  double best = HUGE_VAL;
  for (int k = 0; k < repeats; ++k) {
    const std::string out = dir.file("out" + std::to_string(k) + ".h5");
    rusage before{}, after{};
    ::getrusage(RUSAGE_CHILDREN, &before);
    const auto r = run_granboltz("run " + cfg + args + " -q --threads 1 -o " + out);
    ::getrusage(RUSAGE_CHILDREN, &after);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    auto seconds = [](const rusage& u) {
      return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
             1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
    };
    best = std::min(best, seconds(after) - seconds(before));
  }
  return best;
}

double estimated_seconds(const std::string& text, const std::vector<std::string>& sets) {
  return granboltz::estimate_run(granboltz::parse_config(text, "c.yaml", sets), 1).seconds;
}

}  // namespace

TEST(Estimate, WallTimeOfEveryEngineIsWithinAFactorTwoOfTheMeasured) {
  // The constants are CPU times of an idle machine; a shared one runs everything slower by
  // about the same factor, so each engine is compared after dividing by that factor, measured
  // on the reference (RW05 Maxwell molecules, the config of the per-event cost). SWPM is
  // measured by its pilot on this machine as it runs: compared as it is. Runs of 0.1-0.2 s
  // (idle); the reference's factor is the least of three runs (before and after).
  const std::vector<std::string> kLarge = {"dsmc.particles=4096", "dsmc.t_end=12",
                                           "dsmc.observe_every=1"};
  auto with = [](std::vector<std::string> a, const std::vector<std::string>& b) {
    a.insert(a.end(), b.begin(), b.end());
    return a;
  };
  const std::vector<std::string> reference_sets = {
      "dsmc.kernel.lambda=0", "dsmc.particles=4096", "dsmc.gamma=50",         "dsmc.alpha=0.8",
      "dsmc.beta=1",          "dsmc.t_end=12",       "dsmc.observe_every=12", "ensembles=1"};
  const double ref_estimate = estimated_seconds(kHardSpheres, reference_sets);
  double machine = measured_cpu(kHardSpheres, reference_sets, 2) / ref_estimate;
  struct Engine {
    const char* name;
    std::string text;
    std::vector<std::string> sets;
  };
  const std::vector<Engine> engines = {
      {"hard spheres, heated, no splitting", kHardSpheres, with(kLarge, {"dsmc.beta=0.125"})},
      {"Maxwell molecules, Gaussian thermostat", kHardSpheres,
       with(kLarge, {"dsmc.kernel.lambda=0", "dsmc.thermostat=gaussian", "dsmc.beta=0",
                     "dsmc.t_end=96", "dsmc.observe_every=8"})},
      {"Strang splitting, pairwise majorant", kHardSpheres,
       with(kLarge, {"dsmc.alpha=0.7", "dsmc.beta=0.5", "dsmc.scheme=strang", "dsmc.steps=384",
                     "dsmc.majorant=pairwise"})},
      {"hard disks (d = 2)", kHardSpheres,
       with(kLarge, {"dsmc.dimension=2", "dsmc.alpha=0.6", "dsmc.beta=0.5"})},
      {"binary mixture", kMixture, with(kLarge, {"dsmc.beta=0.5"})},
      {"rough spheres", kRough, with(kLarge, {"dsmc.observe_every=2"})},
      {"rough disks, mixture, Gaussian thermostat", kMixture,
       with(kLarge, {"dsmc.dimension=2", "dsmc.alpha=0.9",
                     "dsmc.species=[{name: a, fraction: 0.5}, {name: b, fraction: 0.5, mass: 4, "
                     "diameter: 2}]",
                     "dsmc.roughness={beta: 0, inertia: 0.5}", "dsmc.thermostat=gaussian",
                     "dsmc.beta=0", "dsmc.t_end=24"})},
      {"steady histogram of 1.5*10^4 shells",
       kTiny,
       {"ensembles=16", "dsmc.t_end=2", "dsmc.observe_every=0.1", "dsmc.steady_from=0.5",
        "dsmc.histogram={shells: 15000, radius: 5}"}},
      {"TV06 intruder, Gillespie", kIntruder, {"intruder.collisions=400000"}},
      {"TV06 intruder, DSMC", kIntruder, {"intruder.collisions=200000", "intruder.method=dsmc"}},
      {"TV06 needle", kNeedle, {"needle.collisions=60000"}},
  };
  std::vector<std::pair<const char*, double>> ratios;
  for (const Engine& e : engines)
    ratios.emplace_back(e.name,
                        measured_cpu(e.text, e.sets, 1) / estimated_seconds(e.text, e.sets));
  // The machine's factor again at the end: the least of both (the quieter moment).
  machine = std::min(machine, measured_cpu(kHardSpheres, reference_sets, 1) / ref_estimate);
  for (const auto& [name, ratio] : ratios) {
    if (std::getenv("GRANBOLTZ_PRINT_RATIOS"))
      std::printf("measured/estimated %-45s %.2f (machine %.2f)\n", name, ratio / machine, machine);
    EXPECT_GT(ratio / machine, 0.5) << name << ": measured " << ratio << " x the estimate";
    EXPECT_LT(ratio / machine, 2.0) << name << ": measured " << ratio << " x the estimate";
  }
  const std::vector<std::string> swpm = {"dsmc.t_end=4", "dsmc.observe_every=0.25"};
  const double weighted = measured_cpu(kWeighted, swpm, 1) / estimated_seconds(kWeighted, swpm);
  if (std::getenv("GRANBOLTZ_PRINT_RATIOS"))
    std::printf("measured/estimated %-45s %.2f\n", "weighted particles (SWPM, pilot)", weighted);
  EXPECT_GT(weighted, 0.5);
  EXPECT_LT(weighted, 2.0);
}

TEST(Estimate, MemoryCountsEveryAccumulatorOfTheLayout) {
  // The steady histogram's exact sums (1.1 kB a shell) and SWPM's weight per row and shell were
  // left out: an SWPM run with 10^5 shells and 101 rows was estimated at 317 MiB and took 23 GB.
  auto bytes = [](const char* text, const std::vector<std::string>& sets) {
    return static_cast<double>(
        granboltz::estimate_memory(granboltz::parse_config(text, "c.yaml", sets), 1));
  };
  const double moments2 = 2.0 * 584.0;  // two exact sums of 72 limbs and a counter
  const std::vector<std::string> hist = {"dsmc.histogram={shells: 99999, radius: 5}"};
  EXPECT_GT(bytes(kHardSpheres, {hist[0], "dsmc.steady_from=1"}) - bytes(kHardSpheres, hist),
            1e5 * moments2);
  std::vector<std::string> weighted = {hist[0], "dsmc.t_end=2", "dsmc.observe_every=0.02"};
  EXPECT_GT(bytes(kWeighted, weighted), 101.0 * 1e5 * moments2);
}

TEST(Estimate, WeightedPilotThatCannotFitIsSkippedNotAnAllocationFailure) {
  // max_particles: 10^9 (allowed) needs over 100 GB for one ensemble: the pilot used to build it
  // and `estimate` ended in a bare "std::bad_alloc". Now the pilot is skipped where it does not
  // fit (the time is then a lower bound) and `run` refuses the memory in one line.
  TempDir dir;
  const std::string cfg = dir.write("w.yaml", kWeighted);
  const auto r = run_granboltz("estimate " + cfg + " --set dsmc.weights.max_particles=1e9", 60);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output.find("bad_alloc"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("peak memory "), std::string::npos) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  const granboltz::Config big =
      granboltz::parse_config(kWeighted, "w.yaml", {"dsmc.weights.max_particles=1e9"});
  if (static_cast<double>(granboltz::estimate_memory(big, 1)) <
      0.9 * static_cast<double>(granboltz::available_memory()))
    GTEST_SKIP() << "this machine has the memory for the run itself";
  const auto q = run_granboltz(
      "run " + cfg + " --set dsmc.weights.max_particles=1e9 -q -o " + dir.file("o.h5"), 60);
  EXPECT_EQ(q.exit_code, 2) << q.output;
  EXPECT_NE(q.output.find("of memory on"), std::string::npos) << q.output;
  EXPECT_FALSE(std::filesystem::exists(dir.file("o.h5")));
}
