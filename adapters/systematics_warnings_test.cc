#include "odomcal/adapters/systematics_warnings.h"

#include <gtest/gtest.h>

namespace odomcal {
namespace {

// The rendered 1 000-image drive's estimate: wheels +0.3 / -0.2 % on a 0.4 m
// track give yaw_per_metre 0.0124 rad/m; y's stated 3 sigma 0.27 mm.
struct UnequalWheels {
  UnequalWheels() {
    estimate.time_offset_estimated = true;
    estimate.intrinsics.yaw_scale = 0.99914;
    estimate.intrinsics.yaw_per_metre_rad = 0.01244;
    estimate.intrinsics_estimated = {true, true, true};
    estimate.intrinsics_stddev = {0.00018, 0.00016, 0.00003};
    result.status = CalibrationStatus::kSuccess;
    result.has_estimate = true;
    result.stddev_translation_xy_m = {0.00011, 0.00009};
  }
  SystematicsEstimate estimate;
  CalibrationResult result;
};

TEST(WheelTrackWarning, NamesTheShiftOfYAndTheTrackBeyondWhichItExceeds) {
  const UnequalWheels drive;
  const auto warning = WheelTrackWarning(drive.estimate, drive.result);
  ASSERT_TRUE(warning.has_value());
  // 0.01244 * 0.4^2 / (4 * 0.99914) = 0.498 mm; the 0.27 mm 3 sigma is
  // reached at sqrt(4 * 0.99914 * 0.00027 / 0.01244) = 0.294 m.
  EXPECT_EQ(*warning,
            "unequal wheels (yaw_per_metre 0.0124 rad/m) and no "
            "--wheel_track_m: if the odometry's heading comes from the wheel "
            "encoders, translation y would be off by about yaw_per_metre * "
            "b^2 / 4 for a wheel track b (0.5 mm for 0.4 m), more than its "
            "stated 3 sigma (0.27 mm) for a track over 0.29 m; give "
            "--wheel_track_m");
  CalibrationResult result = drive.result;
  AddSystematicsWarnings(drive.estimate, &result);
  ASSERT_EQ(result.warnings.size(), 1u);
  EXPECT_EQ(result.warnings[0], *warning);
}

TEST(WheelTrackWarning, NoneWhenTheTrackIsGivenOrTheShiftIsWithinTheNoise) {
  {  // --wheel_track_m given: the term is applied.
    UnequalWheels drive;
    drive.estimate.intrinsics.wheel_track_m = 0.4;
    EXPECT_FALSE(WheelTrackWarning(drive.estimate, drive.result));
  }
  {  // yaw_per_metre within its 3 sigma of 0.
    UnequalWheels drive;
    drive.estimate.intrinsics_stddev[1] = 0.005;
    EXPECT_FALSE(WheelTrackWarning(drive.estimate, drive.result));
  }
  {  // held (not estimated): nothing measured.
    UnequalWheels drive;
    drive.estimate.intrinsics_estimated[1] = false;
    EXPECT_FALSE(WheelTrackWarning(drive.estimate, drive.result));
  }
  {  // y's uncertainty covers the shift up to a 1.5 m track.
    UnequalWheels drive;
    drive.result.stddev_translation_xy_m.y() = 0.003;
    EXPECT_FALSE(WheelTrackWarning(drive.estimate, drive.result));
  }
  {  // no successful calibration, no warning.
    UnequalWheels drive;
    drive.result.status = CalibrationStatus::kUnobservable;
    EXPECT_FALSE(WheelTrackWarning(drive.estimate, drive.result));
  }
  {  // no stated uncertainty of y: nothing to compare with.
    UnequalWheels drive;
    drive.result.stddev_translation_xy_m.y() = 0.0;
    EXPECT_FALSE(WheelTrackWarning(drive.estimate, drive.result));
  }
}

// A log whose offset was to be estimated and was not (planar or 3-D): a
// warning.
TEST(SystematicsWarnings, WarnsWhenTheOffsetIsNotEstimated) {
  SystematicsEstimate estimate;
  estimate.time_offset_reason = "not determined by the motion";
  CalibrationResult result;
  AddSystematicsWarnings(estimate, &result);
  ASSERT_EQ(result.warnings.size(), 1u);
  EXPECT_EQ(result.warnings[0],
            "camera_time_offset_s not estimated (not determined by the "
            "motion): kept at 0 s");
}

}  // namespace
}  // namespace odomcal
