#include "granboltz/driver/run.hpp"

#include <signal.h>
#include <unistd.h>

#include <bit>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>

#include "granboltz/driver/estimate.hpp"
#include "granboltz/dsmc/run.hpp"
#include "granboltz/stats/exact_sum.hpp"
#include "granboltz/io/hdf5_io.hpp"
#include "granboltz/dsmc/observables.hpp"
#include "granboltz/io/output.hpp"
#include "granboltz/dsmc/particles.hpp"
#include "granboltz/tv06/run.hpp"

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

std::string utc_now() {
  const std::time_t t = std::time(nullptr);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
  return buf;
}

std::string hostname() {
  char host[256] = "";
  gethostname(host, sizeof host - 1);
  return host;
}

// Removes temporary files "<path>.tmp.<pid>" left by runs that were killed.
void remove_stale_temporaries(const std::string& path) {
  namespace fs = std::filesystem;
  const fs::path p(path);
  const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
  const std::string prefix = p.filename().string() + ".tmp.";
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind(prefix, 0) != 0) continue;
    const std::string pid = name.substr(prefix.size());
    if (pid.empty() || pid.find_first_not_of("0123456789") != std::string::npos) continue;
    if (::kill(static_cast<pid_t>(std::stol(pid)), 0) != 0 && errno == ESRCH)
      fs::remove(entry.path(), ec);
  }
}

void write_checkpoint(const std::string& path, const Config& config, const Record& record,
                      const std::function<void(H5Writer&)>& in_progress) {
  H5Writer out(path);
  record.write(out);
  in_progress(out);
  out.attr("/", "config", config.to_yaml(true));
  out.attr("/", "shard_index", config.shard.index);
  out.attr("/", "shard_count", config.shard.count);
  out.attr("/", "saved_utc", utc_now());
  out.commit();  // atomic: a checkpoint is either the old one or the new one
}

// The record saved by an earlier, interrupted run of the same config and shard, if any.
bool load_checkpoint(const std::string& path, const Config& config, Record& record) {
  if (!std::filesystem::exists(path)) return false;
  H5Reader in(path);
  if (!in.has_attr("/", "config") || in.attr_string("/", "config") != config.to_yaml(true) ||
      in.attr_uint64("/", "shard_index") != config.shard.index ||
      in.attr_uint64("/", "shard_count") != config.shard.count)
    throw ConfigError(path + ": checkpoint of a different config or shard; delete it to start "
                      "afresh, or write to another output");
  record.read(in);
  return true;
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
    if (d.weights.swpm) {
      // Up to N_max + 2 particles and weights, twice over (a split sweep's copies may outgrow
      // the reserve before the reduction; the vector then moves), the sum tree (two doubles per
      // leaf, leaves a power of two) and the reduction's and the split's sort keys (assumed).
      const double cap = static_cast<double>(d.weights.max_particles + 2);
      bytes += t * (cap * (2.0 * (sizeof(Particle) + 8.0) + 32.0) +
                    16.0 * static_cast<double>(std::bit_ceil(d.weights.max_particles + 2)));
    } else {
      bytes += t * static_cast<double>(d.particles) * sizeof(Particle);
    }
    if (d.majorant == MajorantKind::kPairwise) bytes += t * static_cast<double>(d.particles) * 8.0;
    const double scalars = kNumScalars + d.moments;
    bytes += t * rows * (scalars * 8.0 + shells * 8.0);      // per-ensemble observations
    bytes += rows * scalars * 2.0 * sizeof(ExactSum) * 2.0;  // accumulators and output copy
    bytes += rows * shells * 24.0 * 2.0;
    bytes += static_cast<double>(config.last_ensemble() - config.first_ensemble()) * 200.0;
    // A checkpoint is built in memory (io/hdf5_io.cpp): 32 bytes per particle in progress, and
    // a copy while it is written out.
    if (config.checkpoint.every_seconds > 0)
      bytes += 2.0 * t * static_cast<double>(d.particles) * 32.0 +
               (d.weights.swpm ? 2.0 * t * static_cast<double>(d.weights.max_particles) * 40.0 : 0.0);
  } else {
    bytes += tv06_memory_estimate(config, threads);
  }
  // Absurd sizes exceed 2^64 bytes, where the conversion would be undefined (and wrap to small).
  return bytes < 18446744073709551616.0 ? static_cast<std::uint64_t>(bytes)
                                        : std::numeric_limits<std::uint64_t>::max();
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

  const std::string checkpoint = path + ".checkpoint";
  remove_stale_temporaries(path);
  remove_stale_temporaries(checkpoint);
  // Create the output first, so that an unwritable path fails before hours of work.
  H5Writer out(path);
  std::strncpy(g_temporary, out.temp_path().c_str(), sizeof g_temporary - 1);
  const std::string started = utc_now();
  const auto start = std::chrono::steady_clock::now();

  Record record = layout_of(config);
  const bool resumed = load_checkpoint(checkpoint, config, record);
  if (resumed && options.progress)
    std::fprintf(stderr, "[granboltz] %s: resuming from %s, %llu of %llu ensembles done\n",
                 options.label.c_str(), checkpoint.c_str(),
                 static_cast<unsigned long long>(record.ensembles()),
                 static_cast<unsigned long long>(work));

  DriverOptions opts = options;
  opts.threads = threads;
  if (config.checkpoint.every_seconds > 0) {
    opts.checkpoint_every = config.checkpoint.every_seconds;
    opts.checkpoint = [&](const Record& r, const std::function<void(H5Writer&)>& in_progress) {
      write_checkpoint(checkpoint, config, r, in_progress);
      // SIGTERM (a batch system about to preempt the job): stop now, leaving the checkpoint
      // to resume from and no output; non-zero, so that the job is seen as failed and rerun.
      if (final_checkpoint_requested()) {
        std::fprintf(stderr, "[granboltz] %s: SIGTERM: checkpoint written to %s, stopping\n",
                     options.label.c_str(), checkpoint.c_str());
        ::unlink(g_temporary);
        std::_Exit(128 + SIGTERM);
      }
    };
  }
  if (resumed) opts.resume_from = checkpoint;
  if (config.model == Model::kDsmc) run_dsmc(config, opts, record);
  else run_tv06(config, opts, record);
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  write_output(out, config, record,
               {{"run_config", config.to_yaml(false)},
                {"command", command},
                {"threads", std::to_string(threads)},
                {"shard", std::to_string(config.shard.index) + "/" +
                              std::to_string(config.shard.count)},
                {"wall_seconds", std::to_string(wall)},
                {"resumed_from_checkpoint", resumed ? "yes" : "no"},
                {"started_utc", started},
                {"host", hostname()},
                {"build", std::string(GRANBOLTZ_BUILD_TYPE) + ", " GRANBOLTZ_COMPILER}});
  out.commit();
  g_temporary[0] = '\0';
  std::error_code ec;
  std::filesystem::remove(checkpoint, ec);  // the output now holds everything
}

}  // namespace granboltz
