#include "granboltz/app/run.hpp"

#include <signal.h>
#include <sys/stat.h>
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

#include "granboltz/app/estimate.hpp"
#include "granboltz/app/output.hpp"
#include "granboltz/core/version.hpp"
#include "granboltz/dsmc/observables.hpp"
#include "granboltz/dsmc/particles.hpp"
#include "granboltz/dsmc/run.hpp"
#include "granboltz/h5/hdf5_io.hpp"
#include "granboltz/h5/verify.hpp"
#include "granboltz/stats/exact_sum.hpp"
#include "granboltz/tv06/run.hpp"

namespace granboltz {

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

namespace {

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

// A checkpoint is trusted only as far as it is checked: it names the build that wrote it, the
// hash of its config and a digest of every dataset (HDF5 recomputes its own checksums when a
// file is edited, so they cannot tell an edited checkpoint from a sound one).
void write_checkpoint(const std::string& path, const Config& config, const Record& record,
                      const std::function<void(H5Writer&)>& in_progress) {
  H5Writer out(path);
  record.write(out);
  in_progress(out);
  const std::string text = config.to_yaml(true);
  out.attr("/", "config", text);
  out.attr("/", "shard_index", config.shard.index);
  out.attr("/", "shard_count", config.shard.count);
  out.attr("/", "saved_utc", utc_now());
  out.attr("/", "kind", std::string("checkpoint"));
  out.attr("/", "version", std::string(kVersion));
  out.attr("/", "git_sha", std::string(kGitSha));
  out.attr("/", "config_hash", text_hash(text));
  out.attr("/", "digest", out.digest());
  out.commit();  // atomic: a checkpoint is either the old one or the new one
}

// The record saved by an earlier, interrupted run of the same config and shard, if any.
bool load_checkpoint(const std::string& path, const Config& config, Record& record) {
  struct stat st {};
  if (::lstat(path.c_str(), &st) != 0) return false;
  const std::string fix = "; delete it to start afresh, or write to another output";
  if (!S_ISREG(st.st_mode))
    throw ConfigError(path + ": the checkpoint is not a regular file" + fix);
  // Read through once in a child process first: a damaged file can crash the HDF5 library.
  const FileCheck check = check_file(path);
  if (!check.problems.empty()) throw std::runtime_error(path + ": " + check.problems.front() + fix);
  H5Reader in(path);
  const std::string text = config.to_yaml(true);
  auto attr = [&](const char* name) {
    return in.has_attr("/", name) ? in.attr_string("/", name) : std::string("(none)");
  };
  if (attr("kind") != "checkpoint")
    throw ConfigError(path + ": not a checkpoint of this granboltz (no kind attribute)" + fix);
  const std::string built = attr("version") + " (" + attr("git_sha") + ")";
  if (built != std::string(kVersion) + " (" + kGitSha + ")")
    throw ConfigError(path + ": checkpoint written by granboltz " + built + ", this is " +
                      kVersion + " (" + kGitSha + ")" + fix);
  if (!in.has_attr("/", "config") || in.attr_string("/", "config") != text ||
      !in.has_attr("/", "config_hash") || in.attr_uint64("/", "config_hash") != text_hash(text) ||
      in.attr_uint64("/", "shard_index") != config.shard.index ||
      in.attr_uint64("/", "shard_count") != config.shard.count)
    throw ConfigError(path + ": checkpoint of a different config or shard" + fix);
  // check_file compared the digest with the datasets already; here only its presence.
  if (!in.has_attr("/", "digest"))
    throw ConfigError(path + ": a checkpoint without its digest attribute" + fix);
  record.read(in);
  // Only ensembles of this shard, each once (add_ensemble refuses repeats).
  for (const std::uint64_t e : record.ensemble_indices())
    if (e < config.first_ensemble() || e >= config.last_ensemble())
      throw ConfigError(path + ": the checkpoint holds ensemble " + std::to_string(e) +
                        ", which is not of this shard" + fix);
  return true;
}

}  // namespace

std::uint64_t estimate_memory(const Config& config, unsigned threads) {
  const double t = threads;
  double bytes = 64.0 * 1024 * 1024;  // program, libraries, HDF5 buffers
  if (config.model == Model::kDsmc) {
    const DsmcConfig& d = config.dsmc;
    const double rows = static_cast<double>(d.observations() + 1);
    // The radial histogram, and as many bins again for the component histogram.
    const double shells = d.histogram.shells ? static_cast<double>(d.histogram.shells + 1) *
                                                   (d.histogram.component ? 2.0 : 1.0)
                                             : 0;
    if (d.weights.swpm) {
      // Up to N_max + 2 particles and weights, twice over (a split sweep's copies may outgrow
      // the reserve before the reduction; the vector then moves), the sum tree (two doubles per
      // leaf, leaves a power of two) and the reduction's and the split's sort keys (assumed).
      const double cap = static_cast<double>(d.weights.max_particles + 2);
      bytes += t * (cap * (2.0 * (sizeof(Particle) + 8.0) + 32.0) +
                    16.0 * static_cast<double>(std::bit_ceil(d.weights.max_particles + 2)));
    } else {
      bytes += t * static_cast<double>(d.particles) * sizeof(Particle);
      // Rough particles: the spins beside them, and a scaled copy of the state at observations.
      if (d.roughness.on) bytes += t * static_cast<double>(d.particles) * sizeof(Vec3);
      if (d.general()) bytes += t * static_cast<double>(d.particles) * sizeof(Particle);
    }
    if (d.majorant == MajorantKind::kPairwise) bytes += t * static_cast<double>(d.particles) * 8.0;
    // Per ensemble under way, its rows: the scalars and speed moments of the gas (and of each
    // species, and T_rot), the histograms' counts (and, SWPM, their weights).
    const double sets = 1.0 + (d.species_written ? static_cast<double>(d.species.size()) : 0.0);
    const double scalars = (kNumScalars + d.moments) * sets + (d.roughness.on ? 1.0 : 0.0);
    bytes += t * rows * (scalars * 8.0 + shells * 8.0 * (d.weights.swpm ? 2.0 : 1.0));
    // The record: every moment sum and count its layout declares (found by building it without
    // allocating: the steady histogram's exact sums and SWPM's weight per row and shell, 1.1 kB
    // each, used to be left out, and a run said 317 MiB and took 23 GB), and the output's copy of
    // it while it is written.
    Record::Sizing size;
    layout_of(config);
    bytes += 2.0 * (static_cast<double>(size.moments) * sizeof(Moments2) +
                    static_cast<double>(size.counts) * (sizeof(std::uint64_t) + sizeof(uint128)));
    bytes += static_cast<double>(config.last_ensemble() - config.first_ensemble()) * 200.0;
    // A checkpoint is built in memory (h5/hdf5_io.cpp): 32 bytes per particle in progress, and
    // a copy while it is written out.
    if (config.checkpoint.every_seconds > 0)
      bytes +=
          2.0 * t * static_cast<double>(d.particles) * 32.0 +
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
  // A run whose cost has no bound (it would never end) is refused, quiet or not.
  check_cost_bounded(config);

  const std::string checkpoint = path + ".checkpoint";
  // Create the output first, so that an unwritable path fails before hours of work, and a second
  // run on the same output is refused before it reads or writes the checkpoint.
  H5Writer out(path);
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
        if (options.on_final_checkpoint) return options.on_final_checkpoint();
        std::fprintf(stderr, "[granboltz] %s: SIGTERM: checkpoint written to %s, stopping\n",
                     options.label.c_str(), checkpoint.c_str());
        remove_temporaries_now();
        std::_Exit(128 + SIGTERM);
      }
    };
  }
  if (resumed) opts.resume_from = checkpoint;
  if (config.model == Model::kDsmc)
    run_dsmc(config, opts, record);
  else
    run_tv06(config, opts, record);
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  write_output(
      out, config, record,
      {{"run_config", config.to_yaml(false)},
       {"command", command},
       {"threads", std::to_string(threads)},
       {"shard", std::to_string(config.shard.index) + "/" + std::to_string(config.shard.count)},
       {"wall_seconds", std::to_string(wall)},
       {"resumed_from_checkpoint", resumed ? "yes" : "no"},
       {"started_utc", started},
       {"host", hostname()},
       {"build", std::string(GRANBOLTZ_BUILD_TYPE) + ", " GRANBOLTZ_COMPILER}});
  out.commit();
  std::error_code ec;
  std::filesystem::remove(checkpoint, ec);  // the output now holds everything
}

}  // namespace granboltz
