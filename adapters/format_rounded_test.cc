#include "odomcal/adapters/format_rounded.h"

#include <gtest/gtest.h>

#include <limits>

namespace odomcal {
namespace {

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
