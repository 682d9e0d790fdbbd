// Time correlations (dsmc.correlations, dsmc/observers/correlations.hpp): the exact single
// exponentials of Maxwell molecules under the Gaussian thermostat, the same bits on any number of
// threads, as merged shards and after a SIGTERM checkpoint, and the refusals of the config.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "granboltz/app/config.hpp"
#include "granboltz/dsmc/engine.hpp"
#include "granboltz/h5/hdf5_io.hpp"
#include "test_support.hpp"

using namespace granboltz;
using granboltz::test::TempDir;

namespace {

// lambda = 0, 4 pi gamma C = 1: every particle collides at rate nu = 1.
std::string maxwell(int ensembles, double t_end, const std::string& correlations) {
  return "model: dsmc\nseed: 21\nensembles: " + std::to_string(ensembles) +
         "\ndsmc:\n  particles: 2000\n  alpha: 0.8\n  thermostat: gaussian\n  geometry: uniform\n"
         "  kernel: {lambda: 0, C: 0.0795774715459477}\n  t_end: " +
         format_real(t_end) +
         "\n  observe_every: 1\n  steady_from: 2\n  correlations: " + correlations + "\n";
}

}  // namespace

TEST(Correlations, MaxwellMoleculesDecayAtTheExactRatesUnderTheGaussianThermostat) {
  // Under the thermostat (transport.md section 1, alpha = 0.8): the tagged velocity and the
  // shear stress decay at (1 + alpha)^2/8, the heat flux at (1 + alpha)^2/12, in units of nu.
  TempDir dir;
  const std::string cfg =
      dir.write("c.yaml", maxwell(30, 30, "{velocity: {}, stress: {}, heat_flux: {}}"));
  const auto r = granboltz::test::run_granboltz("run " + cfg + " -q -o " + dir.file("o.h5"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  H5Reader in(dir.file("o.h5"));
  const double a = 0.8;
  const struct {
    const char* name;
    double rate;
  } cases[] = {{"velocity", (1 + a) * (1 + a) / 8},
               {"stress", (1 + a) * (1 + a) / 8},
               {"normal_stress", (1 + a) * (1 + a) / 8},
               {"heat_flux", (1 + a) * (1 + a) / 12}};
  // The lags are correlated, so each is checked at the interval's own level (lambda_p = 3.2),
  // with a family-wise margin for the lags checked.
  for (const auto& c : cases) {
    const std::string g = std::string("/correlations/") + c.name;
    const auto lag = in.read_double(g + "/lag"), mean = in.read_double(g + "/mean"),
               ci = in.read_double(g + "/ci");
    ASSERT_EQ(lag.size(), mean.size());
    EXPECT_EQ(mean[0], 1.0) << c.name;
    int checked = 0;
    for (std::size_t l = 1; l < lag.size(); ++l) {
      if (lag[l] > 4.0) break;
      const double sigma = ci[l] / 3.2;
      EXPECT_NEAR(mean[l], std::exp(-c.rate * lag[l]), granboltz::test::family_z(40) * sigma)
          << c.name << " at lag " << lag[l];
      ++checked;
    }
    EXPECT_GE(checked, 10) << c.name;
    // The lag-0 values of a near-Maxwellian at T = 1: T, T^2, T^2, (d + 2)/2 T^3 per component.
    const double lag0 = in.read_double(g + "/lag0")[0], lag0_ci = in.read_double(g + "/lag0_ci")[0];
    const double expected = std::string(c.name) == "heat_flux" ? 2.5 : 1.0;
    EXPECT_LT(std::abs(lag0 - expected), lag0_ci + 0.1 * expected) << c.name;
  }
}

TEST(Correlations, ThreadsShardsAndCheckpointsKeepTheBits) {
  TempDir dir;
  const std::string cfg = dir.write(
      "c.yaml",
      maxwell(6, 6, "{velocity: {particles: 50}, stress: {every: 0.05}, heat_flux: {from: 0}}"));
  granboltz::test::expect_threads_and_shards_identical(dir, cfg);
  TempDir again;
  // Long ensembles, so that SIGTERM finds them in progress: the correlators' state is saved.
  const std::string big = again.write(
      "c.yaml",
      "model: dsmc\nseed: 3\nensembles: 2\ncheckpoint: {every_seconds: 3600}\ndsmc:\n"
      "  particles: 40000\n  alpha: 0.7\n  beta: 1\n  kernel: {lambda: 1, C: 0.0795774715459477}\n"
      "  gamma: 4\n  t_end: 6\n  observe_every: 1\n"
      "  correlations: {velocity: {}, stress: {}, heat_flux: {}}\n");
  granboltz::test::expect_sigterm_resumes_identically(again, big);
}

TEST(Correlations, InPlaceSamplesKeepTheBitsOnThreadsShardsAndCheckpoints) {
  // The Gaussian thermostat and no thermostat are sampled in place (Ensemble::advance_lazily):
  // the stored velocities and the running scale, no stop. Hard spheres with either majorant, so
  // that the lazy scale, its folds and the weights in stored units all enter.
  const std::string hs =
      "model: dsmc\nseed: 5\nensembles: 4\ndsmc:\n  particles: 1500\n  alpha: 0.6\n"
      "  kernel: {lambda: 1, C: 0.0795774715459477}\n  t_end: 4\n  observe_every: 1\n"
      "  correlations: {velocity: {particles: 40}, stress: {every: 0.03}, heat_flux: {}}\n";
  for (const char* extra :
       {"  thermostat: gaussian\n  majorant: pairwise\n",
        "  thermostat: gaussian\n  majorant: global\n", "  thermostat: none\n"}) {
    TempDir dir;
    std::string cfg = hs;
    cfg.replace(cfg.find("  t_end"), 0, extra);
    granboltz::test::expect_threads_and_shards_identical(dir, dir.write("c.yaml", cfg));
  }
  TempDir again;
  const std::string big =
      again.write("c.yaml",
                  "model: dsmc\nseed: 3\nensembles: 2\ncheckpoint: {every_seconds: 3600}\ndsmc:\n"
                  "  particles: 40000\n  alpha: 0.7\n  thermostat: gaussian\n"
                  "  kernel: {lambda: 1, C: 0.0795774715459477}\n  gamma: 4\n  t_end: 20\n"
                  "  observe_every: 1\n"
                  "  correlations: {velocity: {}, stress: {}, heat_flux: {}}\n");
  granboltz::test::expect_sigterm_resumes_identically(again, big);
}

TEST(Correlations, TheRowsSeeTheTrueStateWhereSamplesFallOnThem) {
  // Samples every 0.25 fall on the rows (every 1): the row must still see the folded state, at
  // T = T0 under the Gaussian thermostat, not the stored velocities of an in-place sample.
  TempDir dir;
  const std::string cfg =
      dir.write("c.yaml",
                "model: dsmc\nseed: 4\nensembles: 2\ndsmc:\n  particles: 1000\n  alpha: 0.5\n"
                "  thermostat: gaussian\n  kernel: {lambda: 1, C: 0.0795774715459477}\n  t_end: 6\n"
                "  observe_every: 1\n  correlations: {stress: {every: 0.25}}\n");
  const auto r = granboltz::test::run_granboltz("run " + cfg + " -q -o " + dir.file("o.h5"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  H5Reader in(dir.file("o.h5"));
  const auto T = in.read_double("/temperature/mean");
  ASSERT_EQ(T.size(), 7u);
  for (std::size_t m = 0; m < T.size(); ++m) EXPECT_NEAR(T[m], 1.0, 1e-12) << "row " << m;
}

TEST(Correlations, AnInPlaceSampleSeesTheTrueState) {
  // The lazy view maps the stored velocities to the true ones: the same velocities, to round-off,
  // as a stop at that time (advance_to runs the same events, then kicks and folds the scale,
  // whose map is the view's up to the running energy's round-off and the centring on the mean).
  const std::string base =
      "model: dsmc\nseed: 9\nensembles: 1\ndsmc:\n  particles: 3000\n  alpha: 0.5\n"
      "  kernel: {lambda: 1, C: 0.0795774715459477}\n  t_end: 2\n";
  for (const char* extra :
       {"  thermostat: gaussian\n  majorant: pairwise\n",
        "  thermostat: gaussian\n  majorant: global\n", "  thermostat: none\n"}) {
    SCOPED_TRACE(extra);
    const Config config = parse_config(base + extra, "test");
    const auto lazy = make_ensemble(config.dsmc, config.seed, 0);
    const auto stopped = make_ensemble(config.dsmc, config.seed, 0);
    ASSERT_TRUE(lazy->advance_lazily(1.0));
    ASSERT_TRUE(stopped->advance_to(1.0));
    const ParticleView v = lazy->lazy_view(), u = stopped->view();
    ASSERT_NE(v.bulk, nullptr);
    if (std::string(extra).find("gaussian") != std::string::npos) EXPECT_GT(v.scale, 1.0);
    double worst = 0.0;
    for (std::size_t i = 0; i < v.particles.size(); ++i)
      worst = std::max(worst,
                       norm(*v.bulk + v.scale * (v.particles[i].v - *v.bulk) - u.particles[i].v));
    EXPECT_LT(worst, 1e-9);
    EXPECT_EQ(lazy->counts().collisions, stopped->counts().collisions);
  }
  // White-noise kicks are random: a lazy particle's state is not yet drawn, so the engine stops.
  const Config heated = parse_config(base + "  beta: 1\n", "test");
  const auto e = make_ensemble(heated.dsmc, heated.seed, 0);
  ASSERT_TRUE(e->advance_lazily(1.0));
  EXPECT_EQ(e->lazy_view().bulk, nullptr);
}

TEST(Correlations, TheConfigIsResolvedAndBadOnesAreRefusedInOneLine) {
  const Config c = parse_config(maxwell(2, 10, "{velocity: {}}"), "test");
  const CorrelationSpec& v = c.dsmc.correlations.velocity;
  EXPECT_TRUE(v.on);
  EXPECT_FALSE(c.dsmc.correlations.stress.on);
  EXPECT_DOUBLE_EQ(v.every, 0.1);  // a tenth of the mean free time 1/nu
  EXPECT_EQ(v.from, 2.0);          // dsmc.steady_from
  EXPECT_EQ(v.samples, 81u);
  EXPECT_EQ(v.particles, 256u);
  EXPECT_EQ(v.levels, 2u);  // 16 * 2^(K-1) <= 81/2
  using granboltz::test::config_error;
  auto refused = [](const std::string& text, const std::string& part) {
    const std::string e = config_error(text);
    EXPECT_NE(e.find(part), std::string::npos) << "got: " << e;
  };
  refused(maxwell(2, 10, "{}"), "dsmc.correlations: names none of velocity");
  refused(maxwell(2, 10, "{velocity: {every: -1}}"), "dsmc.correlations.velocity.every");
  refused(maxwell(2, 10, "{velocity: {levels: 9}}"), "dsmc.correlations.velocity.levels");
  refused(maxwell(2, 10, "{stress: {points: 7}}"), "dsmc.correlations.stress.points");
  refused(maxwell(2, 10, "{stress: {particles: 7}}"), "particles");
  refused(maxwell(2, 10, "{velocity: {particles: 5000}}"), "dsmc.correlations.velocity.particles");
  refused(maxwell(2, 10, "{density: {}}"), "density");
  std::string split = maxwell(2, 10, "{velocity: {}}");
  split.replace(split.find("  t_end"), 0, "  scheme: strang\n  steps: 100\n");
  refused(split, "dsmc.correlations: needs scheme nosplit");
  // The resolved config reads back to the same spec.
  const Config again = parse_config(c.to_yaml(false), "again");
  EXPECT_EQ(again.dsmc.correlations.velocity.every, v.every);
  EXPECT_EQ(again.dsmc.correlations.velocity.levels, v.levels);
}
