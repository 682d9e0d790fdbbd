#include "granboltz/io/verify.hpp"

#include <stdexcept>

#include "granboltz/io/hdf5_io.hpp"

namespace granboltz {

std::vector<std::string> file_problems(const std::string& path) {
  try {
    const H5Reader in(path);
    std::vector<std::string> problems = in.damaged();
    if (problems.empty() && in.has_attr("/", "kind") && in.attr_string("/", "kind") == "checkpoint") {
      if (!in.has_attr("/", "digest"))
        problems.push_back("/: a checkpoint without its digest attribute");
      else if (in.attr_uint64("/", "digest") != in.digest())
        problems.push_back("/: the datasets do not match the checkpoint's digest (edited?)");
    }
    return problems;
  } catch (const std::runtime_error& e) {
    const std::string what = e.what(), prefix = path + ": ";
    return {what.rfind(prefix, 0) == 0 ? what.substr(prefix.size()) : what};
  }
}

bool verify_files(const std::vector<std::string>& paths, std::ostream& out, std::ostream& err) {
  bool sound = true;
  for (const auto& path : paths) {
    const std::vector<std::string> problems = file_problems(path);
    if (problems.empty()) {
      const H5Reader in(path);
      out << path << ": ok, " << in.datasets().size() << " datasets checked\n";
      continue;
    }
    sound = false;
    // A few lines name what is damaged; a file damaged everywhere does not flood the terminal.
    constexpr std::size_t kShown = 5;
    for (std::size_t k = 0; k < problems.size() && k < kShown; ++k)
      err << "granboltz: error: " << path << ": damaged: " << problems[k] << "\n";
    if (problems.size() > kShown)
      err << "granboltz: error: " << path << ": and " << problems.size() - kShown
          << " more damaged datasets\n";
  }
  return sound;
}

}  // namespace granboltz
