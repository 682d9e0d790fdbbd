// dsmc.initial.from: a run started from the final state of an earlier output. The source's
// ensemble e is replayed from its stored config and seed, so the continued run's first row is the
// source's last row bit for bit; threads and shards do not change it; a changed or incompatible
// source is refused in one line; and a continuation under the same physics follows the law of
// the uninterrupted run.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cmath>
#include <string>
#include <vector>

#include "granboltz/dsmc/observables.hpp"
#include "test_support.hpp"

using namespace granboltz;

namespace {

const char* kSource = R"(model: dsmc
seed: 5
ensembles: 6
dsmc:
  particles: 400
  alpha: 0.5
  beta: 0.5
  kernel: {lambda: 1, C: 0.0795774715459477}
  t_end: 1
  observe_every: 0.5
)";

std::string continued(const std::string& source, const std::string& extra = "") {
  return "model: dsmc\nseed: 9\nensembles: 6\ndsmc:\n  particles: 400\n  alpha: 0.5\n"
         "  beta: 0\n  shear: {rate: 1.0}\n  kernel: {lambda: 1, C: 0.0795774715459477}\n"
         "  initial: {from: \"" +
         source + "\"}\n  t_end: 1\n  observe_every: 0.5\n" + extra;
}

void expect_first_row_is_the_sources_last(const std::string& source, const std::string& out,
                                          const std::vector<std::string>& datasets) {
  H5Reader a(source), b(out);
  for (const std::string& name : datasets) {
    const std::vector<double> x = a.read_double("/" + name + "/mean");
    const std::vector<double> y = b.read_double("/" + name + "/mean");
    const std::size_t width = x.size() / a.read_double("/time").size();
    for (std::size_t k = 0; k < width; ++k)
      EXPECT_EQ(y[k], x[x.size() - width + k]) << name << "[" << k << "]";
  }
}

}  // namespace

TEST(InitialFrom, FirstRowIsTheSourcesLastBitForBitOnThreadsAndShards) {
  test::TempDir dir;
  const std::string src = dir.file("source.h5");
  ASSERT_EQ(
      test::run_granboltz("run " + dir.write("source.yaml", kSource) + " -q -o " + src).exit_code,
      0);
  // The continued run: a sheared gas from the heated state.
  const std::string cfg = dir.write("c.yaml", continued(src));
  const std::string one = test::expect_threads_and_shards_identical(dir, cfg);
  expect_first_row_is_the_sources_last(src, one, {"temperature", "pressure_tensor", "moment_4"});
  // Its stored config names the source and the hash of the source's config.
  H5Reader out(one);
  const std::string stored = out.attr_string("/provenance", "run_config");
  EXPECT_NE(stored.find("from: \"" + src + "\""), std::string::npos) << stored;
  EXPECT_NE(stored.find("from_hash:"), std::string::npos) << stored;
}

TEST(InitialFrom, RoughMixtureContinuesWithItsSpins) {
  test::TempDir dir;
  const std::string species =
      "  species: [{name: a, fraction: 0.5, mass: 2}, {name: b, fraction: 0.5}]\n"
      "  roughness: {beta: 0.5, inertia: 0.4}\n";
  std::string source = kSource;
  source.replace(source.find("  alpha"), 0, species);
  const std::string src = dir.file("source.h5"), out = dir.file("out.h5");
  ASSERT_EQ(test::run_granboltz("run " + dir.write("s.yaml", source) + " -q -o " + src).exit_code,
            0);
  std::string next = "model: dsmc\nseed: 3\nensembles: 4\ndsmc:\n  particles: 400\n" + species +
                     "  alpha: 0.9\n  beta: 0\n  thermostat: none\n"
                     "  kernel: {lambda: 1, C: 0.0795774715459477}\n"
                     "  initial: {from: \"" +
                     src + "\"}\n  t_end: 0.5\n  observe_every: 0.5\n";
  const auto r = test::run_granboltz("run " + dir.write("n.yaml", next) + " -q -o " + out);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // The first 4 of the source's 6 ensembles: compare the rotational temperature's sums through
  // a second source run of 4 ensembles (the same first 4, bit for bit).
  source.replace(source.find("ensembles: 6"), 12, "ensembles: 4");
  const std::string src4 = dir.file("source4.h5");
  ASSERT_EQ(test::run_granboltz("run " + dir.write("s4.yaml", source) + " -q -o " + src4).exit_code,
            0);
  expect_first_row_is_the_sources_last(
      src4, out, {"temperature", "temperature_rotational", "species/a/temperature"});
}

TEST(InitialFrom, MaxwellGasContinuesOnItsExactLaw) {
  // White-noise Maxwell molecules: T(t) = T_inf + (T0 - T_inf) e^{-zeta t} for the centred
  // n-particle temperature (tests/support/test_support.hpp). A run of 1 continued for 2 under the
  // same physics has at its t the law of the uninterrupted run at 1 + t.
  test::TempDir dir;
  const std::string base =
      "model: dsmc\nseed: 21\nensembles: 200\ndsmc:\n  particles: 500\n"
      "  alpha: 0.5\n  beta: 1\n  gamma: 4\n"
      "  kernel: {lambda: 0, C: 0.0795774715459477}\n";
  const std::string src = dir.file("s.h5"), out = dir.file("o.h5");
  ASSERT_EQ(test::run_granboltz("run " +
                                dir.write("s.yaml", base + "  t_end: 1\n  observe_every: 0.5\n") +
                                " -q -o " + src)
                .exit_code,
            0);
  ASSERT_EQ(test::run_granboltz("run " +
                                dir.write("c.yaml", base + "  initial: {from: \"" + src +
                                                        "\"}\n"
                                                        "  t_end: 2\n  observe_every: 0.5\n") +
                                " -q -o " + out)
                .exit_code,
            0);
  H5Reader r(out);
  const auto time = r.read_double("/time"), T = r.read_double("/temperature/mean"),
             var = r.read_double("/temperature/variance");
  // zeta = gamma pi C (1 - alpha^2) = 0.75, T_inf = 2 beta / zeta (GRW05 eq. 17), centred (1 -
  // 1/n).
  const double zeta = 4 * M_PI * 0.0795774715459477 * 0.75, T_inf = 2 * 1.0 / zeta, n = 500;
  const double z = test::family_z(static_cast<int>(time.size()));
  for (std::size_t m = 0; m < time.size(); ++m) {
    const double t = 1 + time[m];
    const double exact = (1 - 1 / n) * (T_inf + (1 - T_inf) * std::exp(-zeta * t));
    EXPECT_NEAR(T[m], exact, z * std::sqrt(var[m] / 200)) << "t = " << t;
  }
}

TEST(InitialFrom, IncompatibleOrChangedSourcesAreRefusedInOneLine) {
  test::TempDir dir;
  const std::string src = dir.file("source.h5");
  ASSERT_EQ(
      test::run_granboltz("run " + dir.write("source.yaml", kSource) + " -q -o " + src).exit_code,
      0);
  const Config ok = parse_config(continued(src), "c", {});
  const std::string stored = ok.to_yaml(true);
  auto refused = [&](const std::string& text, const std::vector<std::string>& sets,
                     const std::string& part) {
    const std::string message = test::config_error(text, sets);
    EXPECT_NE(message.find(part), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  };
  refused(continued(src), {"dsmc.particles=401"}, "dsmc.particles must be the same");
  refused(continued(src), {"ensembles=7"}, "must be <= the 6 ensembles of dsmc.initial.from");
  refused(continued(src), {"dsmc.initial.heat_flux=[0.01, 0, 0]"}, "dsmc.initial.from");
  refused(continued(src), {"dsmc.dimension=2"}, "dsmc.initial.from");
  refused(continued(dir.file("missing.h5")), {}, "dsmc.initial.from");
  refused(continued(dir.write("text.h5", "not hdf5")), {}, "dsmc.initial.from");
  refused(continued(dir.path.string()), {}, "not a regular file");
  ASSERT_EQ(::mkfifo(dir.file("fifo.h5").c_str(), 0600), 0);
  refused(continued(dir.file("fifo.h5")), {}, "not a regular file");  // and does not block
  refused(continued(src), {"dsmc.weights={method: swpm, kappa: 0, max_particles: 800}"},
          "weighted particles");
  // The source rewritten by another config: the stored config of the continued run refuses it.
  std::string other = kSource;
  other.replace(other.find("seed: 5"), 7, "seed: 6");
  std::filesystem::remove(src);
  ASSERT_EQ(test::run_granboltz("run " + dir.write("o.yaml", other) + " -q -o " + src).exit_code,
            0);
  refused(stored, {}, "its stored config has changed");
}
