// granboltz._core: the simulator in-process for Python (granboltz.simulate, granboltz.Simulation;
// the Python side is src/python/granboltz/inprocess.py). Whole runs go through run_to_file, as
// `granboltz run` does; Simulation wraps the engine of one DSMC ensemble.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <signal.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <csignal>
#include <exception>
#include <fstream>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "granboltz/app/config.hpp"
#include "granboltz/app/estimate.hpp"
#include "granboltz/app/run.hpp"
#include "granboltz/config/reader.hpp"
#include "granboltz/core/gsl_errors.hpp"
#include "granboltz/dsmc/engine.hpp"
#include "granboltz/dsmc/observables.hpp"
#include "granboltz/dsmc/run.hpp"
#include "granboltz/exec/ensemble_pool.hpp"
#include "granboltz/h5/hdf5_io.hpp"
#include "granboltz/h5/verify.hpp"

namespace py = pybind11;
using namespace granboltz;

namespace {

// Python's own handler for SIGINT only sets a flag that bytecode notices; while C++ runs with the
// GIL released nobody looks at it. During Simulation.advance this handler asks the engine to stop
// at its next safe point instead.
std::atomic<bool> g_interrupted{false};
static_assert(std::atomic<bool>::is_always_lock_free);
extern "C" void on_sigint(int) { g_interrupted.store(true); }

struct SigintGuard {  // installs on_sigint for its lifetime, then puts the previous handler back
  struct sigaction previous {};
  bool installed = false;
  explicit SigintGuard(bool install) {
    g_interrupted.store(false);
    if (!install) return;
    struct sigaction action {};
    action.sa_handler = on_sigint;
    sigemptyset(&action.sa_mask);
    installed = sigaction(SIGINT, &action, &previous) == 0;
  }
  ~SigintGuard() {
    if (installed) sigaction(SIGINT, &previous, nullptr);
  }
};

// SIGTERM during simulate, where the process would die of it (the default disposition): as in
// `granboltz run`, a run that checkpoints writes a last checkpoint; the run then stops at a
// safe point, its temporary files go, and Python ends the process with SIGTERM itself
// (end_by_sigterm) once its own clean-up has run. A handler of the user's own (Python's
// signal.signal) or an ignored SIGTERM is left alone. One handler for the whole process:
// concurrent runs (threads) share it, the last to finish puts the default back.
std::atomic<bool> g_terminate{false};   // SIGTERM arrived
std::atomic<bool> g_term_final{false};  // ... and a run that checkpoints took it as its last one
static_assert(std::atomic<bool>::is_always_lock_free);
extern "C" void on_sigterm(int) {
  g_term_final.store(request_final_checkpoint());
  g_terminate.store(true);
}

std::mutex g_term_mutex;
int g_term_users = 0;
bool g_term_installed = false;
struct sigaction g_term_previous {};

struct SigtermGuard {  // on_sigterm while at least one run is under way, if SIGTERM is default
  SigtermGuard() {
    std::lock_guard<std::mutex> lock(g_term_mutex);
    if (g_term_users++ > 0) return;
    g_terminate.store(false);
    g_term_final.store(false);
    struct sigaction current {};
    if (sigaction(SIGTERM, nullptr, &current) != 0 || (current.sa_flags & SA_SIGINFO) ||
        current.sa_handler != SIG_DFL)
      return;
    struct sigaction action {};
    action.sa_handler = on_sigterm;
    sigemptyset(&action.sa_mask);
    g_term_installed = sigaction(SIGTERM, &action, &g_term_previous) == 0;
  }
  ~SigtermGuard() {
    std::lock_guard<std::mutex> lock(g_term_mutex);
    if (--g_term_users > 0 || !g_term_installed) return;
    g_term_installed = false;
    // Only if it is still ours: a handler set meanwhile (signal.signal in another thread) stays.
    struct sigaction current {};
    if (sigaction(SIGTERM, nullptr, &current) == 0 && current.sa_handler == on_sigterm)
      sigaction(SIGTERM, &g_term_previous, nullptr);
  }
};

/// Ends the process with SIGTERM under its default disposition, as it would have died without
/// simulate's handler (a parent sees "killed by signal 15"; a shell, status 143).
[[noreturn]] void end_by_sigterm() {
  struct sigaction action {};
  action.sa_handler = SIG_DFL;
  sigemptyset(&action.sa_mask);
  sigaction(SIGTERM, &action, nullptr);
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGTERM);
  pthread_sigmask(SIG_UNBLOCK, &set, nullptr);
  raise(SIGTERM);
  std::_Exit(128 + SIGTERM);  // not reached
}

/// A call on a Simulation while another thread is inside one (advance releases the GIL).
struct SimulationBusy : std::runtime_error {
  using std::runtime_error::runtime_error;
};
/// A file Simulation.restore refuses (Python: granboltz.RunReadError).
struct StateError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Refuses an engine that would not fit in the memory available (as run_to_file refuses a run):
/// a config with 10^9 particles would otherwise be allocated and filled until the kernel kills
/// the interpreter.
void check_memory(const Config& config) {
  std::uint64_t have = 0;
  std::ifstream in("/proc/meminfo");
  std::string key, unit;
  std::uint64_t kb = 0;
  while (in >> key >> kb >> unit)
    if (key == "MemAvailable:") have = kb * 1024;
  const std::uint64_t need = estimate_memory(config, 1);
  if (have > 0 && static_cast<double>(need) > 0.9 * static_cast<double>(have))
    throw ConfigError("granboltz.Simulation: the engine needs about " +
                      human_bytes(static_cast<double>(need)) + " of memory, but only " +
                      human_bytes(static_cast<double>(have)) +
                      " is available; reduce dsmc.particles (dsmc.weights.max_particles)");
}

/// Parses a config as the CLI does and returns it with every default explicit.
std::string normalized_config(const std::string& text, const std::string& origin) {
  return parse_config(text, origin).to_yaml(false);
}

/// A whole run, written to `output` by run_to_file on a thread of its own while this (the
/// calling) thread waits with the GIL released, looking every 0.1 s for a signal (Python's
/// handlers run here: KeyboardInterrupt cancels the run) and feeding `progress(fraction)`.
/// `config_path`: the config's file ("" for a dict), which the output must not be. Returns true
/// if SIGTERM arrived (see SigtermGuard): the run is then stopped and cleaned up, whatever it
/// raised, and the caller ends the process with end_by_sigterm after its own clean-up.
bool run_file(const std::string& text, const std::string& origin, const std::string& config_path,
              const std::string& output, std::optional<unsigned> threads,
              const py::object& progress, const std::string& command) {
  Config config = parse_config(text, origin);
  if (threads) config.threads = *threads;
  // As `granboltz run`: never over the config (by device and inode: a hard link or another
  // spelling of it), a link, a directory or a FIFO (check_output_path), before anything exists.
  check_output_path(output, {config_path, output + ".checkpoint"});
  std::atomic<bool> cancel{false};
  std::atomic<double> fraction{0.0};
  DriverOptions options;
  options.threads = config.threads;
  options.progress = false;  // Python shows the progress (or nothing)
  options.label = origin;
  options.cancel = &cancel;
  options.fraction = &fraction;
  options.on_final_checkpoint = [&cancel] { cancel.store(true); };

  SigtermGuard sigterm;
  std::mutex mutex;
  std::condition_variable changed;
  bool finished = false;
  std::exception_ptr error;
  std::thread worker([&] {
    try {
      run_to_file(config, output, options, command);
    } catch (...) {
      error = std::current_exception();
    }
    std::lock_guard<std::mutex> lock(mutex);
    finished = true;
    changed.notify_all();
  });
  auto stop = [&] {  // cancel and wait for the worker: its temporary file is removed on unwinding
    cancel.store(true);
    py::gil_scoped_release release;
    worker.join();
  };
  for (;;) {
    bool done;
    {
      py::gil_scoped_release release;
      std::unique_lock<std::mutex> lock(mutex);
      done = changed.wait_for(lock, std::chrono::milliseconds(100), [&] { return finished; });
    }
    if (done) break;
    // SIGTERM: a run that checkpoints cancels itself once its last checkpoint is written
    // (on_final_checkpoint); any other stops now.
    if (g_terminate.load() && !g_term_final.load()) cancel.store(true);
    try {
      if (PyErr_CheckSignals() != 0) throw py::error_already_set();
      if (!progress.is_none()) progress(fraction.load());
    } catch (...) {
      stop();
      if (g_terminate.load()) return true;
      throw;
    }
  }
  worker.join();
  if (g_terminate.load()) return true;
  if (error) std::rethrow_exception(error);
  if (!progress.is_none()) progress(1.0);
  return false;
}

/// One ensemble of a DSMC run, advanced on request.
inline std::string shown(double x) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

/// "(a, b)" of an array's shape, as numpy prints it.
inline std::string shape_text(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t k = 0; k < a.ndim(); ++k) s += (k ? ", " : "") + std::to_string(a.shape(k));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

/// The rows of an (n, cols) array (cols 1: the z component of a disk's spin) as vectors, every
/// entry finite and at most 1e150 in magnitude (its square must not overflow an energy sum).
inline std::vector<Vec3> state_rows(
    const py::array_t<double, py::array::c_style | py::array::forcecast>& a, std::size_t n,
    int cols, const char* call, const char* what) {
  const double* x = a.data();
  std::vector<Vec3> rows(n);
  for (std::size_t i = 0; i < n; ++i) {
    double r[3] = {0.0, 0.0, 0.0};
    for (int k = 0; k < cols; ++k) {
      const double value = x[i * static_cast<std::size_t>(cols) + static_cast<std::size_t>(k)];
      if (!(std::fabs(value) <= 1e150))
        throw py::value_error(std::string(call) + ": " + what + "[" + std::to_string(i) +
                              (cols > 1 ? ", " + std::to_string(k) : "") + "] = " + shown(value) +
                              ": must be finite and at most 1e150 in magnitude");
      r[cols == 1 ? 2 : k] = value;
    }
    rows[i] = {r[0], r[1], r[2]};
  }
  return rows;
}

class Simulation {
 public:
  Simulation(const std::string& text, const std::string& origin, std::uint64_t ensemble)
      : config_(std::make_unique<Config>(parse_config(text, origin))), ensemble_(ensemble) {
    check_model();
    check_memory(*config_);
    const DsmcConfig& d = config_->dsmc;
    engine_ = make_ensemble(d, config_->seed, ensemble);
  }

  /// Reads a state written by save(), trusted only as far as it is checked, as a checkpoint is
  /// (app/run.cpp): a regular file (a FIFO would block), read through in a child process first
  /// (a damaged file can crash the HDF5 library), its config against its config_hash, every
  /// dataset against the engine's invariants (shapes, dtypes, streams not all-zero) and then
  /// against the digest written by save(). A state without a digest (an older granboltz) is
  /// refused: nothing else could tell an edited one. Every refusal is a StateError naming the
  /// file and, where one is to blame, the dataset or attribute.
  static std::unique_ptr<Simulation> restore(const std::string& path) {
    try {
      check_input_file(path, "a simulation state (granboltz.Simulation.save)");
      const FileCheck check = check_file(path);
      // check_file compares the digest too; named problems (the engine's checks below) are
      // more useful than "does not match", so that one is reported last.
      const bool digest_only =
          check.problems.size() == 1 &&
          check.problems[0].find("do not match its digest") != std::string::npos;
      if (!check.problems.empty() && !digest_only)
        throw StateError(path + ": " + check.problems.front());
      H5Reader in(path);
      if (!in.has_attr("/", "kind") || in.attr_string("/", "kind") != "simulation")
        throw StateError(path +
                         ": not a state written by granboltz.Simulation.save (no attribute "
                         "kind = simulation)");
      if (!in.has_attr("/", "digest"))
        throw StateError(path +
                         ": a state without its digest attribute (saved by an older "
                         "granboltz): it cannot be checked, so it is refused");
      for (const char* name : {"config", "config_hash", "ensemble"})
        if (!in.has_attr("/", name)) throw StateError(path + ": attribute " + name + ": missing");
      const std::string text = in.attr_string("/", "config");
      if (in.attr_uint64("/", "config_hash") != text_hash(text))
        throw StateError(path +
                         ": attribute config: does not match its config_hash (edited or "
                         "damaged)");
      auto s = std::unique_ptr<Simulation>(new Simulation());
      try {
        s->config_ = std::make_unique<Config>(parse_config(text, path));
        s->ensemble_ = in.attr_uint64("/", "ensemble");
        s->check_model();
      } catch (const std::runtime_error& e) {
        throw StateError(path + ": attribute config: " + e.what());
      }
      check_memory(*s->config_);
      const DsmcConfig& d = s->config_->dsmc;
      s->engine_ = restore_ensemble(d, in, "/state");
      if (digest_only || in.attr_uint64("/", "digest") != in.digest())
        throw StateError(path +
                         ": the datasets do not match the digest it was saved with "
                         "(edited or damaged)");
      return s;
    } catch (const StateError&) {
      throw;
    } catch (const ConfigError&) {
      throw;  // check_memory's: the state is sound, this machine too small
    } catch (const std::runtime_error& e) {
      throw StateError(e.what());
    }
  }

  /// As a checkpoint is written: the config with its hash and a digest of every dataset, which
  /// restore() checks. Never over `config_path`, the file the config was read from ("" if none),
  /// as simulate never writes over its config.
  void save(const std::string& path, const std::string& config_path) const {
    Use use(*this, "save");
    check_output_path(path, {config_path});
    H5Writer out(path);
    const std::string text = config_->to_yaml(false);
    out.attr("/", "kind", std::string("simulation"));
    out.attr("/", "config", text);
    out.attr("/", "config_hash", text_hash(text));
    out.attr("/", "ensemble", ensemble_);
    engine_->save(out, "/state");
    out.attr("/", "digest", out.digest());
    out.commit();
  }

  /// Advances to time t; returns false if SIGINT arrived (the state is then at a safe point,
  /// from which a later call continues as if uninterrupted).
  bool advance(double t, bool interruptible) {
    Use use(*this, "advance");
    const DsmcConfig& d = config_->dsmc;
    const double now = this->now();
    // Not beyond t_end: the engines' states hold t <= t_end (a saved one beyond would not
    // restore), and an advance to 1e308 would never end.
    if (!std::isfinite(t) || t < now || t > d.t_end)
      throw py::value_error("advance(" + format(t) +
                            "): t must be finite, >= time = " + format(now) +
                            " and <= t_end = " + format(d.t_end) + " (the config's dsmc.t_end)");
    if (d.scheme != Scheme::kNoSplit) {
      const double k = t / d.time_step();
      if (std::fabs(k - std::round(k)) > 1e-9 * std::max(1.0, std::fabs(k)))
        throw py::value_error("advance(" + format(t) + "): the " + scheme_name() +
                              " scheme steps by dt = t_end/steps = " + format(d.time_step()) +
                              "; t must be a multiple of dt");
    }
    if (t == now) return true;
    bool reached;
    {
      py::gil_scoped_release release;
      SigintGuard guard(interruptible);
      const std::atomic<bool>* pause = &g_interrupted;
      reached = engine_->advance_to(t, pause);
      reached = reached && !g_interrupted.load();
    }
    return reached;
  }

  double time() const {
    Use use(*this, "time");
    return now();
  }
  std::size_t particle_count() const {
    Use use(*this, "particle_count");
    return particles().size();
  }
  double t_end() const { return config_->dsmc.t_end; }
  int dimension() const { return config_->dsmc.dimension; }
  std::uint64_t ensemble() const { return ensemble_; }
  std::string config_text() const { return config_->to_yaml(false); }
  std::string engine() const { return engine_->engine(); }

  std::span<const Particle> particles() const { return engine_->view().particles; }

  py::array_t<double> velocities() const {
    Use use(*this, "velocities");
    const std::span<const Particle> p = particles();
    const auto n = static_cast<py::ssize_t>(p.size());
    const int d = dimension();
    py::array_t<double> out({n, static_cast<py::ssize_t>(d)});
    auto a = out.mutable_unchecked<2>();
    for (py::ssize_t i = 0; i < n; ++i) {
      const Vec3& v = p[static_cast<std::size_t>(i)].v;
      a(i, 0) = v.x;
      a(i, 1) = v.y;
      if (d == 3) a(i, 2) = v.z;
    }
    return out;
  }

  /// Simulation.set_velocities: an (n, d) float64 array (the Python layer converts and checks
  /// first; checked again here), every entry finite and at most 1e150 in magnitude.
  void set_velocities(const py::array_t<double, py::array::c_style | py::array::forcecast>& v) {
    Use use(*this, "set_velocities");
    const std::size_t n = particles().size();
    const int d = dimension();
    const auto shape = shape_text(v);
    if (v.ndim() != 2 || static_cast<std::size_t>(v.shape(0)) != n || v.shape(1) != d)
      throw py::value_error("set_velocities: velocities has shape " + shape + ", not (" +
                            std::to_string(n) + ", " + std::to_string(d) +
                            ") (particles, dimension)");
    const std::vector<Vec3> rows = state_rows(v, n, d, "set_velocities", "velocities");
    engine_->set_velocities(rows);
  }

  /// Simulation.set_spins (rough particles): (n, 3) in d = 3, (n,) (the z component) in d = 2.
  void set_spins(const py::array_t<double, py::array::c_style | py::array::forcecast>& w) {
    Use use(*this, "set_spins");
    if (!config_->dsmc.roughness.on)
      throw py::value_error("set_spins: only rough particles (dsmc.roughness) have spins");
    const std::size_t n = particles().size();
    const int d = dimension();
    const bool ok =
        d == 3 ? w.ndim() == 2 && static_cast<std::size_t>(w.shape(0)) == n && w.shape(1) == 3
               : w.ndim() == 1 && static_cast<std::size_t>(w.shape(0)) == n;
    if (!ok)
      throw py::value_error("set_spins: spins has shape " + shape_text(w) + ", not " +
                            (d == 3 ? "(" + std::to_string(n) + ", 3)"
                                    : "(" + std::to_string(n) + ",) (the z component in d = 2)"));
    engine_->set_spins(state_rows(w, n, d == 3 ? 3 : 1, "set_spins", "spins"));
  }

  py::object spins() const {
    Use use(*this, "spins");
    const std::span<const Vec3> w = engine_->view().spins;
    if (w.empty()) return py::none();
    const auto n = static_cast<py::ssize_t>(w.size());
    if (dimension() == 2) {
      py::array_t<double> out(n);
      auto a = out.mutable_unchecked<1>();
      for (py::ssize_t i = 0; i < n; ++i) a(i) = w[static_cast<std::size_t>(i)].z;
      return out;
    }
    py::array_t<double> out({n, py::ssize_t{3}});
    auto a = out.mutable_unchecked<2>();
    for (py::ssize_t i = 0; i < n; ++i) {
      const Vec3& v = w[static_cast<std::size_t>(i)];
      a(i, 0) = v.x, a(i, 1) = v.y, a(i, 2) = v.z;
    }
    return out;
  }

  py::object weights() const {
    Use use(*this, "weights");
    if (!engine_->weighted()) return py::none();
    const std::span<const double> g = engine_->view().weights;
    py::array_t<double> out(static_cast<py::ssize_t>(g.size()));
    std::copy(g.begin(), g.end(), out.mutable_data());
    return out;
  }

  py::dict counts() const {
    Use use(*this, "counts");
    const EventCounts& c = engine_->counts();
    py::dict out;
    out["collisions"] = c.collisions;
    out["fictitious"] = c.fictitious;
    out["kicks"] = c.kicks;
    for (const auto& [name, count] : engine_->extra_counts()) out[py::str(name)] = count;
    return out;
  }

  /// {"scalars": the Observation, "moments": <|v-V|^2p>, p = 1..dsmc.moments, and for the
  /// general gas "rows": [(group, scalars, moments)] of extra_row_sets}.
  py::dict observe() const {
    Use use(*this, "observe");
    const DsmcConfig& d = config_->dsmc;
    const auto P = static_cast<std::size_t>(d.moments);
    std::vector<double> moments(P, 0.0);
    py::list rows;
    const std::vector<RowSet> sets = extra_row_sets(d);
    std::vector<std::vector<double>> xo, xm;
    RowTargets row;
    row.moments = moments;
    for (const RowSet& x : sets) {
      xo.emplace_back(x.width, 0.0);
      xm.emplace_back(x.P, 0.0);
    }
    for (std::size_t k = 0; k < sets.size(); ++k)
      row.rows.push_back(xo[k].data()), row.row_moments.push_back(xm[k].data());
    const Observation obs = engine_->observe(d, row);
    for (std::size_t k = 0; k < sets.size(); ++k)
      rows.append(py::make_tuple(sets[k].group, xo[k], xm[k]));
    py::dict out;
    out["scalars"] = std::vector<double>(obs.begin(), obs.end());
    out["moments"] = moments;
    out["rows"] = rows;
    return out;
  }

 private:
  Simulation() = default;

  // advance releases the GIL: while it runs, another thread could read or change the engine
  // under it (a torn copy, a heap corrupted by a reallocating vector). Every member that touches
  // the engine holds this mark for its length, and a second caller is refused at once (waiting
  // would block that thread, GIL released or not, for as long as an advance may take). The
  // config members need no mark: the config never changes after construction.
  struct Use {
    const Simulation& s;
    Use(const Simulation& sim, const char* what) : s(sim) {
      const char* holder = nullptr;
      if (!s.user_.compare_exchange_strong(holder, what))
        throw SimulationBusy(std::string("granboltz.Simulation.") + what +
                             ": refused: another thread is inside " + holder +
                             "() of this Simulation; one Simulation is used by one thread at a "
                             "time (wait for that call, or give each thread its own Simulation)");
    }
    ~Use() { s.user_.store(nullptr); }
    Use(const Use&) = delete;
    Use& operator=(const Use&) = delete;
  };
  mutable std::atomic<const char*> user_{nullptr};

  double now() const { return engine_->time(); }

  void check_model() const {
    if (config_->model != Model::kDsmc)
      throw py::value_error("granboltz.Simulation: model " + model_name(config_->model) +
                            ": only model dsmc can be advanced step by step; run intruder and "
                            "needle configs with granboltz.simulate");
    // A Simulation stops where its caller says: it takes no samples between the stops.
    if (config_->dsmc.correlations.any())
      throw ConfigError(
          "dsmc.correlations: sampled by granboltz.simulate and `granboltz run`, "
          "not by granboltz.Simulation (whose caller chooses its stops); remove the "
          "key, or record the signals from Simulation.velocities at your own stops");
    if (ensemble_ >= config_->ensembles)
      throw py::value_error("granboltz.Simulation: ensemble " + std::to_string(ensemble_) +
                            " is not one of the config's ensembles 0.." +
                            std::to_string(config_->ensembles - 1));
  }
  std::string scheme_name() const {
    return config_->dsmc.scheme == Scheme::kEuler ? "euler" : "strang";
  }
  static std::string format(double x) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.17g", x);
    return buf;
  }

  std::unique_ptr<Config> config_;  // on the heap: the engines keep a reference to its dsmc
  std::uint64_t ensemble_ = 0;
  std::unique_ptr<Ensemble> engine_;  // make_ensemble's choice for the config
};

}  // namespace

PYBIND11_MODULE(_core, m) {
  m.doc() = "granboltz simulator in-process (use granboltz.simulate and granboltz.Simulation)";
  install_gsl_error_handler();  // GSL errors become statuses, never abort()
  static py::exception<ConfigError> config_error(m, "ConfigError", PyExc_ValueError);
  config_error.attr("__doc__") =
      "A config the simulator refuses: the CLI's one-line message, naming the key.";
  static py::exception<SimulationBusy> busy_error(m, "SimulationBusyError", PyExc_RuntimeError);
  busy_error.attr("__doc__") =
      "A call on a granboltz.Simulation while another thread is inside one of its calls "
      "(advance): refused at once; one Simulation is used by one thread at a time.";
  static py::exception<StateError> state_error(m, "StateError", PyExc_RuntimeError);
  state_error.attr("__doc__") =
      "A saved state that Simulation.restore refuses (edited, damaged or not a state); "
      "granboltz.Simulation.restore raises it again as granboltz.RunReadError.";
  // Every message is one line, as the CLI prints it: control characters escaped, bytes that
  // are not UTF-8 (a path's) shown as \xNN, cut at 1000 characters.
  py::register_exception_translator([](std::exception_ptr p) {
    auto line = [](const std::exception& e) { return quote_value(e.what(), 1000); };
    try {
      if (p) std::rethrow_exception(p);
    } catch (const py::error_already_set&) {
      throw;
    } catch (const py::builtin_exception& e) {
      throw;  // pybind11's own (value_error: ValueError), translated by pybind11
    } catch (const ConfigError& e) {
      config_error(line(e).c_str());
    } catch (const SimulationBusy& e) {
      busy_error(line(e).c_str());
    } catch (const StateError& e) {
      state_error(line(e).c_str());
    } catch (const RunCancelled& e) {
      PyErr_SetString(PyExc_KeyboardInterrupt, e.what());
    } catch (const std::bad_alloc&) {
      PyErr_SetString(PyExc_MemoryError, "out of memory");
    } catch (const std::runtime_error& e) {
      PyErr_SetString(PyExc_RuntimeError, line(e).c_str());
    }
  });
  m.attr("kObservables") = [] {
    py::list out;
    for (const ObservableInfo& o : kObservables)
      out.append(py::make_tuple(o.name, o.offset, o.rank, o.description));
    return out;
  }();
  m.attr("kMaxConfigDepth") = kMaxDepth;  // the config reader's limits: nested levels, bytes
  m.attr("kMaxConfigBytes") = kMaxConfigBytes;
  m.attr("kMaxConfigNodes") = kMaxNodes;
  m.def("normalized_config", &normalized_config,
        "The config text validated by parse_config, every default explicit", py::arg("text"),
        py::arg("origin"));
  m.def("run_file", &run_file,
        "Runs a config with run_to_file (as `granboltz run`); progress(fraction) or None; "
        "True if SIGTERM arrived (then call end_by_sigterm)",
        py::arg("text"), py::arg("origin"), py::arg("config_path"), py::arg("output"),
        py::arg("threads"), py::arg("progress"), py::arg("command"));
  m.def("end_by_sigterm", &end_by_sigterm,
        "Ends the process with SIGTERM under its default disposition (after run_file said so)");
  py::class_<Simulation>(m, "Simulation", "One DSMC ensemble's engine (use granboltz.Simulation)")
      .def(py::init<const std::string&, const std::string&, std::uint64_t>(), py::arg("text"),
           py::arg("origin"), py::arg("ensemble"))
      .def_static("restore", &Simulation::restore, py::arg("path"))
      .def("save", &Simulation::save, py::arg("path"), py::arg("config_path"))
      .def("advance", &Simulation::advance, py::arg("t"), py::arg("interruptible"))
      .def_property_readonly("time", &Simulation::time)
      .def_property_readonly("particle_count", &Simulation::particle_count)
      .def_property_readonly("t_end", &Simulation::t_end)
      .def_property_readonly("dimension", &Simulation::dimension)
      .def_property_readonly("ensemble", &Simulation::ensemble)
      .def_property_readonly("config_text", &Simulation::config_text)
      .def_property_readonly("engine", &Simulation::engine)
      .def_property_readonly("velocities", &Simulation::velocities)
      .def_property_readonly("spins", &Simulation::spins)
      .def_property_readonly("weights", &Simulation::weights)
      .def_property_readonly("counts", &Simulation::counts)
      .def("observe", &Simulation::observe)
      .def("set_velocities", &Simulation::set_velocities, py::arg("velocities"))
      .def("set_spins", &Simulation::set_spins, py::arg("spins"));
}
