// The command line: reproducibility across thread counts, and clear errors for bad input.
#include <gtest/gtest.h>

#include "granboltz/h5/hdf5_io.hpp"
#include "test_support.hpp"

using granboltz::H5Reader;
using granboltz::test::run_granboltz;
using granboltz::test::TempDir;

namespace {

const char* kHardSpheres = R"(model: dsmc
seed: 77
ensembles: 6
dsmc:
  particles: 300
  scheme: nosplit
  alpha: 0.5
  beta: 0.125
  gamma: 4
  kernel: {lambda: 1, C: 0.0795774715459477}
  t_end: 1
  observe_every: 0.25
  histogram: {shells: 16, radius: 6}
)";

}  // namespace

TEST(CommandLine, VersionAndValidateWork) {
  EXPECT_EQ(run_granboltz("--version").exit_code, 0);
  TempDir dir;
  const auto r = run_granboltz("validate " + dir.write("c.yaml", kHardSpheres));
  EXPECT_EQ(r.exit_code, 0) << r.output;
  // The defaults: the majorant chosen automatically, and the true bound for its update.
  EXPECT_NE(r.output.find("majorant: auto"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("majorant_update: strict"), std::string::npos) << r.output;
}

TEST(CommandLine, ThreadsTakeTheIntegersAConfigTakes) {
  // --threads 1e3 is 1000, as `threads: 1e3` in a config (CLI11's range check used to refuse it
  // with "Value 1e3 not in range 0 to 1024").
  TempDir dir;
  const std::string cfg = dir.write("c.yaml", kHardSpheres);
  const auto r = run_granboltz("estimate " + cfg + " --threads 1e3");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  const auto q = run_granboltz("estimate " + cfg + " --threads 1.0e0");
  EXPECT_EQ(q.exit_code, 0) << q.output;
  EXPECT_NE(q.output.find("on 1 thread"), std::string::npos) << q.output;
}

TEST(CommandLine, ProvenanceNamesTheMajorantThatAutoChose) {
  // Kicks between the events (no-splitting, heated) leave only the global majorant; a splitting
  // scheme of a small hard-sphere gas takes the pairwise one, with the same bits as asking for it.
  TempDir dir;
  const std::string cfg = dir.write("c.yaml", kHardSpheres);
  const std::string nosplit = dir.file("n.h5"), strang = dir.file("s.h5"), pw = dir.file("p.h5");
  const std::string split = " --set dsmc.scheme=strang --set dsmc.steps=8";
  ASSERT_EQ(run_granboltz("run " + cfg + " -q -o " + nosplit).exit_code, 0);
  ASSERT_EQ(run_granboltz("run " + cfg + " -q -o " + strang + split).exit_code, 0);
  ASSERT_EQ(run_granboltz("run " + cfg + " -q -o " + pw + split + " --set dsmc.majorant=pairwise")
                .exit_code,
            0);
  EXPECT_EQ(H5Reader(nosplit).attr_string("/provenance", "majorant"), "global");
  EXPECT_EQ(H5Reader(strang).attr_string("/provenance", "majorant"), "pairwise");
  EXPECT_EQ(H5Reader(strang).read_double("/temperature/mean"),
            H5Reader(pw).read_double("/temperature/mean"));
}

TEST(CommandLine, OneAndTwoThreadsGiveIdenticalOutputForEveryScheme) {
  TempDir dir;
  const std::string cfg = dir.write("c.yaml", kHardSpheres);
  for (const char* scheme : {"nosplit", "euler", "strang"}) {
    const std::string extra = std::string(" --set dsmc.scheme=") + scheme +
                              (scheme[0] == 'n' ? "" : " --set dsmc.steps=8");
    const std::string a = dir.file(std::string(scheme) + "1.h5");
    const std::string b = dir.file(std::string(scheme) + "2.h5");
    ASSERT_EQ(run_granboltz("run " + cfg + " -q --threads 1 -o " + a + extra).exit_code, 0);
    ASSERT_EQ(run_granboltz("run " + cfg + " -q --threads 2 -o " + b + extra).exit_code, 0);
    granboltz::test::expect_identical_outputs(a, b);
  }
}

TEST(CommandLine, OutputExplainsItself) {
  TempDir dir;
  const std::string out = dir.file("o.h5");
  ASSERT_EQ(run_granboltz("run " + dir.write("c.yaml", kHardSpheres) + " -q -o " + out).exit_code,
            0);
  H5Reader r(out);
  EXPECT_NE(r.attr_string("/", "config").find("lambda: 1"), std::string::npos);
  EXPECT_FALSE(r.attr_string("/", "version").empty());
  EXPECT_FALSE(r.attr_string("/", "git_sha").empty());
  EXPECT_EQ(r.dims("/bulk_velocity/mean"), (granboltz::Dims{5, 3}));
  EXPECT_EQ(r.dims("/histogram/mean"), (granboltz::Dims{5, 17}));
  EXPECT_EQ(r.dims("/events/collisions"), (granboltz::Dims{6}));
}

struct BadInput {
  const char* what;
  const char* args;     // extra arguments (--set ...)
  const char* message;  // must appear in the error
  int exit_code;
};

void PrintTo(const BadInput& b, std::ostream* os) { *os << b.what; }

class BadInputs : public ::testing::TestWithParam<BadInput> {};

TEST_P(BadInputs, FailWithAClearMessageAndLeaveNoOutput) {
  const BadInput& b = GetParam();
  TempDir dir;
  const std::string cfg = dir.write("c.yaml", kHardSpheres);
  const auto r = run_granboltz("run " + cfg + " -q -o " + dir.file("out.h5") + " " + b.args);
  EXPECT_EQ(r.exit_code, b.exit_code) << r.output;
  EXPECT_NE(r.output.find(b.message), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find('\n'), r.output.size() - 1) << "one line: " << r.output;
  EXPECT_EQ(dir.entries(), 1u) << "only the config may remain";
}

INSTANTIATE_TEST_SUITE_P(
    Config, BadInputs,
    ::testing::Values(
        BadInput{"alpha zero", "--set dsmc.alpha=0", "dsmc.alpha = 0: must satisfy 0 < alpha <= 1",
                 2},
        BadInput{"alpha above one", "--set dsmc.alpha=1.01", "dsmc.alpha = 1.01", 2},
        BadInput{"negative beta", "--set dsmc.beta=-1", "dsmc.beta = -1: must be >= 0", 2},
        BadInput{"lambda above one", "--set dsmc.kernel.lambda=1.5", "dsmc.kernel.lambda = 1.5", 2},
        BadInput{"negative lambda", "--set dsmc.kernel.lambda=-0.1", "dsmc.kernel.lambda = -0.1",
                 2},
        BadInput{"one particle", "--set dsmc.particles=1", "dsmc.particles = 1: must be >= 2", 2},
        BadInput{"unknown key", "--set dsmc.particels=5", "dsmc.particels: unknown key", 2},
        BadInput{"unknown top key", "--set sed=5", "sed: unknown key", 2},
        BadInput{"negative time", "--set dsmc.t_end=-1", "dsmc.t_end = -1: must be > 0", 2},
        BadInput{"missing value", "--set dsmc.alpha=", "dsmc.alpha: missing", 2},
        BadInput{"not a number", "--set dsmc.beta=abc", "dsmc.beta = abc: not a number", 2},
        BadInput{"nan", "--set dsmc.gamma=.nan", "dsmc.gamma = .nan: must be a finite number", 2},
        BadInput{"infinity", "--set dsmc.t_end=.inf", "dsmc.t_end = .inf", 2},
        BadInput{"zero C", "--set dsmc.kernel.C=0", "dsmc.kernel.C = 0: must be > 0", 2},
        BadInput{"bad scheme", "--set dsmc.scheme=leapfrog", "dsmc.scheme = leapfrog", 2},
        BadInput{"splitting without steps", "--set dsmc.scheme=euler", "dsmc.steps: missing", 2},
        BadInput{"observation off the step grid", "--set dsmc.scheme=strang --set dsmc.steps=3",
                 "dsmc.observe_every = 0.25: must be a whole multiple of the time step", 2},
        BadInput{"observation not dividing t_end", "--set dsmc.observe_every=0.3",
                 "dsmc.observe_every = 0.3", 2},
        BadInput{"zero ensembles", "--set ensembles=0", "ensembles = 0: must be >= 1", 2},
        BadInput{"negative seed", "--set seed=-3", "seed = -3: must be >= 0", 2},
        BadInput{"unknown model", "--set model=lattice", "model = lattice: must be one of", 2},
        BadInput{"zero shells", "--set dsmc.histogram.shells=0", "dsmc.histogram.shells = 0", 2},
        BadInput{"does not fit in memory", "--set dsmc.particles=1e15", "of memory", 2},
        BadInput{"malformed --set", "--set dsmc.alpha", "expected key=value", 2},
        BadInput{"pairwise majorant with heating and no splitting", "--set dsmc.majorant=pairwise",
                 "dsmc.majorant = pairwise: not exact for scheme nosplit with beta > 0", 2},
        BadInput{"pairwise majorant for Maxwell molecules",
                 "--set dsmc.majorant=pairwise --set dsmc.kernel.lambda=0 --set dsmc.beta=0",
                 "needs kernel.lambda > 0", 2}),
    [](const auto& info) {
      std::string s = info.param.what;
      for (auto& ch : s)
        if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
      return s;
    });

TEST(CommandLine, MissingConfigAndUnwritableOutputAreReported) {
  TempDir dir;
  auto r = run_granboltz("run " + dir.file("nope.yaml") + " -o " + dir.file("o.h5"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("cannot open config file"), std::string::npos) << r.output;
  r = run_granboltz("run " + dir.write("c.yaml", kHardSpheres) + " -o /nonexistent/dir/o.h5");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("/nonexistent/dir/o.h5: directory /nonexistent/dir does not exist"),
            std::string::npos)
      << r.output;
  r = run_granboltz("run " + dir.write("bad.yaml", "model: dsmc\nseed: [1\n") + " -o " +
                    dir.file("o.h5"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("YAML syntax error"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir.file("o.h5")));
}
