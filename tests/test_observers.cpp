// The observers of a DSMC run (dsmc/observers/): the registry builds the ones a config asks for,
// an observer's rows of a particle view are what the engine's own observation gives (so the
// moved observers keep their bits), and its rows survive a checkpoint.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "granboltz/app/config.hpp"
#include "granboltz/dsmc/engine.hpp"
#include "granboltz/dsmc/observers/histogram.hpp"
#include "granboltz/dsmc/observers/registry.hpp"
#include "granboltz/dsmc/run.hpp"
#include "granboltz/h5/hdf5_io.hpp"
#include "test_support.hpp"

using namespace granboltz;
using granboltz::test::TempDir;

namespace {

const std::string kHeader =
    "model: dsmc\nseed: 5\nensembles: 2\ndsmc:\n  particles: 120\n  alpha: 0.7\n"
    "  kernel: {lambda: 1, C: 0.0795774715459477}\n  t_end: 0.4\n  observe_every: 0.2\n";
const std::string kHistogram = "  histogram: {shells: 8, radius: 4, component: true, center: bulk}\n";
const std::string kWeighted = "  weights: {method: swpm, kappa: 1, max_particles: 300}\n";

std::vector<std::string> names(const std::string& text) {
  const Config config = parse_config(text, "test");
  std::vector<std::string> out;
  for (const auto& o : make_observers(config.dsmc)) out.push_back(o->name());
  return out;
}

}  // namespace

TEST(Observers, TheRegistryBuildsWhatTheConfigAsksFor) {
  using V = std::vector<std::string>;
  EXPECT_EQ(names(kHeader + "  beta: 1\n"), V{});
  EXPECT_EQ(names(kHeader + "  beta: 1\n" + kHistogram), (V{"histogram", "histogram_component"}));
  EXPECT_EQ(names(kHeader + "  beta: 1\n  histogram: {shells: 8, radius: 4}\n"), V{"histogram"});
  EXPECT_EQ(names(kHeader + "  beta: 0\n  thermostat: gaussian\n" + kWeighted),
            V{"cooling_rate"});
  EXPECT_EQ(names(kHeader + "  beta: 0\n  thermostat: gaussian\n" + kHistogram + kWeighted),
            (V{"histogram", "cooling_rate", "histogram_component"}));
}

// The histograms observed through the particle view are the engine's own (RowTargets), counts
// and weights alike, for each engine.
TEST(Observers, HistogramRowsAreTheEnginesOwn) {
  const std::string species =
      "  species:\n    - {name: a, fraction: 0.5, mass: 1.0, diameter: 1.0}\n"
      "    - {name: b, fraction: 0.5, mass: 4.0, diameter: 1.5}\n";
  for (const std::string& text :
       {kHeader + "  beta: 1\n" + kHistogram, kHeader + "  beta: 1\n" + kHistogram + species,
        kHeader + "  beta: 1\n" + kHistogram + kWeighted}) {
    SCOPED_TRACE(text);
    const Config config = parse_config(text, "test");
    const DsmcConfig& d = config.dsmc;
    const auto e = make_ensemble(d, config.seed, 0);
    ASSERT_TRUE(e->advance_to(0.2));
    const std::uint64_t K1 = d.histogram.shells + 1;
    std::vector<std::uint64_t> hist(K1, 0), comp(K1, 0);
    std::vector<double> whist(K1, 0.0), wcomp(K1, 0.0);
    RowTargets row;
    row.histogram = hist.data();
    row.component = comp.data();
    if (e->weighted()) row.histogram_weight = whist.data(), row.component_weight = wcomp.data();
    std::vector<std::vector<double>> extra;  // the general gas's species rows, as the run has them
    const std::vector<RowSet> sets = extra_row_sets(d);
    for (const RowSet& x : sets) extra.emplace_back(x.width + x.P, 0.0);
    for (std::size_t k = 0; k < sets.size(); ++k) {
      row.rows.push_back(extra[k].data());
      row.row_moments.push_back(extra[k].data() + sets[k].width);
    }
    const Observation o = e->observe(d, row);
    const ParticleView view = e->view();
    const ObservedRow at{view, o, 1};
    for (const auto kind : {HistogramObserver::kRadial, HistogramObserver::kComponent}) {
      const HistogramObserver h(d, kind);
      ObserverRows rows = h.start(e->weighted());
      h.observe(at, rows);
      const bool radial = kind == HistogramObserver::kRadial;
      EXPECT_EQ(std::vector<std::uint64_t>(rows.counts.begin() + K1, rows.counts.begin() + 2 * K1),
                radial ? hist : comp);
      if (e->weighted())
        EXPECT_EQ(std::vector<double>(rows.values.begin() + K1, rows.values.begin() + 2 * K1),
                  radial ? whist : wcomp);
    }
  }
}

TEST(Observers, HistogramRowsSurviveACheckpointAndABadOneIsRefused) {
  const Config config = parse_config(kHeader + "  beta: 1\n" + kHistogram + kWeighted, "test");
  const HistogramObserver h(config.dsmc, HistogramObserver::kComponent);
  ObserverRows rows = h.start(true);
  for (std::size_t k = 0; k < rows.counts.size(); ++k) rows.counts[k] = 3 * k, rows.values[k] = 0.5 * k;
  TempDir dir;
  {
    H5Writer w(dir.file("state.h5"));
    h.save(w, "/e", rows);
    w.write("/bad/histogram_component", std::vector<std::uint64_t>{1, 2}, {2});
    w.write("/bad/histogram_component_weight", std::vector<double>{1, 2}, {2});
    w.commit();
  }
  H5Reader r(dir.file("state.h5"));
  const ObserverRows back = h.load(r, "/e", true);
  EXPECT_EQ(back.counts, rows.counts);
  EXPECT_EQ(back.values, rows.values);
  try {
    h.load(r, "/bad", true);
    FAIL() << "a histogram of the wrong size was accepted";
  } catch (const std::runtime_error& err) {
    EXPECT_NE(std::string(err.what()).find("malformed ensemble state /bad"), std::string::npos) << err.what();
  }
}
