// The recording GSL error handler (gsl_errors.hpp).
#include "granboltz/core/gsl_errors.hpp"

#include <gsl/gsl_errno.h>

#include <atomic>
#include <cstdio>
#include <mutex>

namespace granboltz {

namespace {

thread_local GslError t_last;
std::atomic<bool> g_installed{false};

// Fixed buffers and snprintf only: nothing here may throw or allocate.
extern "C" void record_gsl_error(const char* reason, const char* file, int line,
                                 int gsl_errno) noexcept {
  t_last.gsl_errno = gsl_errno;
  t_last.line = line;
  std::snprintf(t_last.reason, sizeof t_last.reason, "%s", reason ? reason : "");
  std::snprintf(t_last.file, sizeof t_last.file, "%s", file ? file : "");
}

// Also at load time, for any program that links this object (a static library keeps it only
// when something refers to it, hence the explicit calls as well).
[[maybe_unused]] const bool g_installed_at_load = (install_gsl_error_handler(), true);

}  // namespace

void install_gsl_error_handler() {
  static std::once_flag once;
  std::call_once(once, [] {
    gsl_set_error_handler(&record_gsl_error);
    g_installed.store(true);
  });
}

bool gsl_error_handler_installed() { return g_installed.load(); }

const GslError& last_gsl_error() { return t_last; }

void clear_gsl_error() { t_last = GslError{}; }

std::string describe_gsl_status(int status) {
  std::string s = "GSL: ";
  if (t_last.gsl_errno == status && t_last.reason[0]) {
    s += t_last.reason;
    s += " (";
    s += gsl_strerror(status);
    s += ")";
  } else {
    s += gsl_strerror(status);
  }
  for (auto& ch : s)
    if (ch == '\n' || ch == '\r') ch = ' ';
  return s;
}

}  // namespace granboltz
