#pragma once
// Typed, validated access to one YAML mapping of a run config. Every error names the full key,
// the offending value and what is allowed; keys that are never read are reported as unknown.
//
// Typing is strict: a number is a plain (unquoted, untagged or !!int/!!float) scalar, so '0.5'
// and !!str 0.5 are strings; an explicit null (~, null, nothing) is an error for every key, and
// only a key left out takes its default. Errors are one line: values and keys are shown through
// quote_value.
#include <yaml-cpp/yaml.h>

#include <cstddef>
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

/// The largest integer a config takes: every integer up to it is exact in a double.
inline constexpr std::uint64_t kMaxInteger = std::uint64_t{1} << 53;

/// The values an integer key allows, and the words that say so: a value outside them, a
/// negative one included, is refused with "<key> = <value>: <allowed>", so that -2 and 0 get
/// the same message.
struct IntegerRange {
  std::uint64_t min = 0;
  std::uint64_t max = kMaxInteger;  ///< above 2^53 the refusal says "too large (> 2^53)"
  std::string allowed = "must be >= 0";
};

/// An integer as a config or the command line writes it: plain digits (read exactly), or a
/// decimal number that is exactly whole (1e7, 1.0e+4, 2.0); anything else (1.5, 1e-400, which a
/// double would round to 0, 0x10, inf) is "not an integer". Throws ConfigError "<name> = <text>:
/// ..." with `range.allowed` for a value outside the range.
std::uint64_t parse_integer(const std::string& text, const std::string& name,
                            const IntegerRange& range, const std::string& shown_text);

class Section {
 public:
  /// `node` must be a mapping (a null is refused); `path` is its dotted key, "" at the top.
  Section(const YAML::Node& node, std::string path);

  /// Whether the key is written, even with a null value (which every accessor then refuses).
  bool has(const std::string& key) const;
  /// The full dotted name of a key of this section, as written in error messages.
  std::string name(const std::string& key) const;

  double real(const std::string& key) const;  ///< required finite number
  double real(const std::string& key, double fallback) const;
  std::uint64_t integer(const std::string& key) const;  ///< required integer >= 0
  std::uint64_t integer(const std::string& key, std::uint64_t fallback) const;
  /// A required integer in `range`, or with a fallback when left out.
  std::uint64_t integer(const std::string& key, const IntegerRange& range) const;
  std::uint64_t integer(const std::string& key, std::uint64_t fallback,
                        const IntegerRange& range) const;
  std::string choice(const std::string& key, const std::vector<std::string>& allowed) const;
  std::string choice(const std::string& key, const std::vector<std::string>& allowed,
                     const std::string& fallback) const;
  /// A sub-mapping; an absent key gives an empty section, a null one is an error.
  Section sub(const std::string& key) const;
  /// Whether a written key holds a sequence, or a mapping.
  bool is_sequence(const std::string& key) const;
  bool is_mapping(const std::string& key) const;
  /// A required sequence of mappings, each a section named "<key>[i]"; at most `max` entries.
  std::vector<Section> list(const std::string& key, std::size_t max) const;
  /// A required non-empty list of finite numbers, each named "<key>[i]"; at most `max` entries.
  std::vector<double> reals(const std::string& key, std::size_t max) const;
  /// A required square matrix of finite numbers written as a sequence of `size` sequences.
  std::vector<double> matrix(const std::string& key, std::size_t size) const;
  /// A required vector of `size` finite numbers written as a sequence.
  std::vector<double> vector(const std::string& key, std::size_t size) const;
  /// A required plain text of 1..64 characters from [A-Za-z0-9_-] (a name used in output paths).
  std::string identifier(const std::string& key) const;
  /// A required file path: a non-empty text of at most 4096 bytes without NUL or line breaks.
  std::string path(const std::string& key) const;
  /// The keys written in this section, in order.
  std::vector<std::string> keys() const;

  /// Throws for a value outside its allowed range: "<key> = <value>: <allowed>".
  void check(bool ok, const std::string& key, double value, const std::string& allowed) const;
  /// Throws if the section holds a key that was never asked for.
  void finish(const std::vector<std::string>& allowed_keys) const;

 private:
  /// The value of a written key that is not null; `what` is what it must be ("a number").
  YAML::Node at(const std::string& key, const std::string& what, bool has_default) const;
  // The non-empty list at key (of `what`: "mappings", "numbers") of at most max entries.
  YAML::Node sequence(const std::string& key, const std::string& what, std::size_t max) const;
  double real_of(const YAML::Node& n, const std::string& key) const;
  std::uint64_t integer_of(const YAML::Node& n, const std::string& key,
                           const IntegerRange& range) const;
  std::string choice_of(const YAML::Node& n, const std::string& key,
                        const std::vector<std::string>& allowed) const;
  YAML::Node node_;
  std::string path_;
  mutable std::set<std::string> seen_;
};

/// Bounds on a config as written (see load_yaml_with_overrides). A config has about a hundred
/// nodes and a few hundred bytes: these leave a thousandfold margin and still bound the work.
inline constexpr std::size_t kMaxConfigBytes = std::size_t{1} << 20;
inline constexpr std::size_t kMaxNodes = 100'000;  ///< as written, and again with aliases expanded
inline constexpr int kMaxDepth = 64;               ///< nested mappings and sequences

/// `s` as shown in a one-line message: control characters escaped (\n, \t, \x1b, ...) and, if
/// longer than `max` characters, cut there with "… (N characters)".
std::string quote_value(const std::string& s, std::size_t max = 80);

/// Parses `text` as YAML and applies "--set a.b.c=value" overrides (value parsed as YAML).
/// The text and every value are first checked as written, with the event parser: at most
/// kMaxConfigBytes and kMaxNodes (also counting every alias as the nodes it stands for, so an
/// alias bomb is refused without being expanded), kMaxDepth levels (also through aliases), no
/// alias inside the node it refers to, and no key given twice in a mapping.
YAML::Node load_yaml_with_overrides(const std::string& text, const std::string& origin,
                                    const std::vector<std::string>& overrides);

/// Formats a double so that reading it back gives the same double.
std::string format_real(double x);

}  // namespace granboltz
