#include "granboltz/config_reader.hpp"

#include <charconv>
#include <cmath>
#include <limits>
#include <sstream>

namespace granboltz {

namespace {

std::string scalar_text(const YAML::Node& n) {
  if (n.IsScalar()) return n.Scalar();
  if (n.IsNull()) return "null";
  if (n.IsSequence()) return "[...]";
  return "{...}";
}

std::string join(const std::vector<std::string>& v, const std::string& sep) {
  std::string out;
  for (std::size_t i = 0; i < v.size(); ++i) out += (i ? sep : "") + v[i];
  return out;
}

}  // namespace

std::string format_real(double x) {
  char buf[64];
  auto res = std::to_chars(buf, buf + sizeof buf, x);
  return std::string(buf, res.ptr);
}

Section::Section(const YAML::Node& node, std::string path) : node_(node), path_(std::move(path)) {
  if (node_ && !node_.IsNull() && !node_.IsMap())
    throw ConfigError((path_.empty() ? std::string("config") : path_) + " = " +
                      scalar_text(node_) + ": must be a mapping of keys to values");
}

std::string Section::name(const std::string& key) const {
  return path_.empty() ? key : path_ + "." + key;
}

bool Section::has(const std::string& key) const {
  seen_.insert(key);
  return node_ && node_.IsMap() && node_[key] && !node_[key].IsNull();
}

YAML::Node Section::at(const std::string& key) const {
  if (!has(key)) throw ConfigError(name(key) + ": missing (required)");
  return node_[key];
}

double Section::real(const std::string& key) const {
  const YAML::Node n = at(key);
  if (!n.IsScalar()) throw ConfigError(name(key) + " = " + scalar_text(n) + ": must be a number");
  const std::string& s = n.Scalar();
  double x = 0;
  try {
    x = n.as<double>();
  } catch (const YAML::Exception&) {
    throw ConfigError(name(key) + " = " + s + ": not a number");
  }
  if (!std::isfinite(x)) throw ConfigError(name(key) + " = " + s + ": must be a finite number");
  return x;
}

double Section::real(const std::string& key, double fallback) const {
  return has(key) ? real(key) : fallback;
}

std::uint64_t Section::integer(const std::string& key) const {
  const YAML::Node n = at(key);
  if (!n.IsScalar())
    throw ConfigError(name(key) + " = " + scalar_text(n) + ": must be an integer");
  const std::string& s = n.Scalar();
  // Accept 4096 as well as 1e7 or 1.0e+4 when the value is a whole number.
  double x = 0;
  try {
    x = n.as<double>();
  } catch (const YAML::Exception&) {
    throw ConfigError(name(key) + " = " + s + ": not an integer");
  }
  if (!std::isfinite(x) || x != std::floor(x))
    throw ConfigError(name(key) + " = " + s + ": not an integer");
  if (x < 0) throw ConfigError(name(key) + " = " + s + ": must be >= 0");
  if (x > 9007199254740992.0) throw ConfigError(name(key) + " = " + s + ": too large (> 2^53)");
  return static_cast<std::uint64_t>(x);
}

std::uint64_t Section::integer(const std::string& key, std::uint64_t fallback) const {
  return has(key) ? integer(key) : fallback;
}

std::string Section::choice(const std::string& key, const std::vector<std::string>& allowed) const {
  const YAML::Node n = at(key);
  const std::string s = n.IsScalar() ? n.Scalar() : scalar_text(n);
  for (const auto& a : allowed)
    if (s == a) return s;
  throw ConfigError(name(key) + " = " + s + ": must be one of " + join(allowed, ", "));
}

std::string Section::choice(const std::string& key, const std::vector<std::string>& allowed,
                            const std::string& fallback) const {
  return has(key) ? choice(key, allowed) : fallback;
}

Section Section::sub(const std::string& key) const {
  seen_.insert(key);
  if (!node_ || !node_.IsMap() || !node_[key]) return Section(YAML::Node(), name(key));
  return Section(node_[key], name(key));
}

void Section::check(bool ok, const std::string& key, double value,
                    const std::string& allowed) const {
  if (!ok) throw ConfigError(name(key) + " = " + format_real(value) + ": " + allowed);
}

void Section::finish(const std::vector<std::string>& allowed_keys) const {
  if (!node_ || !node_.IsMap()) return;
  for (const auto& kv : node_) {
    const std::string key = kv.first.as<std::string>();
    bool ok = false;
    for (const auto& a : allowed_keys) ok = ok || a == key;
    if (!ok)
      throw ConfigError(name(key) + ": unknown key; allowed here: " + join(allowed_keys, ", "));
  }
}

YAML::Node load_yaml_with_overrides(const std::string& text, const std::string& origin,
                                    const std::vector<std::string>& overrides) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw ConfigError(origin + ": YAML syntax error at line " + std::to_string(e.mark.line + 1) +
                      ", column " + std::to_string(e.mark.column + 1) + ": " + e.msg);
  }
  if (root.IsNull()) root = YAML::Node(YAML::NodeType::Map);
  if (!root.IsMap()) throw ConfigError(origin + ": the config must be a mapping of keys to values");
  for (const auto& item : overrides) {
    const auto eq = item.find('=');
    if (eq == std::string::npos || eq == 0)
      throw ConfigError("--set " + item + ": expected key=value, e.g. --set dsmc.particles=1024");
    const std::string key = item.substr(0, eq);
    YAML::Node value;
    try {
      value = YAML::Load(item.substr(eq + 1));
    } catch (const YAML::Exception& e) {
      throw ConfigError("--set " + item + ": value is not valid YAML: " + e.msg);
    }
    std::vector<std::string> parts;
    std::stringstream ss(key);
    for (std::string p; std::getline(ss, p, '.');) {
      if (p.empty()) throw ConfigError("--set " + item + ": empty component in key " + key);
      parts.push_back(p);
    }
    // Walk down with fresh handles: yaml-cpp's operator= on a held node would alias.
    std::vector<YAML::Node> chain{root};
    for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
      YAML::Node child = chain.back()[parts[i]];
      if (!child || child.IsNull()) {
        chain.back()[parts[i]] = YAML::Node(YAML::NodeType::Map);
        child = chain.back()[parts[i]];
      } else if (!child.IsMap()) {
        throw ConfigError("--set " + item + ": " + parts[i] + " is not a mapping");
      }
      chain.push_back(child);
    }
    chain.back()[parts.back()] = value;
  }
  return root;
}

}  // namespace granboltz
