// Results that cannot be silently corrupted or lost: checksummed datasets (a flipped byte in a
// shard or a checkpoint is refused, naming the file and the dataset), a merge that cannot
// overwrite its inputs, and a full disk (tmpfs, or `ulimit -f`) that ends a run, a merge or a
// checkpointing run with a one-line message, no temporary file and the last good checkpoint kept.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/mount.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <functional>
#include <thread>

#include "granboltz/dsmc/particles_io.hpp"
#include "granboltz/h5/hdf5_io.hpp"
#include "granboltz/record/state_archive.hpp"
#include "test_support.hpp"

using granboltz::H5Reader;
using granboltz::test::chunk_offset;
using granboltz::test::CommandResult;
using granboltz::test::flip_byte;
using granboltz::test::read_all;
using granboltz::test::run_granboltz;
using granboltz::test::spawn_granboltz;
using granboltz::test::TempDir;
using granboltz::test::wait_for_file;
namespace fs = std::filesystem;

namespace {

const char* kDsmc = R"(model: dsmc
seed: 11
ensembles: 4
dsmc:
  particles: 200
  alpha: 0.5
  beta: 0.125
  gamma: 4
  kernel: {lambda: 1, C: 0.0795774715459477}
  t_end: 2
  observe_every: 0.5
  histogram: {shells: 12, radius: 5}
  steady_from: 0.5
)";

// Long enough (several seconds) to write a few checkpoints; its output (~350 kB) is about twice
// its checkpoints (~190 kB): the presented histograms are in the output only.
const char* kCheckpointing = R"(model: dsmc
seed: 5
ensembles: 400
checkpoint: {every_seconds: 0.1}
dsmc:
  particles: 2000
  alpha: 0.5
  beta: 0.125
  gamma: 4
  kernel: {lambda: 0, C: 0.0795774715459477}
  t_end: 2
  observe_every: 0.25
  histogram: {shells: 3000, radius: 5}
)";

// Runs granboltz under `sh -c "ulimit -f KIB; exec granboltz ARGS"`: writes past KIB KiB fail.
CommandResult run_limited(int kib, const std::string& args) {
  const std::string cmd =
      "ulimit -f " + std::to_string(kib) + "; exec " + GRANBOLTZ_BINARY + " " + args + " 2>&1";
  FILE* pipe = ::popen(cmd.c_str(), "r");
  std::string out;
  char buf[4096];
  while (pipe && std::fgets(buf, sizeof buf, pipe)) out += buf;
  const int status = pipe ? ::pclose(pipe) : -1;
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

// A failure the way a user should see it: exit 1 (not a signal), one line naming the file.
void expect_one_line_io_error(const CommandResult& r, const std::string& names) {
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_EQ(r.output.rfind("granboltz: error: ", 0), 0u) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  EXPECT_NE(r.output.find(names), std::string::npos) << r.output;
}

// No "<name>.tmp.<pid>" left in `dir`.
void expect_no_temporaries(const std::string& dir) {
  for (const auto& e : fs::directory_iterator(dir))
    EXPECT_EQ(e.path().filename().string().find(".tmp."), std::string::npos) << e.path();
}

// A tmpfs of `kib` KiB mounted on a fresh directory for the test's duration (needs root).
struct Tmpfs {
  TempDir dir;
  bool mounted = false;
  explicit Tmpfs(int kib) {
    const std::string opts = "size=" + std::to_string(kib) + "k";
    mounted = ::mount("tmpfs", dir.path.c_str(), "tmpfs", 0, opts.c_str()) == 0;
  }
  ~Tmpfs() {
    if (mounted) ::umount(dir.path.c_str());
  }
  std::string file(const std::string& name) const { return dir.file(name); }
};

}  // namespace

TEST(Checksums, EveryDatasetWithDataIsChecksummedAndScalarsAreCompact) {
  TempDir dir;
  const std::string cfg = dir.write("c.yaml", kDsmc), out = dir.file("out.h5");
  ASSERT_EQ(run_granboltz("run " + cfg + " -q -o " + out).exit_code, 0);
  const hid_t f = H5Fopen(out.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  H5Reader in(out);
  int scalars = 0;
  for (const auto& name : in.datasets()) {
    const hid_t d = H5Dopen2(f, name.c_str(), H5P_DEFAULT);
    const hid_t dcpl = H5Dget_create_plist(d);
    if (in.dims(name).empty()) {
      EXPECT_EQ(H5Pget_layout(dcpl), H5D_COMPACT) << name;
      ++scalars;
    } else {
      bool fletcher = false;
      for (int k = 0; k < H5Pget_nfilters(dcpl); ++k) {
        unsigned flags = 0;
        std::size_t n = 0;
        fletcher |= H5Pget_filter2(dcpl, static_cast<unsigned>(k), &flags, &n, nullptr, 0, nullptr,
                                   nullptr) == H5Z_FILTER_FLETCHER32;
      }
      EXPECT_TRUE(fletcher) << name;
    }
    H5Pclose(dcpl);
    H5Dclose(d);
  }
  H5Fclose(f);
  EXPECT_GT(scalars, 0);
}

TEST(Checksums, MergeRefusesAShardWithAFlippedByteNamingTheFileAndDataset) {
  TempDir dir;
  const std::string cfg = dir.write("c.yaml", kDsmc);
  const std::string a = dir.file("a.h5"), b = dir.file("b.h5"), m = dir.file("m.h5");
  for (int i = 0; i < 2; ++i)
    ASSERT_EQ(run_granboltz("run " + cfg + " -q --set shard.count=2 --set shard.index=" +
                            std::to_string(i) + " -o " + (i ? b : a))
                  .exit_code,
              0);
  ASSERT_EQ(run_granboltz("merge " + a + " " + b + " -o " + m).exit_code, 0);  // intact: fine
  fs::remove(m);
  const haddr_t at = chunk_offset(b, "/events/collisions");
  ASSERT_NE(at, HADDR_UNDEF);
  flip_byte(b, at + 3);
  const auto r = run_granboltz("merge " + a + " " + b + " -o " + m);
  expect_one_line_io_error(r, b + ": checksum mismatch in dataset /events/collisions");
  EXPECT_FALSE(fs::exists(m));
  expect_no_temporaries(dir.path.string());
}

TEST(Checksums, AFlippedByteInACompactScalarIsCaughtByItsHeaderChecksum) {
  TempDir dir;
  const std::string cfg = dir.write("c.yaml", kDsmc), out = dir.file("out.h5");
  ASSERT_EQ(run_granboltz("run " + cfg + " -q -o " + out).exit_code, 0);
  double value = 0;
  {
    H5Reader in(out);
    value = in.read_double("/steady/crit/mean").at(0);
  }
  // The scalar's 8 bytes are inside its object header: find them by value.
  std::string bytes = read_all(out);
  const std::string needle(reinterpret_cast<const char*>(&value), sizeof value);
  const auto at = bytes.find(needle);
  ASSERT_NE(at, std::string::npos);
  ASSERT_EQ(bytes.find(needle, at + 1), std::string::npos) << "value not unique in the file";
  flip_byte(out, at + 2);
  H5Reader in(out);
  try {
    in.read_double("/steady/crit/mean");
    ADD_FAILURE() << "corrupt scalar was read";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(out + ": checksum mismatch in dataset /steady/crit/mean"),
              std::string::npos)
        << e.what();
  }
}

TEST(Checksums, ResumeRefusesACheckpointWithAFlippedByte) {
  TempDir dir;
  const std::string cfg = dir.write("c.yaml", kCheckpointing), out = dir.file("out.h5");
  const std::string ckpt = out + ".checkpoint";
  const pid_t pid = spawn_granboltz({"run", cfg, "-q", "-o", out});
  const bool written = wait_for_file(ckpt, 30);
  ::kill(pid, SIGKILL);
  waitpid(pid, nullptr, 0);
  ASSERT_TRUE(written);
  const haddr_t at = chunk_offset(ckpt, "/accumulators/series");
  ASSERT_NE(at, HADDR_UNDEF);
  flip_byte(ckpt, at + 5);
  const auto r = run_granboltz("run " + cfg + " -q -o " + out);
  expect_one_line_io_error(r, ckpt + ": checksum mismatch in dataset /accumulators/series");
  EXPECT_FALSE(fs::exists(out));
  EXPECT_TRUE(fs::exists(ckpt)) << "the checkpoint is the user's to inspect or delete";
}

TEST(SafeMerge, OutputThatIsAnInputThroughASymlinkOrHardLinkIsRefusedBeforeWriting) {
  TempDir dir;
  const std::string cfg = dir.write("c.yaml", kDsmc);
  const std::string a = dir.file("a.h5"), b = dir.file("b.h5");
  for (int i = 0; i < 2; ++i)
    ASSERT_EQ(run_granboltz("run " + cfg + " -q --set shard.count=2 --set shard.index=" +
                            std::to_string(i) + " -o " + (i ? b : a))
                  .exit_code,
              0);
  const std::string before = read_all(a);
  fs::create_symlink(a, dir.file("link.h5"));
  fs::create_hard_link(a, dir.file("hard.h5"));
  for (const std::string out : {dir.file("link.h5"), dir.file("hard.h5"), a}) {
    const auto r = run_granboltz("merge " + a + " " + b + " -o " + out);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find(out + " is the input " + a), std::string::npos) << r.output;
  }
  EXPECT_EQ(read_all(a), before);
  EXPECT_EQ(dir.entries(), 5u);  // c.yaml, a.h5, b.h5, link.h5, hard.h5: nothing new
}

// ---- A full disk. `ulimit -f` always; a real tmpfs as well (CI runs as root).

TEST(FullDisk, RunAndMergeOverASizeLimitFailCleanly) {
  TempDir dir;
  const std::string cfg = dir.write("c.yaml", kDsmc), out = dir.file("out.h5");
  const std::string big = " --set dsmc.histogram.shells=20000";
  auto r = run_limited(64, "run " + cfg + " -q" + big + " -o " + out);
  expect_one_line_io_error(r, out + ": cannot write the file (File too large)");
  EXPECT_FALSE(fs::exists(out));
  expect_no_temporaries(dir.path.string());

  const std::string a = dir.file("a.h5"), b = dir.file("b.h5"), m = dir.file("m.h5");
  for (int i = 0; i < 2; ++i)
    ASSERT_EQ(run_granboltz("run " + cfg + " -q" + big + " --set shard.count=2 --set shard.index=" +
                            std::to_string(i) + " -o " + (i ? b : a))
                  .exit_code,
              0);
  const auto size = fs::file_size(a);
  r = run_limited(static_cast<int>(size / 1024 / 2), "merge " + a + " " + b + " -o " + m);
  expect_one_line_io_error(r, m + ": cannot write the file (File too large)");
  EXPECT_FALSE(fs::exists(m));
  expect_no_temporaries(dir.path.string());
}

TEST(FullDisk, RunAndMergeOnAFullTmpfsFailCleanly) {
  Tmpfs disk(96);
  ASSERT_TRUE(disk.mounted || geteuid() != 0) << "root could not mount a tmpfs";
  if (!disk.mounted) GTEST_SKIP() << "not root: the ulimit -f tests cover this";
  TempDir dir;
  const std::string cfg = dir.write("c.yaml", kDsmc), out = disk.file("out.h5");
  const std::string big = " --set dsmc.histogram.shells=20000";
  auto r = run_granboltz("run " + cfg + " -q" + big + " -o " + out);
  expect_one_line_io_error(r, out + ": cannot write the file (No space left on device)");
  EXPECT_EQ(disk.dir.entries(), 0u);

  const std::string a = dir.file("a.h5"), b = dir.file("b.h5"), m = disk.file("m.h5");
  for (int i = 0; i < 2; ++i)
    ASSERT_EQ(run_granboltz("run " + cfg + " -q" + big + " --set shard.count=2 --set shard.index=" +
                            std::to_string(i) + " -o " + (i ? b : a))
                  .exit_code,
              0);
  r = run_granboltz("merge " + a + " " + b + " -o " + m);
  expect_one_line_io_error(r, m + ": cannot write the file (No space left on device)");
  EXPECT_EQ(disk.dir.entries(), 0u);
}

TEST(FullDisk, CheckpointingRunOverASizeLimitKeepsTheLastGoodCheckpointUntouched) {
  // A checkpoint from a killed run, then a resumed run under a limit that no file fits: its
  // next checkpoint (or its output) cannot be written.
  TempDir dir;
  const std::string cfg = dir.write("c.yaml", kCheckpointing), out = dir.file("out.h5");
  const std::string ckpt = out + ".checkpoint";
  const pid_t pid = spawn_granboltz({"run", cfg, "-q", "-o", out});
  const bool written = wait_for_file(ckpt, 30);
  ::kill(pid, SIGKILL);
  waitpid(pid, nullptr, 0);
  ASSERT_TRUE(written);
  for (const auto& e : fs::directory_iterator(dir.path))  // the killed run's temporaries
    if (e.path().string().find(".tmp.") != std::string::npos) fs::remove(e.path());
  const std::string good = read_all(ckpt);
  const auto r = run_limited(8, "run " + cfg + " -q -o " + out);
  expect_one_line_io_error(r, ": cannot write the file (File too large)");
  EXPECT_FALSE(fs::exists(out));
  ASSERT_TRUE(fs::exists(ckpt)) << "the last good checkpoint was not kept";
  EXPECT_EQ(read_all(ckpt), good) << "the last good checkpoint was changed";
  expect_no_temporaries(dir.path.string());
  // With room again, the run resumes from it and finishes.
  const auto again = run_granboltz("run " + cfg + " -o " + out);
  EXPECT_EQ(again.exit_code, 0) << again.output;
  EXPECT_NE(again.output.find("resuming from"), std::string::npos) << again.output;
}

TEST(FullDisk, CheckpointThatNoLongerFitsOnATmpfsEndsTheRunAndKeepsThePreviousOne) {
  Tmpfs disk(1024);
  ASSERT_TRUE(disk.mounted || geteuid() != 0) << "root could not mount a tmpfs";
  if (!disk.mounted) GTEST_SKIP() << "not root: the ulimit -f test covers this";
  TempDir dir;
  const std::string cfg = dir.write("c.yaml", kCheckpointing), out = disk.file("out.h5");
  const std::string ckpt = out + ".checkpoint";
  const pid_t pid = spawn_granboltz({"run", cfg, "-q", "-o", out});
  ASSERT_TRUE(wait_for_file(ckpt, 30));
  {  // fill the disk: the next checkpoint cannot be written
    std::ofstream filler(disk.file("filler"), std::ios::binary);
    const std::string block(4096, 'x');
    while (filler.write(block.data(), block.size())) {
    }
  }
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status)) << "killed by signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 1);
  EXPECT_FALSE(fs::exists(out));
  ASSERT_TRUE(fs::exists(ckpt));
  H5Reader kept(ckpt);  // a complete checkpoint, readable
  EXPECT_TRUE(kept.exists("/accumulators/series"));
  expect_no_temporaries(disk.dir.path.string());
}

// An edited state (a checkpoint or a granboltz.Simulation.save whose digest was rewritten too,
// or one read before its digest is compared) is refused where the engine reads it, naming the
// dataset: a stream in xoshiro256++'s all-zero fixed point (it would draw zeros forever: the
// restored run hangs), a dataset stored as another type than written (HDF5 would convert it
// silently), particles of another shape with as many numbers.
TEST(EditedState, ReadersRefuseZeroStreamsOtherDtypesAndShapesNamingTheDataset) {
  TempDir dir;
  const std::string path = dir.file("state.h5");
  {
    granboltz::H5Writer out(path);
    out.write("/zero_stream", std::vector<std::uint64_t>{0, 0, 0, 0, 17}, {5});
    out.write("/stream", std::vector<std::uint64_t>{0, 0, 0, 1, 17}, {5});
    out.write("/flat", std::vector<double>(8, 0.5), {8});
    out.write("/integers", std::vector<std::int64_t>(8, 1), {2, 4});
    out.write("/rows", std::vector<double>(8, 0.5), {2, 4});
    out.commit();
  }
  const H5Reader in(path);
  auto message = [&](const std::function<void()>& read) {
    try {
      read();
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  granboltz::StateArchive state(in, "");
  granboltz::Engine e;
  state.stream("stream", e);
  EXPECT_EQ(e.draws(), 17u);  // any other state is fine
  EXPECT_NE(
      message([&] { state.stream("zero_stream", e); })
          .find(path + ": malformed ensemble state : dataset /zero_stream: a random stream in "
                       "the all-zero state"),
      std::string::npos);
  EXPECT_EQ(message([&] { state.stream("flat", e); }),
            path + ": malformed ensemble state : dataset /flat: has shape (8,), not (5,)");
  granboltz::Particles p;
  const auto any = granboltz::counts_between(0, 1000);
  granboltz::visit_particles(state, "rows", p, nullptr, 3, any);
  EXPECT_EQ(p.size(), 2u);
  EXPECT_EQ(message([&] { granboltz::visit_particles(state, "flat", p, nullptr, 3, any); }),
            path + ": malformed ensemble state : dataset /flat: has shape (8,), not (n, 4)");
  EXPECT_EQ(message([&] { granboltz::visit_particles(state, "integers", p, nullptr, 3, any); }),
            path + ": dataset /integers: has dtype int64, not float64");
  EXPECT_EQ(message([&] { in.read_uint64("/rows"); }),
            path + ": dataset /rows: has dtype float64, not uint64");
}
