#include "granboltz/app/merge.hpp"

#include <chrono>
#include <cstdio>
#include <filesystem>

#include "granboltz/app/output.hpp"
#include "granboltz/h5/verify.hpp"

namespace granboltz {

namespace {

// Refuses, before anything is read or written, an output that is one of the inputs (by any path:
// a symlink, a hard link, ./x) or that lies in a directory that does not exist.
void check_merge_output(const std::vector<std::string>& inputs, const std::string& output) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path out(output);
  const fs::path dir = out.has_parent_path() ? out.parent_path() : fs::path(".");
  if (!fs::is_directory(dir, ec))
    throw ConfigError("merge: -o " + output + ": directory " + dir.string() +
                      " does not exist; create it first");
  if (!fs::exists(out, ec)) return;
  for (const auto& in : inputs)
    if (fs::equivalent(out, in, ec))
      throw ConfigError("merge: -o " + output + " is the input " + in +
                        "; the merged output must be a new file");
}

}  // namespace

void merge_outputs(const std::vector<std::string>& inputs, const std::string& output) {
  if (inputs.empty()) throw ConfigError("merge: no input files");
  check_merge_output(inputs, output);
  check_output_path(output, inputs);
  // Every dataset of every input, not only the accumulators the merge reads: a damaged input is
  // named even where its damage would not reach the merged output.
  for (const auto& path : inputs) {
    check_input_file(path, "an HDF5 file");
    const std::vector<std::string> problems = file_problems(path);
    if (!problems.empty())
      throw std::runtime_error(
          path + ": " + problems.front() +
          (problems.size() > 1
               ? " (and " + std::to_string(problems.size() - 1) + " more damaged datasets)"
               : std::string()));
  }
  std::string config_text, version;
  Config config;
  Record record;
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    H5Reader in(inputs[i]);
    if (in.has_attr("/", "kind") && in.attr_string("/", "kind") == "checkpoint")
      throw ConfigError(inputs[i] +
                        ": is the checkpoint of an unfinished run, not an output; "
                        "finish the run (granboltz run resumes from it) and merge its output");
    const Config c = config_of_file(in);
    const std::string text = in.attr_string("/", "config");
    const std::string v = in.attr_string("/", "version") + " " + in.attr_string("/", "git_sha");
    if (i == 0) {
      config_text = text;
      version = v;
      config = c;
      record = layout_of(config);
    } else if (text != config_text) {
      throw ConfigError(inputs[i] + ": different config from " + inputs[0] +
                        " (merge takes the shards of one run)");
    } else if (v != version) {
      throw ConfigError(inputs[i] + ": made by granboltz " + v + ", " + inputs[0] + " by " +
                        version + " (merge takes outputs of one version)");
    }
    Record part = layout_of(config);
    try {
      part.read(in);
      record.merge(part);
    } catch (const std::runtime_error& e) {
      // A damaged file (checksum, truncation) is an I/O error naming itself; anything else
      // (overlapping shards) is a wrong input.
      if (std::string(e.what()).rfind(inputs[i] + ": ", 0) == 0) throw;
      throw ConfigError(inputs[i] + ": " + e.what());
    }
  }
  // Shards must partition the ensembles of the run: anything else is not that run's result.
  const std::uint64_t N = config.ensembles;
  const auto have = record.ensembles();
  if (have != N || record.ensemble_indices().back() != N - 1)
    throw ConfigError("merge: the inputs hold " + std::to_string(have) + " of the run's " +
                      std::to_string(N) + " ensembles; give every shard");
  H5Writer out(output);
  std::string from;
  for (const auto& p : inputs) {
    if (!from.empty()) from += ' ';
    from += p;
  }
  write_output(out, config, record, {{"command", "granboltz merge"}, {"merged_from", from}});
  out.commit();
}

}  // namespace granboltz
