#include "odomcal/plugin/report/systematics_report.h"

#include <gtest/gtest.h>

namespace odomcal {
namespace {

using nlohmann::json;

// Offsets are written as ns / 1e9, the double nearest the decimal, so the
// JSON says 0.3001, not 1e-9 * ns = 0.30010000000000003.
TEST(SystematicsJson, WritesOffsetsAsTheirShortDecimal) {
  SystematicsEstimate estimate;
  estimate.camera_time_offset_ns = 300100000;
  estimate.coarse_search_ran = true;
  estimate.coarse.peak_ns = 123456789;
  json out = json::object();
  AddSystematicsJson(estimate, &out);
  EXPECT_EQ(out["camera_time_offset_s"].dump(), "0.3001");
  EXPECT_EQ(out["diagnostics"]["time_offset"]["coarse_peak_s"].dump(),
            "0.123456789");
}

}  // namespace
}  // namespace odomcal
