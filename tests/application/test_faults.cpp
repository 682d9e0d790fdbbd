// Runs that survive faults: sharded runs merge into the unsharded result bit for bit, and a run
// killed at a random moment resumes from its checkpoint to the same output as an uninterrupted
// run.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <random>
#include <thread>

#include "configs.hpp"
#include "granboltz/h5/hdf5_io.hpp"
#include "test_support.hpp"

using granboltz::H5Reader;
using granboltz::test::run_granboltz;
using granboltz::test::spawn_granboltz;
using granboltz::test::TempDir;

namespace {

const std::string kDsmcText = std::string(R"(model: dsmc
seed: 11
ensembles: 7
dsmc:
  particles: 200
  alpha: 0.5
)") + granboltz::test::kHeatedStatefulOutputs;
const char* kDsmc = kDsmcText.c_str();  // compared by address below, as the other configs

const char* kIntruder = R"(model: intruder
seed: 12
ensembles: 5
intruder:
  bath: {kind: gaussian, a: 1}
  mass: 0.5
  alpha: 0.3
  collisions: 20000
  histogram: {bins: 20, range: 3}
)";

const char* kNeedle = R"(model: needle
seed: 13
ensembles: 5
needle:
  mass: 0.5
  alpha: 0.4
  collisions: 5000
  velocity_histogram: {bins: 10, range: 3}
  omega_histogram: {bins: 10, range: 10}
)";

void expect_ok(const granboltz::test::CommandResult& r) { ASSERT_EQ(r.exit_code, 0) << r.output; }

}  // namespace

TEST(Sharding, MergedShardsEqualTheUnshardedRunInEveryDatasetForEveryModel) {
  for (const char* text : {kDsmc, kIntruder, kNeedle}) {
    TempDir dir;
    const std::string cfg = dir.write("c.yaml", text);
    const std::string whole = dir.file("whole.h5");
    expect_ok(run_granboltz("run " + cfg + " -q -o " + whole));
    std::string shards;
    for (int i = 0; i < 3; ++i) {
      const std::string s = dir.file("s" + std::to_string(i) + ".h5");
      expect_ok(run_granboltz("run " + cfg + " -q --set shard.count=3 --set shard.index=" +
                              std::to_string(i) + " -o " + s));
      shards = s + " " + shards;  // any order
    }
    const std::string merged = dir.file("merged.h5");
    expect_ok(run_granboltz("merge " + shards + "-o " + merged));
    granboltz::test::expect_identical_outputs(whole, merged);
    if (text == kDsmc) {  // the speed moments are among the datasets compared
      H5Reader in(merged);
      EXPECT_TRUE(in.exists("/moment_32/mean") && in.exists("/steady/moment_32/ci") &&
                  in.exists("/accumulators/moment_series") && in.exists("/steady/histogram/ci"));
    }
  }
}

TEST(Sharding, MergeRefusesShardsThatDoNotMakeOneRun) {
  TempDir dir;
  const std::string cfg = dir.write("c.yaml", kDsmc);
  const std::string s0 = dir.file("s0.h5"), s1 = dir.file("s1.h5"), other = dir.file("o.h5");
  expect_ok(run_granboltz("run " + cfg + " -q --set shard.count=2 --set shard.index=0 -o " + s0));
  expect_ok(run_granboltz("run " + cfg + " -q --set shard.count=2 --set shard.index=1 -o " + s1));
  expect_ok(run_granboltz("run " + cfg +
                          " -q --set seed=12 --set shard.count=2 "
                          "--set shard.index=1 -o " +
                          other));
  auto r = run_granboltz("merge " + s0 + " " + s0 + " -o " + dir.file("m.h5"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("overlapping shards"), std::string::npos) << r.output;
  r = run_granboltz("merge " + s0 + " -o " + dir.file("m.h5"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("give every shard"), std::string::npos) << r.output;
  r = run_granboltz("merge " + s0 + " " + other + " -o " + dir.file("m.h5"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("different config"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir.file("m.h5")));
}

TEST(Checkpoint, RunKilledAtRandomMomentsResumesToTheUninterruptedOutput) {
  TempDir dir;
  const std::string cfg = dir.write("c.yaml", R"(model: dsmc
seed: 21
ensembles: 600
checkpoint: {every_seconds: 0.2}
dsmc:
  particles: 2048
  alpha: 0.5
  beta: 1
  kernel: {lambda: 0, C: 0.3183098861837907}
  t_end: 8
  observe_every: 1
  histogram: {shells: 8, radius: 8, component: true}
  moments: 8
  steady_from: 4
)");
  const std::string reference = dir.file("reference.h5"), out = dir.file("out.h5");
  const auto t0 = std::chrono::steady_clock::now();
  expect_ok(run_granboltz("run " + cfg + " -q -o " + reference));
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  // Kill twice at random moments after a checkpoint was written (the first run's, then the
  // resumed run's own), then let the third attempt finish.
  std::random_device device;
  std::mt19937 rng(device());
  std::uniform_real_distribution<double> delay(0.0, 0.15 * seconds);
  namespace fs = std::filesystem;
  const std::string ckpt = out + ".checkpoint";
  for (int attempt = 0; attempt < 2; ++attempt) {
    const auto before = fs::exists(ckpt) ? fs::last_write_time(ckpt) : fs::file_time_type::min();
    const pid_t pid = spawn_granboltz({"run", cfg, "-q", "-o", out});
    for (int i = 0; i < 3000; ++i) {  // until a (new) checkpoint appears, at most 30 s
      std::error_code ec;
      const auto t = fs::last_write_time(ckpt, ec);
      if (!ec && t != before) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    const double wait = delay(rng);
    std::this_thread::sleep_for(std::chrono::duration<double>(wait));
    ::kill(pid, SIGKILL);
    int status = 0;
    waitpid(pid, &status, 0);
    ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL)
        << "attempt " << attempt << " finished before it was killed (" << wait << " s after "
        << "a checkpoint); the run is too short for this machine";
    EXPECT_FALSE(fs::exists(out)) << "killed " << wait << " s after a checkpoint";
  }
  EXPECT_TRUE(fs::exists(ckpt)) << "no checkpoint written";
  const auto r = run_granboltz("run " + cfg + " -o " + out);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("resuming from"), std::string::npos) << r.output;
  granboltz::test::expect_identical_outputs(reference, out);
  // Nothing is left behind: no checkpoint, no temporary files of the killed runs.
  EXPECT_EQ(dir.entries(), 3u);  // c.yaml, reference.h5, out.h5
}

TEST(Checkpoint, CheckpointOfAnotherConfigIsRefused) {
  TempDir dir;
  const std::string cfg = dir.write("c.yaml", kDsmc);
  const std::string out = dir.file("out.h5");
  const pid_t pid = spawn_granboltz({"run", cfg, "-q", "--set", "checkpoint.every_seconds=0.05",
                                     "--set", "ensembles=100000", "-o", out});
  for (int i = 0; i < 200 && !std::filesystem::exists(out + ".checkpoint"); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ::kill(pid, SIGKILL);
  waitpid(pid, nullptr, 0);
  ASSERT_TRUE(std::filesystem::exists(out + ".checkpoint"));
  const auto r = run_granboltz("run " + cfg + " -q --set seed=99 -o " + out);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("checkpoint of a different config"), std::string::npos) << r.output;
}

TEST(Checkpoint, EnsemblesKilledMidwayResumeFromTheirSavedState) {
  // Two long ensembles: the checkpoints hold them in progress (particles and streams), not only
  // completed ensembles. Unheated, `majorant: auto` takes the pairwise majorant, whose weights
  // and their refresh countdown are part of the state.
  struct Case {
    const char *scheme, *alpha, *beta, *t_end;
  };
  for (const auto& [scheme, alpha, beta, t_end] :
       {Case{"nosplit", "0.5", "1", "4"}, Case{"strang", "0.5", "1", "4"},
        Case{"nosplit", "1", "0", "40"}}) {
    TempDir dir;
    const std::string cfg = dir.write("c.yaml", std::string(R"(model: dsmc
seed: 31
ensembles: 2
checkpoint: {every_seconds: 0.15}
dsmc:
  particles: 60000
  scheme: )") + scheme + R"(
  steps: 256
  alpha: )" + alpha + R"(
  beta: )" + beta + R"(
  gamma: 4
  kernel: {lambda: 1, C: 0.0795774715459477}
  t_end: )" + t_end + R"(
  observe_every: 0.5
  histogram: {shells: 8, radius: 8}
)");
    const std::string reference = dir.file("reference.h5"), out = dir.file("out.h5");
    expect_ok(run_granboltz("run " + cfg + " -q -o " + reference));
    namespace fs = std::filesystem;
    const std::string ckpt = out + ".checkpoint";
    const pid_t pid = spawn_granboltz({"run", cfg, "-q", "-o", out});
    for (int i = 0; i < 3000 && !fs::exists(ckpt); ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    ::kill(pid, SIGKILL);
    int status = 0;
    waitpid(pid, &status, 0);
    ASSERT_TRUE(WIFSIGNALED(status)) << scheme << ": finished before it was killed";
    {
      H5Reader c(ckpt);
      EXPECT_TRUE(c.exists("/in_progress")) << scheme << ": no ensemble saved in progress";
    }
    const auto r = run_granboltz("run " + cfg + " -o " + out);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    granboltz::test::expect_identical_outputs(reference, out);
  }
}

TEST(Checkpoint, SigtermWritesACheckpointStopsAndTheRerunGivesTheUninterruptedOutput) {
  // What a batch system does before preempting a job: SIGTERM. A run that checkpoints saves its
  // state at the next safe point (ensembles in progress included) and exits with 128 + SIGTERM,
  // leaving no output; the same command then resumes to the uninterrupted output.
  TempDir dir;
  const std::string cfg = dir.write("c.yaml", R"(model: dsmc
seed: 41
ensembles: 3
checkpoint: {every_seconds: 3600}
dsmc:
  particles: 60000
  alpha: 0.5
  beta: 1
  gamma: 4
  kernel: {lambda: 1, C: 0.0795774715459477}
  t_end: 4
  observe_every: 0.5
  histogram: {shells: 8, radius: 8}
)");
  granboltz::test::expect_sigterm_resumes_identically(dir, cfg);
}

TEST(Checkpoint, SigtermToARunWithoutCheckpointsLeavesNothing) {
  TempDir dir;
  const std::string cfg = dir.write("c.yaml", kDsmc);
  const pid_t pid =
      spawn_granboltz({"run", cfg, "-q", "--set", "ensembles=100000", "-o", dir.file("o.h5")});
  for (int i = 0; i < 3000 && dir.entries() < 2; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  ::kill(pid, SIGTERM);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 128 + SIGTERM);
  EXPECT_EQ(dir.entries(), 1u);  // c.yaml only: no output, temporary or checkpoint
}
