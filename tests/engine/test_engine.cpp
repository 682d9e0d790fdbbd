// The engine boundary (dsmc/engine.hpp): make_ensemble picks the engine the config asks for, an
// ensemble driven through the Ensemble interface is the engine itself bit for bit, a paused,
// saved and restored one continues exactly, and what the interface reports (the particle view,
// the event columns, the refusals) matches each engine.
#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <string>
#include <vector>

#include "granboltz/app/config.hpp"
#include "granboltz/dsmc/engine.hpp"
#include "granboltz/dsmc/gas.hpp"
#include "granboltz/dsmc/run.hpp"
#include "granboltz/dsmc/weighted.hpp"
#include "granboltz/h5/hdf5_io.hpp"
#include "test_support.hpp"

using namespace granboltz;
using granboltz::test::TempDir;

namespace {

const std::string kHeader =
    "model: dsmc\nseed: 5\nensembles: 2\ndsmc:\n  particles: 120\n  alpha: 0.7\n  beta: 1\n"
    "  kernel: {lambda: 1, C: 0.0795774715459477}\n  t_end: 0.4\n  observe_every: 0.2\n"
    "  histogram: {shells: 8, radius: 4, component: true}\n";

// Without white noise (the Gaussian thermostat heats instead).
std::string gaussian(const std::string& header) {
  std::string s = header;
  s.replace(s.find("beta: 1"), 7, "beta: 0");
  return s + "  thermostat: gaussian\n";
}

struct Case {
  const char* name;
  std::string text;
  const char* engine;
};

std::vector<Case> cases() {
  return {
      {"one species", kHeader, "dsmc"},
      {"one species, gaussian", gaussian(kHeader), "dsmc"},
      {"mixture",
       kHeader + "  species:\n    - {name: a, fraction: 0.5, mass: 1.0, diameter: 1.0}\n"
                 "    - {name: b, fraction: 0.5, mass: 4.0, diameter: 1.5}\n",
       "gas"},
      {"rough", kHeader + "  roughness: {beta: 0.5, inertia: 0.4}\n", "gas"},
      {"weighted", kHeader + "  weights: {method: swpm, kappa: 1, max_particles: 300}\n",
       "weighted"},
      {"weighted, gaussian",
       gaussian(kHeader) + "  weights: {method: swpm, kappa: 1, max_particles: 300}\n", "weighted"},
  };
}

void expect_same_particles(std::span<const Particle> a, std::span<const Particle> b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i)
    ASSERT_TRUE(a[i].v.x == b[i].v.x && a[i].v.y == b[i].v.y && a[i].v.z == b[i].v.z &&
                a[i].t == b[i].t)
        << i;
}

void expect_same_state(const Ensemble& a, const Ensemble& b) {
  expect_same_particles(a.view().particles, b.view().particles);
  const ParticleView va = a.view(), vb = b.view();
  ASSERT_EQ(va.spins.size(), vb.spins.size());
  for (std::size_t i = 0; i < va.spins.size(); ++i)
    ASSERT_TRUE(va.spins[i].x == vb.spins[i].x && va.spins[i].y == vb.spins[i].y &&
                va.spins[i].z == vb.spins[i].z);
  ASSERT_EQ(std::vector<double>(va.weights.begin(), va.weights.end()),
            std::vector<double>(vb.weights.begin(), vb.weights.end()));
  EXPECT_EQ(a.time(), b.time());
  EXPECT_EQ(a.event_columns(), b.event_columns());
}

}  // namespace

TEST(EngineFactory, ChoosesTheEngineTheConfigAsksFor) {
  for (const Case& c : cases()) {
    SCOPED_TRACE(c.name);
    const Config config = parse_config(c.text, "test");
    const auto e = make_ensemble(config.dsmc, config.seed, 0);
    EXPECT_STREQ(e->engine(), c.engine);
    EXPECT_EQ(e->weighted(), std::string(c.engine) == "weighted");
    const ParticleView v = e->view();
    EXPECT_EQ(v.particles.size(), 120u);
    EXPECT_EQ(v.spins.size(), config.dsmc.roughness.on ? 120u : 0u);
    EXPECT_EQ(v.weights.size(), e->weighted() ? 120u : 0u);
    // The species blocks tile the particle array in order.
    std::size_t next = 0;
    for (const SpeciesBlock& b : v.species) {
      EXPECT_EQ(b.offset, next);
      next += b.count;
    }
    EXPECT_EQ(next, v.particles.size());
    EXPECT_EQ(v.species.size(), config.dsmc.species_written ? config.dsmc.species.size() : 1u);
  }
}

// The interface only forwards: the same seed gives the engine's own bits.
TEST(EngineFactory, AnEnsembleThroughTheInterfaceIsTheEngineBitForBit) {
  for (const Case& c : cases()) {
    SCOPED_TRACE(c.name);
    const Config config = parse_config(c.text, "test");
    const DsmcConfig& d = config.dsmc;
    const auto e = make_ensemble(d, config.seed, 1);
    ASSERT_TRUE(e->advance_to(d.t_end));
    const std::string engine = c.engine;
    if (engine == "dsmc") {
      DsmcEnsemble x(d, config.seed, 1);
      x.advance_to(d.t_end);
      expect_same_particles(e->view().particles, x.particles());
      EXPECT_EQ(e->counts().collisions, x.counts().collisions);
      EXPECT_EQ(e->u_max(), x.u_max());
    } else if (engine == "gas") {
      GasEnsemble x(d, config.seed, 1);
      x.advance_to(d.t_end);
      expect_same_particles(e->view().particles, x.particles());
      EXPECT_EQ(e->counts().collisions, x.counts().collisions);
      EXPECT_EQ(e->u_max(), x.u_max());
    } else {
      WeightedEnsemble x(d, config.seed, 1);
      x.advance_to(d.t_end);
      expect_same_particles(e->view().particles, x.particles());
      EXPECT_EQ(e->counts().collisions, x.counts().collisions);
      EXPECT_EQ(e->u_max(), x.u_max());
      EXPECT_EQ(e->mean_cooling_rate(), x.mean_cooling_rate());
    }
    EXPECT_GT(e->counts().collisions, 0u);
  }
}

// A pause flag stops advance_to at a safe point; saved there and restored by restore_ensemble,
// the ensemble continues as the one never stopped.
TEST(EngineFactory, PausedSavedAndRestoredThroughTheInterfaceContinuesBitForBit) {
  for (const Case& c : cases()) {
    SCOPED_TRACE(c.name);
    const Config config = parse_config(c.text, "test");
    const DsmcConfig& d = config.dsmc;
    const auto whole = make_ensemble(d, config.seed, 0);
    ASSERT_TRUE(whole->advance_to(0.2));
    ASSERT_TRUE(whole->advance_to(d.t_end));

    const auto part = make_ensemble(d, config.seed, 0);
    ASSERT_TRUE(part->advance_to(0.2));
    const std::atomic<bool> pause{true};
    EXPECT_FALSE(part->advance_to(d.t_end, &pause));
    TempDir dir;
    {
      H5Writer w(dir.file("state.h5"));
      part->save(w, "/e");
      w.commit();
    }
    H5Reader r(dir.file("state.h5"));
    const auto restored = restore_ensemble(d, r, "/e");
    EXPECT_STREQ(restored->engine(), c.engine);
    ASSERT_TRUE(restored->advance_to(d.t_end));
    expect_same_state(*whole, *restored);
  }
}

// The event columns are the ones the run's layout declares for that config (add_ensemble
// refuses a row of another length).
TEST(EngineFactory, EventColumnsMatchTheLayout) {
  for (const Case& c : cases()) {
    SCOPED_TRACE(c.name);
    const Config config = parse_config(c.text, "test");
    const auto e = make_ensemble(config.dsmc, config.seed, 0);
    Record r = dsmc_layout(config);
    EXPECT_NO_THROW(r.add_ensemble(0, e->event_columns()));
  }
}

TEST(EngineFactory, OnlyRoughParticlesTakeSpins) {
  for (const Case& c : cases()) {
    SCOPED_TRACE(c.name);
    const Config config = parse_config(c.text, "test");
    const auto e = make_ensemble(config.dsmc, config.seed, 0);
    const std::vector<Vec3> spins(120, Vec3{0.5, -0.25, 1.0});
    if (!config.dsmc.roughness.on) {
      EXPECT_THROW(e->set_spins(spins), std::logic_error);
      continue;
    }
    e->set_spins(spins);
    for (const Vec3& w : e->view().spins) EXPECT_TRUE(w.x == 0.5 && w.y == -0.25 && w.z == 1.0);
  }
}
