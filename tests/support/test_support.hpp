#pragma once
// Helpers shared by the C++ tests: temporary directories, running the CLI, exact results for
// Maxwell molecules, and confidence levels.
#include <fcntl.h>
#include <gsl/gsl_cdf.h>
#include <gtest/gtest.h>
#include <hdf5.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "granboltz/app/config.hpp"
#include "granboltz/dsmc/ensemble.hpp"
#include "granboltz/dsmc/observables.hpp"
#include "granboltz/dsmc/run.hpp"
#include "granboltz/h5/hdf5_io.hpp"

namespace granboltz::test {

/// A DSMC run in this process, with the accessors the tests need.
struct DsmcRun {
  std::vector<double> times;
  Record record;
  std::uint64_t ensembles;
  std::vector<double> collisions, fictitious;

  explicit DsmcRun(const Config& c) : times(dsmc_times(c.dsmc)), record(dsmc_layout(c)) {
    DriverOptions o;
    o.progress = false;
    run_dsmc(c, o, record);
    ensembles = record.ensembles();
    collisions = record.column("/events/collisions");
    fictitious = record.column("/events/fictitious");
  }
  /// Mean and confidence of scalar k (an offset into Observation) at observation m.
  MeanCi at(std::size_t m, int k) const {
    return record.moments("series")[m * kNumScalars + k].stats(ensembles);
  }
  /// Mean and confidence of the speed moment <|v - V|^{2p}> at observation m.
  MeanCi moment(std::size_t m, int p, int P) const {
    return record.moments("moment_series")[m * P + (p - 1)].stats(ensembles);
  }
};

/// A fresh directory removed at the end of the test.
struct TempDir {
  std::filesystem::path path;
  TempDir() {
    char tmpl[] = "/tmp/granboltz-test-XXXXXX";
    path = ::mkdtemp(tmpl);
  }
  ~TempDir() { std::filesystem::remove_all(path); }
  std::string file(const std::string& name) const { return (path / name).string(); }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(file(name)) << text;
    return file(name);
  }
  /// Number of entries in the directory.
  std::size_t entries() const {
    std::size_t n = 0;
    for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(path)) ++n;
    return n;
  }
};

struct CommandResult {
  int exit_code;
  std::string output;  ///< stdout and stderr together
};

/// The message of the ConfigError that parsing `text` with `sets` raises ("" if it parses).
inline std::string config_error(const std::string& text,
                                const std::vector<std::string>& sets = {}) {
  try {
    parse_config(text, "test.yaml", sets);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

/// Two output files agree in every dataset, byte for byte, and in the stored config.
inline void expect_identical_outputs(const std::string& a, const std::string& b) {
  H5Reader ra(a), rb(b);
  const auto names = ra.datasets();
  ASSERT_EQ(names, rb.datasets());
  ASSERT_GT(names.size(), 5u);
  for (const auto& name : names) EXPECT_EQ(ra.read_bytes(name), rb.read_bytes(name)) << name;
  EXPECT_EQ(ra.attr_string("/", "config"), rb.attr_string("/", "config"));
}

/// Runs the granboltz binary with `args` (a shell-quoted string); with `timeout_seconds`, killed
/// after that long (exit code 137), so that a hang fails a test instead of blocking the suite.
inline CommandResult run_granboltz(const std::string& args, int timeout_seconds = 0) {
  const std::string limit =
      timeout_seconds > 0 ? "timeout -s KILL " + std::to_string(timeout_seconds) + " " : "";
  const std::string cmd = limit + std::string(GRANBOLTZ_BINARY) + " " + args + " 2>&1";
  FILE* pipe = ::popen(cmd.c_str(), "r");
  std::string out;
  std::array<char, 4096> buf;
  while (pipe && std::fgets(buf.data(), buf.size(), pipe)) out += buf.data();
  const int status = pipe ? ::pclose(pipe) : -1;
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

/// Starts the granboltz binary with `args` in the background (stdout and stderr to /dev/null,
/// or to `log` when given); returns its pid.
inline pid_t spawn_granboltz(const std::vector<std::string>& args, const std::string& log = "") {
  const pid_t pid = fork();
  if (pid == 0) {
    std::vector<char*> argv{const_cast<char*>(GRANBOLTZ_BINARY)};
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    const int out = log.empty() ? ::open("/dev/null", O_WRONLY)
                                : ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(out, 1);
    dup2(out, 2);
    execv(GRANBOLTZ_BINARY, argv.data());
    _exit(127);
  }
  return pid;
}

/// Waits up to `seconds` for `file` to exist.
inline bool wait_for_file(const std::string& file, double seconds) {
  for (int i = 0; i < seconds * 100; ++i) {
    if (std::filesystem::exists(file)) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return false;
}

/// The file offset of the first chunk of a chunked dataset (H5Dget_chunk_info, HDF5 >= 1.10.5).
inline haddr_t chunk_offset(const std::string& file, const std::string& dataset) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t d = H5Dopen2(f, dataset.c_str(), H5P_DEFAULT);
  const hid_t space = H5Dget_space(d);
  hsize_t offset[3] = {0, 0, 0}, size = 0;
  unsigned mask = 0;
  haddr_t addr = HADDR_UNDEF;
  H5Dget_chunk_info(d, space, 0, offset, &mask, &addr, &size);
  H5Sclose(space);
  H5Dclose(d);
  H5Fclose(f);
  return addr;
}

/// Flips one bit of the byte at offset `at` of `file`.
inline void flip_byte(const std::string& file, std::uint64_t at) {
  std::fstream io(file, std::ios::in | std::ios::out | std::ios::binary);
  io.seekg(static_cast<std::streamoff>(at));
  char c = 0;
  io.read(&c, 1);
  c = static_cast<char>(c ^ 0x10);
  io.seekp(static_cast<std::streamoff>(at));
  io.write(&c, 1);
}

/// A run of `cfg` (in `dir`, which holds only it) with checkpoints that never fall due, sent
/// SIGTERM once under way: it must save its ensembles in progress, exit with 128 + SIGTERM and
/// leave no output, and the same command must resume to the uninterrupted run's output.
inline void expect_sigterm_resumes_identically(const TempDir& dir, const std::string& cfg) {
  const std::string reference = dir.file("reference.h5"), out = dir.file("out.h5");
  const auto whole = run_granboltz("run " + cfg + " -q --threads 2 -o " + reference);
  ASSERT_EQ(whole.exit_code, 0) << whole.output;
  namespace fs = std::filesystem;
  const std::string ckpt = out + ".checkpoint";
  const pid_t pid = spawn_granboltz({"run", cfg, "-q", "--threads", "2", "-o", out});
  // The hourly checkpoint is never due: only SIGTERM can make one. Signal once the run has its
  // temporary output (the signal handler is installed before it is created).
  for (int i = 0; i < 3000 && dir.entries() < 3; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  ::kill(pid, SIGTERM);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status)) << "killed by signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 128 + SIGTERM);
  ASSERT_TRUE(fs::exists(ckpt)) << "no checkpoint written on SIGTERM";
  {
    H5Reader c(ckpt);
    EXPECT_TRUE(c.exists("/in_progress")) << "no ensemble saved in progress";
  }
  EXPECT_FALSE(fs::exists(out));
  EXPECT_EQ(dir.entries(), 3u);  // c.yaml, reference.h5, the checkpoint: no temporary output
  const auto r = run_granboltz("run " + cfg + " --threads 2 -o " + out);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("resuming from"), std::string::npos) << r.output;
  expect_identical_outputs(reference, out);
  EXPECT_EQ(dir.entries(), 3u);  // c.yaml, reference.h5, out.h5
}

/// The tiny valid config of a model that the command-line cases break (tests/bad_inputs/base).
/// The run of `cfg` (a config path with any --set arguments) on 1 and 2 threads and as 3 merged
/// shards: three outputs equal dataset for dataset. Returns the first output's path.
inline std::string expect_threads_and_shards_identical(const TempDir& dir, const std::string& cfg) {
  const auto ok = [](const CommandResult& r) { EXPECT_EQ(r.exit_code, 0) << r.output; };
  const std::string one = dir.file("one.h5"), two = dir.file("two.h5");
  ok(run_granboltz("run " + cfg + " -q --threads 1 -o " + one));
  ok(run_granboltz("run " + cfg + " -q --threads 2 -o " + two));
  expect_identical_outputs(one, two);
  std::string shards;
  for (int s = 0; s < 3; ++s) {
    const std::string f = dir.file("s" + std::to_string(s) + ".h5");
    ok(run_granboltz("run " + cfg + " -q --set shard.count=3 --set shard.index=" +
                     std::to_string(s) + " -o " + f));
    shards += f + " ";
  }
  const std::string merged = dir.file("merged.h5");
  ok(run_granboltz("merge " + shards + "-o " + merged));
  expect_identical_outputs(one, merged);
  return one;
}

/// An ensemble of `config` advanced to t_save, saved and restored, continues to t_end exactly as
/// the one that was never saved: particles, times, collisions and random draws.
inline void expect_restored_ensemble_continues_identically(const DsmcConfig& config,
                                                           std::uint64_t seed,
                                                           std::uint64_t ensemble, double t_save,
                                                           double t_end) {
  TempDir dir;
  DsmcEnsemble a(config, seed, ensemble);
  a.advance_to(t_save);
  {
    H5Writer w(dir.file("state.h5"));
    a.save(w, "/e");
    w.commit();
  }
  H5Reader r(dir.file("state.h5"));
  DsmcEnsemble b(config, r, "/e");
  a.advance_to(t_end);
  b.advance_to(t_end);
  ASSERT_EQ(a.particles().size(), b.particles().size());
  for (std::size_t i = 0; i < a.particles().size(); ++i) {
    const Particle &p = a.particles()[i], &q = b.particles()[i];
    ASSERT_TRUE(p.v.x == q.v.x && p.v.y == q.v.y && p.v.z == q.v.z && p.t == q.t) << i;
  }
  EXPECT_EQ(a.counts().collisions, b.counts().collisions);
  EXPECT_EQ(a.random_draws(), b.random_draws());
}

inline std::string base_config(const std::string& model) {
  std::ifstream in(std::string(GRANBOLTZ_SOURCE_DIR) + "/tests/bad_inputs/base/" + model + ".yaml");
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// The bytes of a file.
inline std::string read_all(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// The z-value such that `checks` simultaneous two-sided tests have family-wise level 0.999
/// (Bonferroni). With one check this is 3.29, close to the papers' lambda_p = 3.2.
inline double family_z(int checks) { return gsl_cdf_ugaussian_Qinv(0.0005 / checks); }

/// Exact results for Maxwell molecules (lambda = 0) with n particles, started from n independent
/// Maxwellian velocities at temperature T0. kappa = pi gamma C0 (1 - alpha^2).
struct MaxwellExact {
  double alpha, beta, gamma, C0, T0;
  double kappa() const { return M_PI * gamma * C0 * (1 - alpha * alpha); }

  /// GRW05 eq. (16): the n -> infinity temperature.
  double temperature(double t) const {
    const double k = kappa();
    if (k == 0) return T0 + 2 * beta * t;
    const double Tinf = 2 * beta / k;
    return T0 * std::exp(-k * t) + Tinf * (1 - std::exp(-k * t));
  }
  /// E[T] of the particle system, T centred on the empirical bulk velocity (GRW05 eq. 13):
  /// the collisions conserve momentum and dissipate on average kappa (3T) per unit time, while
  /// the kicks move V with variance 2 beta t / n per component. Hence E[T](t) = (1 - 1/n) T(t)
  /// for the no-splitting scheme.
  double centred_nosplit(double t, double n) const { return (1 - 1 / n) * temperature(t); }
  /// E|V|^2 / 3 at time t: initial sampling plus the random walk of the kicks.
  double bulk_term(double t, double n) const { return (T0 + 2 * beta * t) / n; }
  /// E[T] of the Euler (strang = false) or Strang splitting scheme after k steps of length dt:
  /// z_{k+1} = z_k e^{-kappa dt} + 6 beta dt (1 - 1/n) [e^{-kappa dt/2} for Strang], z = 3T.
  double centred_split(int k, double dt, double n, bool strang) const {
    double z = 3 * T0 * (1 - 1 / n);
    const double decay = std::exp(-kappa() * dt);
    const double gain = 6 * beta * dt * (1 - 1 / n) * (strang ? std::exp(-kappa() * dt / 2) : 1);
    for (int i = 0; i < k; ++i) z = z * decay + gain;
    return z / 3;
  }
};

// Edits a dataset in place with HDF5 itself, as a user with h5py would: HDF5 recomputes the
// Fletcher32 checksums, so they stay valid.
template <class T>
void edit_dataset(const std::string& file, const std::string& dataset, std::size_t index, T value,
                  hid_t type) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(f, 0) << file;
  const hid_t d = H5Dopen2(f, dataset.c_str(), H5P_DEFAULT);
  ASSERT_GE(d, 0) << dataset;
  const hid_t space = H5Dget_space(d);
  std::vector<T> data(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space)));
  H5Dread(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data());
  data.at(index) = value;
  ASSERT_GE(H5Dwrite(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data()), 0);
  H5Sclose(space);
  H5Dclose(d);
  H5Fclose(f);
}

}  // namespace granboltz::test
