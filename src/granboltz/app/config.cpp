// Top level of a run config: model, seed, ensembles, execution keys; dispatch to the sections.
#include "granboltz/app/config.hpp"

#include <sys/stat.h>
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace granboltz {

std::string model_name(Model m) {
  switch (m) {
    case Model::kDsmc:
      return "dsmc";
    case Model::kIntruder:
      return "intruder";
    case Model::kNeedle:
      return "needle";
  }
  return "?";
}

Config parse_config(const std::string& yaml_text, const std::string& origin,
                    const std::vector<std::string>& overrides) {
  const YAML::Node root = load_yaml_with_overrides(yaml_text, origin, overrides);
  const Section s(root, "");
  Config c;
  const std::string model = s.choice("model", {"dsmc", "intruder", "needle"});
  c.model = model == "intruder" ? Model::kIntruder
            : model == "needle" ? Model::kNeedle
                                : Model::kDsmc;
  c.seed = s.integer("seed");
  c.ensembles = s.integer("ensembles", 1, {1, kMaxInteger, "must be >= 1"});
  c.threads = static_cast<unsigned>(s.integer("threads", 0, kThreadsRange));

  if (s.has("shard")) {
    const Section sh = s.sub("shard");
    c.shard.count = sh.integer("count", {1, c.ensembles, "must satisfy 1 <= count <= ensembles"});
    c.shard.index =
        sh.integer("index", {0, c.shard.count - 1, "must satisfy 0 <= index < shard.count"});
    sh.finish({"index", "count"});
  }
  if (s.has("checkpoint")) {
    const Section cp = s.sub("checkpoint");
    c.checkpoint.every_seconds = cp.real("every_seconds");
    cp.check(c.checkpoint.every_seconds >= 0, "every_seconds", c.checkpoint.every_seconds,
             "must be >= 0 (0: no checkpoints)");
    cp.finish({"every_seconds"});
  }

  const std::string section = model;
  for (const char* other : {"dsmc", "intruder", "needle"})
    if (section != other && s.has(other))
      throw ConfigError(std::string(other) + ": section given but model is " + model);
  if (!s.has(section)) throw ConfigError(section + ": missing (required for model " + model + ")");
  switch (c.model) {
    case Model::kDsmc:
      c.dsmc = read_dsmc(s.sub("dsmc"));
      if (c.dsmc.source && c.ensembles > c.dsmc.source->ensembles)
        throw ConfigError("ensembles = " + std::to_string(c.ensembles) + ": must be <= the " +
                          std::to_string(c.dsmc.source->ensembles) +
                          " ensembles of dsmc.initial.from (ensemble e continues the source's e)");
      break;
    case Model::kIntruder:
      c.intruder = read_intruder(s.sub("intruder"));
      break;
    case Model::kNeedle:
      c.needle = read_needle(s.sub("needle"));
      break;
  }
  s.finish({"model", "seed", "ensembles", "threads", "shard", "checkpoint", section});
  return c;
}

Config load_config(const std::string& path, const std::vector<std::string>& overrides) {
  const std::string shown = quote_value(path, 300);
  // stat, not open: opening a FIFO would block until someone writes to it, and a device such as
  // /dev/zero would be read without end.
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0) {
    if (S_ISDIR(st.st_mode)) throw ConfigError(shown + ": is a directory, not a config file");
    if (!S_ISREG(st.st_mode))
      throw ConfigError(shown + ": is not a regular file (a FIFO or a device?), not a config file");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ConfigError(shown + ": cannot open config file");
  // One byte more than a config may hold, and no more: a file growing while read is cut short.
  std::string text(kMaxConfigBytes + 1, '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  if (in.bad()) throw ConfigError(shown + ": cannot read config file");
  text.resize(static_cast<std::size_t>(in.gcount()));
  if (text.size() > kMaxConfigBytes)
    throw ConfigError(shown + ": more than " + std::to_string(kMaxConfigBytes) +
                      " bytes; a config is at most " + std::to_string(kMaxConfigBytes) + " bytes");
  return parse_config(text, path, overrides);
}

std::string Config::to_yaml(bool physics_only) const {
  YAML::Emitter out;
  out << YAML::BeginMap;
  out << YAML::Key << "model" << YAML::Value << model_name(model);
  out << YAML::Key << "seed" << YAML::Value << seed;
  out << YAML::Key << "ensembles" << YAML::Value << ensembles;
  if (!physics_only) {
    out << YAML::Key << "threads" << YAML::Value << threads;
    if (shard.count > 1)
      out << YAML::Key << "shard" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key
          << "index" << YAML::Value << shard.index << YAML::Key << "count" << YAML::Value
          << shard.count << YAML::EndMap;
    if (checkpoint.every_seconds > 0)
      out << YAML::Key << "checkpoint" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key
          << "every_seconds" << YAML::Value << format_real(checkpoint.every_seconds)
          << YAML::EndMap;
  }
  switch (model) {
    case Model::kDsmc:
      emit_dsmc(out, dsmc);
      break;
    case Model::kIntruder:
      emit_intruder(out, intruder);
      break;
    case Model::kNeedle:
      emit_needle(out, needle);
      break;
  }
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

}  // namespace granboltz
