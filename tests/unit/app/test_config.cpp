// Config parsing: defaults made explicit, overrides, and errors that name the key.
#include <gtest/gtest.h>

#include "granboltz/app/config.hpp"
#include "test_support.hpp"

using namespace granboltz;

namespace {
const char* kExample3 = R"(
model: dsmc
seed: 42
ensembles: 10
dsmc:
  particles: 64
  alpha: 0.5
  beta: 1
  gamma: 4
  kernel: {lambda: 0, C: 0.0795774715459477}
  t_end: 8
  observe_every: 0.25
)";

}  // namespace

TEST(Config, ReadsGRW05Example3WithDefaults) {
  const Config c = parse_config(kExample3, "test.yaml");
  EXPECT_EQ(c.model, Model::kDsmc);
  EXPECT_EQ(c.seed, 42u);
  EXPECT_EQ(c.dsmc.particles, 64u);
  EXPECT_EQ(c.dsmc.scheme, Scheme::kNoSplit);
  EXPECT_EQ(c.dsmc.observations(), 32u);
  EXPECT_DOUBLE_EQ(c.dsmc.initial_temperature, 1.0);
  EXPECT_EQ(c.dsmc.majorant, MajorantKind::kGlobal);
}

TEST(Config, ResolvedYamlReadsBackToTheSameConfig) {
  const Config c = parse_config(kExample3, "test.yaml");
  const Config d = parse_config(c.to_yaml(false), "resolved");
  EXPECT_EQ(c.to_yaml(false), d.to_yaml(false));
  EXPECT_EQ(d.dsmc.kernel.C, c.dsmc.kernel.C);  // bit for bit
}

TEST(Config, SpeedMomentsDefaultToFourAndAreStoredInTheResolvedYaml) {
  const Config c = parse_config(kExample3, "test.yaml");
  EXPECT_EQ(c.dsmc.moments, 4);
  EXPECT_NE(c.to_yaml(true).find("moments: 4"), std::string::npos);
  for (const int P : {0, 16}) {
    const Config d = parse_config(kExample3, "t", {"dsmc.moments=" + std::to_string(P)});
    EXPECT_EQ(d.dsmc.moments, P);
    EXPECT_EQ(parse_config(d.to_yaml(true), "resolved").dsmc.moments, P);
  }
  EXPECT_EQ(test::config_error(kExample3, {"dsmc.moments=17"}),
            "dsmc.moments = 17: must satisfy 0 <= moments <= 16");
}

TEST(Config, PhysicsOnlyYamlLeavesOutThreadsAndShards) {
  const Config c = parse_config(kExample3, "t", {"threads=2", "shard.count=2", "shard.index=1"});
  EXPECT_EQ(c.to_yaml(true).find("threads"), std::string::npos);
  EXPECT_EQ(c.to_yaml(true).find("shard"), std::string::npos);
  EXPECT_NE(c.to_yaml(false).find("threads: 2"), std::string::npos);
}

TEST(Config, SetOverridesNestedKeysAndCreatesSections) {
  const Config c = parse_config(kExample3, "t",
                                {"dsmc.particles=1e4", "dsmc.histogram.shells=8",
                                 "dsmc.histogram.radius=4", "dsmc.scheme=strang", "dsmc.steps=32"});
  EXPECT_EQ(c.dsmc.particles, 10000u);
  EXPECT_EQ(c.dsmc.histogram.shells, 8u);
  EXPECT_EQ(c.dsmc.scheme, Scheme::kStrang);
  EXPECT_DOUBLE_EQ(c.dsmc.time_step(), 0.25);
}

TEST(Config, ShardsPartitionTheEnsembles) {
  std::uint64_t covered = 0;
  for (int i = 0; i < 3; ++i) {
    const Config c =
        parse_config(kExample3, "t", {"shard.count=3", "shard.index=" + std::to_string(i)});
    EXPECT_EQ(c.first_ensemble(), covered);
    covered = c.last_ensemble();
  }
  EXPECT_EQ(covered, 10u);
}

TEST(Config, ErrorsNameTheKeyTheValueAndWhatIsAllowed) {
  EXPECT_EQ(test::config_error(kExample3, {"dsmc.alpha=1.5"}),
            "dsmc.alpha = 1.5: must satisfy 0 < alpha <= 1");
  EXPECT_EQ(
      test::config_error(kExample3, {"dsmc.partcles=4"}).rfind("dsmc.partcles: unknown key", 0),
      0u);
  EXPECT_EQ(test::config_error(kExample3, {"dsmc.beta=.nan"}),
            "dsmc.beta = .nan: must be a finite number");
  EXPECT_EQ(test::config_error(kExample3, {"dsmc.particles=12.5"}),
            "dsmc.particles = 12.5: not an integer");
  EXPECT_EQ(test::config_error(kExample3, {"dsmc.scheme=rk4"}),
            "dsmc.scheme = rk4: must be one of nosplit, euler, strang");
  EXPECT_EQ(test::config_error(kExample3, {"dsmc.scheme=euler"}).rfind("dsmc.steps: missing", 0),
            0u);
  EXPECT_EQ(test::config_error("model: dsmc\nseed: 1\ndsmc: {particles: [1, 2]}\n"),
            "dsmc.particles = [...]: must be an integer");
  EXPECT_NE(test::config_error("model: dsmc\nseed: [1\n").find("YAML syntax error at line"),
            std::string::npos);
}

TEST(Config, AutoMajorantIsPairwiseWhereItIsExactAndFaster) {
  // docs/config.md: pairwise for lambda > 0 without kicks between events, constant weights, and
  // at most kAutoPairwiseMaxParticles particles; global otherwise.
  auto chosen = [](std::vector<std::string> sets) {
    sets.insert(sets.begin(), {"dsmc.kernel.lambda=1", "dsmc.beta=0"});
    return parse_config(kExample3, "test.yaml", sets).dsmc.majorant;
  };
  const std::string at_limit = "dsmc.particles=" + std::to_string(kAutoPairwiseMaxParticles);
  const std::string beyond = "dsmc.particles=" + std::to_string(kAutoPairwiseMaxParticles + 1);
  EXPECT_EQ(chosen({}), MajorantKind::kPairwise);
  EXPECT_EQ(chosen({at_limit}), MajorantKind::kPairwise);
  EXPECT_EQ(chosen({beyond}), MajorantKind::kGlobal);
  EXPECT_EQ(chosen({"dsmc.kernel.lambda=0"}), MajorantKind::kGlobal);
  EXPECT_EQ(chosen({"dsmc.beta=1"}), MajorantKind::kGlobal);  // kicks between the events
  EXPECT_EQ(chosen({"dsmc.beta=1", "dsmc.scheme=strang", "dsmc.steps=32"}),
            MajorantKind::kPairwise);
  EXPECT_EQ(chosen({"dsmc.majorant=global"}), MajorantKind::kGlobal);
}

TEST(Config, IntegerKeysTakeExactlyWholeDecimalsAndNothingElse) {
  // Whole numbers written as decimals are integers, dsmc.dimension included (it used to be read
  // as text, so '2' and !!str 2 passed while every other integer key refused them).
  const Config c = parse_config(
      kExample3, "t", {"dsmc.particles=1e3", "dsmc.dimension=2.0", "seed=4.2e1", "ensembles=+3"});
  EXPECT_EQ(c.dsmc.particles, 1000u);
  EXPECT_EQ(c.dsmc.dimension, 2);
  EXPECT_EQ(c.seed, 42u);
  EXPECT_EQ(c.ensembles, 3u);
  EXPECT_EQ(parse_config(kExample3, "t", {"seed=-0.0e5"}).seed, 0u);
  // A value a double would round to a whole number is not one: 1e-400 used to be seed 0.
  EXPECT_EQ(test::config_error(kExample3, {"seed=1e-400"}), "seed = 1e-400: not an integer");
  EXPECT_EQ(test::config_error(kExample3, {"seed=-1e-400"}), "seed = -1e-400: not an integer");
  EXPECT_EQ(test::config_error(kExample3, {"dsmc.particles=100.00000000000000001"}),
            "dsmc.particles = 100.00000000000000001: not an integer");
  EXPECT_EQ(test::config_error(kExample3, {"dsmc.dimension='3'"}),
            "dsmc.dimension = \"3\": must be an integer, not a quoted string");
  // A negative value gets the key's own range, as 0 does.
  EXPECT_EQ(test::config_error(kExample3, {"ensembles=-2"}), "ensembles = -2: must be >= 1");
  EXPECT_EQ(test::config_error(kExample3, {"ensembles=0"}), "ensembles = 0: must be >= 1");
  EXPECT_EQ(test::config_error(kExample3, {"dsmc.moments=-1"}),
            "dsmc.moments = -1: must satisfy 0 <= moments <= 16");
}
