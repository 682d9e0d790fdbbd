// The YAML reader on hostile input: alias bombs and deep nesting are refused from the text as
// written (quickly), numbers are typed strictly, nulls are not defaults, and every error is one
// short line whatever the value or key holds.
#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <vector>

#include "granboltz/app/config.hpp"
#include "test_support.hpp"

using namespace granboltz;

namespace {

const std::string kBase = R"(model: dsmc
seed: 1
ensembles: 4
dsmc:
  particles: 64
  alpha: 0.5
  beta: 1
  kernel: {lambda: 0, C: 0.0795774715459477}
  t_end: 0.5
  observe_every: 0.25
)";

// Anchors nested `levels` deep, each used ten times by the next: 10^levels nodes once expanded.
std::string bomb(int levels, const std::string& indent) {
  std::string s = indent + "l0: &a0 [1,1,1,1,1,1,1,1,1,1]\n";
  for (int i = 1; i < levels; ++i) {
    s += indent + "l" + std::to_string(i) + ": &a" + std::to_string(i) + " [";
    for (int k = 0; k < 10; ++k) s += (k ? ",*a" : "*a") + std::to_string(i - 1);
    s += "]\n";
  }
  return s;
}

std::string flow_bomb(int levels) {
  std::string s = "{l0: &a0 [1,1,1,1,1,1,1,1,1,1]";
  for (int i = 1; i < levels; ++i) {
    s += ", l" + std::to_string(i) + ": &a" + std::to_string(i) + " [";
    for (int k = 0; k < 10; ++k) s += (k ? ",*a" : "*a") + std::to_string(i - 1);
    s += "]";
  }
  return s + "}";
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// An error a user sees: one line, and short (the value in it is cut to 80 characters, a --set
// item too; some messages add a list of the allowed keys).
void expect_one_short_line(const std::string& e, std::size_t max = 250) {
  EXPECT_FALSE(e.empty());
  EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  EXPECT_EQ(e.find('\r'), std::string::npos) << e;
  EXPECT_EQ(e.find('\x1b'), std::string::npos) << e;
  EXPECT_LE(e.size(), max) << e;
}

}  // namespace

TEST(YamlReader, AliasBombsAreRefusedQuicklyWhereverTheyAre) {
  const std::string msg = "aliases expand to more than 100000 nodes (an alias bomb?)";
  struct Case {
    std::string text;
    std::vector<std::string> sets;
  };
  const Case cases[] = {
      {kBase + "bomb:\n" + bomb(9, "  "), {}},           // an unknown key
      {kBase + "  histogram:\n" + bomb(9, "    "), {}},  // a section read
      {kBase + "dsmc2:\n" + bomb(12, "  "), {}},         // 10^12 nodes
      {kBase, {"bomb=" + flow_bomb(9)}},                 // --set
      {kBase, {"dsmc.histogram=" + flow_bomb(9)}},
  };
  for (const Case& c : cases) {
    const auto t0 = std::chrono::steady_clock::now();
    const std::string e = test::config_error(c.text, c.sets);
    EXPECT_LT(seconds_since(t0), 2.0);
    EXPECT_NE(e.find(msg), std::string::npos) << e;
    expect_one_short_line(e);
  }
}

TEST(YamlReader, AliasBombsAreRefusedQuicklyByTheCommandLine) {
  test::TempDir dir;
  const std::string file = dir.write("bomb.yaml", kBase + "bomb:\n" + bomb(9, "  "));
  const std::string base = dir.write("base.yaml", kBase);
  for (const std::string& args :
       {"validate " + file, "run " + file + " -q -o " + dir.file("out.h5"), "estimate " + file,
        "validate " + base + " --set 'bomb=" + flow_bomb(9) + "'",
        "run " + base + " -q -o " + dir.file("out.h5") + " --set 'bomb=" + flow_bomb(9) + "'"}) {
    const auto t0 = std::chrono::steady_clock::now();
    const test::CommandResult r = test::run_granboltz(args);
    EXPECT_LT(seconds_since(t0), 2.0) << args;
    EXPECT_EQ(r.exit_code, 2) << args;
    EXPECT_NE(r.output.find("aliases expand to more than"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find('\n'), r.output.size() - 1) << r.output;
  }
  EXPECT_EQ(dir.entries(), 2u);  // no output left
}

TEST(YamlReader, AliasesThatAConfigMightUseAreFine) {
  // One value anchored and used for several keys.
  const std::string text =
      "model: dsmc\nseed: 1\nensembles: &n 4\ndsmc:\n  particles: 64\n"
      "  alpha: &a 0.5\n  beta: *a\n  kernel: {lambda: 0, C: *a}\n"
      "  t_end: *a\n  observe_every: 0.25\n";
  const Config d = parse_config(text, "t");
  EXPECT_EQ(d.dsmc.beta, 0.5);
  EXPECT_EQ(d.dsmc.kernel.C, 0.5);
  EXPECT_EQ(d.ensembles, 4u);
  // About 12 000 nodes once expanded: within the bound, however they are written.
  EXPECT_EQ(test::config_error(kBase + "extra:\n" + bomb(4, "  ")).rfind("extra: unknown key", 0),
            0u);
}

TEST(YamlReader, NodesAndDepthAreBoundedAsWrittenAndThroughAliases) {
  std::string many = kBase + "many: [";
  for (int i = 0; i < 100'001; ++i) many += i ? ",1" : "1";
  many += "]\n";
  const auto t0 = std::chrono::steady_clock::now();
  const std::string e = test::config_error(many);
  EXPECT_LT(seconds_since(t0), 2.0);
  EXPECT_NE(e.find("test.yaml: more than 100000 YAML nodes"), std::string::npos) << e;

  const std::string deep = kBase + "deep: " + std::string(65, '[') + std::string(65, ']') + "\n";
  EXPECT_NE(
      test::config_error(deep).find("test.yaml: nested more than 64 levels deep (at line 11)"),
      std::string::npos);
  const std::string ok = kBase + "deep: " + std::string(63, '[') + std::string(63, ']') + "\n";
  EXPECT_EQ(test::config_error(ok).rfind("deep: unknown key", 0), 0u);
  // Each level alone is shallow; through the alias the whole is 80 levels deep.
  const std::string through = kBase + "a: &d " + std::string(40, '[') + std::string(40, ']') +
                              "\nb: " + std::string(40, '[') + "*d" + std::string(40, ']') + "\n";
  EXPECT_NE(test::config_error(through).find("nested more than 64 levels deep once the alias at "
                                             "line 12 is expanded"),
            std::string::npos)
      << test::config_error(through);
  // An alias inside the node it names would be infinitely deep.
  EXPECT_NE(test::config_error(kBase + "loop: &l [1, [*l]]\n")
                .find("test.yaml: the alias *l at line 11 is inside the node it refers to"),
            std::string::npos);
  // Text beyond the byte bound is refused before parsing.
  const std::string huge = kBase + "# " + std::string(kMaxConfigBytes, 'x') + "\n";
  EXPECT_NE(test::config_error(huge).find("bytes; a config is at most 1048576 bytes"),
            std::string::npos);
}

TEST(YamlReader, KeysGivenTwiceAreReportedAsWritten) {
  // In an anchored mapping repeated by aliases: once, at its written line.
  const std::string anchored = kBase + "x: &m {a: 1, b: 2, a: 3}\ny: [*m, *m, *m]\n";
  EXPECT_EQ(test::config_error(anchored), "x.a: given twice (line 11 of test.yaml)");
  // A key written as an alias of a scalar is that scalar.
  EXPECT_EQ(test::config_error("&k seed: 1\nmodel: dsmc\n*k : 2\n"),
            "seed: given twice (line 3 of test.yaml)");
  // In a sequence, and in a --set value.
  EXPECT_EQ(test::config_error(kBase + "list: [{p: 1}, {q: 1, q: 2}]\n"),
            "list[1].q: given twice (line 11 of test.yaml)");
  EXPECT_EQ(test::config_error(kBase, {"dsmc.kernel={lambda: 0, C: 1, C: 2}"}),
            "dsmc.kernel.C: given twice (line 1 of --set dsmc.kernel={lambda: 0, C: 1, C: 2})");
  // The same key in two mappings is no repetition.
  EXPECT_EQ(test::config_error(kBase + "x: {a: 1}\n").rfind("x: unknown key", 0), 0u);
}

TEST(YamlReader, QuotedAndTaggedNumbersAreStrings) {
  EXPECT_EQ(test::config_error(kBase, {"dsmc.kernel.C=!!str 0.5"}),
            "dsmc.kernel.C = !!str 0.5: must be a number, not a value tagged !!str");
  EXPECT_EQ(test::config_error(kBase, {"dsmc.kernel.C=\"0.5\""}),
            "dsmc.kernel.C = \"0.5\": must be a number, not a quoted string");
  EXPECT_EQ(test::config_error(kBase, {"dsmc.kernel.C='0.5'"}),
            "dsmc.kernel.C = \"0.5\": must be a number, not a quoted string");
  EXPECT_EQ(test::config_error(kBase, {"dsmc.particles='100'"}),
            "dsmc.particles = \"100\": must be an integer, not a quoted string");
  EXPECT_EQ(test::config_error(kBase, {"seed=!!str 7"}),
            "seed = !!str 7: must be an integer, not a value tagged !!str");
  EXPECT_EQ(test::config_error(kBase, {"dsmc.alpha=!x 0.5"}),
            "dsmc.alpha = !x 0.5: must be a number, not a value tagged !x");
  EXPECT_EQ(test::config_error(kBase, {"dsmc.alpha=! 0.5"}),
            "dsmc.alpha = \"0.5\": must be a number, not a quoted string");
  EXPECT_EQ(test::config_error(kBase, {"dsmc.alpha=|\n  0.5\n"}),
            "dsmc.alpha = \"0.5\\n\": must be a number, not a quoted string");
  // Booleans are no numbers either.
  EXPECT_EQ(test::config_error(kBase, {"dsmc.beta=true"}), "dsmc.beta = true: not a number");
  // The core schema's number tags are numbers, and strings may be quoted or tagged.
  const Config c =
      parse_config(kBase, "t",
                   {"dsmc.alpha=!!float 0.25", "dsmc.particles=!!int 100", "dsmc.scheme='strang'",
                    "dsmc.steps=2", "model=!!str dsmc", "dsmc.majorant=\"global\""});
  EXPECT_EQ(c.dsmc.alpha, 0.25);
  EXPECT_EQ(c.dsmc.particles, 100u);
  EXPECT_EQ(c.dsmc.scheme, Scheme::kStrang);
  // Quoted keys are keys.
  EXPECT_EQ(parse_config("\"model\": dsmc\n'seed': 3\ndsmc: {particles: 64, alpha: 1, beta: 0, "
                         "kernel: {lambda: 0, C: 1}, t_end: 1}\n",
                         "t")
                .seed,
            3u);
}

TEST(YamlReader, AnExplicitNullIsAnErrorAndOnlyAnAbsentKeyTakesItsDefault) {
  EXPECT_EQ(test::config_error(kBase, {"ensembles=~"}),
            "ensembles = null: must be an integer, not null (leave the key out for its default)");
  EXPECT_EQ(test::config_error(kBase, {"ensembles=null"}),
            test::config_error(kBase, {"ensembles=~"}));
  EXPECT_EQ(test::config_error(kBase, {"seed=~"}), "seed = null: must be an integer, not null");
  EXPECT_EQ(test::config_error(kBase, {"dsmc.alpha=~"}),
            "dsmc.alpha = null: must be a number, not null");
  EXPECT_EQ(test::config_error(kBase, {"dsmc.gamma=~"}),
            "dsmc.gamma = null: must be a number, not null (leave the key out for its default)");
  EXPECT_EQ(test::config_error(kBase, {"model=~"}),
            "model = null: must be one of dsmc, intruder, needle, not null");
  EXPECT_EQ(test::config_error(kBase, {"dsmc.steady_from=~"}),
            "dsmc.steady_from = null: must be a number, not null");
  EXPECT_EQ(test::config_error(kBase, {"shard=~"}),
            "shard = null: must be a mapping of keys to values, not null");
  EXPECT_EQ(test::config_error(kBase, {"dsmc.initial=~"}),
            "dsmc.initial = null: must be a mapping of keys to values, not null");
  EXPECT_EQ(test::config_error(kBase + "threads:\n"),
            "threads = null: must be an integer, not null (leave the key out for its default)");
  EXPECT_EQ(test::config_error(kBase, {"dsmc.alpha="}),
            "dsmc.alpha: missing value in --set dsmc.alpha= (write --set dsmc.alpha=VALUE)");
  // Absent keys keep their defaults, and the sections that may be left out stay out.
  const Config c = parse_config(kBase, "t");
  EXPECT_EQ(c.threads, 0u);
  EXPECT_EQ(c.dsmc.kernel.gamma, 1.0);
  EXPECT_EQ(c.dsmc.histogram.shells, 0u);
  EXPECT_FALSE(c.dsmc.steady);
  EXPECT_EQ(c.shard.count, 1u);
}

TEST(YamlReader, ErrorsAreOneShortLineWhateverTheValueOrKeyHolds) {
  const std::string big(100'000, 'x');
  for (const std::string& e : {
           test::config_error(kBase, {"model=" + big}),
           test::config_error(kBase, {"dsmc.alpha=" + big}),
           test::config_error(kBase, {"dsmc.particles=" + big}),
           test::config_error(kBase, {"dsmc." + big + "=1"}),
           test::config_error(kBase, {big + "=1"}),
           test::config_error(kBase + big + ": 1\n"),
           test::config_error(kBase + "dsmc2: {" + big + ": 1, " + big + ": 2}\n"),
           test::config_error(kBase, {"dsmc.alpha=\"a\\nb\\r\\e[2J\""}),
           test::config_error(kBase, {"dsmc.alpha=|\n  two\n  lines\n"}),
           test::config_error(kBase, {"dsmc.alpha=[0.5"}),
           test::config_error(kBase, {"dsmc.kernel={\"lam\\nbda\": 1}"}),
           test::config_error(kBase + "\"x\\ny\": 1\n"),
           test::config_error(kBase, {"a\nb=1"}),
           test::config_error(kBase, {"a\nb"}),
       }) {
    expect_one_short_line(
        e, 420);  // the longest: a cut key (80 characters) and the 27 dsmc keys (402)
  }
  EXPECT_EQ(test::config_error(kBase, {"dsmc.scheme=" + big}),
            "dsmc.scheme = " + std::string(80, 'x') +
                "\u2026 (100000 characters): must be one of nosplit, euler, strang");
  EXPECT_EQ(test::config_error(kBase + "\"x\\ny\": 1\n").rfind("x\\ny: unknown key", 0), 0u);

  // And through the command line, with the value in a file.
  test::TempDir dir;
  const std::string file = dir.write("big.yaml", kBase + "  scheme: " + big + "\n");
  const test::CommandResult r = test::run_granboltz("validate " + file);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_LE(r.output.size(), 300u) << r.output.substr(0, 300);
  EXPECT_EQ(r.output.find('\n'), r.output.size() - 1);
}

TEST(YamlReader, QuoteValueEscapesControlCharactersAndCutsLongValues) {
  EXPECT_EQ(quote_value("plain 0.5"), "plain 0.5");
  EXPECT_EQ(quote_value("a\nb\tc\rd\x1b[0m\x7f"), "a\\nb\\tc\\rd\\x1B[0m\\x7F");
  EXPECT_EQ(quote_value("\xc2\x9b\xe2\x80\xae\xe2\x80\xa8"), "\\u009B\\u202E\\u2028");
  EXPECT_EQ(quote_value("caf\xc3\xa9 \xce\xbb"), "caf\xc3\xa9 \xce\xbb");  // UTF-8 stays
  EXPECT_EQ(quote_value("bad \xff\xc3"), "bad \\xFF\\xC3");  // not UTF-8: byte by byte
  EXPECT_EQ(quote_value(std::string(80, 'y')), std::string(80, 'y'));
  EXPECT_EQ(quote_value(std::string(81, 'y')), std::string(80, 'y') + "\u2026 (81 characters)");
  EXPECT_EQ(quote_value("\xce\xbb\xce\xbb\xce\xbb", 2), "\xce\xbb\xce\xbb\u2026 (3 characters)");
  EXPECT_EQ(quote_value(std::string(10, '\n'), 6), "\\n\\n\\n\u2026 (10 characters)");
}
