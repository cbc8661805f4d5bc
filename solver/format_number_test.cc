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

}  // namespace
}  // namespace odomcal
