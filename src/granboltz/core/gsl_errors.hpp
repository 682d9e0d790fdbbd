#pragma once
// GSL's default error handler calls abort(), which would end the process with a temporary output
// left behind. Ours only records the error (per thread) and lets GSL return its status code; the
// caller checks the status and throws a project error. The handler never throws: an exception
// must not cross GSL's C frames.
#include <string>

namespace granboltz {

/// What GSL reported last on this thread (gsl_errno 0: nothing since the last clear).
struct GslError {
  int gsl_errno = 0;
  int line = 0;
  char reason[160] = {};
  char file[96] = {};
};

/// Replaces GSL's aborting handler with the recording one, for the whole process. Idempotent and
/// thread-safe; called from main() and from the library's entry points that use GSL.
void install_gsl_error_handler();
/// Whether the recording handler is the one installed.
bool gsl_error_handler_installed();

/// The last error GSL reported on this thread.
const GslError& last_gsl_error();
void clear_gsl_error();

/// One line: "GSL: <reason> (<gsl_strerror(status)>)", the recorded reason when it is this
/// thread's last error, else the status's text alone.
std::string describe_gsl_status(int status);

}  // namespace granboltz
