#include "granboltz/app/summary.hpp"

#include <cstdio>
#include <exception>
#include <vector>

#include "granboltz/h5/hdf5_io.hpp"

namespace granboltz {
namespace {

std::string number(double x, int digits) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*g", digits, x);
  return buf;
}

// "name = mean ± ci" of the element k of group's mean and ci, or "" if the output has none.
std::string value(const H5Reader& in, const std::string& group, const std::string& name,
                  bool last = false) {
  if (!in.exists(group + "/mean") || !in.exists(group + "/ci")) return "";
  const std::vector<double> mean = in.read_double(group + "/mean"),
                            ci = in.read_double(group + "/ci");
  if (mean.empty() || mean.size() != ci.size() || (!last && mean.size() != 1)) return "";
  return name + " = " + number(mean.back(), 5) + " ± " + number(ci.back(), 2);
}

}  // namespace

std::string run_summary(const std::string& path, double seconds) {
  std::string line = "wrote " + path + " in " + number(seconds, seconds < 100 ? 3 : 6) + " s";
  try {
    const H5Reader in(path);
    std::vector<std::string> parts;
    auto add = [&](const std::string& s) {
      if (!s.empty()) parts.push_back(s);
    };
    if (in.exists("/steady/temperature/mean")) {
      add(value(in, "/steady/temperature", "steady T"));
      add(value(in, "/steady/a2", "a2"));
      add(value(in, "/steady/theta", "theta"));
    } else if (in.exists("/temperature/mean")) {
      add(value(in, "/temperature", "T(t_end)", true));
    }
    for (const char* tv06 : {"temperature_ratio", "translational_temperature_ratio",
                             "rotational_temperature_ratio", "R"})
      add(value(in, std::string("/") + tv06, tv06));
    for (std::size_t k = 0; k < parts.size(); ++k) line += (k == 0 ? ": " : ", ") + parts[k];
  } catch (const std::exception&) {
    // The run wrote its output; a summary that cannot be read back is left out, not an error.
  }
  return line;
}

}  // namespace granboltz
