#include "odomcal/adapters/odometry_csv_header.h"

#include "odomcal/solver/angles.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace odomcal {
namespace {

std::optional<OdometryCsvColumns> Parse(std::vector<std::string_view> fields,
                                        std::string* error = nullptr) {
  return ParseOdometryCsvHeader(fields, error);
}

std::string ErrorOf(std::vector<std::string_view> fields) {
  std::string error;
  EXPECT_FALSE(ParseOdometryCsvHeader(fields, &error).has_value());
  return error;
}

TEST(ParseOdometryCsvHeader, PlainNamesKeepTheDefaultUnits) {
  for (const auto& fields : std::vector<std::vector<std::string_view>>{
           {"timestamp", "x", "y", "yaw"},
           {"t", "x", "y", "theta"},
           {"time", "x_m", "y_m", "yaw_rad"}}) {
    const auto columns = Parse(fields);
    ASSERT_TRUE(columns.has_value()) << fields[0];
    EXPECT_EQ(columns->time, 0);
    EXPECT_EQ(columns->x, 1);
    EXPECT_EQ(columns->y, 2);
    EXPECT_EQ(columns->yaw, 3);
    EXPECT_FALSE(columns->time_unit.has_value());
    EXPECT_EQ(columns->x_to_m, 1.0);
    EXPECT_EQ(columns->y_to_m, 1.0);
    EXPECT_EQ(columns->yaw_to_rad, 1.0);
  }
}

TEST(ParseOdometryCsvHeader, AnyOrderAnyCase) {
  const auto columns = Parse({"Yaw", "TIMESTAMP", "x", "Y"});
  ASSERT_TRUE(columns.has_value());
  EXPECT_EQ(columns->yaw, 0);
  EXPECT_EQ(columns->time, 1);
  EXPECT_EQ(columns->x, 2);
  EXPECT_EQ(columns->y, 3);
  EXPECT_EQ(columns->yaw_name, "Yaw");
  EXPECT_EQ(columns->time_name, "TIMESTAMP");
}

TEST(ParseOdometryCsvHeader, TimeSuffixesGiveTheUnit) {
  const std::pair<const char*, TimeUnit> cases[] = {
      {"t_s", TimeUnit::kSeconds},
      {"time_ms", TimeUnit::kMilliseconds},
      {"timestamp_us", TimeUnit::kMicroseconds},
      {"Timestamp_NS", TimeUnit::kNanoseconds}};
  for (const auto& [name, unit] : cases) {
    const auto columns = Parse({name, "x", "y", "yaw"});
    ASSERT_TRUE(columns.has_value()) << name;
    ASSERT_TRUE(columns->time_unit.has_value()) << name;
    EXPECT_EQ(*columns->time_unit, unit) << name;
  }
}

TEST(ParseOdometryCsvHeader, LengthAndAngleSuffixesGiveFactors) {
  const auto cm = Parse({"time", "x_cm", "y_mm", "yaw_deg"});
  ASSERT_TRUE(cm.has_value());
  EXPECT_EQ(cm->x_to_m, 0.01);
  EXPECT_EQ(cm->y_to_m, 0.001);
  EXPECT_DOUBLE_EQ(cm->yaw_to_rad, kPi / 180.0);
  const auto theta = Parse({"theta_deg", "t", "y_cm", "x_mm"});
  ASSERT_TRUE(theta.has_value());
  EXPECT_EQ(theta->x_to_m, 0.001);
  EXPECT_EQ(theta->y_to_m, 0.01);
  EXPECT_DOUBLE_EQ(theta->yaw_to_rad, kPi / 180.0);
}

TEST(ParseOdometryCsvHeader, RefusesUnknownNamesAndSuffixes) {
  const std::string accepted =
      std::string("; accepted: ") + kOdometryCsvHeaderGrammar;
  EXPECT_EQ(ErrorOf({"time", "x", "y", "heading"}),
            "header column 'heading' is not an odometry column" + accepted);
  EXPECT_EQ(ErrorOf({"time", "x_km", "y", "yaw"}),
            "header column 'x_km' is not an odometry column" + accepted);
  EXPECT_EQ(ErrorOf({"time_h", "x", "y", "yaw"}),
            "header column 'time_h' is not an odometry column" + accepted);
  // A unit suffix of another column.
  EXPECT_EQ(ErrorOf({"time_deg", "x", "y", "yaw"}),
            "header column 'time_deg' is not an odometry column" + accepted);
  EXPECT_EQ(ErrorOf({"time", "x", "y", "yaw_ms"}),
            "header column 'yaw_ms' is not an odometry column" + accepted);
}

TEST(ParseOdometryCsvHeader, RefusesDuplicateAndMissingColumns) {
  const std::string accepted =
      std::string("; accepted: ") + kOdometryCsvHeaderGrammar;
  EXPECT_EQ(ErrorOf({"time", "timestamp_ns", "x", "y"}),
            "header names the time column twice ('time' and 'timestamp_ns')" +
                accepted);
  EXPECT_EQ(ErrorOf({"time", "x", "x_cm", "yaw"}),
            "header names the x column twice ('x' and 'x_cm')" + accepted);
  EXPECT_EQ(ErrorOf({"time", "x", "y"}), "header has no yaw column" + accepted);
  EXPECT_EQ(ErrorOf({"x", "y", "yaw"}), "header has no time column" + accepted);
}

}  // namespace
}  // namespace odomcal
