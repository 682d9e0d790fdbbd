// TV06 configs and runs: defaults, errors that name the key, the output datasets, and output
// that does not depend on the number of threads.
#include <gtest/gtest.h>

#include <string>

#include "granboltz/app/config.hpp"
#include "granboltz/h5/hdf5_io.hpp"
#include "test_support.hpp"

using namespace granboltz;
using granboltz::test::run_granboltz;
using granboltz::test::TempDir;

namespace {

const char* kIntruder = R"(model: intruder
seed: 5
ensembles: 5
intruder:
  bath: {kind: gaussian, a: 1}
  mass: 1
  alpha: 0.5
  collisions: 20000
  histogram: {bins: 20, range: 3}
)";

const char* kNeedle = R"(model: needle
seed: 6
ensembles: 5
needle:
  mass: 0.5
  alpha: 0.5
  collisions: 5000
  velocity_histogram: {bins: 10, range: 3}
  omega_histogram: {bins: 12, range: 8}
)";

}  // namespace

TEST(TV06Config, ReadsDefaultsAndRoundTrips) {
  const Config c = parse_config(kIntruder, "t");
  EXPECT_EQ(c.intruder.method, IntruderMethod::kGillespie);
  EXPECT_EQ(c.intruder.warmup, 2000u);
  EXPECT_EQ(c.intruder.density, 1.0);
  EXPECT_EQ(c.intruder.bath_refresh, BathRefresh::kTested);
  const Config d = parse_config(c.to_yaml(false), "resolved");
  EXPECT_EQ(c.to_yaml(false), d.to_yaml(false));
  const Config n = parse_config(kNeedle, "t", {"needle.waiting_time=inversion"});
  EXPECT_EQ(n.needle.waiting_time, NeedleWaitingTime::kInversion);
  EXPECT_EQ(n.needle.length, 1.0);
  EXPECT_EQ(parse_config(n.to_yaml(false), "r").to_yaml(false), n.to_yaml(false));
  const Config m =
      parse_config(kIntruder, "t", {"intruder.method=dsmc", "intruder.bath_refresh=none"});
  EXPECT_EQ(m.intruder.bath_refresh, BathRefresh::kNone);
  EXPECT_NE(m.to_yaml(true).find("bath_refresh: none"), std::string::npos);
}

TEST(TV06Config, BadValuesNameTheKeyTheValueAndWhatIsAllowed) {
  struct Case {
    const char* text;
    std::string set, expected;
  };
  const Case cases[] = {
      {kIntruder, "intruder.alpha=1.5", "intruder.alpha = 1.5: must satisfy 0 <= alpha <= 1"},
      {kIntruder, "intruder.mass=0", "intruder.mass = 0: must be > 0"},
      {kIntruder, "intruder.bath.a=-1", "intruder.bath.a = -1: must be > 0"},
      {kIntruder, "intruder.bath.kind=cauchy", "intruder.bath.kind = cauchy: must be one of"},
      {kIntruder, "intruder.method=md", "intruder.method = md: must be one of"},
      {kIntruder, "intruder.bath_refresh=always", "intruder.bath_refresh = always"},
      {kIntruder, "intruder.density=0", "intruder.density = 0: must be > 0"},
      {kIntruder, "intruder.collisions=0", "intruder.collisions = 0: must be >= 1"},
      {kIntruder, "intruder.sample_every=-1", "intruder.sample_every = -1: must be >= 0"},
      {kIntruder, "intruder.histogram.bins=0", "intruder.histogram.bins = 0"},
      {kIntruder, "intruder.colisions=5", "intruder.colisions"},
      {kNeedle, "needle.length=0", "needle.length = 0: must be > 0"},
      {kNeedle, "needle.a=0", "needle.a = 0: must be > 0"},
      {kNeedle, "needle.alpha=-0.1", "needle.alpha = -0.1: must satisfy 0 <= alpha <= 1"},
      {kNeedle, "needle.waiting_time=newton", "needle.waiting_time = newton: must be one of"},
      {kNeedle, "needle.omega_histogram.range=0", "needle.omega_histogram.range = 0: must be > 0"},
  };
  for (const Case& c : cases) {
    const std::string e = test::config_error(c.text, {c.set});
    EXPECT_NE(e.find(c.expected), std::string::npos) << c.set << " gave: " << e;
  }
}

TEST(TV06Run, OutputsAreIdenticalOnOneAndTwoThreadsAndHoldTheDocumentedDatasets) {
  TempDir dir;
  const std::string intruder = dir.write("i.yaml", kIntruder);
  const std::string needle = dir.write("n.yaml", kNeedle);
  struct Run {
    std::string config, extra;
    std::vector<std::string> datasets;
  };
  const Run runs[] = {
      {intruder,
       "",
       {"/temperature_ratio/mean", "/temperature_ratio/ci", "/temperature_ratio/variance",
        "/temperature_ratio/per_ensemble", "/exact/temperature_ratio", "/histogram/edges",
        "/histogram/counts", "/histogram/density", "/histogram/overflow", "/events/collisions",
        "/events/samples"}},
      {intruder,
       " --set intruder.method=dsmc --set intruder.bath_particles=50",
       {"/temperature_ratio/mean", "/events/fictitious", "/events/majorant_exceeded",
        "/events/omega_max_final"}},
      {intruder, " --set intruder.bath.kind=powerlaw --set intruder.mass=0.7", {}},
      {needle,
       "",
       {"/R/mean", "/R/ci", "/translational_temperature_ratio/mean",
        "/rotational_temperature_ratio/ci", "/velocity_histogram/counts",
        "/omega_histogram/density", "/events/fictitious"}},
  };
  int k = 0;
  for (const Run& r : runs) {
    const std::string a = dir.file("a" + std::to_string(k) + ".h5");
    const std::string b = dir.file("b" + std::to_string(k) + ".h5");
    ++k;
    auto ra = run_granboltz("run " + r.config + " -q --threads 1 -o " + a + r.extra);
    ASSERT_EQ(ra.exit_code, 0) << ra.output;
    auto rb = run_granboltz("run " + r.config + " -q --threads 2 -o " + b + r.extra);
    ASSERT_EQ(rb.exit_code, 0) << rb.output;
    H5Reader fa(a), fb(b);
    const auto names = fa.datasets();
    ASSERT_EQ(names, fb.datasets());
    for (const auto& name : names) EXPECT_EQ(fa.read_bytes(name), fb.read_bytes(name)) << name;
    for (const auto& d : r.datasets) EXPECT_TRUE(fa.exists(d)) << d;
  }
  // Values: the exact ratio of eq. 18, and a power-law run at M != alpha writes none.
  H5Reader f(dir.file("a0.h5"));
  EXPECT_DOUBLE_EQ(f.read_double("/exact/temperature_ratio")[0], 1.5 / 2.5);
  EXPECT_EQ(f.read_uint64("/events/collisions").size(), 5u);
  EXPECT_EQ(f.read_double("/histogram/edges").size(), 21u);
  EXPECT_FALSE(H5Reader(dir.file("a2.h5")).exists("/exact/temperature_ratio"));
}
