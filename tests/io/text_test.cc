#include "io/text.h"

#include <gtest/gtest.h>

#include <cmath>

#include "io/result.h"
#include "kernel/random.h"

namespace splam::io {
namespace {

TEST(SplitTokens, SplitsOnSpacesTabsAndCarriageReturns) {
  EXPECT_EQ(SplitTokens("  a b\tc\r"), (std::vector<std::string_view>{"a", "b", "c"}));
  EXPECT_TRUE(SplitTokens("   ").empty());
}

TEST(Quoted, EscapesControlBytesAndCutsLongTokens) {
  EXPECT_EQ(Quoted("abc"), "'abc'");
  EXPECT_EQ(Quoted(std::string_view("a\0b\x7f", 4)), "'a\\x00b\\x7f'");
  EXPECT_EQ(Quoted(std::string(100, 'z')), "'" + std::string(40, 'z') + "...'");
}

TEST(ParseDouble, AcceptsNumbersAndSpecialValuesOnly) {
  EXPECT_EQ(ParseDouble("1.5"), 1.5);
  EXPECT_EQ(ParseDouble("+2"), 2.0);
  EXPECT_EQ(ParseDouble("-1e-3"), -1e-3);
  EXPECT_TRUE(std::isnan(*ParseDouble("nan")));
  EXPECT_TRUE(std::isinf(*ParseDouble("inf")));
  EXPECT_FALSE(ParseDouble("1.5x"));
  EXPECT_FALSE(ParseDouble(""));
  EXPECT_FALSE(ParseDouble("abc"));
  EXPECT_EQ(ParseInteger("42"), 42);
  EXPECT_FALSE(ParseInteger("4.2"));
}

TEST(FormatDouble, PropertyRoundTripsExactly) {
  kernel::Random random(1);
  for (int i = 0; i < 10000; ++i) {
    const double v = random.Gaussian(1.0) * std::pow(10.0, random.Uniform(-20, 20));
    EXPECT_EQ(*ParseDouble(FormatDouble(v)), v);
  }
  EXPECT_EQ(FormatDouble(0.1), "0.1");
  EXPECT_EQ(FormatDouble(INFINITY), "inf");
  EXPECT_EQ(FormatDouble(NAN), "nan");
}

TEST(FileError, NamesFileAndLine) {
  EXPECT_EQ(FileError("a.clf", 3, "bad").message(), "a.clf:3: bad");
  EXPECT_EQ(FileError("a.clf", 0, "bad").message(), "a.clf: bad");
}

}  // namespace
}  // namespace splam::io
