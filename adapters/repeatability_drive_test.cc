// The repeatability check (solver/repeatability.h) on simulated drives,
// associated as the command line associates them: a clean drive repeats,
// a knock of the mount halfway is found and placed.
#include "odomcal/adapters/association.h"
#include "odomcal/datasets/simulation/drive_simulator.h"
#include "odomcal/solver/calibrate.h"
#include "odomcal/solver/repeatability.h"

#include <gtest/gtest.h>

#include <cmath>

namespace odomcal {
namespace {

struct DriveCheck {
  CalibrationResult result;
  Repeatability repeatability;
  double duration_s = 0.0;
};

DriveCheck CheckDrive(uint64_t seed, double knock_deg) {
  DriveSimulatorOptions options;
  options.seed = seed;
  options.duration_s = 120.0;
  options.odometry_rate_hz = 50.0;
  options.camera_rate_hz = 5.0;
  options.camera_rotation_noise_deg = 0.05;
  options.camera_position_noise = 0.003;
  options.wheel_travel_noise_rel = 0.01;
  options.mount_knock_deg = knock_deg;
  options.mount_knock_time_s = 60.0;
  const SimulatedDrive drive = SimulateDrive(options);
  const AssociationResult association =
      AssociateCameraWithOdometry({drive.camera}, drive.odometry, {});
  CalibrationOptions calibration;
  calibration.fixed_translation_z_m = drive.odom_from_cam.translation.z();
  DriveCheck check;
  check.duration_s = options.duration_s;
  check.result = CalibrateOdomCam(association.pairs, calibration);
  check.repeatability = CheckRepeatability(
      association.pairs, check.result, calibration, RepeatabilityOptions());
  return check;
}

TEST(Repeatability, ACleanDriveRepeats) {
  const DriveCheck check = CheckDrive(21, 0.0);
  ASSERT_TRUE(check.result.IsSuccess()) << check.result.message;
  ASSERT_TRUE(check.repeatability.ran) << check.repeatability.reason;
  ASSERT_EQ(check.repeatability.tests.size(), 2u);
  for (const RepeatabilityTest& test : check.repeatability.tests) {
    EXPECT_TRUE(test.ran) << test.name << ": " << test.reason;
    EXPECT_EQ(static_cast<int>(test.blocks.size()), test.num_blocks);
    EXPECT_EQ(test.dof, (test.num_blocks - 1) * 6) << test.name;
  }
  EXPECT_TRUE(check.repeatability.consistent)
      << RepeatabilityWarning(check.repeatability);
  EXPECT_FALSE(check.repeatability.change_stamp_ns.has_value());
  EXPECT_EQ(RepeatabilityWarning(check.repeatability), "");
}

TEST(Repeatability, AKnockHalfwayIsNamedWithItsTime) {
  const DriveCheck check = CheckDrive(21, 1.0);
  ASSERT_TRUE(check.repeatability.ran) << check.repeatability.reason;
  EXPECT_FALSE(check.repeatability.consistent);
  ASSERT_TRUE(check.repeatability.change_stamp_ns.has_value());
  const double change_s =
      1e-9 * static_cast<double>(*check.repeatability.change_stamp_ns -
                                 check.repeatability.first_stamp_ns);
  // The first pair starts at the drive's start: the knock is at 60 s.
  EXPECT_NEAR(change_s, 60.0, 0.1 * check.duration_s);
  const std::string warning = RepeatabilityWarning(check.repeatability);
  EXPECT_EQ(warning.rfind("the calibration does not repeat:", 0), 0u)
      << warning;
  EXPECT_NE(warning.find("the camera mount may have moved about"),
            std::string::npos)
      << warning;
}

TEST(Repeatability, ARefusedCalibrationIsNotChecked) {
  CalibrationResult refused;
  refused.status = CalibrationStatus::kUnobservable;
  const Repeatability repeatability =
      CheckRepeatability({}, refused, CalibrationOptions(), {});
  EXPECT_FALSE(repeatability.ran);
  EXPECT_EQ(repeatability.reason, "the calibration did not succeed");
  RepeatabilityOptions bad;
  bad.alarm_probability = 0.0;
  EXPECT_THROW(bad.Check(), std::invalid_argument);
}

}  // namespace
}  // namespace odomcal
