// granboltz: command line. Parses arguments, loads the config, dispatches; nothing else.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <new>
#include <stdexcept>

#include "granboltz/app/config.hpp"
#include "granboltz/app/estimate.hpp"
#include "granboltz/app/merge.hpp"
#include "granboltz/app/run.hpp"
#include "granboltz/app/summary.hpp"
#include "granboltz/core/gsl_errors.hpp"
#include "granboltz/core/version.hpp"
#include "granboltz/h5/hdf5_io.hpp"
#include "granboltz/h5/verify.hpp"

namespace {

// An interrupted run removes its temporary files (output, checkpoint, merge), so nothing
// half-written is left behind. SIGTERM to a run that checkpoints instead asks for a last
// checkpoint (then the run stops).
extern "C" void on_signal(int sig) {
  if (sig == SIGTERM && granboltz::request_final_checkpoint()) return;
  granboltz::remove_temporaries_now();
  ::_exit(128 + sig);
}

// Every error is printed as one line: whatever a message carries (a path or an argument with a
// newline, a library's text), control characters are escaped; a message is cut at 1000.
std::string one_line(const std::string& message) { return granboltz::quote_value(message, 1000); }

std::string joined(int argc, char** argv) {
  std::string s;
  for (int i = 0; i < argc; ++i) s += (i ? " " : "") + std::string(argv[i]);
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  granboltz::install_gsl_error_handler();  // GSL errors become statuses, never abort()
  CLI::App app{
      "granboltz: DSMC and event-driven simulation of the heated inelastic Boltzmann "
      "equation (GRW05, RW05, TV06)"};
  app.set_version_flag("--version", std::string("granboltz ") + granboltz::kVersion + " (" +
                                        granboltz::kGitSha + ")");
  app.require_subcommand(1);

  std::string config_path, output;
  std::vector<std::string> sets, inputs;
  std::string threads_text;  // --threads, read as the config's `threads` is (after parsing)
  bool quiet = false;
  double max_hours = 0.0;

  auto* run = app.add_subcommand("run", "run a config and write its HDF5 output");
  run->add_option("config", config_path, "run config (YAML)")->required();
  run->add_option("-o,--output", output, "output file (HDF5)")->required();
  run->add_option("--threads", threads_text,
                  "worker threads, 0 ... 1024 (0: all cores; never changes results)");
  run->add_option("--set", sets, "override a config key: --set dsmc.particles=1024");
  run->add_flag("-q,--quiet", quiet, "no progress reports");
  run->add_option("--max-hours", max_hours,
                  "refuse the run if its estimated wall time exceeds this (default: no limit)")
      ->check(CLI::Validator(
          [](std::string& s) -> std::string {
            // CLI11's PositiveNumber lets nan through (every comparison with it is false), and
            // an inf limit is no limit: only a finite number > 0 means something here.
            char* end = nullptr;
            const double x = std::strtod(s.c_str(), &end);
            if (end == s.c_str() || *end != '\0' || !std::isfinite(x) || !(x > 0))
              return s + ": must be a finite number > 0";
            return {};
          },
          "HOURS"));

  auto* estimate = app.add_subcommand(
      "estimate", "print the expected events, peak memory and wall time of a run");
  estimate->add_option("config", config_path, "run config (YAML)")->required();
  estimate->add_option("--set", sets, "override a config key");
  estimate->add_option("--threads", threads_text, "worker threads, 0 ... 1024 (0: all cores)");

  auto* validate = app.add_subcommand("validate", "check a config and print it in full");
  validate->add_option("config", config_path, "run config (YAML)")->required();
  validate->add_option("--set", sets, "override a config key");

  auto* merge = app.add_subcommand("merge", "merge the outputs of the shards of one run");
  merge->add_option("inputs", inputs, "shard outputs (HDF5)")->required();
  merge->add_option("-o,--output", output, "merged output (HDF5)")->required();

  auto* verify = app.add_subcommand(
      "verify", "check every dataset of outputs or checkpoints against its checksum");
  verify->add_option("files", inputs, "granboltz outputs or checkpoints (HDF5)")->required();

  // Command-line errors are one line on stderr with exit code 2, like config errors; --help and
  // --version keep CLI11's output and exit code 0.
  if (argc == 1) {
    std::fprintf(stderr,
                 "granboltz: error: a command is required: run, estimate, validate, merge or "
                 "verify "
                 "(see granboltz --help)\n");
    return 2;
  }
  if (argv[1][0] == '-') {
    const std::string option = argv[1];
    if (option != "-h" && option != "--help" && option != "--version") {
      std::fprintf(stderr,
                   "granboltz: error: %s: unknown option; expected a command: run, estimate, "
                   "validate, merge or verify (see granboltz --help)\n",
                   one_line(argv[1]).c_str());
      return 2;
    }
  } else {
    const std::string command = argv[1];
    if (command != "run" && command != "estimate" && command != "validate" && command != "merge" &&
        command != "verify") {
      std::fprintf(stderr,
                   "granboltz: error: %s: unknown command; expected run, estimate, validate, "
                   "merge or verify (see granboltz --help)\n",
                   one_line(argv[1]).c_str());
      return 2;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);
    std::string what = e.what();
    for (auto& ch : what)
      if (ch == '\n' || ch == '\r') ch = ' ';
    std::fprintf(stderr, "granboltz: error: %s (see granboltz --help)\n", one_line(what).c_str());
    return 2;
  }

  if ((*run || *merge) && output.empty()) {
    std::fprintf(stderr, "granboltz: error: --output is empty: give the output file's name\n");
    return 2;
  }

  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  std::signal(SIGHUP, on_signal);
  // Past `ulimit -f` a write fails with EFBIG and is reported like a full disk, instead of the
  // process being killed with the temporary file left behind.
  std::signal(SIGXFSZ, SIG_IGN);
  try {
    if (*merge) {
      granboltz::merge_outputs(inputs, output);
      return 0;
    }
    if (*verify) return granboltz::verify_files(inputs, std::cout, std::cerr) ? 0 : 1;
    // The same integers as the config's `threads` (1e3 is 1000), and one message naming the
    // option and what it allows for anything else.
    const bool threads_given = run->count("--threads") || estimate->count("--threads");
    unsigned threads = 0;
    if (threads_given) try {
        threads = static_cast<unsigned>(granboltz::parse_integer(
            threads_text, "--threads", granboltz::kThreadsRange, threads_text));
      } catch (const granboltz::ConfigError&) {
        throw granboltz::ConfigError("--threads " + granboltz::quote_value(threads_text) +
                                     ": must be an integer from 0 to 1024 (0: all cores)");
      }
    // Before the config is read: an output that must not be written fails at once.
    if (*run) granboltz::check_output_path(output, {config_path, output + ".checkpoint"});
    granboltz::Config config = granboltz::load_config(config_path, sets);
    if (*validate) {
      std::cout << config.to_yaml(false);
      return 0;
    }
    if (threads_given) config.threads = threads;
    // Only when someone reads it: for weighted particles the estimate runs a pilot (0.1-0.3 s).
    if (*estimate || max_hours > 0 || !quiet) {
      const granboltz::RunEstimate cost = granboltz::estimate_run(config, config.threads);
      if (*estimate) {
        std::cout << granboltz::describe(cost) << "\n";
        return 0;
      }
      if (max_hours > 0 && cost.seconds > 3600.0 * max_hours) {
        std::fprintf(stderr, "granboltz: error: --max-hours %g: the run would take longer: %s\n",
                     max_hours, granboltz::describe(cost).c_str());
        return 2;
      }
      if (!quiet)
        std::fprintf(stderr, "[granboltz] estimate: %s\n", granboltz::describe(cost).c_str());
    }
    granboltz::DriverOptions options;
    options.threads = config.threads;
    options.progress = !quiet;
    options.label = config_path;
    const auto start = std::chrono::steady_clock::now();
    granboltz::run_to_file(config, output, options, joined(argc, argv));
    if (!quiet) {
      const std::chrono::duration<double> wall = std::chrono::steady_clock::now() - start;
      std::cout << "granboltz: " << granboltz::run_summary(output, wall.count()) << std::endl;
    }
    return 0;
  } catch (const granboltz::ConfigError& e) {
    std::fprintf(stderr, "granboltz: error: %s\n", one_line(e.what()).c_str());
    return 2;
  } catch (const std::bad_alloc&) {
    // The memory check before a run counts what it will allocate; this is what it missed (or
    // memory taken by others meanwhile), said in one line rather than by the library's name.
    std::fprintf(stderr,
                 "granboltz: error: out of memory: an allocation failed; reduce "
                 "particles, threads, histogram shells or observation times\n");
    return 1;
  } catch (const std::length_error&) {
    std::fprintf(stderr,
                 "granboltz: error: out of memory: a size beyond what can be allocated; "
                 "reduce particles, histogram shells or observation times\n");
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "granboltz: error: %s\n", one_line(e.what()).c_str());
    return 1;
  } catch (...) {
    std::fprintf(stderr, "granboltz: error: unexpected internal error\n");
    return 1;
  }
}
