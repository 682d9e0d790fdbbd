#include "granboltz/h5/verify.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "granboltz/h5/hdf5_io.hpp"

namespace granboltz {

namespace {

// The checks themselves, in this process.
FileCheck check_here(const std::string& path) {
  FileCheck c;
  try {
    const H5Reader in(path);
    c.problems = in.damaged();
    c.datasets = in.datasets().size();
    // Fletcher32 cannot tell 0x0000 from 0xFFFF words; the digest can, where the file has one
    // (every checkpoint, and outputs of this version).
    if (c.problems.empty() && in.has_attr("/", "digest") &&
        in.attr_uint64("/", "digest") != in.digest())
      c.problems.push_back("/: the datasets do not match its digest (edited or damaged)");
    if (c.problems.empty() && in.has_attr("/", "kind") &&
        in.attr_string("/", "kind") == "checkpoint" && !in.has_attr("/", "digest"))
      c.problems.push_back("/: a checkpoint without its digest attribute");
  } catch (const std::runtime_error& e) {
    const std::string what = e.what(), prefix = path + ": ";
    c.problems = {what.rfind(prefix, 0) == 0 ? what.substr(prefix.size()) : what};
  }
  return c;
}

void write_all(int fd, const std::string& s) {
  std::size_t done = 0;
  while (done < s.size()) {
    const ssize_t n = ::write(fd, s.data() + done, s.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;
    done += static_cast<std::size_t>(n);
  }
}

}  // namespace

FileCheck check_file(const std::string& path) {
  // HDF5 1.10 can crash (an invalid free in its heap code) on some damaged internal structures,
  // which no error handler can catch: a file that is not trusted yet is read in a child process,
  // and its death is reported as damage instead of ending this one.
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) return check_here(path);
  const pid_t pid = ::fork();
  if (pid < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    return check_here(path);
  }
  if (pid == 0) {
    ::close(fds[0]);
    // What the C library prints when the HDF5 library crashes is not for the user: the parent
    // reports the crash in one line.
    const int null = ::open("/dev/null", O_WRONLY | O_CLOEXEC);
    if (null >= 0) ::dup2(null, STDERR_FILENO);
    const FileCheck c = check_here(path);
    std::string text = std::to_string(c.datasets) + "\n";
    for (const auto& p : c.problems) text += p + "\n";
    write_all(fds[1], text);
    ::_exit(0);  // no exit handlers: HDF5's could meet the same damage again
  }
  ::close(fds[1]);
  std::string text;
  char buf[4096];
  for (;;) {
    const ssize_t n = ::read(fds[0], buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    text.append(buf, static_cast<std::size_t>(n));
  }
  ::close(fds[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  FileCheck c;
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    const std::string how = WIFSIGNALED(status) ? "signal " + std::to_string(WTERMSIG(status))
                                                : "exit " + std::to_string(WEXITSTATUS(status));
    c.problems = {"/: the HDF5 library crashed reading the file (" + how +
                  "): a damaged internal structure"};
    return c;
  }
  std::size_t start = 0;
  for (std::size_t line = 0, end; (end = text.find('\n', start)) != std::string::npos;
       start = end + 1, ++line) {
    const std::string s = text.substr(start, end - start);
    if (line == 0)
      c.datasets = static_cast<std::size_t>(std::stoull(s.empty() ? "0" : s));
    else
      c.problems.push_back(s);
  }
  return c;
}

std::vector<std::string> file_problems(const std::string& path) {
  return check_file(path).problems;
}

bool verify_files(const std::vector<std::string>& paths, std::ostream& out, std::ostream& err) {
  bool sound = true;
  for (const auto& path : paths) {
    const FileCheck c = check_file(path);
    if (c.problems.empty()) {
      out << path << ": ok, " << c.datasets << " datasets checked\n";
      continue;
    }
    sound = false;
    // A few lines name what is damaged; a file damaged everywhere does not flood the terminal.
    constexpr std::size_t kShown = 5;
    for (std::size_t k = 0; k < c.problems.size() && k < kShown; ++k)
      err << "granboltz: error: " << path << ": damaged: " << c.problems[k] << "\n";
    if (c.problems.size() > kShown)
      err << "granboltz: error: " << path << ": and " << c.problems.size() - kShown
          << " more damaged datasets\n";
  }
  return sound;
}

}  // namespace granboltz
