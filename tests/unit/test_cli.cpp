// The command-line parser that every subcommand shares: strict, so typos fail loudly.
#include "app/cli.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace hdof {
namespace {

// Options shaped like the render command's, bound to a parser.
struct Parsed {
  std::string scene, out = "default.png";
  double aperture = 0;
  float focus = 0;
  uint32_t spp = 1;
  bool json = false;
  ArgParser parser{"test", "SCENE [options]", "A parser for tests."};

  Parsed() {
    parser.positional("SCENE", "scene to load", &scene);
    parser.option("--out", "FILE", "output image", &out);
    parser.option("--aperture", "F", "f-number", &aperture);
    parser.option("--focus", "M", "focus distance", &focus);
    parser.option("--spp", "N", "samples per pixel", &spp);
    parser.flag("--json", "print JSON", &json);
  }
  Parsed(const Parsed&) = delete;
  Parsed& operator=(const Parsed&) = delete;
};

bool parse(const std::vector<std::string>& args, Parsed& p) { return p.parser.parse(args); }

TEST(ArgParser, ReadsOptionsFlagsAndPositionals) {
  Parsed p;
  ASSERT_TRUE(
      parse({"--spp", "64", "room.gltf", "--aperture", "2.8", "--focus", "1.5", "--json"}, p));
  EXPECT_EQ(p.scene, "room.gltf");
  EXPECT_EQ(p.spp, 64u);
  EXPECT_DOUBLE_EQ(p.aperture, 2.8);
  EXPECT_FLOAT_EQ(p.focus, 1.5f);
  EXPECT_TRUE(p.json);
  EXPECT_EQ(p.out, "default.png");  // untouched when not given
  EXPECT_TRUE(p.parser.given("--spp"));
  EXPECT_FALSE(p.parser.given("--out"));
  EXPECT_FALSE(p.parser.given("--no-such-option"));
}

TEST(ArgParser, AcceptsTheEqualsForm) {
  Parsed p;
  ASSERT_TRUE(parse({"s", "--out=a=b.png", "--spp=8", "--aperture=-1.5"}, p));
  EXPECT_EQ(p.out, "a=b.png");  // only the first '=' separates
  EXPECT_EQ(p.spp, 8u);
  EXPECT_DOUBLE_EQ(p.aperture, -1.5);
}

TEST(ArgParser, UnknownOptionIsAUsageError) {
  Parsed p;
  EXPECT_THROW(parse({"s", "--sp", "4"}, p), UsageError);
  EXPECT_THROW(parse({"s", "--spp4"}, p), UsageError);
  try {
    parse({"s", "--colour"}, p);
    FAIL();
  } catch (const UsageError& e) {
    EXPECT_NE(std::string(e.what()).find("unknown option --colour"), std::string::npos);
  }
}

TEST(ArgParser, MissingValueIsAUsageError) {
  Parsed p;
  EXPECT_THROW(parse({"s", "--spp"}, p), UsageError);
  EXPECT_THROW(parse({"s", "--out"}, p), UsageError);
}

TEST(ArgParser, FlagWithAValueIsAUsageError) {
  Parsed p;
  EXPECT_THROW(parse({"s", "--json=yes"}, p), UsageError);
}

TEST(ArgParser, MissingOrExtraPositionalIsAUsageError) {
  Parsed p;
  EXPECT_THROW(parse({"--spp", "4"}, p), UsageError);
  EXPECT_THROW(parse({"a", "b"}, p), UsageError);
}

TEST(ArgParser, BadNumbersAreUsageErrors) {
  for (const char* bad : {"abc", "nan", "inf", "1e999", "", "2.5x"}) {
    Parsed p;
    EXPECT_THROW(parse({"s", "--aperture", bad}, p), UsageError) << bad;
    EXPECT_THROW(parse({"s", "--focus", bad}, p), UsageError) << bad;
  }
}

TEST(ArgParser, BadCountsAreUsageErrors) {
  for (const char* bad : {"abc", "nan", "1e999", "-3", "", "2.5", "4294967296", "1e3"}) {
    Parsed p;
    EXPECT_THROW(parse({"s", "--spp", bad}, p), UsageError) << bad;
  }
  Parsed p;
  ASSERT_TRUE(parse({"s", "--spp", "4294967295"}, p));
  EXPECT_EQ(p.spp, 4294967295u);
}

TEST(ArgParser, HelpReturnsFalseAndListsTheOptions) {
  Parsed p;
  testing::internal::CaptureStdout();
  bool proceed = parse({"s", "--help"}, p);
  std::string help = testing::internal::GetCapturedStdout();
  EXPECT_FALSE(proceed);
  EXPECT_NE(help.find("usage: hdof test SCENE [options]"), std::string::npos) << help;
  EXPECT_NE(help.find("--spp N"), std::string::npos) << help;
  EXPECT_NE(help.find("--json"), std::string::npos) << help;
}

TEST(ParseNumber, AcceptsFiniteNumbersOnly) {
  EXPECT_DOUBLE_EQ(parseNumber("2.5", "x"), 2.5);
  EXPECT_DOUBLE_EQ(parseNumber("-1e-3", "x"), -1e-3);
  for (const char* bad : {"nan", "inf", "-inf", "1e999", "abc", "", "1,5"})
    EXPECT_THROW(parseNumber(bad, "x"), UsageError) << bad;
}

TEST(ParseCount, AcceptsWholeNumbersInRange) {
  EXPECT_EQ(parseCount("0", "n"), 0u);
  EXPECT_EQ(parseCount("64", "n"), 64u);
  for (const char* bad : {"abc", "nan", "1e999", "-3", "-0", "", "4294967296"})
    EXPECT_THROW(parseCount(bad, "n"), UsageError) << bad;
}

TEST(ParseSize, AcceptsWidthByHeight) {
  Size2 size = parseSize("640x360");
  EXPECT_EQ(size.width, 640u);
  EXPECT_EQ(size.height, 360u);
  EXPECT_EQ(parseSize("1x1").width, 1u);
  EXPECT_EQ(parseSize("8192x8192").height, 8192u);
  EXPECT_EQ(parseSize("100x200", 200).height, 200u);
}

TEST(ParseSize, RejectsMalformedAndOutOfRange) {
  for (const char* bad : {"0x0", "0x360", "640x0", "100000x100000", "8193x1", "640", "x360", "640x",
                          "axb", "", "640x360x2", "-640x360", "640*360"})
    EXPECT_THROW(parseSize(bad), UsageError) << bad;
  EXPECT_THROW(parseSize("300x200", 256), UsageError);
}

}  // namespace
}  // namespace hdof
