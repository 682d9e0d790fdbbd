#include "granboltz/run.hpp"

#include <unistd.h>

#include <chrono>
#include <cstring>
#include <ctime>
#include <fstream>

#include "granboltz/dsmc_run.hpp"
#include "granboltz/exact_sum.hpp"
#include "granboltz/hdf5_io.hpp"
#include "granboltz/observables.hpp"
#include "granboltz/particles.hpp"
#include "granboltz/tv06_run.hpp"
#include "granboltz/version.hpp"

namespace granboltz {

namespace {

char g_temporary[4096] = "";

std::uint64_t available_memory() {
  std::ifstream in("/proc/meminfo");
  std::string key;
  std::uint64_t kb = 0;
  std::string unit;
  while (in >> key >> kb >> unit)
    if (key == "MemAvailable:") return kb * 1024;
  const long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGE_SIZE);
  return pages > 0 && size > 0 ? static_cast<std::uint64_t>(pages) * size : 0;
}

std::string human_bytes(double b) {
  const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB", "PiB"};
  int u = 0;
  while (b >= 1024 && u < 5) {
    b /= 1024;
    ++u;
  }
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f %s", b, units[u]);
  return buf;
}

std::string utc_now() {
  const std::time_t t = std::time(nullptr);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
  return buf;
}

}  // namespace

const char* current_temporary_output() { return g_temporary; }

std::uint64_t estimate_memory(const Config& config, unsigned threads) {
  const double t = threads;
  double bytes = 64.0 * 1024 * 1024;  // program, libraries, HDF5 buffers
  if (config.model == Model::kDsmc) {
    const DsmcConfig& d = config.dsmc;
    const double rows = static_cast<double>(d.observations() + 1);
    const double shells = d.histogram.shells ? static_cast<double>(d.histogram.shells + 1) : 0;
    bytes += t * static_cast<double>(d.particles) * sizeof(Particle);
    bytes += t * rows * (kNumScalars * 8.0 + shells * 8.0);      // per-ensemble observations
    bytes += rows * kNumScalars * 2.0 * sizeof(ExactSum) * 2.0;  // accumulators and output copy
    bytes += rows * shells * 24.0 * 2.0;
    bytes += static_cast<double>(config.last_ensemble() - config.first_ensemble()) * 40.0;
  } else {
    bytes += tv06_memory_estimate(config, threads);
  }
  return static_cast<std::uint64_t>(bytes);
}

void run_to_file(const Config& config, const std::string& path, const DriverOptions& options,
                 const std::string& command) {
  const std::uint64_t work = config.last_ensemble() - config.first_ensemble();
  const unsigned threads = resolve_threads(options.threads, work);
  const std::uint64_t need = estimate_memory(config, threads);
  const std::uint64_t have = available_memory();
  if (have > 0 && static_cast<double>(need) > 0.9 * static_cast<double>(have))
    throw ConfigError("the run needs about " + human_bytes(static_cast<double>(need)) +
                      " of memory on " + std::to_string(threads) + " thread(s), but only " +
                      human_bytes(static_cast<double>(have)) +
                      " is available; reduce particles, threads or observation times");

  // Create the output first, so that an unwritable path fails before hours of work.
  H5Writer out(path);
  std::strncpy(g_temporary, out.temp_path().c_str(), sizeof g_temporary - 1);
  const std::string started = utc_now();
  const auto start = std::chrono::steady_clock::now();

  DriverOptions opts = options;
  opts.threads = threads;
  switch (config.model) {
    case Model::kDsmc: write_dsmc(out, config, run_dsmc(config, opts)); break;
    case Model::kIntruder:
    case Model::kNeedle: run_tv06(out, config, opts); break;
  }
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  out.attr("/", "config", config.to_yaml(true));
  out.attr("/", "model", model_name(config.model));
  out.attr("/", "seed", config.seed);
  out.attr("/", "ensembles", config.ensembles);
  out.attr("/", "version", std::string(kVersion));
  out.attr("/", "git_sha", std::string(kGitSha));
  out.group("/provenance");
  out.attr("/provenance", "run_config", config.to_yaml(false));
  out.attr("/provenance", "command", command);
  out.attr("/provenance", "threads", static_cast<std::uint64_t>(threads));
  out.attr("/provenance", "shard_index", config.shard.index);
  out.attr("/provenance", "shard_count", config.shard.count);
  out.attr("/provenance", "wall_seconds", wall);
  out.attr("/provenance", "started_utc", started);
  char host[256] = "";
  gethostname(host, sizeof host - 1);
  out.attr("/provenance", "host", std::string(host));
  out.attr("/provenance", "build", std::string(GRANBOLTZ_BUILD_TYPE) + ", " GRANBOLTZ_COMPILER);
  out.commit();
  g_temporary[0] = '\0';
}

}  // namespace granboltz
