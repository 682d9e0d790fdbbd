#pragma once
// Typed, validated access to one YAML mapping of a run config. Every error names the full key,
// the offending value and what is allowed; keys that are never read are reported as unknown.
#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace granboltz {

/// A configuration or command-line error with a one-line message for the user.
class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class Section {
 public:
  /// `node` must be a mapping (or null, read as empty); `path` is its dotted key, "" at the top.
  Section(const YAML::Node& node, std::string path);

  bool has(const std::string& key) const;
  /// The full dotted name of a key of this section, as written in error messages.
  std::string name(const std::string& key) const;

  double real(const std::string& key) const;  ///< required finite number
  double real(const std::string& key, double fallback) const;
  std::uint64_t integer(const std::string& key) const;  ///< required integer >= 0
  std::uint64_t integer(const std::string& key, std::uint64_t fallback) const;
  std::string choice(const std::string& key, const std::vector<std::string>& allowed) const;
  std::string choice(const std::string& key, const std::vector<std::string>& allowed,
                     const std::string& fallback) const;
  /// A sub-mapping; absent keys give an empty section.
  Section sub(const std::string& key) const;

  /// Throws for a value outside its allowed range: "<key> = <value>: <allowed>".
  void check(bool ok, const std::string& key, double value, const std::string& allowed) const;
  /// Throws if the section holds a key that was never asked for.
  void finish(const std::vector<std::string>& allowed_keys) const;

 private:
  YAML::Node at(const std::string& key) const;
  YAML::Node node_;
  std::string path_;
  mutable std::set<std::string> seen_;
};

/// Parses `text` as YAML and applies "--set a.b.c=value" overrides (value parsed as YAML).
YAML::Node load_yaml_with_overrides(const std::string& text, const std::string& origin,
                                    const std::vector<std::string>& overrides);

/// Formats a double so that reading it back gives the same double.
std::string format_real(double x);

}  // namespace granboltz
