#include "granboltz/config/reader.hpp"

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

constexpr std::uint64_t kMaxInteger = std::uint64_t{1} << 53;

std::string join(const std::vector<std::string>& v, const std::string& sep) {
  std::string out;
  for (std::size_t i = 0; i < v.size(); ++i) out += (i ? sep : "") + v[i];
  return out;
}

// yaml-cpp keeps both entries of a repeated key and lookups see only the first: reject them.
// The depth bound also stops at aliases that refer to an enclosing node.
void check_unique_keys(const YAML::Node& n, const std::string& path, const std::string& origin,
                       int depth) {
  if (depth > 64)
    throw ConfigError(origin +
                      ": nested more than 64 levels deep (an alias to an enclosing node?)");
  if (n.IsSequence()) {
    for (std::size_t i = 0; i < n.size(); ++i)
      check_unique_keys(n[i], path + "[" + std::to_string(i) + "]", origin, depth + 1);
    return;
  }
  if (!n.IsMap()) return;
  std::set<std::string> keys;
  for (const auto& kv : n) {
    const std::string key = kv.first.IsScalar() ? kv.first.Scalar() : scalar_text(kv.first);
    const std::string full = path.empty() ? key : path + "." + key;
    if (kv.first.IsScalar() && !keys.insert(key).second)
      throw ConfigError(full + ": given twice (line " + std::to_string(kv.first.Mark().line + 1) +
                        " of " + origin + ")");
    check_unique_keys(kv.second, full, origin, depth + 1);
  }
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
  // Plain digits are read exactly, so that 2^53 + 1 is not silently rounded to 2^53.
  if (!s.empty() && s.find_first_not_of("0123456789") == std::string::npos) {
    std::uint64_t v = 0;
    const auto res = std::from_chars(s.data(), s.data() + s.size(), v);
    if (res.ec == std::errc::result_out_of_range || v > kMaxInteger)
      throw ConfigError(name(key) + " = " + s + ": too large (> 2^53)");
    return v;
  }
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
  // A double at 2^53 may be a rounded larger integer: only smaller ones are exact.
  if (x >= static_cast<double>(kMaxInteger))
    throw ConfigError(name(key) + " = " + s + ": too large (> 2^53)");
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
  if (ok) return;
  // Whole numbers (counts, and reals like 2) are written out: 2000000, not 2e+06.
  const bool whole = value == std::floor(value) && std::fabs(value) < 9007199254740992.0;
  const std::string text =
      whole ? std::to_string(static_cast<std::int64_t>(value)) : format_real(value);
  throw ConfigError(name(key) + " = " + text + ": " + allowed);
}

void Section::finish(const std::vector<std::string>& allowed_keys) const {
  if (!node_ || !node_.IsMap()) return;
  for (const auto& kv : node_) {
    if (!kv.first.IsScalar())
      throw ConfigError(name(scalar_text(kv.first)) +
                        ": unknown key (keys are plain names); allowed here: " +
                        join(allowed_keys, ", "));
    const std::string key = kv.first.Scalar();
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
    const std::vector<YAML::Node> documents = YAML::LoadAll(text);
    if (documents.size() > 1)
      throw ConfigError(origin + ": holds " + std::to_string(documents.size()) +
                        " YAML documents; a config is a single document");
    if (!documents.empty()) root = documents.front();
  } catch (const YAML::Exception& e) {
    throw ConfigError(origin + ": YAML syntax error at line " + std::to_string(e.mark.line + 1) +
                      ", column " + std::to_string(e.mark.column + 1) + ": " + e.msg);
  }
  if (!root || root.IsNull()) {
    // An empty file is an error unless --set gives the whole config.
    if (overrides.empty())
      throw ConfigError(origin + ": empty config; it needs at least model, seed and the section "
                        "of the model");
    root = YAML::Node(YAML::NodeType::Map);
  }
  if (!root.IsMap()) throw ConfigError(origin + ": the config must be a mapping of keys to values");
  check_unique_keys(root, "", origin, 0);
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
    check_unique_keys(value, item.substr(0, eq), "--set " + item, 0);
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
