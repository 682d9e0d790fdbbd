// The engines' state archive (record/state_archive.hpp) against checkpoints of the build before
// it (tests/checkpoints/): every ensemble restores and saves again byte for byte (the layout of
// earlier checkpoints is kept: names, shapes, types, the order of packed fields), and a field
// edited out of its range, or a dataset removed, is refused in one line that names the file, the
// dataset and element and what is allowed.
#include <hdf5.h>

#include <filesystem>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "granboltz/app/config.hpp"
#include "granboltz/dsmc/engine.hpp"
#include "granboltz/record/state_archive.hpp"
#include "test_support.hpp"

namespace {

namespace fs = std::filesystem;
using granboltz::H5Reader;
using granboltz::H5Writer;
using granboltz::test::TempDir;

std::string fixture(const std::string& name) {
  return std::string(GRANBOLTZ_SOURCE_DIR) + "/tests/checkpoints/" + name + ".checkpoint";
}

granboltz::Config config_of(const H5Reader& in) {
  return granboltz::parse_config(in.attr_string("/", "config"), in.path());
}

// The datasets of `group` that the engine owns (the run driver adds the rows observed so far).
std::set<std::string> engine_datasets(const H5Reader& in, const std::string& group) {
  static const std::set<std::string> driver = {"observations",        "moment_observations",
                                               "histogram",           "histogram_weight",
                                               "histogram_component", "histogram_component_weight"};
  std::set<std::string> out;
  for (const auto& name : in.datasets()) {
    if (name.rfind(group + "/", 0) != 0) continue;
    const std::string rest = name.substr(group.size() + 1);
    if (driver.count(rest) || rest.rfind("row_set_", 0) == 0) continue;
    out.insert(name);
  }
  return out;
}

TEST(StateArchive, CheckpointsOfTheEarlierBuildRestoreAndSaveAgainByteForByte) {
  TempDir dir;
  std::set<std::string> engines;
  int restored = 0;
  for (const char* name : {"plain", "shear", "gas", "swpm"}) {
    SCOPED_TRACE(name);
    const H5Reader in(fixture(name));
    const granboltz::Config config = config_of(in);
    for (const std::string group : {"/in_progress/0", "/in_progress/1"}) {
      if (!in.exists(group + "/scalars")) continue;  // an ensemble not in progress
      const auto ensemble = granboltz::restore_ensemble(config.dsmc, in, group);
      engines.insert(ensemble->engine());
      const std::string again = dir.file(std::string(name) + ".h5");
      ++restored;
      {
        H5Writer out(again);
        ensemble->save(out, group);
        out.commit();
      }
      const H5Reader back(again);
      const auto written = engine_datasets(back, group);
      EXPECT_EQ(written, engine_datasets(in, group)) << group;
      for (const auto& d : written) {
        EXPECT_EQ(back.dims(d), in.dims(d)) << d;
        EXPECT_EQ(back.read_bytes(d), in.read_bytes(d)) << d;
      }
      fs::remove(again);
    }
  }
  EXPECT_EQ(engines, (std::set<std::string>{"dsmc", "gas", "weighted"}));
  EXPECT_EQ(restored, 7);
}

void edit_real(const std::string& file, const std::string& dataset, std::size_t index, double x) {
  granboltz::test::edit_dataset<double>(file, dataset, index, x, H5T_NATIVE_DOUBLE);
}
void edit_word(const std::string& file, const std::string& dataset, std::size_t index,
               std::uint64_t x) {
  granboltz::test::edit_dataset<std::uint64_t>(file, dataset, index, x, H5T_NATIVE_UINT64);
}
void remove_dataset(const std::string& file, const std::string& dataset) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(H5Ldelete(f, dataset.c_str(), H5P_DEFAULT), 0) << dataset;
  H5Fclose(f);
}

struct Edit {
  const char* engine;  // the fixture
  const char* what;
  void (*apply)(const std::string& file);
  const char* message;  // after "<file>: malformed ensemble state /in_progress/0: dataset "
};

const std::string g = "/in_progress/0";

const std::vector<Edit> kEdits = {
    // One species, pairwise majorant, Gaussian thermostat.
    {"plain", "time beyond t_end",
     [](const std::string& f) { edit_real(f, g + "/scalars", 0, 1e300); },
     "/in_progress/0/scalars[0] (t) = 1e+300, not in [0, t_end = 1500]"},
    {"plain", "time NaN",
     [](const std::string& f) { edit_real(f, g + "/scalars", 0, std::nan("")); },
     "/in_progress/0/scalars[0] (t) = nan, not in [0, t_end = 1500]"},
    {"plain", "negative u_max", [](const std::string& f) { edit_real(f, g + "/scalars", 4, -1.0); },
     "/in_progress/0/scalars[4] (u_max) = -1, not >= 0"},
    {"plain", "bulk velocity infinite",
     [](const std::string& f) { edit_real(f, g + "/scalars", 2, HUGE_VAL); },
     "/in_progress/0/scalars[2] (V_y) = inf, not finite"},
    {"plain", "weights' sum zero",
     [](const std::string& f) { edit_real(f, g + "/scalars", 5, 0.0); },
     "/in_progress/0/scalars[5] (w_sum) = 0, not > 0"},
    {"plain", "pair index out of range",
     [](const std::string& f) { edit_word(f, g + "/ring_index", 3, 200); },
     "/in_progress/0/ring_index[1, 1] = 200, not in [0, n = 200)"},
    {"plain", "look-ahead head out of range",
     [](const std::string& f) { edit_word(f, g + "/counters", 0, 16); },
     "/in_progress/0/counters[0] (head) = 16, not in [0, the look-ahead = 16)"},
    {"plain", "sweep countdown beyond 2n",
     [](const std::string& f) { edit_word(f, g + "/counters", 4, 401); },
     "/in_progress/0/counters[4] (sweep countdown) = 401, not in [0, 2n = 400]"},
    {"plain", "a particle's time beyond t",
     [](const std::string& f) { edit_real(f, g + "/particles", 4 * 7 + 3, 12345678.5); },
     "/in_progress/0/particles[7, 3] = 12345678.5, not in [0, t = "},
    {"plain", "a negative pair weight",
     [](const std::string& f) { edit_real(f, g + "/weights", 9, -0.5); },
     "/in_progress/0/weights[9] = -0.5, not in [0, w_max = "},
    {"plain", "index stream position beyond its block",
     [](const std::string& f) { edit_word(f, g + "/candidates/position", 0, 65); },
     "/in_progress/0/candidates/position[0] (position) = 65, not in [0, the block = 64]"},
    {"plain", "index stream index out of range",
     [](const std::string& f) { edit_word(f, g + "/partners/buffer", 2 * 5, 199); },
     "/in_progress/0/partners/buffer[5, 0] = 199, not in [0, the range = 199)"},
    {"plain", "a lane of an index stream all zero",
     [](const std::string& f) {
       for (std::size_t k = 0; k < 4; ++k) edit_word(f, g + "/candidates/lane_2", k, 0);
     },
     "/in_progress/0/candidates/lane_2: a random stream in the all-zero state"},
    {"plain", "thermostat energy zero",
     [](const std::string& f) { edit_real(f, g + "/thermostat", 0, 0.0); },
     "/in_progress/0/thermostat[0] (energy) = 0, not > 0"},
    {"plain", "a dataset removed", [](const std::string& f) { remove_dataset(f, g + "/counters"); },
     "/in_progress/0/counters: missing"},
    // One species under shear: the majorant's window and centre.
    {"shear", "window index 0",
     [](const std::string& f) { edit_word(f, g + "/flight_window", 0, 0); },
     "/in_progress/0/flight_window[0] (next window) = 0, not >= 1"},
    {"shear", "a window that does not hold the time",
     [](const std::string& f) { edit_word(f, g + "/flight_window", 0, 1); },
     "/in_progress/0/flight_window: a shear window that does not hold the time"},
    {"shear", "majorant centre off 0",
     [](const std::string& f) { edit_real(f, g + "/scalars", 1, 0.25); },
     "/in_progress/0/scalars[1] (V_x) = 0.25, not 0 under drag or shear"},
    // The general gas: species, bounds, spins.
    {"gas", "a negative bound", [](const std::string& f) { edit_real(f, g + "/bounds", 1, -1.0); },
     "/in_progress/0/bounds[1] = -1, not >= 0"},
    {"gas", "a bound below a speed",
     [](const std::string& f) { edit_real(f, g + "/bounds", 0, 1e-3); },
     "/in_progress/0/particles: a velocity beyond its species' bound (bounds)"},
    {"gas", "a spin not finite",
     [](const std::string& f) { edit_real(f, g + "/spins", 3 * 4 + 2, HUGE_VAL); },
     "/in_progress/0/spins[4, 2] = inf, not finite"},
    {"gas", "a velocity NaN",
     [](const std::string& f) { edit_real(f, g + "/particles", 4 * 2 + 1, std::nan("")); },
     "/in_progress/0/particles[2, 1] = nan, not finite"},
    {"gas", "time negative", [](const std::string& f) { edit_real(f, g + "/scalars", 0, -1.0); },
     "/in_progress/0/scalars[0] (t) = -1, not in [0, t_end = 1000]"},
    {"gas", "a species count removed",
     [](const std::string& f) { remove_dataset(f, g + "/species_collisions"); },
     "/in_progress/0/species_collisions: missing"},
    // Weighted particles.
    {"swpm", "a weight zero",
     [](const std::string& f) { edit_real(f, g + "/weighted_particles", 5 * 3 + 4, 0.0); },
     "/in_progress/0/weighted_particles[3, 4] = 0, not > 0"},
    {"swpm", "split scale negative",
     [](const std::string& f) { edit_real(f, g + "/scalars", 5, -2.0); },
     "/in_progress/0/scalars[5] (split scale) = -2, not >= 0"},
    {"swpm", "cooling mark after the time",
     [](const std::string& f) { edit_real(f, g + "/thermostat", 4, 12345678.5); },
     "/in_progress/0/thermostat[4] (mark time) = 12345678.5, not in [0, t = "},
    {"swpm", "reduce stream all zero",
     [](const std::string& f) {
       for (std::size_t k = 0; k < 4; ++k) edit_word(f, g + "/reduce_stream", k, 0);
     },
     "/in_progress/0/reduce_stream: a random stream in the all-zero state"},
};

TEST(StateArchive, EachEngineRefusesAnEditedFieldInOneLineNamingItAndItsRange) {
  TempDir dir;
  for (const Edit& e : kEdits) {
    SCOPED_TRACE(std::string(e.engine) + ": " + e.what);
    const std::string file = dir.file(std::string(e.engine) + ".h5");
    fs::copy_file(fixture(e.engine), file, fs::copy_options::overwrite_existing);
    e.apply(file);
    const H5Reader in(file);
    const granboltz::Config config = config_of(in);
    std::string message = "accepted";
    try {
      granboltz::restore_ensemble(config.dsmc, in, g);
    } catch (const std::runtime_error& x) {
      message = x.what();
    }
    const std::string want = file + ": malformed ensemble state " + g + ": dataset " + e.message;
    EXPECT_EQ(message.rfind(want, 0), 0u) << message << "\nwanted: " << want;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    // The other ensemble of the file is untouched and still restores.
    if (in.exists("/in_progress/1/scalars"))
      EXPECT_NO_THROW(granboltz::restore_ensemble(config.dsmc, in, "/in_progress/1"));
  }
}

TEST(StateArchive, RangesSayWhatIsAllowed) {
  EXPECT_EQ(granboltz::within(0.0, 2.0, "t_end").text(), "in [0, t_end = 2]");
  EXPECT_EQ(granboltz::below(16, "n").text(), "in [0, n = 16)");
  EXPECT_EQ(granboltz::at_least(0.0).text(), ">= 0");
  EXPECT_EQ(granboltz::positive().text(), "> 0");
  EXPECT_EQ(granboltz::finite().text(), "finite");
  EXPECT_EQ(granboltz::zero_if(true, "in dimension 2").text(), "0 in dimension 2");
  EXPECT_FALSE(granboltz::finite().contains(std::nan("")));
  EXPECT_FALSE(granboltz::within(0.0, 1.0).contains(std::nan("")));
  EXPECT_FALSE(granboltz::positive().contains(0.0));
  EXPECT_TRUE(granboltz::below(16, "n").contains(15));
  EXPECT_FALSE(granboltz::below(16, "n").contains(16));
  EXPECT_TRUE(granboltz::zero_if(true, "").contains(-0.0));
}

}  // namespace
