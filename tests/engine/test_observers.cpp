// The observers of a DSMC run (dsmc/observers/): the registry builds the ones a config asks for
// in the order of the output, and an observer's rows survive a checkpoint. That the moved
// observers keep their bits is the bit fixture's (tests/bits).
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
const std::string kHistogram =
    "  histogram: {shells: 8, radius: 4, component: true, center: bulk}\n";
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
  EXPECT_EQ(names(kHeader + "  beta: 1\n"), V{"moments"});
  EXPECT_EQ(names(kHeader + "  beta: 1\n" + kHistogram),
            (V{"moments", "histogram", "histogram_component"}));
  EXPECT_EQ(names(kHeader + "  beta: 1\n  histogram: {shells: 8, radius: 4}\n"),
            (V{"moments", "histogram"}));
  EXPECT_EQ(names(kHeader + "  beta: 0\n  thermostat: gaussian\n" + kWeighted),
            (V{"moments", "cooling_rate"}));
  EXPECT_EQ(names(kHeader + "  beta: 0\n  thermostat: gaussian\n" + kHistogram + kWeighted),
            (V{"moments", "histogram", "cooling_rate", "histogram_component"}));
  const std::string two =
      "  species:\n    - {name: a, fraction: 0.5, mass: 1.0, diameter: 1.0}\n"
      "    - {name: b, fraction: 0.5, mass: 4.0, diameter: 1.5}\n";
  EXPECT_EQ(names(kHeader + "  beta: 1\n" + two), (V{"moments", "species", "ratios"}));
  EXPECT_EQ(names(kHeader + "  beta: 1\n  roughness: {beta: 0.5, inertia: 0.4}\n"),
            (V{"moments", "rotation", "ratios"}));
  EXPECT_EQ(names(kHeader + "  beta: 1\n  roughness: {beta: 0.5, inertia: 0.4}\n" + two),
            (V{"moments", "species", "rotation", "ratios"}));
}

TEST(Observers, HistogramRowsSurviveACheckpointAndABadOneIsRefused) {
  const Config config = parse_config(kHeader + "  beta: 1\n" + kHistogram + kWeighted, "test");
  const HistogramObserver h(config.dsmc, HistogramObserver::kComponent);
  ObserverRows rows = h.start(true);
  for (std::size_t k = 0; k < rows.counts.size(); ++k)
    rows.counts[k] = 3 * k, rows.values[k] = 0.5 * k;
  TempDir dir;
  {
    H5Writer w(dir.file("state.h5"));
    h.save(w, "/e", rows, 1);
    w.write("/bad/histogram_component", std::vector<std::uint64_t>{1, 2}, {2});
    w.write("/bad/histogram_component_weight", std::vector<double>{1, 2}, {2});
    w.commit();
  }
  H5Reader r(dir.file("state.h5"));
  const ObserverRows back = h.load(r, "/e", true, 1);
  EXPECT_EQ(back.counts, rows.counts);
  EXPECT_EQ(back.values, rows.values);
  try {
    h.load(r, "/bad", true, 1);
    FAIL() << "a histogram of the wrong size was accepted";
  } catch (const std::runtime_error& err) {
    EXPECT_NE(std::string(err.what()).find("malformed ensemble state /bad"), std::string::npos)
        << err.what();
  }
}
