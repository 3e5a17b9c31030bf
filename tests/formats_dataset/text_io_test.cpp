#include "slamprep/eval/formats/text_io.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <charconv>
#include <cmath>
#include <limits>
#include <random>

#include "slamprep/core/error.hpp"

namespace slamprep::eval {
namespace {

double parse(const std::string& text) {
  return parseFiniteDouble(text, {"f.csv", 3}, "x");
}

std::string format(double value) {
  std::string out;
  appendDouble(out, value);
  return out;
}

TEST(TextIo, DoublesRoundTripBitForBit) {
  std::mt19937_64 rng(1);
  int tested = 0;
  for (int k = 0; k < 200000; ++k) {
    const double value = std::bit_cast<double>(rng());  // every exponent, every mantissa
    if (!std::isfinite(value)) continue;
    ASSERT_EQ(std::bit_cast<std::uint64_t>(parse(format(value))),
              std::bit_cast<std::uint64_t>(value))
        << format(value);
    ++tested;
  }
  EXPECT_GT(tested, 199000);  // NaN/Inf patterns are 1/2048 of random bits
  for (double v : {0.0, -0.0, 1.0, 0.1, std::numeric_limits<double>::denorm_min(),
                   std::numeric_limits<double>::max(), -std::numeric_limits<double>::lowest()})
    EXPECT_EQ(std::bit_cast<std::uint64_t>(parse(format(v))), std::bit_cast<std::uint64_t>(v));
}

TEST(TextIo, NegativeZeroKeepsItsSignAsAJsonFloat) {
  EXPECT_EQ(format(-0.0), "-0.0");
  EXPECT_EQ(format(0.0), "0");
  EXPECT_EQ(format(0.1), "0.1");  // shortest, not %.17g's 0.10000000000000001
}

TEST(TextIo, RejectsWhatIsNotAFiniteNumber) {
  for (const char* bad : {"", "nan", "NaN", "inf", "-inf", "1e400", "1.0x", "+1", " 1", "0x10"}) {
    try {
      parse(bad);
      ADD_FAILURE() << "accepted \"" << bad << "\"";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("f.csv:3: x: "), std::string::npos) << e.what();
    }
  }
  EXPECT_EQ(parse("-1.5e-3"), -1.5e-3);
}

TEST(TextIo, ParsesInt64Strictly) {
  const TextLocation where{"e.csv", 9};
  EXPECT_EQ(parseInt64("-9223372036854775808", where, "n"),
            std::numeric_limits<std::int64_t>::min());
  for (const char* bad : {"1.5", "9223372036854775808", "12a", "", "1e3"})
    EXPECT_THROW(parseInt64(bad, where, "n"), InputError) << bad;
}

TEST(TextIo, RequireIncreasingNamesDuplicatesAndOrder) {
  const TextLocation where{"g.tum", 4};
  EXPECT_NO_THROW(requireIncreasing(1.0, 1.5, where, "t"));
  try {
    requireIncreasing(1.5, 1.5, where, "t");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(
        e.what(),
        "g.tum:4: t: duplicate timestamp 1.5 after 1.5 (timestamps must increase strictly)");
  }
  EXPECT_THROW(requireIncreasing(2.0, 1.0, where, "t"), InputError);
}

TEST(TextIo, LineCursorCountsLinesAndStripsCarriageReturns) {
  LineCursor cursor("a\r\n\nb\nc");
  std::string_view line;
  std::vector<std::string> lines;
  while (cursor.next(line)) lines.emplace_back(line);
  EXPECT_EQ(lines, (std::vector<std::string>{"a", "", "b", "c"}));
  EXPECT_EQ(cursor.lineNumber(), 4u);
}

TEST(TextIo, SplitsFields) {
  std::vector<std::string_view> f;
  splitFields(" 1, 2 ,3\r", ',', f);
  EXPECT_EQ(f, (std::vector<std::string_view>{"1", "2", "3"}));
  splitFields("1,,", ',', f);
  EXPECT_EQ(f.size(), 3u);
  splitWhitespace("\t1  2 3 ", f);
  EXPECT_EQ(f, (std::vector<std::string_view>{"1", "2", "3"}));
}

TEST(TextIo, MissingFileIsAnInputError) {
  try {
    readTextFile("/nonexistent/slamprep/x.csv");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/slamprep/x.csv"), std::string::npos);
  }
}

}  // namespace
}  // namespace slamprep::eval
