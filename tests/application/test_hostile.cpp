// Paths and files as a careless or hostile user gives them: special files as outputs or inputs,
// links planted at the temporary name, an output that is the run's own config, two runs on one
// output, signals during checkpoint writes, edited or damaged checkpoints, damaged inputs of a
// merge. Each must end in a clean refusal (exit 1 or 2, at most three lines, no signal, no hang)
// that changes no file and leaves none behind, or in a correct run.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <random>
#include <set>
#include <thread>

#include "granboltz/h5/hdf5_io.hpp"
#include "test_support.hpp"

using granboltz::H5Reader;
using granboltz::test::CommandResult;
using granboltz::test::flip_byte;
using granboltz::test::read_all;
using granboltz::test::run_granboltz;
using granboltz::test::spawn_granboltz;
using granboltz::test::TempDir;
using granboltz::test::wait_for_file;
namespace fs = std::filesystem;

namespace {

const char* kTiny = R"(model: dsmc
seed: 3
ensembles: 4
dsmc:
  particles: 100
  alpha: 0.5
  beta: 0.125
  gamma: 4
  kernel: {lambda: 1, C: 0.0795774715459477}
  t_end: 1
  observe_every: 0.5
  histogram: {shells: 12, radius: 5}
  steady_from: 0.25
)";

// Runs for seconds and checkpoints often, with ensembles in progress in every checkpoint.
const char* kLong = R"(model: dsmc
seed: 9
ensembles: 6
checkpoint: {every_seconds: 0.05}
dsmc:
  particles: 4000
  alpha: 0.5
  beta: 0.125
  gamma: 4
  kernel: {lambda: 1, C: 0.0795774715459477}
  t_end: 200
  observe_every: 0.5
)";

// The entries of a directory, by name.
std::set<std::string> listing(const TempDir& dir) {
  std::set<std::string> names;
  for (const auto& e : fs::directory_iterator(dir.path)) names.insert(e.path().filename());
  return names;
}

// A clean refusal: exit 1 or 2, one to three lines, each a granboltz error.
void expect_refusal(const CommandResult& r, const std::string& says) {
  EXPECT_TRUE(r.exit_code == 1 || r.exit_code == 2) << r.exit_code << ": " << r.output;
  const auto lines = std::count(r.output.begin(), r.output.end(), '\n');
  EXPECT_TRUE(lines >= 1 && lines <= 3) << r.output;
  EXPECT_EQ(r.output.rfind("granboltz: error: ", 0), 0u) << r.output;
  EXPECT_NE(r.output.find(says), std::string::npos) << r.output;
}

// Runs `args` with a time limit: a hang fails the test instead of blocking the suite.
// The bound only catches a hang: a refusal takes well under a second, but the sanitizer build
// on a loaded machine once took over 20 s for one.
CommandResult run_bounded(const std::string& args, int seconds = 90) {
  return run_granboltz(args, seconds);
}

// A checkpoint of kLong with ensembles in progress: the run is stopped by SIGTERM, which asks
// for a last checkpoint.
std::string make_checkpoint(const TempDir& dir, const std::string& cfg, const std::string& out,
                            int threads = 1) {
  const pid_t pid =
      spawn_granboltz({"run", cfg, "-q", "--threads", std::to_string(threads), "-o", out});
  const std::string ckpt = out + ".checkpoint";
  const bool written = wait_for_file(ckpt, 30);
  // At once: a fast machine on two threads finishes a short run (and removes its checkpoint)
  // within a few hundred milliseconds.
  ::kill(pid, SIGTERM);
  waitpid(pid, nullptr, 0);
  EXPECT_TRUE(written);
  H5Reader in(ckpt);
  bool in_progress = false;
  for (const auto& name : in.datasets())
    in_progress = in_progress || name.find("/in_progress/") == 0;
  EXPECT_TRUE(in_progress) << "no ensemble in progress in the checkpoint";
  (void)dir;
  return ckpt;
}

// The first dataset of a file whose name ends in `suffix`.
std::string find_dataset(const std::string& file, const std::string& suffix) {
  H5Reader in(file);
  for (const auto& name : in.datasets())
    if (name.size() >= suffix.size() &&
        name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0)
      return name;
  return "";
}

// Rewrites the checkpoint's digest attribute to match its edited datasets, as an editor who knew
// the format would: what is left to refuse the checkpoint is the check of every field.
void forge_digest(const std::string& file) {
  const std::uint64_t digest = H5Reader(file).digest();
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  const hid_t a = H5Aopen(f, "digest", H5P_DEFAULT);
  H5Awrite(a, H5T_NATIVE_UINT64, &digest);
  H5Aclose(a);
  H5Fclose(f);
}

// The two shards of a run of `cfg` (with `extra` arguments); true if both runs succeed.
bool make_two_shards(const std::string& cfg, const std::string& a, const std::string& b,
                     const std::string& extra = "") {
  for (int i = 0; i < 2; ++i)
    if (run_granboltz("run " + cfg + " -q" + extra + " --set shard.count=2 --set shard.index=" +
                      std::to_string(i) + " -o " + (i ? b : a))
            .exit_code != 0)
      return false;
  return true;
}

}  // namespace

TEST(HostilePaths, AFifoOrADeviceAsOutputIsRefusedAndLeftAsItWas) {
  TempDir dir;
  const std::string cfg = dir.write("d.yaml", kTiny), fifo = dir.file("p");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
  const auto before = listing(dir);
  expect_refusal(run_bounded("run " + cfg + " -q -o " + fifo), "p: exists and is a FIFO");
  struct stat st {};
  ASSERT_EQ(::lstat(fifo.c_str(), &st), 0);
  EXPECT_TRUE(S_ISFIFO(st.st_mode)) << "the FIFO was replaced";
  EXPECT_EQ(listing(dir), before);
  // A device node (mknod needs root): /dev/null's numbers, made in the test's directory.
  const std::string node = dir.file("n");
  if (::mknod(node.c_str(), S_IFCHR | 0666, makedev(1, 3)) == 0) {
    expect_refusal(run_bounded("run " + cfg + " -q -o " + node), "is a character device");
    ASSERT_EQ(::lstat(node.c_str(), &st), 0);
    EXPECT_TRUE(S_ISCHR(st.st_mode)) << "the device node was replaced";
    expect_refusal(run_bounded("merge " + node + " -o " + dir.file("m.h5")), "character device");
  }
  // A symbolic link as output is not written through, nor replaced.
  const std::string target = dir.write("target", "keep"), link = dir.file("link.h5");
  fs::create_symlink(target, link);
  expect_refusal(run_bounded("run " + cfg + " -q -o " + link), "is a symbolic link");
  EXPECT_EQ(read_all(target), "keep");
  EXPECT_TRUE(fs::is_symlink(link));
}

TEST(HostilePaths, ALinkPlantedAtTheTemporaryNameIsNeitherFollowedNorReplaced) {
  TempDir dir;
  const std::string cfg = dir.write("d.yaml", kTiny), out = dir.file("out.h5");
  const std::string victim = dir.write("victim", "precious");
  // The temporary name of old, "<out>.tmp.<pid>", planted by the process itself before exec.
  const pid_t pid = fork();
  if (pid == 0) {
    const std::string planted = out + ".tmp." + std::to_string(::getpid());
    if (::symlink(victim.c_str(), planted.c_str()) != 0) _exit(126);
    const int null = ::open("/dev/null", O_WRONLY);
    dup2(null, 1);
    dup2(null, 2);
    execl(GRANBOLTZ_BINARY, GRANBOLTZ_BINARY, "run", cfg.c_str(), "-q", "-o", out.c_str(),
          static_cast<char*>(nullptr));
    _exit(127);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0);
  EXPECT_EQ(read_all(victim), "precious") << "the link's target was written";
  struct stat st {};
  ASSERT_EQ(::lstat(out.c_str(), &st), 0);
  EXPECT_TRUE(S_ISREG(st.st_mode)) << "the output is not a regular file";
  EXPECT_GT(H5Reader(out).datasets().size(), 5u);
}

TEST(HostilePaths, AnOutputThatIsTheRunsOwnConfigOrAHardLinkOfItIsRefused) {
  TempDir dir;
  const std::string cfg = dir.write("d.yaml", kTiny);
  expect_refusal(run_bounded("run " + cfg + " -q -o " + cfg), "is the input");
  EXPECT_EQ(read_all(cfg), kTiny);
  const std::string hard = dir.file("hard.h5");
  fs::create_hard_link(cfg, hard);
  expect_refusal(run_bounded("run " + cfg + " -q -o " + hard), "is the input");
  expect_refusal(run_bounded("run " + hard + " -q -o " + dir.path.string() + "/./d.yaml"),
                 "is the input");
  EXPECT_EQ(read_all(cfg), kTiny);
  EXPECT_EQ(listing(dir), (std::set<std::string>{"d.yaml", "hard.h5"}));
}

TEST(HostilePaths, AFifoAsConfigOrMergeInputIsRefusedWithoutBlocking) {
  TempDir dir;
  const std::string cfg = dir.write("d.yaml", kTiny), fifo = dir.file("p");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
  const auto t0 = std::chrono::steady_clock::now();
  expect_refusal(run_bounded("run " + fifo + " -q -o " + dir.file("o.h5"), 10),
                 "p: is not a regular file");
  expect_refusal(run_bounded("validate " + fifo, 10), "not a regular file");
  const std::string shard = dir.file("s0.h5");
  ASSERT_EQ(run_granboltz("run " + cfg + " -q --set shard.count=2 --set shard.index=0 -o " + shard)
                .exit_code,
            0);
  expect_refusal(run_bounded("merge " + shard + " " + fifo + " -o " + dir.file("m.h5"), 10),
                 "p: is a FIFO, not an HDF5 file");
  expect_refusal(run_bounded("verify " + fifo, 10), "is a FIFO");
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 8.0);
  EXPECT_FALSE(fs::exists(dir.file("o.h5")) || fs::exists(dir.file("m.h5")));
}

TEST(HostilePaths, ASecondRunOnTheSameOutputIsRefusedWhileTheFirstRuns) {
  TempDir dir;
  const std::string cfg = dir.write("long.yaml", kLong), out = dir.file("out.h5");
  const pid_t first = spawn_granboltz(
      {"run", cfg, "-q", "--set", "checkpoint.every_seconds=0", "--set", "ensembles=4", "-o", out});
  // The first run's temporary output exists (and is locked) from its start.
  bool started = false;
  for (int i = 0; i < 500 && !started; ++i) {
    for (const auto& e : fs::directory_iterator(dir.path))
      started = started || e.path().filename().string().rfind("out.h5.tmp.", 0) == 0;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ASSERT_TRUE(started);
  expect_refusal(run_bounded("run " + cfg + " -q --set ensembles=4 -o " + out),
                 "is writing this output now");
  int status = 0;
  waitpid(first, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0) << "the first run was disturbed";
  EXPECT_GT(H5Reader(out).datasets().size(), 5u);
  EXPECT_EQ(listing(dir), (std::set<std::string>{"long.yaml", "out.h5"}));
}

TEST(HostilePaths, AStrayTemporaryWhoseNameDoesNotParseIsIgnored) {
  TempDir dir;
  const std::string cfg = dir.write("d.yaml", kTiny), out = dir.file("out.h5");
  const std::string stray = dir.write("out.h5.tmp.99999999999999999999999", "not ours");
  const std::string odd = dir.write("out.h5.tmp.12x", "not ours either");
  const auto r = run_bounded("run " + cfg + " -q -o " + out);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(read_all(stray), "not ours");
  EXPECT_EQ(read_all(odd), "not ours either");
  // A temporary of a process that died (no lock held) is removed by the next run.
  const std::string dead = dir.write("out.h5.tmp.1.abcdef", "left by a killed run");
  EXPECT_EQ(run_bounded("run " + cfg + " -q -o " + out).exit_code, 0);
  EXPECT_FALSE(fs::exists(dead));
}

TEST(HostileSignals, SigintDuringCheckpointWritesLeavesNoTemporaryFile) {
  std::mt19937 pick(17);
  int interrupted = 0;
  for (int trial = 0; trial < 8; ++trial) {
    TempDir dir;
    const std::string cfg = dir.write("long.yaml", kLong), out = dir.file("out.h5");
    // Long enough that no machine finishes it before the signal, on any number of threads.
    const pid_t pid = spawn_granboltz({"run", cfg, "-q", "--set", "checkpoint.every_seconds=0.001",
                                       "--set", "dsmc.t_end=2000", "-o", out});
    std::this_thread::sleep_for(
        std::chrono::milliseconds(std::uniform_int_distribution<int>(200, 700)(pick)));
    ::kill(pid, SIGINT);
    int status = 0;
    waitpid(pid, &status, 0);
    const bool stopped = WIFEXITED(status) && WEXITSTATUS(status) == 128 + SIGINT;
    interrupted += stopped;
    for (const auto& name : listing(dir))
      EXPECT_EQ(name.find(".tmp."), std::string::npos) << "trial " << trial << ": " << name;
    if (stopped) EXPECT_FALSE(fs::exists(out)) << "trial " << trial;
  }
  EXPECT_GE(interrupted, 6);
}

TEST(HostileCheckpoints, EditedCheckpointsAreRefusedWithOneLine) {
  TempDir dir;
  const std::string cfg = dir.write("long.yaml", kLong), out = dir.file("out.h5");
  const std::string ckpt = make_checkpoint(dir, cfg, out);
  const std::string good = dir.file("good.checkpoint");
  fs::copy_file(ckpt, good);
  const std::string ring = find_dataset(good, "/ring_index");
  const std::string scalars = find_dataset(good, "/scalars");
  const std::string counters = find_dataset(good, "/counters");
  ASSERT_FALSE(ring.empty() || scalars.empty() || counters.empty());
  struct Edit {
    const char* what;
    std::function<void(const std::string&)> apply;
    const char* refused_for;  // once the digest is forged to match
  };
  const std::vector<Edit> edits = {
      {"pair index out of range",
       [&](const std::string& f) {
         granboltz::test::edit_dataset<std::uint64_t>(f, ring, 0, 4000000000ull, H5T_NATIVE_UINT64);
       },
       "ring_index[0, 0] = 4000000000, not in [0, n = 4000)"},
      {"time NaN",
       [&](const std::string& f) {
         granboltz::test::edit_dataset<double>(f, scalars, 0, std::nan(""), H5T_NATIVE_DOUBLE);
       },
       "scalars[0] (t) = nan, not in [0, t_end = 200]"},
      {"time beyond t_end",
       [&](const std::string& f) {
         granboltz::test::edit_dataset<double>(f, scalars, 0, 1e300, H5T_NATIVE_DOUBLE);
       },
       "scalars[0] (t) = 1e+300, not in [0, t_end = 200]"},
      {"u_max changed",
       [&](const std::string& f) {
         granboltz::test::edit_dataset<double>(f, scalars, 4, 123.0, H5T_NATIVE_DOUBLE);
       },
       nullptr},
      {"a counter changed",
       [&](const std::string& f) {
         granboltz::test::edit_dataset<std::uint64_t>(f, counters, 1, 5ull, H5T_NATIVE_UINT64);
       },
       nullptr},
  };
  for (const Edit& e : edits) {
    SCOPED_TRACE(e.what);
    fs::copy_file(good, ckpt, fs::copy_options::overwrite_existing);
    e.apply(ckpt);
    const auto edited = read_all(ckpt);
    expect_refusal(run_bounded("run " + cfg + " -q -o " + out), "do not match its digest");
    EXPECT_FALSE(fs::exists(out));
    EXPECT_EQ(read_all(ckpt), edited) << "the checkpoint was changed";
    const auto v = run_bounded("verify " + ckpt);
    EXPECT_EQ(v.exit_code, 1) << v.output;
    EXPECT_NE(v.output.find("digest"), std::string::npos) << v.output;
    if (e.refused_for) {  // an editor who also rewrote the digest: the field checks refuse it
      forge_digest(ckpt);
      expect_refusal(run_bounded("run " + cfg + " -q -o " + out), e.refused_for);
      EXPECT_FALSE(fs::exists(out));
    }
  }
  // A checkpoint of another build is refused too.
  fs::copy_file(good, ckpt, fs::copy_options::overwrite_existing);
  {
    const hid_t f = H5Fopen(ckpt.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    H5Adelete(f, "git_sha");
    H5Fclose(f);
  }
  expect_refusal(run_bounded("run " + cfg + " -q -o " + out), "checkpoint written by granboltz");
  // The sound checkpoint resumes.
  fs::copy_file(good, ckpt, fs::copy_options::overwrite_existing);
  const auto ok =
      run_bounded("run " + cfg + " -o " + out, 600);  // a hang guard (ASan under load: 115 s)
  EXPECT_EQ(ok.exit_code, 0) << ok.output;
  EXPECT_NE(ok.output.find("resuming from"), std::string::npos) << ok.output;
}

TEST(HostileCheckpoints, ADamagedCheckpointOnWorkerThreadsGivesOneLineNotHdf5sStack) {
  TempDir dir;
  const std::string cfg = dir.write("long.yaml", kLong), out = dir.file("out.h5");
  const std::string ckpt = make_checkpoint(dir, cfg, out, 2);
  const std::string particles = find_dataset(ckpt, "/particles");
  ASSERT_FALSE(particles.empty());
  flip_byte(ckpt, granboltz::test::chunk_offset(ckpt, particles) + 40);
  const auto r = run_bounded("run " + cfg + " -q --threads 2 -o " + out);
  expect_refusal(r, "checksum mismatch");
  EXPECT_EQ(r.output.find("HDF5-DIAG"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(out));
}

TEST(HostileMerge, AnInputWithADamagedDerivedDatasetIsNamedAndVerifyFindsIt) {
  TempDir dir;
  const std::string cfg = dir.write("d.yaml", kTiny);
  const std::string a = dir.file("a.h5"), b = dir.file("b.h5"), m = dir.file("m.h5");
  ASSERT_TRUE(make_two_shards(cfg, a, b));
  const auto ok = run_bounded("verify " + a + " " + b);
  EXPECT_EQ(ok.exit_code, 0) << ok.output;
  EXPECT_NE(ok.output.find("a.h5: ok"), std::string::npos) << ok.output;
  // /histogram/mean is presented from the accumulators: a merge never reads it.
  flip_byte(b, granboltz::test::chunk_offset(b, "/histogram/mean") + 3);
  const auto r = run_bounded("merge " + a + " " + b + " -o " + m);
  expect_refusal(r, "b.h5: checksum mismatch in dataset /histogram/mean");
  EXPECT_FALSE(fs::exists(m));
  const auto v = run_bounded("verify " + a + " " + b);
  EXPECT_EQ(v.exit_code, 1) << v.output;
  EXPECT_NE(v.output.find("b.h5: damaged: checksum mismatch in dataset /histogram/mean"),
            std::string::npos)
      << v.output;
  EXPECT_NE(v.output.find("a.h5: ok"), std::string::npos) << v.output;
}

// Found by the mutation fuzzer (tests/fuzz): verify read only datasets, so a damaged header of
// /provenance, which holds attributes and no dataset, passed as ok while read_run refused the file.
TEST(HostileMerge, VerifyReadsTheAttributesOfGroupsWithoutDatasets) {
  TempDir dir;
  const std::string cfg = dir.write("d.yaml", kTiny);
  const std::string a = dir.file("a.h5");
  ASSERT_EQ(run_granboltz("run " + cfg + " -q -o " + a).exit_code, 0);
  const std::string bytes = read_all(a);
  const std::size_t at = bytes.find("started_utc");  // an attribute name of /provenance
  ASSERT_NE(at, std::string::npos);
  flip_byte(a, at + 2);
  const auto v = run_bounded("verify " + a);
  expect_refusal(v, "a.h5: damaged: /provenance: its attributes are unreadable");
}

TEST(HostileMerge, ACheckpointIsNotAMergeInput) {
  TempDir dir;
  const std::string cfg = dir.write("long.yaml", kLong), out = dir.file("out.h5");
  const std::string ckpt = make_checkpoint(dir, cfg, out);
  expect_refusal(run_bounded("merge " + ckpt + " -o " + dir.file("m.h5")),
                 "is the checkpoint of an unfinished run");
  const auto v = run_bounded("verify " + ckpt);
  EXPECT_EQ(v.exit_code, 0) << v.output;
}

TEST(HostileMerge, ZeroWordsTurnedToOnesWhichFletcher32CannotSeeAreCaughtByTheDigest) {
  // Fletcher32 sums 16-bit words modulo 65535, where 0x0000 and 0xFFFF are the same number.
  TempDir dir;
  const std::string cfg = dir.write("d.yaml", kTiny);
  const std::string a = dir.file("a.h5"), b = dir.file("b.h5"), m = dir.file("m.h5");
  ASSERT_TRUE(make_two_shards(cfg, a, b, " --set dsmc.histogram.shells=400"));
  // The outer shells of the histogram's counts are zero: 8 zero bytes each, stored as written
  // (fewer than 4096 elements are not deflated).
  const std::string dataset = "/accumulators/histogram";
  const auto at = granboltz::test::chunk_offset(b, dataset);
  std::string bytes = read_all(b);
  std::size_t run = std::string::npos;
  for (std::size_t k = at; k + 16 <= bytes.size() && k < at + 8 * 1000; k += 8)
    if (bytes.compare(k, 16, std::string(16, '\0')) == 0) {
      run = k;
      break;
    }
  ASSERT_NE(run, std::string::npos) << "no zero counts to turn into ones";
  {
    std::fstream io(b, std::ios::in | std::ios::out | std::ios::binary);
    io.seekp(static_cast<std::streamoff>(run));
    io.write(std::string(16, '\xff').data(), 16);
  }
  EXPECT_NO_THROW(H5Reader(b).read_bytes(dataset)) << "Fletcher32 saw it: the test needs no digest";
  const auto v = run_bounded("verify " + b);
  EXPECT_EQ(v.exit_code, 1) << v.output;
  EXPECT_NE(v.output.find("do not match its digest"), std::string::npos) << v.output;
  expect_refusal(run_bounded("merge " + a + " " + b + " -o " + m), "do not match its digest");
  EXPECT_FALSE(fs::exists(m));
}
