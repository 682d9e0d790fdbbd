// The corpus of bad configs and command lines (tests/bad_inputs/cases.tsv): every case must fail
// with a one-line error naming what is wrong, the documented exit code, no crash, and nothing
// left behind in its directory. The manifest is read when the tests are registered, so a new
// line is a new test (the build re-links this binary when the manifest changes).
#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "granboltz/h5/hdf5_io.hpp"
#include "test_support.hpp"

extern char** environ;

namespace {

namespace fs = std::filesystem;
using granboltz::test::TempDir;

const std::string kCasesDir = std::string(GRANBOLTZ_SOURCE_DIR) + "/tests/bad_inputs";

struct Case {
  std::string name, command, args, message, setup;
  int exit_code = 0;
  int line = 0;
  std::string error;  ///< set when the manifest itself is broken: the test reports it
};

void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

std::vector<std::string> split(const std::string& s, const std::string& sep) {
  std::vector<std::string> out;
  std::size_t start = 0;
  for (std::size_t pos; (pos = s.find(sep, start)) != std::string::npos; start = pos + sep.size())
    out.push_back(s.substr(start, pos - start));
  out.push_back(s.substr(start));
  return out;
}

std::vector<Case> load_manifest() {
  const std::string path = kCasesDir + "/cases.tsv";
  std::ifstream in(path);
  if (!in) return {Case{"manifest", "", "", "", "", 0, 0, path + ": cannot open"}};
  std::vector<Case> cases;
  std::set<std::string> names;
  std::string text;
  for (int line = 1; std::getline(in, text); ++line) {
    if (text.empty() || text[0] == '#') continue;
    const auto f = split(text, "\t");
    Case c;
    c.line = line;
    if (f.size() != 6) {
      c.name = "manifest_line_" + std::to_string(line);
      c.error = path + ":" + std::to_string(line) + ": expected 6 TAB-separated columns, got " +
                std::to_string(f.size());
      cases.push_back(c);
      continue;
    }
    c.name = f[0];
    c.command = f[1] == "-" ? "" : f[1];
    c.args = f[2] == "-" ? "" : f[2];
    c.message = f[4];
    c.setup = f[5] == "-" ? "" : f[5];
    try {
      c.exit_code = std::stoi(f[3]);
    } catch (const std::exception&) {
      c.error = path + ":" + std::to_string(line) + ": exit code " + f[3] + " is not a number";
    }
    const bool plain =
        !c.name.empty() &&
        c.name.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789_") == std::string::npos;
    if (!plain || !names.insert(c.name).second) {
      c.error = path + ":" + std::to_string(line) + ": name " + c.name +
                " is not [a-z0-9_]+ or not unique";
      c.name = "manifest_line_" + std::to_string(line);
    }
    cases.push_back(c);
  }
  return cases;
}

const std::vector<Case>& manifest() {
  static const std::vector<Case> cases = load_manifest();
  return cases;
}

/// Splits a command line like a shell: blanks separate words, quotes group ('' is an empty word).
std::vector<std::string> words(const std::string& s) {
  std::vector<std::string> out;
  std::string cur;
  bool in_word = false;
  char quote = 0;
  for (char ch : s) {
    if (quote) {
      if (ch == quote)
        quote = 0;
      else
        cur += ch;
    } else if (ch == '\'' || ch == '"') {
      quote = ch;
      in_word = true;
    } else if (ch == ' ') {
      if (in_word) out.push_back(cur);
      cur.clear();
      in_word = false;
    } else {
      cur += ch;
      in_word = true;
    }
  }
  if (in_word) out.push_back(cur);
  return out;
}

std::string replace_all(std::string s, const std::string& from, const std::string& to) {
  for (std::size_t pos = 0; (pos = s.find(from, pos)) != std::string::npos; pos += to.size())
    s.replace(pos, from.size(), to);
  return s;
}

struct Outcome {
  bool exited = false;  ///< terminated by exit() rather than by a signal
  int code = -1;        ///< exit code, or the signal number
  bool timed_out = false;
  std::string output;  ///< stdout and stderr, interleaved as written
};

/// Runs GRANBOLTZ_BINARY with `args` directly (no shell), stdout and stderr into one pipe.
Outcome run_binary(const std::vector<std::string>& args, double timeout_seconds = 120) {
  std::vector<std::string> argv_s{GRANBOLTZ_BINARY};
  argv_s.insert(argv_s.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : argv_s) argv.push_back(a.data());
  argv.push_back(nullptr);

  Outcome o;
  int fds[2];
  if (::pipe(fds) != 0) {
    o.output = "pipe() failed";
    return o;
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addclose(&actions, fds[0]);
  posix_spawn_file_actions_adddup2(&actions, fds[1], 1);
  posix_spawn_file_actions_adddup2(&actions, fds[1], 2);
  posix_spawn_file_actions_addclose(&actions, fds[1]);
  pid_t pid = -1;
  const int rc = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(fds[1]);
  if (rc != 0) {
    ::close(fds[0]);
    o.output = "posix_spawn failed";
    return o;
  }
  const auto deadline =
      std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_seconds);
  char buf[4096];
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
                          deadline - std::chrono::steady_clock::now())
                          .count();
    if (left <= 0) {
      o.timed_out = true;
      ::kill(pid, SIGKILL);
      break;
    }
    pollfd p{fds[0], POLLIN, 0};
    if (::poll(&p, 1, static_cast<int>(left)) <= 0) continue;
    const ssize_t n = ::read(fds[0], buf, sizeof buf);
    if (n <= 0) break;
    o.output.append(buf, static_cast<std::size_t>(n));
  }
  ::close(fds[0]);
  int status = 0;
  ::waitpid(pid, &status, 0);
  o.exited = WIFEXITED(status);
  o.code = o.exited ? WEXITSTATUS(status) : WIFSIGNALED(status) ? WTERMSIG(status) : -1;
  return o;
}

/// Every path below `root`, relative to it, with its size (directories: -1).
std::set<std::pair<std::string, std::intmax_t>> snapshot(const fs::path& root) {
  std::set<std::pair<std::string, std::intmax_t>> s;
  for (const auto& e : fs::recursive_directory_iterator(root)) {
    const bool dir = e.is_directory();
    s.insert({fs::relative(e.path(), root).string(),
              dir ? -1 : static_cast<std::intmax_t>(e.file_size())});
  }
  return s;
}

std::string describe(const Outcome& o) {
  std::string s = o.timed_out ? "timed out and was killed"
                  : o.exited  ? "exit code " + std::to_string(o.code)
                              : "killed by signal " + std::to_string(o.code);
  return s + "; output:\n" + o.output;
}

class BadInputCorpus : public ::testing::TestWithParam<Case> {};

TEST_P(BadInputCorpus, FailCleanlyWithOneLineNamingTheProblem) {
  const Case& c = GetParam();
  ASSERT_TRUE(c.error.empty()) << c.error;
  TempDir dir;
  const std::string d = dir.path.string();

  // A read-only directory. Root may write anywhere, so then /sys stands in (no one can create a
  // file in sysfs).
  std::string rodir = d + "/readonly";
  if ((c.args + c.setup).find("{rodir}") != std::string::npos) {
    fs::create_directory(rodir);
    ::chmod(rodir.c_str(), 0555);
    const std::string probe = rodir + "/probe";
    const int fd = ::open(probe.c_str(), O_CREAT | O_WRONLY, 0644);
    if (fd >= 0) {
      ::close(fd);
      ::unlink(probe.c_str());
      if (!fs::is_directory("/sys")) GTEST_SKIP() << "no read-only directory (root, no /sys)";
      rodir = "/sys";
    }
  }
  auto expand = [&](std::string s) {
    s = replace_all(s, "{case}", kCasesDir + "/" + c.name + ".yaml");
    s = replace_all(s, "{base}", kCasesDir + "/base");
    s = replace_all(s, "{rodir}", rodir);
    return replace_all(s, "{dir}", d);
  };

  if (!c.setup.empty()) {
    for (const std::string& step : split(c.setup, " ; ")) {
      const auto w = words(expand(step));
      ASSERT_FALSE(w.empty()) << "empty setup step in " << c.name;
      if (w[0] == "granboltz") {
        const Outcome o = run_binary({w.begin() + 1, w.end()});
        ASSERT_TRUE(o.exited && o.code == 0) << "setup " << step << ": " << describe(o);
      } else if (w[0] == "truncate" && w.size() == 3) {
        fs::resize_file(w[1], std::stoull(w[2]));
      } else if (w[0] == "hdf5" && w.size() == 2) {
        granboltz::H5Writer out(w[1]);
        out.write("/values", std::vector<double>{1.0, 2.0, 3.0}, {3});
        out.attr("/", "note", std::string("an HDF5 file written by someone else"));
        out.commit();
      } else {
        FAIL() << "unknown setup step in " << c.name << ": " << step;
      }
    }
  }

  std::vector<std::string> args;
  if (!c.command.empty()) args.push_back(c.command);
  for (auto& w : words(expand(c.args))) args.push_back(w);
  const auto before = snapshot(dir.path);
  // The cases of runs that used to hang get 30 s, so that the old behaviour fails quickly.
  const Outcome o = run_binary(args, c.name.rfind("hang_", 0) == 0 ? 30.0 : 120.0);

  ASSERT_FALSE(o.timed_out) << describe(o);
  ASSERT_TRUE(o.exited) << describe(o);
  EXPECT_TRUE(!o.output.empty() && o.output.find('\n') == o.output.size() - 1)
      << "the error must be exactly one line: " << describe(o);
  for (const char* crash : {"Sanitizer", "runtime error", "terminate called", "HDF5-DIAG"})
    EXPECT_EQ(o.output.find(crash), std::string::npos) << describe(o);
  EXPECT_EQ(snapshot(dir.path), before) << "files were left behind or removed";

  EXPECT_EQ(o.code, c.exit_code) << describe(o);
  EXPECT_EQ(o.output.rfind("granboltz: error: ", 0), 0u) << describe(o);
  EXPECT_NE(o.output.find(expand(c.message)), std::string::npos)
      << "expected \"" << expand(c.message) << "\"; " << describe(o);
}

INSTANTIATE_TEST_SUITE_P(Manifest, BadInputCorpus, ::testing::ValuesIn(manifest()),
                         [](const auto& info) { return info.param.name; });

TEST(BadInputsManifest, HasEnoughCasesAndEveryConfigFileIsACase) {
  const auto& cases = manifest();
  EXPECT_GE(cases.size(), 40u);
  std::set<std::string> used;
  for (const auto& c : cases) {
    EXPECT_TRUE(c.error.empty()) << c.error;
    if ((c.args + c.setup).find("{case}") != std::string::npos) {
      used.insert(c.name + ".yaml");
      EXPECT_TRUE(fs::exists(kCasesDir + "/" + c.name + ".yaml")) << c.name << ": no case file";
    }
  }
  for (const auto& e : fs::directory_iterator(kCasesDir))
    if (e.path().extension() == ".yaml")
      EXPECT_EQ(used.count(e.path().filename().string()), 1u)
          << e.path() << " is not used by any case of cases.tsv";
}

TEST(BadInputsManifest, BaseConfigsAreValidSoThatEveryCaseFailsForItsOwnReason) {
  for (const char* model : {"dsmc", "dsmc_observe", "intruder", "needle"}) {
    const Outcome o = run_binary({"validate", kCasesDir + "/base/" + model + ".yaml"});
    EXPECT_TRUE(o.exited && o.code == 0) << model << ": " << describe(o);
  }
}

}  // namespace
