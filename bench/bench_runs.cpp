// Whole-run benchmark harness (make bench): runs fixed configs on one thread, each repetition in
// a child process so that its peak memory is its own, and prints events/s, ns per event, ns per
// real collision, peak memory, and the floor: the time the same number of raw random numbers
// takes to draw, measured side by side. Medians of several repetitions.
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "granboltz/app/config.hpp"
#include "granboltz/dsmc/ensemble.hpp"
#include "granboltz/dsmc/run.hpp"
#include "granboltz/random/rng.hpp"
#include "granboltz/tv06/intruder.hpp"
#include "granboltz/tv06/needle.hpp"

using namespace granboltz;
using Clock = std::chrono::steady_clock;

namespace {

struct Case {
  const char* name;
  const char* description;
  std::vector<std::string> sets;
};

// RW05 / GRW05 parameters; durations chosen for 10^6 - 10^7 events per repetition.
const std::vector<std::string> kRw05 = {"dsmc.alpha=0.5", "dsmc.beta=1", "dsmc.kernel.lambda=0",
                                        "dsmc.kernel.C=0.3183098861837907", "dsmc.t_end=8"};
std::vector<std::string> with(std::vector<std::string> base, std::vector<std::string> more) {
  base.insert(base.end(), more.begin(), more.end());
  return base;
}
std::vector<std::string> peer(const char* n, const char* t_end, const char* majorant) {
  return {"dsmc.alpha=1",
          "dsmc.beta=0",
          "dsmc.kernel.lambda=1",
          "dsmc.kernel.C=0.0795774715459477",
          std::string("dsmc.particles=") + n,
          std::string("dsmc.t_end=") + t_end,
          "ensembles=1",
          std::string("dsmc.majorant=") + majorant};
}

const std::vector<Case> kCases = {
    {"maxwell_nosplit_n4096", "RW05 Maxwell, no-splitting, n=4096, t in [0,8], 8 ensembles",
     with(kRw05, {"dsmc.particles=4096", "ensembles=8"})},
    {"euler_K32_n4096", "RW05 Euler splitting, K=32, n=4096, 8 ensembles",
     with(kRw05, {"dsmc.particles=4096", "ensembles=8", "dsmc.scheme=euler", "dsmc.steps=32"})},
    {"strang_K32_n4096", "RW05 Strang splitting, K=32, n=4096, 8 ensembles",
     with(kRw05, {"dsmc.particles=4096", "ensembles=8", "dsmc.scheme=strang", "dsmc.steps=32"})},
    {"hs_nosplit_n65536",
     "GRW05 Ex. 5 hard spheres, n=65536, t in [0,0.5]",
     {"dsmc.alpha=0.5", "dsmc.beta=0.125", "dsmc.gamma=4", "dsmc.kernel.lambda=1",
      "dsmc.kernel.C=0.0795774715459477", "dsmc.particles=65536", "dsmc.t_end=0.5", "ensembles=1"}},
    {"hs_nosplit_n1e7",
     "GRW05 Ex. 8 hard spheres, n=10^7, t in [0,0.02]",
     {"dsmc.alpha=0.1", "dsmc.beta=30", "dsmc.gamma=16", "dsmc.kernel.lambda=1",
      "dsmc.kernel.C=0.0795774715459477", "dsmc.particles=1e7", "dsmc.t_end=0.02", "ensembles=1"}},
    {"tv06_intruder_gillespie",
     "TV06 intruder, Gaussian bath, M=1, alpha=0.5, 2*10^6 collisions",
     {"model=intruder", "intruder.bath.kind=gaussian", "intruder.bath.a=1", "intruder.mass=1",
      "intruder.alpha=0.5", "intruder.collisions=2e6", "intruder.warmup=0", "ensembles=1"}},
    {"tv06_intruder_dsmc",
     "TV06 intruder by DSMC, same, 5*10^5 collisions",
     {"model=intruder", "intruder.bath.kind=gaussian", "intruder.bath.a=1", "intruder.mass=1",
      "intruder.alpha=0.5", "intruder.collisions=5e5", "intruder.warmup=0", "intruder.method=dsmc",
      "ensembles=1"}},
    {"tv06_needle",
     "TV06 needle, M=0.1, alpha=0.1, 2*10^5 collisions",
     {"model=needle", "needle.mass=0.1", "needle.alpha=0.1", "needle.collisions=2e5",
      "needle.warmup=0", "ensembles=1"}},
    {"peer_elastic_hs_n1e4", "elastic hard spheres (alpha=1, beta=0, lambda=1), n=10^4, global",
     peer("1e4", "100", "global")},
    {"peer_elastic_hs_n1e5", "elastic hard spheres, n=10^5, global majorant",
     peer("1e5", "10", "global")},
    {"peer_elastic_hs_n1e6", "elastic hard spheres, n=10^6, global majorant",
     peer("1e6", "1", "global")},
    {"peer_pairwise_n1e4", "elastic hard spheres, n=10^4, pairwise majorant",
     peer("1e4", "100", "pairwise")},
    {"peer_pairwise_n1e5", "elastic hard spheres, n=10^5, pairwise majorant",
     peer("1e5", "10", "pairwise")},
    {"peer_pairwise_n1e6", "elastic hard spheres, n=10^6, pairwise majorant",
     peer("1e6", "1", "pairwise")},
};

// The peer problem against SPARTA: SPARTA's serial NTC loop time per real collision
// for elastic hard spheres in one periodic cell, measured side by side on one machine
// (SPARTA master; the lower end of each measured range). `make bench-peer` replaces them with a
// SPARTA build's own figures (--sparta FILE: lines "n,ns_per_real_collision").
struct PeerRow {
  double n;
  const char *global, *pairwise;
  double sparta_ns;
};
const PeerRow kPeerRows[] = {{1e4, "peer_elastic_hs_n1e4", "peer_pairwise_n1e4", 295},
                             {1e5, "peer_elastic_hs_n1e5", "peer_pairwise_n1e5", 359},
                             {1e6, "peer_elastic_hs_n1e6", "peer_pairwise_n1e6", 1160}};
constexpr double kPeerGoal = 0.20;  // granboltz at most 1/5 of SPARTA's time

struct Sample {
  double seconds = 0;
  double events = 0, real = 0, kicks = 0, draws = 0;
  double peak_mb = 0;
};

Config config_of(const Case& c, const std::vector<std::string>& extra) {
  std::vector<std::string> sets = {"model=dsmc", "seed=1"};
  if (c.sets[0].rfind("model=", 0) == 0) sets = {"seed=1"};
  sets.insert(sets.end(), c.sets.begin(), c.sets.end());
  sets.insert(sets.end(), extra.begin(), extra.end());
  return parse_config("{}", c.name, sets);
}

// One repetition, in this process: every ensemble advanced from 0 to t_end on one thread.
Sample run_once(const Config& cfg) {
  Sample s;
  if (cfg.model != Model::kDsmc) {  // TV06: an event is a collision (or a thinned candidate)
    const auto t0 = Clock::now();
    if (cfg.model == Model::kIntruder) {
      const auto r = tv06::simulate_intruder(cfg.intruder, cfg.seed, 0);
      s.real = static_cast<double>(r.collisions);
      s.events = s.real + static_cast<double>(r.fictitious);
      s.draws = static_cast<double>(r.draws);
    } else {
      const auto r = tv06::simulate_needle(cfg.needle, cfg.seed, 0);
      s.real = static_cast<double>(r.collisions);
      s.events = s.real + static_cast<double>(r.fictitious);
      s.draws = static_cast<double>(r.draws);
    }
    s.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    return s;
  }
  for (std::uint64_t e = 0; e < cfg.ensembles; ++e) {
    DsmcEnsemble ens(cfg.dsmc, cfg.seed, e);
    const auto t0 = Clock::now();
    ens.advance_to(cfg.dsmc.t_end);
    s.seconds += std::chrono::duration<double>(Clock::now() - t0).count();
    s.events += static_cast<double>(ens.counts().collisions + ens.counts().fictitious);
    s.real += static_cast<double>(ens.counts().collisions);
    s.kicks += static_cast<double>(ens.counts().kicks);
    s.draws += static_cast<double>(ens.random_draws());
  }
  return s;
}

// The same repetition in a child process, for its own peak memory.
Sample run_in_child(const Config& cfg) {
  int fd[2];
  if (pipe(fd) != 0) std::perror("pipe");
  const pid_t pid = fork();
  if (pid == 0) {
    close(fd[0]);
    const Sample s = run_once(cfg);
    if (write(fd[1], &s, sizeof s) != static_cast<ssize_t>(sizeof s)) _exit(1);
    _exit(0);
  }
  close(fd[1]);
  Sample s;
  const ssize_t got = read(fd[0], &s, sizeof s);
  close(fd[0]);
  int status = 0;
  struct rusage usage;
  wait4(pid, &status, 0, &usage);
  if (got != static_cast<ssize_t>(sizeof s) || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    std::fprintf(stderr, "benchmark child failed\n");
    std::exit(1);
  }
  s.peak_mb = static_cast<double>(usage.ru_maxrss) / 1024.0;
  return s;
}

// The floor: drawing `draws` raw 64-bit numbers from the same engine type, nothing else.
double floor_seconds(double draws) {
  Engine e = make_stream(99, 0, Consumer::kEvents);
  const auto n = static_cast<std::uint64_t>(draws);
  std::uint64_t sink = 0;
  const auto t0 = Clock::now();
  for (std::uint64_t i = 0; i < n; ++i) sink ^= e();
  const double s = std::chrono::duration<double>(Clock::now() - t0).count();
  if (sink == 42) std::puts("");  // keep the loop
  return s;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

// Wall time of a run_dsmc of 64 ensembles on `threads` threads.
double threaded_seconds(const Case& c, unsigned threads) {
  const Config cfg = config_of(c, {"ensembles=64"});
  DriverOptions o;
  o.threads = threads;
  o.progress = false;
  const auto t0 = Clock::now();
  Record record = dsmc_layout(cfg);
  run_dsmc(cfg, o, record);
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

}  // namespace

// The peer table: ns per real collision of both majorants, the one `auto` picks, SPARTA's.
void print_peer_table(const std::map<std::string, double>& ns_real, const std::string& sparta_csv,
                      std::ofstream& csv) {
  std::map<double, double> sparta;
  for (const auto& row : kPeerRows) sparta[row.n] = row.sparta_ns;
  std::string source = "reference figures, SPARTA master measured side by side";
  if (!sparta_csv.empty()) {
    std::ifstream in(sparta_csv);
    double n, ns;
    char comma;
    while (in >> n >> comma >> ns) sparta[n] = ns;
    source = sparta_csv;
  }
  std::printf(
      "\npeer problem (elastic hard spheres, one cell; ns per real collision; SPARTA: %s)\n",
      source.c_str());
  std::printf("%-8s %9s %9s %-9s %9s %9s %6s %s\n", "n", "global", "pairwise", "auto", "auto ns",
              "SPARTA", "ratio", "goal <= 0.20");
  for (const auto& row : kPeerRows) {
    if (!ns_real.count(row.global) || !ns_real.count(row.pairwise)) continue;
    Config cfg = parse_config(
        "{}", "peer",
        {"model=dsmc", "seed=1", "dsmc.alpha=1", "dsmc.beta=0", "dsmc.kernel.lambda=1",
         "dsmc.kernel.C=0.08", "dsmc.t_end=1", "dsmc.particles=" + format_real(row.n)});
    const bool pairwise = cfg.dsmc.majorant == MajorantKind::kPairwise;
    const double chosen = ns_real.at(pairwise ? row.pairwise : row.global);
    const double ratio = chosen / sparta[row.n];
    std::printf("%-8.0e %9.1f %9.1f %-9s %9.1f %9.0f %6.3f %s\n", row.n, ns_real.at(row.global),
                ns_real.at(row.pairwise), pairwise ? "pairwise" : "global", chosen, sparta[row.n],
                ratio, ratio <= kPeerGoal ? "met" : "not met");
    csv << "peer_auto_n" << format_real(row.n) << ",\"auto: " << (pairwise ? "pairwise" : "global")
        << "; SPARTA " << sparta[row.n] << " ns (" << source << ")\",,,,,,,,,," << chosen << ",,"
        << ratio << ",\n";
  }
}

int main(int argc, char** argv) {
  int repeat = 5;
  std::string csv_path = "bench/results.csv", only, sparta_csv;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--repeat") && i + 1 < argc)
      repeat = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--csv") && i + 1 < argc)
      csv_path = argv[++i];
    else if (!std::strcmp(argv[i], "--only") && i + 1 < argc)
      only = argv[++i];
    else if (!std::strcmp(argv[i], "--sparta") && i + 1 < argc)
      sparta_csv = argv[++i];
    else {
      std::fprintf(
          stderr,
          "usage: granboltz_bench [--repeat R] [--csv FILE] [--only NAME] [--sparta FILE]\n");
      return 2;
    }
  }
  std::ofstream csv(csv_path);
  csv << "config,description,repeats,events,real_collisions,kicks,draws_per_event,"
         "seconds_median,events_per_s,ns_per_event,ns_per_real_collision,floor_ns_per_event,"
         "ratio_to_floor,peak_mb\n";
  std::printf("%-22s %11s %9s %9s %9s %9s %7s %9s\n", "config", "events", "Mevents/s", "ns/event",
              "ns/real", "floor ns", "ratio", "peak MB");
  std::map<std::string, double> ns_real;
  for (const Case& c : kCases) {
    if (!only.empty() && std::string(c.name).find(only) == std::string::npos) continue;
    const Config cfg = config_of(c, {});
    std::vector<double> secs, floors, peaks;
    Sample s;
    for (int r = 0; r < repeat; ++r) {
      s = run_in_child(cfg);
      secs.push_back(s.seconds);
      peaks.push_back(s.peak_mb);
      floors.push_back(floor_seconds(s.draws));
    }
    const double t = median(secs), f = median(floors);
    const double ns = 1e9 * t / s.events, fns = 1e9 * f / s.events;
    std::printf("%-22s %11.0f %9.2f %9.1f %9.1f %9.1f %7.2f %9.0f\n", c.name, s.events,
                s.events / t / 1e6, ns, 1e9 * t / s.real, fns, ns / fns, median(peaks));
    ns_real[c.name] = 1e9 * t / s.real;
    csv << c.name << ",\"" << c.description << "\"," << repeat << "," << s.events << "," << s.real
        << "," << s.kicks << "," << s.draws / s.events << "," << t << "," << s.events / t << ","
        << ns << "," << 1e9 * t / s.real << "," << fns << "," << ns / fns << "," << median(peaks)
        << "\n";
    std::fflush(stdout);
  }
  print_peer_table(ns_real, sparta_csv, csv);
  if (only.empty() || only == "threads") {
    std::vector<double> one, two;
    for (int r = 0; r < std::max(3, repeat); ++r) {
      one.push_back(threaded_seconds(kCases[0], 1));
      two.push_back(threaded_seconds(kCases[0], 2));
    }
    std::printf("threads: 64 ensembles of %s: 1 thread %.3f s, 2 threads %.3f s, speed-up %.2f\n",
                kCases[0].name, median(one), median(two), median(one) / median(two));
    csv << "speedup_1_to_2_threads,\"" << kCases[0].description << "\"," << repeat << ",,,,,"
        << median(two) << ",,,,,," << median(one) / median(two) << "\n";
  }
  std::printf("CSV: %s\n", csv_path.c_str());
  return 0;
}
