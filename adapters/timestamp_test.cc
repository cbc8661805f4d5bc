#include "odomcal/adapters/timestamp.h"

#include "odomcal/adapters/test_support.h"

#include <gtest/gtest.h>

#include <limits>
#include <stdexcept>
#include <string>

namespace odomcal {
namespace {

// Parses or fails the test; returns 0 on failure so the caller's EXPECT fails.
int64_t ParseOrFail(const std::string& text, TimeUnit unit) {
  std::string error;
  const std::optional<int64_t> stamp_ns = ParseTimestampNs(text, unit, &error);
  EXPECT_TRUE(stamp_ns.has_value()) << text << ": " << error;
  return stamp_ns.value_or(0);
}

std::string ErrorOf(const std::string& text, TimeUnit unit) {
  std::string error;
  const std::optional<int64_t> stamp_ns = ParseTimestampNs(text, unit, &error);
  EXPECT_FALSE(stamp_ns.has_value()) << text << " parsed as " << *stamp_ns;
  EXPECT_FALSE(error.empty()) << text;
  return error;
}

TEST(ParseTimeUnit, AcceptsTheFourNames) {
  EXPECT_EQ(ParseTimeUnit("s"), TimeUnit::kSeconds);
  EXPECT_EQ(ParseTimeUnit("ms"), TimeUnit::kMilliseconds);
  EXPECT_EQ(ParseTimeUnit("us"), TimeUnit::kMicroseconds);
  EXPECT_EQ(ParseTimeUnit("ns"), TimeUnit::kNanoseconds);
  EXPECT_STREQ(TimeUnitName(TimeUnit::kMicroseconds), "us");
}

TEST(ParseTimeUnit, RejectsOtherNames) {
  EXPECT_THROW(ParseTimeUnit("sec"), std::invalid_argument);
  EXPECT_THROW(ParseTimeUnit(""), std::invalid_argument);
  EXPECT_THROW(ParseTimeUnit("NS"), std::invalid_argument);
}

TEST(ParseTimestampNs, ExactSecondsWithoutDoubleRounding) {
  // As a double, 1403636579.763555584 is 1403636579.7635555267...
  EXPECT_EQ(ParseOrFail("1403636579.763555584", TimeUnit::kSeconds),
            1403636579763555584);
  EXPECT_EQ(ParseOrFail("1403636579.000000001", TimeUnit::kSeconds),
            1403636579000000001);
  EXPECT_EQ(ParseOrFail("1403636579", TimeUnit::kSeconds), 1403636579000000000);
  EXPECT_EQ(ParseOrFail("1403636579.5", TimeUnit::kSeconds),
            1403636579500000000);
}

TEST(ParseTimestampNs, NineteenDigitNanoseconds) {
  EXPECT_EQ(ParseOrFail("1403636579763555584", TimeUnit::kNanoseconds),
            1403636579763555584);
  EXPECT_EQ(ParseOrFail("9223372036854775807", TimeUnit::kNanoseconds),
            std::numeric_limits<int64_t>::max());
  EXPECT_EQ(ParseOrFail("-9223372036854775807", TimeUnit::kNanoseconds),
            -std::numeric_limits<int64_t>::max());
}

TEST(ParseTimestampNs, OtherUnits) {
  EXPECT_EQ(ParseOrFail("1403636579763.555584", TimeUnit::kMilliseconds),
            1403636579763555584);
  EXPECT_EQ(ParseOrFail("1403636579763555.584", TimeUnit::kMicroseconds),
            1403636579763555584);
  EXPECT_EQ(ParseOrFail("+2.25", TimeUnit::kMilliseconds), 2250000);
  EXPECT_EQ(ParseOrFail("12", TimeUnit::kMicroseconds), 12000);
}

TEST(ParseTimestampNs, SignsAndShortForms) {
  EXPECT_EQ(ParseOrFail("-1.5", TimeUnit::kSeconds), -1500000000);
  EXPECT_EQ(ParseOrFail("+1.5", TimeUnit::kSeconds), 1500000000);
  EXPECT_EQ(ParseOrFail(".5", TimeUnit::kSeconds), 500000000);
  EXPECT_EQ(ParseOrFail("5.", TimeUnit::kSeconds), 5000000000);
  EXPECT_EQ(ParseOrFail("-0", TimeUnit::kSeconds), 0);
  EXPECT_EQ(ParseOrFail("007", TimeUnit::kNanoseconds), 7);
  EXPECT_EQ(ParseOrFail("  42\t", TimeUnit::kNanoseconds), 42);
}

TEST(ParseTimestampNs, RoundsExtraFractionDigitsHalfAwayFromZero) {
  EXPECT_EQ(ParseOrFail("0.0000000005", TimeUnit::kSeconds), 1);
  EXPECT_EQ(ParseOrFail("-0.0000000005", TimeUnit::kSeconds), -1);
  EXPECT_EQ(ParseOrFail("0.00000000049999", TimeUnit::kSeconds), 0);
  EXPECT_EQ(ParseOrFail("1.9999999999", TimeUnit::kSeconds), 2000000000);
  EXPECT_EQ(ParseOrFail("-1.9999999994", TimeUnit::kSeconds), -1999999999);
  EXPECT_EQ(ParseOrFail("1.0005", TimeUnit::kMicroseconds), 1001);
  EXPECT_EQ(ParseOrFail("-1.0005", TimeUnit::kMicroseconds), -1001);
}

// Seconds read as nanoseconds would otherwise round to duplicates.
TEST(ParseTimestampNs, RejectsFractionalNanoseconds) {
  EXPECT_TRUE(
      Contains(ErrorOf("1700000000.1", TimeUnit::kNanoseconds), "time unit"));
  EXPECT_EQ(ParseOrFail("42.000", TimeUnit::kNanoseconds), 42);
}

TEST(ParseTimestampNs, RejectsNonDecimalText) {
  for (const char* text : {"",
                           " ",
                           "-",
                           "+",
                           ".",
                           "-.",
                           "abc",
                           "1.2.3",
                           "1 2",
                           "nan",
                           "inf",
                           "0x10",
                           "1,5",
                           "--1",
                           "1-"}) {
    SCOPED_TRACE(text);
    const std::string error = ErrorOf(text, TimeUnit::kSeconds);
  }
  EXPECT_TRUE(Contains(ErrorOf("abc", TimeUnit::kSeconds), "'abc'"));
}

TEST(ParseTimestampNs, RejectsExponent) {
  const std::string error = ErrorOf("1.4e9", TimeUnit::kSeconds);
  EXPECT_TRUE(Contains(error, "exponent")) << error;
  ErrorOf("1E3", TimeUnit::kNanoseconds);
}

TEST(ParseTimestampNs, RejectsOverflow) {
  EXPECT_TRUE(Contains(ErrorOf("9223372036854775808", TimeUnit::kNanoseconds),
                       "int64"));
  ErrorOf("-9223372036854775808", TimeUnit::kNanoseconds);
  ErrorOf("99999999999999999999999", TimeUnit::kNanoseconds);
  // 9223372036.854775807 s is the largest representable value.
  EXPECT_EQ(ParseOrFail("9223372036.854775807", TimeUnit::kSeconds),
            std::numeric_limits<int64_t>::max());
  ErrorOf("9223372036.854775808", TimeUnit::kSeconds);
  ErrorOf("9223372036854776", TimeUnit::kMicroseconds);
}

TEST(ParseTimestampNs, PlausibilityGuardForSeconds) {
  const std::string error = ErrorOf("1403636579763555584", TimeUnit::kSeconds);
  EXPECT_TRUE(Contains(error, "1403636579763555584")) << error;
  EXPECT_TRUE(Contains(error, "looks like nanoseconds or microseconds"))
      << error;
  EXPECT_TRUE(Contains(error, "time unit is seconds")) << error;
  EXPECT_TRUE(Contains(error, "pass the time unit flag")) << error;
  // Microseconds read as seconds, and negative values, too.
  ErrorOf("1403636579763555", TimeUnit::kSeconds);
  ErrorOf("-1403636579763555", TimeUnit::kSeconds);
  // Below the 1e11 s guard but beyond int64 ns (~9.2e9 s): an overflow.
  const std::string overflow = ErrorOf("99999999999", TimeUnit::kSeconds);
  EXPECT_TRUE(Contains(overflow, "int64")) << overflow;
}

TEST(ParseTimestampNs, PlausibilityGuardForMilliseconds) {
  const std::string error =
      ErrorOf("1403636579763555584", TimeUnit::kMilliseconds);
  EXPECT_TRUE(Contains(error, "time unit is milliseconds")) << error;
  ErrorOf("1403636579763555", TimeUnit::kMilliseconds);
  EXPECT_EQ(ParseOrFail("1403636579763", TimeUnit::kMilliseconds),
            1403636579763000000);
}

TEST(ParseTimestampNs, NullErrorPointerIsAllowed) {
  EXPECT_FALSE(ParseTimestampNs("x", TimeUnit::kSeconds, nullptr).has_value());
  EXPECT_EQ(ParseTimestampNs("3", TimeUnit::kSeconds, nullptr), 3000000000);
}

TEST(FormatTimestampSeconds, ExactNineFractionDigits) {
  EXPECT_EQ(FormatTimestampSeconds(1403636579763555584),
            "1403636579.763555584");
  EXPECT_EQ(FormatTimestampSeconds(0), "0.000000000");
  EXPECT_EQ(FormatTimestampSeconds(1), "0.000000001");
  EXPECT_EQ(FormatTimestampSeconds(-1500000000), "-1.500000000");
  EXPECT_EQ(FormatTimestampSeconds(-1), "-0.000000001");
  EXPECT_EQ(FormatTimestampSeconds(std::numeric_limits<int64_t>::min()),
            "-9223372036.854775808");
}

TEST(FormatTimestampSeconds, RoundTripsThroughParse) {
  for (const int64_t stamp_ns : {int64_t{0},
                                 int64_t{1},
                                 int64_t{-1},
                                 int64_t{999999999},
                                 int64_t{1403636579763555584},
                                 int64_t{-1403636579763555584},
                                 std::numeric_limits<int64_t>::max()}) {
    EXPECT_EQ(ParseOrFail(FormatTimestampSeconds(stamp_ns), TimeUnit::kSeconds),
              stamp_ns);
  }
}

TEST(ElapsedSeconds, SubtractsBeforeConverting) {
  const int64_t t0 = 1403636579763555584;
  EXPECT_EQ(ElapsedSeconds(t0, t0 + 1), 1e-9);
  EXPECT_EQ(ElapsedSeconds(t0 + 1, t0), -1e-9);
  EXPECT_EQ(ElapsedSeconds(t0, t0 + 250000000), 0.25);
  // Converting first would lose the nanosecond entirely.
  EXPECT_EQ(NsToSeconds(t0 + 1) - NsToSeconds(t0), 0.0);
  EXPECT_EQ(NsToSeconds(1500000000), 1.5);
  EXPECT_EQ(NsToSeconds(-250000000), -0.25);
}

}  // namespace
}  // namespace odomcal
