#include "odomcal/solver/format_number.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace odomcal {
namespace {

TEST(FormatNumber, ShortestTextThatReadsBackTheSame) {
  EXPECT_EQ(FormatNumber(-1.0), "-1");
  EXPECT_EQ(FormatNumber(0.25), "0.25");
  EXPECT_EQ(FormatNumber(1.5), "1.5");
  EXPECT_EQ(FormatNumber(0.1 + 0.2), "0.30000000000000004");
  EXPECT_EQ(FormatNumber(1e9), "1e+09");  // shorter than 1000000000
  EXPECT_EQ(FormatNumber(123456.0), "123456");
  // Not the 309 digits of std::to_string.
  EXPECT_EQ(FormatNumber(std::numeric_limits<double>::max()),
            "1.7976931348623157e+308");
  EXPECT_EQ(FormatNumber(std::numeric_limits<double>::denorm_min()), "5e-324");
  EXPECT_EQ(FormatNumber(INFINITY), "inf");
  EXPECT_EQ(FormatNumber(-INFINITY), "-inf");
  EXPECT_EQ(FormatNumber(NAN), "nan");
}

TEST(FormatRounded, KeepsThreeSignificantDigits) {
  EXPECT_EQ(FormatRounded(0.36927100577991273), "0.369");
  EXPECT_EQ(FormatRounded(0.030000000000000002), "0.03");
  EXPECT_EQ(FormatRounded(66.43), "66.4");
  EXPECT_EQ(FormatRounded(-0.0004567), "-0.000457");
  EXPECT_EQ(FormatRounded(2.5e-7), "2.5e-07");
}

TEST(FormatRounded, WholeNumbersStayWhole) {
  // Not "%.3g"'s "1e+03" or "1.23e+03".
  EXPECT_EQ(FormatRounded(1000.0), "1000");
  EXPECT_EQ(FormatRounded(1234.5), "1230");
  EXPECT_EQ(FormatRounded(0.0), "0");
}

TEST(FormatRounded, OtherPrecisionsAndNonFiniteValues) {
  EXPECT_EQ(FormatRounded(0.36927, 2), "0.37");
  EXPECT_EQ(FormatRounded(0.36927, 0), "0.4");  // at least one digit
  EXPECT_EQ(FormatRounded(std::numeric_limits<double>::quiet_NaN()), "nan");
  EXPECT_EQ(FormatRounded(-std::numeric_limits<double>::infinity()), "-inf");
}

}  // namespace
}  // namespace odomcal
