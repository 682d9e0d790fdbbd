#include "granboltz/config/reader.hpp"

#include <yaml-cpp/eventhandler.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <limits>
#include <map>
#include <sstream>
#include <string_view>

namespace granboltz {

namespace {

std::string join(const std::vector<std::string>& v, const std::string& sep) {
  std::string out;
  for (std::size_t i = 0; i < v.size(); ++i) out += (i ? sep : "") + v[i];
  return out;
}

std::string hex_escape(const char* prefix, unsigned value, int digits) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "%s%0*X", prefix, digits, value);
  return buf;
}

// Length of the UTF-8 sequence at s[i], or 0 if it is not valid UTF-8.
std::size_t utf8_length(const std::string& s, std::size_t i) {
  const auto c = static_cast<unsigned char>(s[i]);
  const std::size_t n = c < 0x80                 ? 1
                        : c >= 0xC2 && c <= 0xDF ? 2
                        : c >= 0xE0 && c <= 0xEF ? 3
                        : c >= 0xF0 && c <= 0xF4 ? 4
                                                 : 0;
  if (n == 0 || i + n > s.size()) return 0;
  for (std::size_t k = 1; k < n; ++k)
    if ((static_cast<unsigned char>(s[i + k]) & 0xC0) != 0x80) return 0;
  return n;
}

// The tag of a scalar as the user wrote it: !!str for the core schema's tags.
std::string short_tag(const std::string& tag) {
  const std::string core = "tag:yaml.org,2002:";
  return tag.rfind(core, 0) == 0 ? "!!" + quote_value(tag.substr(core.size()), 20)
                                 : quote_value(tag, 20);
}

// A value as shown in a message: scalars as written (quoted ones in quotes, tagged ones with
// their tag), collections abbreviated.
std::string shown(const YAML::Node& n) {
  if (!n) return "(nothing)";
  if (n.IsNull()) return "null";
  if (n.IsSequence()) return "[...]";
  if (n.IsMap()) return "{...}";
  const std::string& tag = n.Tag();
  if (tag == "!") return "\"" + quote_value(n.Scalar()) + "\"";
  if (tag.empty() || tag == "?") return quote_value(n.Scalar());
  return short_tag(tag) + " " + quote_value(n.Scalar());
}

// A number must be written as one: plain, or tagged with the core schema's int or float.
// Quoted ('0.5', "0.5") and otherwise tagged (!!str 0.5) scalars are strings.
void require_plain_number(const YAML::Node& n, const std::string& name, const char* what) {
  const std::string& tag = n.Tag();
  if (tag.empty() || tag == "?" || tag == "tag:yaml.org,2002:int" ||
      tag == "tag:yaml.org,2002:float")
    return;
  throw ConfigError(
      name + " = " + shown(n) + ": must be " + what + ", not " +
      (tag == "!" ? std::string("a quoted string") : "a value tagged " + short_tag(tag)));
}

// Checks a YAML document as written, from the parser's events, before it is loaded as a tree:
// the tree shares aliased nodes, but anything that walks it sees every alias expanded, which an
// alias bomb (anchors nested a few levels deep, each used ten times) makes exponential. Here every
// node is seen once, and an alias counts as the nodes of its anchor, computed when it was closed.
class DocumentChecker : public YAML::EventHandler {
 public:
  DocumentChecker(std::string origin, std::string root_path)
      : origin_(std::move(origin)), root_path_(std::move(root_path)) {}

  int documents() const { return documents_; }

  void OnDocumentStart(const YAML::Mark&) override {
    ++documents_;
    anchors_.clear();  // anchors are local to a document (and the parser reuses their ids)
    frames_.clear();
  }
  void OnDocumentEnd() override {}

  void OnNull(const YAML::Mark& mark, YAML::anchor_t anchor) override {
    leaf(mark, anchor, nullptr);
  }
  void OnScalar(const YAML::Mark& mark, const std::string&, YAML::anchor_t anchor,
                const std::string& value) override {
    texts_.push_back(value);
    leaf(mark, anchor, &texts_.back());
  }
  void OnAlias(const YAML::Mark& mark, YAML::anchor_t anchor) override {
    const auto it = anchors_.find(anchor);
    if (it == anchors_.end()) {  // not expected: the parser refuses an undefined anchor
      leaf(mark, YAML::NullAnchor, nullptr);
      return;
    }
    const Anchor& a = it->second;
    if (a.open)
      throw ConfigError(origin_ + ": the alias *" + quote_value(a.name, 40) + " at line " +
                        std::to_string(mark.line + 1) +
                        " is inside the node it refers to (an infinitely nested value)");
    count(mark, a.nodes);
    if (static_cast<int>(frames_.size()) + a.height > kMaxDepth)
      throw ConfigError(origin_ + ": nested more than " + std::to_string(kMaxDepth) +
                        " levels deep once the alias at line " + std::to_string(mark.line + 1) +
                        " is expanded");
    child_done(mark, a.height, a.scalar);
  }
  void OnAnchor(const YAML::Mark&, const std::string& name) override { pending_name_ = name; }

  void OnSequenceStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t anchor,
                       YAML::EmitterStyle::value) override {
    open(mark, anchor, false);
  }
  void OnMapStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t anchor,
                  YAML::EmitterStyle::value) override {
    open(mark, anchor, true);
  }
  void OnSequenceEnd() override { close(); }
  void OnMapEnd() override { close(); }

 private:
  struct Frame {
    bool map = false;
    YAML::anchor_t anchor = YAML::NullAnchor;
    std::uint64_t expanded_before = 0;  // expanded_ before this node
    int height = 0;                     // levels below this node, aliases expanded
    std::uint64_t children = 0;         // for a mapping: keys and values, alternating
    const std::string* key = nullptr;   // a mapping's current key, if a scalar
    std::set<std::string_view> keys;    // a mapping's scalar keys so far
    YAML::Mark mark;
  };
  struct Anchor {
    std::string name;
    bool open = true;
    std::uint64_t nodes = 0;  // nodes with aliases expanded
    int height = 0;
    const std::string* scalar = nullptr;  // for an anchored scalar: its text (an alias key)
  };

  // The dotted name of the node being read, for messages ("dsmc.kernel", "list[2]").
  std::string path() const {
    std::string out = root_path_;
    for (const Frame& f : frames_) {
      if (f.map) {
        if (f.children % 2 == 0) break;  // inside a key: name the mapping
        if (!out.empty()) out += '.';
        out += f.key ? quote_value(*f.key) : std::string("[...]");
      } else {
        out += "[" + std::to_string(f.children) + "]";
      }
    }
    return out;
  }

  void count(const YAML::Mark& mark, std::uint64_t expanded) {
    if (++written_ > kMaxNodes)
      throw ConfigError(origin_ + ": more than " + std::to_string(kMaxNodes) +
                        " YAML nodes (at line " + std::to_string(mark.line + 1) +
                        "); a config needs no more than a few hundred");
    expanded_ += expanded;  // each term is at most kMaxNodes: no overflow
    if (expanded_ > kMaxNodes)
      throw ConfigError(origin_ + ": aliases expand to more than " + std::to_string(kMaxNodes) +
                        " nodes (an alias bomb?); a config needs no more than a few hundred");
  }

  void register_anchor(YAML::anchor_t anchor) {
    if (anchor == YAML::NullAnchor) return;
    Anchor& a = anchors_[anchor];
    a = Anchor{};
    a.name = std::move(pending_name_);
    pending_name_.clear();
  }

  void leaf(const YAML::Mark& mark, YAML::anchor_t anchor, const std::string* text) {
    register_anchor(anchor);
    count(mark, 1);
    if (anchor != YAML::NullAnchor) {
      Anchor& a = anchors_[anchor];
      a.open = false;
      a.nodes = 1;
      a.scalar = text;
    }
    child_done(mark, 0, text);
  }

  void open(const YAML::Mark& mark, YAML::anchor_t anchor, bool map) {
    register_anchor(anchor);
    const std::uint64_t before = expanded_;
    count(mark, 1);
    if (static_cast<int>(frames_.size()) >= kMaxDepth)
      throw ConfigError(origin_ + ": nested more than " + std::to_string(kMaxDepth) +
                        " levels deep (at line " + std::to_string(mark.line + 1) + ")");
    Frame f;
    f.map = map;
    f.anchor = anchor;
    f.expanded_before = before;
    f.mark = mark;
    frames_.push_back(std::move(f));
  }

  void close() {
    Frame f = std::move(frames_.back());
    frames_.pop_back();
    const int height = f.height + 1;
    if (f.anchor != YAML::NullAnchor) {
      Anchor& a = anchors_[f.anchor];
      a.open = false;
      a.nodes = expanded_ - f.expanded_before;
      a.height = height;
    }
    child_done(f.mark, height, nullptr);
  }

  // A node of height `height` is complete; `text` is its scalar text, if it is a scalar.
  void child_done(const YAML::Mark& mark, int height, const std::string* text) {
    if (frames_.empty()) return;
    Frame& parent = frames_.back();
    parent.height = std::max(parent.height, height);
    if (parent.map && parent.children % 2 == 0) {  // a key
      parent.key = text;
      // yaml-cpp keeps both entries of a repeated key and lookups see only the first.
      if (text && !parent.keys.insert(*text).second) {
        std::string full = path();
        if (!full.empty()) full += '.';
        full += quote_value(*text);
        throw ConfigError(full + ": given twice (line " + std::to_string(mark.line + 1) + " of " +
                          origin_ + ")");
      }
    }
    ++parent.children;
  }

  std::string origin_, root_path_;
  int documents_ = 0;
  std::uint64_t written_ = 0, expanded_ = 0;
  std::vector<Frame> frames_;
  std::map<YAML::anchor_t, Anchor> anchors_;
  std::deque<std::string> texts_;  // every scalar's text, at a stable address
  std::string pending_name_;
};

// Checks `text` (see DocumentChecker) and loads its single document, or a null node if it holds
// none. `path` names the keys of its top level ("" for a config file, the key for --set).
YAML::Node checked_load(const std::string& text, const std::string& origin,
                        const std::string& path) {
  if (text.size() > kMaxConfigBytes)
    throw ConfigError(origin + ": " + std::to_string(text.size()) + " bytes; a config is at most " +
                      std::to_string(kMaxConfigBytes) + " bytes");
  DocumentChecker checker(origin, path);
  try {
    std::istringstream in(text);
    YAML::Parser parser(in);
    while (parser.HandleNextDocument(checker)) {
    }
  } catch (const YAML::Exception& e) {
    throw ConfigError(origin + ": YAML syntax error at line " + std::to_string(e.mark.line + 1) +
                      ", column " + std::to_string(e.mark.column + 1) + ": " +
                      quote_value(e.msg, 200));
  }
  if (checker.documents() > 1)
    throw ConfigError(origin + ": holds " + std::to_string(checker.documents()) +
                      " YAML documents; a config is a single document");
  try {
    // Linear: the tree shares the nodes of an alias with its anchor.
    return YAML::Load(text);
  } catch (const YAML::Exception& e) {  // not expected: the text parsed above
    throw ConfigError(origin + ": YAML syntax error at line " + std::to_string(e.mark.line + 1) +
                      ": " + quote_value(e.msg, 200));
  }
}

}  // namespace

std::string quote_value(const std::string& s, std::size_t max) {
  std::string out;
  std::size_t width = 0, characters = 0;  // as shown so far; in s
  bool cut = false;
  for (std::size_t i = 0; i < s.size();) {
    const auto c = static_cast<unsigned char>(s[i]);
    const std::size_t n = utf8_length(s, i);
    std::string piece;
    if (n == 0) {
      piece = hex_escape("\\x", c, 2);  // not UTF-8: shown byte by byte
    } else if (n == 1 && (c < 0x20 || c == 0x7F)) {
      piece = c == '\n' ? "\\n" : c == '\t' ? "\\t" : c == '\r' ? "\\r" : hex_escape("\\x", c, 2);
    } else {
      // C1 controls (U+0080-U+009F), line and paragraph separators and the bidirectional
      // overrides would break or reorder the line on a terminal: escaped like the C0 ones.
      unsigned cp = n == 1   ? c
                    : n == 2 ? (c & 0x1Fu) << 6 | (static_cast<unsigned char>(s[i + 1]) & 0x3Fu)
                    : n == 3
                        ? (c & 0x0Fu) << 12 | (static_cast<unsigned char>(s[i + 1]) & 0x3Fu) << 6 |
                              (static_cast<unsigned char>(s[i + 2]) & 0x3Fu)
                        : 0x10000;
      const bool control = (cp >= 0x80 && cp <= 0x9F) || cp == 0x2028 || cp == 0x2029 ||
                           (cp >= 0x202A && cp <= 0x202E) || (cp >= 0x2066 && cp <= 0x2069);
      piece = control ? hex_escape("\\u", cp, 4) : s.substr(i, n);
    }
    i += n == 0 ? 1 : n;
    ++characters;
    if (cut) continue;
    const std::size_t w = piece.size() > 1 && piece[0] == '\\' ? piece.size() : 1;
    if (width + w > max) {
      cut = true;
      continue;
    }
    out += piece;
    width += w;
  }
  if (cut) out += "\u2026 (" + std::to_string(characters) + " characters)";
  return out;
}

std::string format_real(double x) {
  char buf[64];
  auto res = std::to_chars(buf, buf + sizeof buf, x);
  return std::string(buf, res.ptr);
}

namespace {

// Whether `s` is a decimal number, [+-]digits[.digits][(e|E)[+-]digits] with at least one
// digit before the exponent, whose exact value is a whole number; `negative` tells whether it is
// below zero. The value is judged from the digits, not from a double: 1e-400 rounds to 0 and
// 1.0000000000000001 to 1, and neither is an integer.
bool whole_decimal(const std::string& s, bool& negative) {
  std::size_t i = 0;
  negative = false;
  if (i < s.size() && (s[i] == '+' || s[i] == '-')) negative = s[i++] == '-';
  std::string digits;      // the significand's digits, the point removed
  long long fraction = 0;  // digits after the point
  bool point = false;
  for (; i < s.size() && (std::isdigit(static_cast<unsigned char>(s[i])) || s[i] == '.'); ++i) {
    if (s[i] == '.') {
      if (point) return false;
      point = true;
    } else {
      digits += s[i];
      fraction += point;
    }
  }
  if (digits.empty()) return false;
  long long exponent = 0;
  if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
    ++i;
    bool minus = false;
    if (i < s.size() && (s[i] == '+' || s[i] == '-')) minus = s[i++] == '-';
    if (i == s.size()) return false;
    for (; i < s.size() && std::isdigit(static_cast<unsigned char>(s[i])); ++i)
      exponent = std::min(exponent * 10 + (s[i] - '0'), 1'000'000'000LL);
    if (minus) exponent = -exponent;
  }
  if (i != s.size()) return false;
  const std::size_t last = digits.find_last_not_of('0');
  if (last == std::string::npos) {  // zero, however written
    negative = false;
    return true;
  }
  const long long trailing_zeros = static_cast<long long>(digits.size() - 1 - last);
  return exponent - fraction + trailing_zeros >= 0;
}

}  // namespace

std::uint64_t parse_integer(const std::string& s, const std::string& name,
                            const IntegerRange& range, const std::string& text) {
  auto refuse = [&](const std::string& why) {
    throw ConfigError(name + " = " + text + ": " + why);
  };
  auto out_of_range = [&](bool above_max_integer) {
    if (above_max_integer && range.max >= kMaxInteger) refuse("too large (> 2^53)");
    refuse(range.allowed);
  };
  std::uint64_t v = 0;
  // Plain digits are read exactly, so that 2^53 + 1 is not silently rounded to 2^53.
  if (!s.empty() && s.find_first_not_of("0123456789") == std::string::npos) {
    const auto res = std::from_chars(s.data(), s.data() + s.size(), v);
    if (res.ec == std::errc::result_out_of_range || v > kMaxInteger) out_of_range(true);
  } else {
    // 4096 as well as 1e7, 1.0e+4 or 2.0: a decimal whose value is exactly whole.
    bool negative = false;
    if (!whole_decimal(s, negative)) refuse("not an integer");
    if (negative) out_of_range(false);
    const double x = std::strtod(s.c_str(), nullptr);
    // A double at 2^53 may be a rounded larger integer: only smaller ones are exact.
    if (!(x < static_cast<double>(kMaxInteger))) out_of_range(true);
    v = static_cast<std::uint64_t>(x);
  }
  if (v < range.min || v > range.max) out_of_range(false);
  return v;
}

Section::Section(const YAML::Node& node, std::string path) : node_(node), path_(std::move(path)) {
  if (!node_ || !node_.IsMap())
    throw ConfigError((path_.empty() ? std::string("config") : path_) + " = " + shown(node_) +
                      ": must be a mapping of keys to values" +
                      (node_ && node_.IsNull() ? ", not null" : ""));
}

std::string Section::name(const std::string& key) const {
  return path_.empty() ? key : path_ + "." + key;
}

bool Section::has(const std::string& key) const {
  seen_.insert(key);
  return static_cast<bool>(node_[key]);
}

YAML::Node Section::at(const std::string& key, const std::string& what, bool has_default) const {
  if (!has(key)) throw ConfigError(name(key) + ": missing (required)");
  YAML::Node n = node_[key];
  // A null is refused rather than read as absent: `--set ensembles=~` must not quietly mean 1.
  if (n.IsNull())
    throw ConfigError(name(key) + " = null: must be " + what + ", not null" +
                      (has_default ? " (leave the key out for its default)" : ""));
  return n;
}

double Section::real_of(const YAML::Node& n, const std::string& key) const {
  if (!n.IsScalar()) throw ConfigError(name(key) + " = " + shown(n) + ": must be a number");
  require_plain_number(n, name(key), "a number");
  double x = 0;
  try {
    x = n.as<double>();
  } catch (const YAML::Exception&) {
    throw ConfigError(name(key) + " = " + shown(n) + ": not a number");
  }
  if (!std::isfinite(x))
    throw ConfigError(name(key) + " = " + shown(n) + ": must be a finite number");
  return x;
}

double Section::real(const std::string& key) const {
  return real_of(at(key, "a number", false), key);
}

double Section::real(const std::string& key, double fallback) const {
  return has(key) ? real_of(at(key, "a number", true), key) : fallback;
}

std::uint64_t Section::integer_of(const YAML::Node& n, const std::string& key,
                                  const IntegerRange& range) const {
  if (!n.IsScalar()) throw ConfigError(name(key) + " = " + shown(n) + ": must be an integer");
  require_plain_number(n, name(key), "an integer");
  return parse_integer(n.Scalar(), name(key), range, shown(n));
}

std::uint64_t Section::integer(const std::string& key) const {
  return integer(key, IntegerRange{});
}

std::uint64_t Section::integer(const std::string& key, std::uint64_t fallback) const {
  return integer(key, fallback, IntegerRange{});
}

std::uint64_t Section::integer(const std::string& key, const IntegerRange& range) const {
  return integer_of(at(key, "an integer", false), key, range);
}

std::uint64_t Section::integer(const std::string& key, std::uint64_t fallback,
                               const IntegerRange& range) const {
  return has(key) ? integer_of(at(key, "an integer", true), key, range) : fallback;
}

std::string Section::choice_of(const YAML::Node& n, const std::string& key,
                               const std::vector<std::string>& allowed) const {
  if (n.IsScalar())
    for (const auto& a : allowed)
      if (n.Scalar() == a) return a;
  throw ConfigError(name(key) + " = " + shown(n) + ": must be one of " + join(allowed, ", "));
}

std::string Section::choice(const std::string& key, const std::vector<std::string>& allowed) const {
  return choice_of(at(key, "one of " + join(allowed, ", "), false), key, allowed);
}

std::string Section::choice(const std::string& key, const std::vector<std::string>& allowed,
                            const std::string& fallback) const {
  return has(key) ? choice_of(at(key, "one of " + join(allowed, ", "), true), key, allowed)
                  : fallback;
}

Section Section::sub(const std::string& key) const {
  if (!has(key)) return Section(YAML::Node(YAML::NodeType::Map), name(key));
  return Section(node_[key], name(key));
}

bool Section::is_sequence(const std::string& key) const {
  return has(key) && node_[key].IsSequence();
}

bool Section::is_mapping(const std::string& key) const { return has(key) && node_[key].IsMap(); }

YAML::Node Section::sequence(const std::string& key, const std::string& what,
                             std::size_t max) const {
  const YAML::Node n = at(key, "a list of " + what, false);
  if (!n.IsSequence() || n.size() == 0)
    throw ConfigError(name(key) + " = " + shown(n) + ": must be a non-empty list of " + what);
  if (n.size() > max)
    throw ConfigError(name(key) + ": " + std::to_string(n.size()) + " entries: at most " +
                      std::to_string(max) + " allowed");
  return n;
}

std::vector<Section> Section::list(const std::string& key, std::size_t max) const {
  const YAML::Node n = sequence(key, "mappings", max);
  std::vector<Section> out;
  for (std::size_t i = 0; i < n.size(); ++i)
    out.emplace_back(n[i], name(key) + "[" + std::to_string(i) + "]");
  return out;
}

std::vector<double> Section::reals(const std::string& key, std::size_t max) const {
  const YAML::Node n = sequence(key, "numbers", max);
  std::vector<double> out;
  out.reserve(n.size());
  for (const auto& x : n) out.push_back(real_of(x, key + "[" + std::to_string(out.size()) + "]"));
  return out;
}

std::vector<double> Section::matrix(const std::string& key, std::size_t size) const {
  const YAML::Node n = at(key, "a matrix", false);
  const std::string shape = std::to_string(size) + " x " + std::to_string(size);
  if (!n.IsSequence() || n.size() != size)
    throw ConfigError(name(key) + " = " + shown(n) + ": must be a number or a " + shape +
                      " matrix (a list of " + std::to_string(size) + " lists)");
  std::vector<double> out;
  for (std::size_t i = 0; i < size; ++i) {
    if (!n[i].IsSequence() || n[i].size() != size)
      throw ConfigError(name(key) + "[" + std::to_string(i) + "] = " + shown(n[i]) +
                        ": must be a list of " + std::to_string(size) + " numbers (a " + shape +
                        " matrix)");
    for (std::size_t j = 0; j < size; ++j)
      out.push_back(
          real_of(n[i][j], key + "[" + std::to_string(i) + "][" + std::to_string(j) + "]"));
  }
  return out;
}

std::vector<double> Section::vector(const std::string& key, std::size_t size) const {
  const YAML::Node n = at(key, "a list of numbers", false);
  if (!n.IsSequence() || n.size() != size)
    throw ConfigError(name(key) + " = " + shown(n) + ": must be a list of " + std::to_string(size) +
                      " numbers");
  std::vector<double> out;
  for (std::size_t i = 0; i < size; ++i)
    out.push_back(real_of(n[i], key + "[" + std::to_string(i) + "]"));
  return out;
}

std::string Section::identifier(const std::string& key) const {
  const YAML::Node n = at(key, "a name", false);
  bool ok = n.IsScalar() && !n.Scalar().empty() && n.Scalar().size() <= 64;
  if (ok)
    for (const char c : n.Scalar())
      ok = ok && (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-');
  if (!ok)
    throw ConfigError(name(key) + " = " + shown(n) +
                      ": must be a name of 1 to 64 characters from A-Z, a-z, 0-9, _ and -");
  return n.Scalar();
}

std::string Section::path(const std::string& key) const {
  const YAML::Node n = at(key, "a file path", false);
  bool ok = n.IsScalar() && !n.Scalar().empty() && n.Scalar().size() <= 4096;
  if (ok)
    for (const char c : n.Scalar()) ok = ok && c != '\0' && c != '\n' && c != '\r';
  if (!ok)
    throw ConfigError(name(key) + " = " + shown(n) +
                      ": must be a file path of 1 to 4096 characters on one line");
  return n.Scalar();
}

std::vector<std::string> Section::keys() const {
  std::vector<std::string> out;
  for (const auto& kv : node_)
    if (kv.first.IsScalar()) out.push_back(kv.first.Scalar());
  return out;
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
  for (const auto& kv : node_) {
    if (!kv.first.IsScalar())
      throw ConfigError(
          name(shown(kv.first)) +
          ": unknown key (keys are plain names); allowed here: " + join(allowed_keys, ", "));
    const std::string key = kv.first.Scalar();
    bool ok = false;
    for (const auto& a : allowed_keys) ok = ok || a == key;
    if (!ok)
      throw ConfigError(name(quote_value(key)) +
                        ": unknown key; allowed here: " + join(allowed_keys, ", "));
  }
}

YAML::Node load_yaml_with_overrides(const std::string& text, const std::string& file,
                                    const std::vector<std::string>& overrides) {
  // A path may hold any byte but a NUL: shown escaped, and cut only if absurdly long.
  const std::string origin = quote_value(file, 300);
  YAML::Node root = checked_load(text, origin, "");
  if (!root || root.IsNull()) {
    // An empty file is an error unless --set gives the whole config.
    if (overrides.empty())
      throw ConfigError(origin +
                        ": empty config; it needs at least model, seed and the section "
                        "of the model");
    root = YAML::Node(YAML::NodeType::Map);
  }
  if (!root.IsMap()) throw ConfigError(origin + ": the config must be a mapping of keys to values");
  for (const auto& item : overrides) {
    const std::string shown_item = "--set " + quote_value(item);
    const auto eq = item.find('=');
    if (eq == std::string::npos || eq == 0)
      throw ConfigError(shown_item + ": expected key=value, e.g. --set dsmc.particles=1024");
    const std::string key = item.substr(0, eq);
    std::vector<std::string> parts;
    std::stringstream ss(key);
    for (std::string p; std::getline(ss, p, '.');) {
      if (p.empty()) throw ConfigError(shown_item + ": empty component in key " + quote_value(key));
      parts.push_back(p);
    }
    if (key.back() == '.')
      throw ConfigError(shown_item + ": empty component in key " + quote_value(key));
    if (eq + 1 == item.size())
      throw ConfigError(quote_value(key) + ": missing value in " + shown_item + " (write " +
                        shown_item + "VALUE)");
    YAML::Node value;
    try {
      value = checked_load(item.substr(eq + 1), shown_item, quote_value(key));
    } catch (const ConfigError& e) {
      const std::string m = e.what();
      // Name the override as the command line has it: "value is not valid YAML".
      const std::string syntax = shown_item + ": YAML syntax error";
      if (m.rfind(syntax, 0) == 0)
        throw ConfigError(shown_item + ": value is not valid YAML:" + m.substr(syntax.size()));
      throw;
    }
    if (!value) value = YAML::Node();  // a value of only blanks or a comment: a null
    // Walk down with fresh handles: yaml-cpp's operator= on a held node would alias.
    std::vector<YAML::Node> chain{root};
    for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
      YAML::Node child = chain.back()[parts[i]];
      if (!child || child.IsNull()) {
        chain.back()[parts[i]] = YAML::Node(YAML::NodeType::Map);
        child = chain.back()[parts[i]];
      } else if (!child.IsMap()) {
        throw ConfigError(shown_item + ": " + quote_value(parts[i]) + " is not a mapping");
      }
      chain.push_back(child);
    }
    chain.back()[parts.back()] = value;
  }
  return root;
}

}  // namespace granboltz
