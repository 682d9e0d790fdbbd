// AFL++ harness for the config entry point (make fuzz): a config text from a file or stdin goes
// through parse_config with --set overrides; ConfigError is the only acceptable failure. A valid
// config must also survive its own round trip (validate prints to_yaml, which must parse back to
// the same text). Lines of the input that start with "#set " are YAML comments, so the seeds
// stay valid configs, and each becomes one override: AFL mutates the overrides too.
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "granboltz/app/config.hpp"

namespace {

std::vector<std::string> overrides_of(const std::string& text) {
  std::vector<std::string> sets{"threads=1"};
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    if (line.rfind("#set ", 0) == 0) sets.push_back(line.substr(5));
  return sets;
}

void check_one(const std::string& text) {
  try {
    const granboltz::Config c = granboltz::parse_config(text, "fuzz.yaml", overrides_of(text));
    const std::string printed = c.to_yaml(false);
    std::string again;
    try {
      again = granboltz::parse_config(printed, "printed.yaml").to_yaml(false);
    } catch (const granboltz::ConfigError& e) {
      std::fprintf(stderr, "round trip: the printed config is refused: %s\n%s", e.what(),
                   printed.c_str());
      std::abort();
    }
    if (again != printed) {
      std::fprintf(stderr, "round trip: printed twice differs:\n%s---\n%s", printed.c_str(),
                   again.c_str());
      std::abort();
    }
  } catch (const granboltz::ConfigError&) {
    // the documented refusal
  }
  // Any other exception escapes: std::terminate aborts and AFL records a crash.
}

}  // namespace

#ifdef __AFL_FUZZ_TESTCASE_LEN  // afl-clang-fast: persistent mode, shared-memory input
__AFL_FUZZ_INIT();
#endif

int main(int argc, char** argv) {
  if (argc > 1) {  // replay: every file named on the command line
    for (int i = 1; i < argc; ++i) {
      std::ifstream in(argv[i], std::ios::binary);
      if (!in) {
        std::fprintf(stderr, "%s: cannot open\n", argv[i]);
        return 2;
      }
      check_one(std::string(std::istreambuf_iterator<char>(in), {}));
    }
    return 0;
  }
#ifdef __AFL_FUZZ_TESTCASE_LEN
  __AFL_INIT();
  const unsigned char* buf = __AFL_FUZZ_TESTCASE_BUF;
  while (__AFL_LOOP(10000)) {
    const auto len = static_cast<std::size_t>(__AFL_FUZZ_TESTCASE_LEN);
    check_one(std::string(reinterpret_cast<const char*>(buf), len));
  }
#else  // any other compiler: one input from stdin per process
  check_one(std::string(std::istreambuf_iterator<char>(std::cin), {}));
#endif
  return 0;
}
