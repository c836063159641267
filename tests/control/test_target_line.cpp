// The interactive mode's lines (src/control/target_line.hpp): reading with a bound on what
// is kept, quoting a long line by its start and length, the words of a target and their
// errors, and the reach beyond which a target is refused.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "common/error.hpp"
#include "control/target_line.hpp"

namespace hs {
namespace {

// The lines of `text` as read_target_line gives them, with their lengths.
std::vector<std::pair<std::string, std::size_t>> lines_of(const std::string& text,
                                                          std::size_t keep = kTargetLineKept) {
  std::istringstream in(text);
  std::vector<std::pair<std::string, std::size_t>> lines;
  std::string kept;
  std::size_t length = 0;
  while (read_target_line(in, keep, kept, length)) lines.emplace_back(kept, length);
  return lines;
}

std::string reason_of(const std::string& line) {
  try {
    parse_target_words(line);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(TargetLine, EveryLineIsReadEmptyOnesAndALastOneWithoutNewlineToo) {
  const auto lines = lines_of("1 2 3\n\n  \nDOS 1 2 3\r\n\r\nlast 4 5 6");
  ASSERT_EQ(lines.size(), 6u);
  EXPECT_EQ(lines[0].first, "1 2 3");
  EXPECT_EQ(lines[1].first, "");
  EXPECT_EQ(lines[2].first, "  ");
  EXPECT_EQ(lines[3].first, "DOS 1 2 3");  // the '\r' of "\r\n" is not part of the line
  EXPECT_EQ(lines[3].second, 9u);
  EXPECT_EQ(lines[4].first, "");
  EXPECT_EQ(lines[5].first, "last 4 5 6");
  EXPECT_TRUE(lines_of("").empty());
  EXPECT_EQ(lines_of("\n").size(), 1u);  // one empty line, then the end
}

TEST(TargetLine, AMegabyteLineKeepsItsStartAndItsLengthAndTheNextLineIsIntact) {
  const std::string huge(1 << 20, '7');
  const auto lines = lines_of(huge + "\n1 2 3\n");
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0].first.size(), kTargetLineKept);
  EXPECT_EQ(lines[0].second, huge.size());
  EXPECT_EQ(lines[1].first, "1 2 3");
  const std::string quoted = quote_target_line(lines[0].first, lines[0].second);
  EXPECT_LT(quoted.size(), 100u) << quoted;
  EXPECT_NE(quoted.find("(1048576 characters)"), std::string::npos) << quoted;
  EXPECT_EQ(quote_target_line("1 2 3", 5), "'1 2 3'");  // a short line is quoted whole
}

TEST(TargetLine, WordsOfATarget) {
  const TargetWords first = parse_target_words(" 0.09 0 -1.2e-2 ");
  EXPECT_EQ(first.effector, "");
  EXPECT_EQ(first.position[2], -0.012);
  const TargetWords named = parse_target_words("tip\t1 2 3");
  EXPECT_EQ(named.effector, "tip");
  EXPECT_EQ(named.position[0], 1.0);
}

TEST(TargetLine, BadWordsSayWhy) {
  EXPECT_NE(reason_of("").find("empty line"), std::string::npos);
  EXPECT_NE(reason_of(" \t ").find("empty line"), std::string::npos);
  EXPECT_NE(reason_of("1 2").find("got 2 words"), std::string::npos);
  EXPECT_NE(reason_of("a 1 2 3 4").find("got 5 words"), std::string::npos);
  for (const char* word : {"nan", "NaN", "inf", "-inf", "1e999", "abc", "1.5x", "0x"}) {
    const std::string reason = reason_of(std::string("0 ") + word + " 0");
    EXPECT_NE(reason.find("coordinate y '" + std::string(word) + "' is not a finite number"),
              std::string::npos)
        << reason;
  }
  // A long word is quoted by its start only.
  EXPECT_LT(reason_of("0 0 " + std::string(10000, '9') + "x").size(), 200u);
}

// Before, a NUL cut the message where it stood (an exception's what() is a C string): the
// line "0.09 0<NUL> -0.012" was refused with "coordinate y '0" and nothing after it.
TEST(TargetLine, ANulIsWrittenOutAndTheMessageKeepsItsEnd) {
  const std::string line("0.09 0\0 -0.012", 14);
  EXPECT_EQ(reason_of(line), "coordinate y '0\\x00' is not a finite number");
  EXPECT_EQ(quote_target_line(line, line.size()), "'0.09 0\\x00 -0.012'");
  std::string long_line = line + std::string(100, ' ') + "\x1b[2J";
  EXPECT_EQ(quote_target_line(long_line, long_line.size()),
            "'0.09 0\\x00 -0.012                          ...' (118 characters)");
  EXPECT_EQ(quote_target_line("a\tb\r", 4), "'a\\tb\\r'");
}

// Before, 1e-320 was refused as "not a finite number": std::stod throws on the ERANGE that
// strtod sets for an underflow. A subnormal is finite, and is read as the number it is.
TEST(TargetLine, SubnormalsAndUnderflowsAreFiniteNumbers) {
  const TargetWords t = parse_target_words("1e-320 -5e-324 1e-400");
  EXPECT_EQ(t.position[0], 1e-320);
  EXPECT_GT(t.position[0], 0);
  EXPECT_EQ(t.position[1], -5e-324);
  EXPECT_EQ(t.position[2], 0);  // below the least subnormal: rounds to 0
  EXPECT_EQ(parse_target_words("0x1p3 0 0").position[0], 8);
}

TEST(TargetLine, ReachIsAThousandBodySizes) {
  const std::array<double, 3> low = {0, 0, 0}, high = {3, 4, 0};     // size 5
  EXPECT_EQ(target_reach_problem({1, 1, 0}, low, high), "");         // inside
  EXPECT_EQ(target_reach_problem({3 + 4999, 4, 0}, low, high), "");  // 999.8 sizes away
  EXPECT_EQ(target_reach_problem({0, 0, -5000}, low, high), "");     // 1000 sizes
  const std::string far = target_reach_problem({0, 0, -5001}, low, high);
  EXPECT_NE(far.find("5001 m from the body, farther than 1000 times its size (5 m"),
            std::string::npos)
      << far;
  // Beyond the square root of the largest double: the distance is still a number.
  const std::string huge = target_reach_problem({1e300, -1e300, 1e300}, low, high);
  EXPECT_NE(huge.find("1.73205e+300 m from the body"), std::string::npos) << huge;
}

}  // namespace
}  // namespace hs
