#include "odomcal/adapters/input_plausibility.h"

#include "odomcal/adapters/test_support.h"
#include "odomcal/solver/angles.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace odomcal {
namespace {

constexpr int64_t kStart = 1700000000000000000;

// A planar log at 50 Hz driving along x at `speed` (units per second).
Trajectory StraightLog(double speed) {
  Trajectory odometry;
  odometry.source = "odometry.csv";
  odometry.planar = true;
  for (int i = 0; i < 100; ++i) {
    StampedPose pose;
    pose.stamp_ns = kStart + i * 20000000LL;
    pose.world_from_sensor.translation =
        Eigen::Vector3d(speed * 0.02 * i, 0.0, 0.0);
    odometry.poses.push_back(pose);
  }
  return odometry;
}

TEST(YawStepProblem, AcceptsSmallStepsAndTwoPiWraps) {
  EXPECT_FALSE(YawStepProblem(0.1, 0.3, false).has_value());
  EXPECT_FALSE(YawStepProblem(3.1, -3.1, false).has_value());  // wrap at pi
  EXPECT_FALSE(YawStepProblem(-3.12, 3.13, false).has_value());
  EXPECT_FALSE(YawStepProblem(100.0, 100.5, false).has_value());  // unwrapped
  EXPECT_FALSE(YawStepProblem(6.2, 0.1, false).has_value());  // wrap at 2 pi
  // pi written with six digits, at both ends of -pi..pi.
  EXPECT_FALSE(YawStepProblem(-3.14159, 3.14159, false).has_value());
}

// Odometry logged once per image turns up to pi between samples: a 70 deg
// turn across +-pi (the paper's simulation protocol) is a radian log's step.
TEST(YawStepProblem, SparseLogsTurnUpToPiAcrossTheWrap) {
  EXPECT_FALSE(YawStepProblem(-1.98621, 3.07096, false).has_value());
  EXPECT_FALSE(YawStepProblem(1.6, -1.6, false).has_value());  // 176 deg
  EXPECT_FALSE(YawStepProblem(0.0, 4.0, false).has_value());   // in 0..2 pi
  EXPECT_FALSE(YawStepProblem(2.5, 0.0, false).has_value());   // no wrap
}

TEST(YawStepProblem, DegreesWrappingAtPlusMinus180AreNamed) {
  const auto problem = YawStepProblem(179.0, -179.0, false);
  ASSERT_TRUE(problem.has_value());
  EXPECT_EQ(*problem,
            "yaw jumps from 179 to -179 rad, more than pi and not a wrap of a "
            "yaw kept in -pi..pi or 0..2 pi: the yaw looks like degrees; name "
            "the column yaw_deg in the header or convert it to radians");
  // Outside -pi..pi and 0..2 pi a step of more than pi is no wrap: degrees
  // of an unwrapped log, or a glitch.
  EXPECT_TRUE(YawStepProblem(10.0, 14.0, false).has_value());
  EXPECT_TRUE(YawStepProblem(-2.0, 5.0, false).has_value());
  // With the unit named in the header there is nothing to rename.
  EXPECT_EQ(*YawStepProblem(0.0, 7.0, true),
            "yaw jumps from 0 to 7 rad, more than pi and not a wrap of a yaw "
            "kept in -pi..pi or 0..2 pi");
}

TEST(CheckOdometrySpeed, AcceptsARobotAndACar) {
  CheckOdometrySpeed(StraightLog(0.5));
  CheckOdometrySpeed(StraightLog(19.0));
  CheckOdometrySpeed(Trajectory());
}

TEST(CheckOdometrySpeed, CentimetresAreNamed) {
  EXPECT_EQ(
      FormatErrorOf([] { CheckOdometrySpeed(StraightLog(50.0)); }),
      "odometry.csv: the odometry moves at 50.0 m/s between samples (90th "
      "percentile), faster than 20 m/s: the positions look like centimetres or "
      "millimetres; name the columns x_cm,y_cm or x_mm,y_mm in the header or "
      "convert them to metres");
  Trajectory tum = StraightLog(500.0);
  tum.planar = false;
  EXPECT_TRUE(Contains(FormatErrorOf([&] { CheckOdometrySpeed(tum); }),
                       "millimetres; convert them to metres"));
}

TEST(CheckOdometrySpeed, OneGlitchIsNotAUnitMistake) {
  Trajectory odometry = StraightLog(0.5);
  odometry.poses[50].world_from_sensor.translation.x() += 3.0;  // 150 m/s twice
  CheckOdometrySpeed(odometry);
}

// Pairs turning by `angles` (rad) as the camera sees them; the odometry
// reports each angle multiplied by `odometry_factor` and wrapped.
MotionPairs TurningPairs(const std::vector<double>& angles,
                         double odometry_factor) {
  MotionPairs pairs;
  const Eigen::Quaterniond cam_from_odom(
      Eigen::AngleAxisd(1.0, Eigen::Vector3d(1, 2, 3).normalized()));
  for (const double angle : angles) {
    MotionPair pair;
    pair.odom_i_from_odom_j.rotation = YawRotation(odometry_factor * angle);
    pair.cam_i_from_cam_j.rotation =
        cam_from_odom * YawRotation(angle) * cam_from_odom.inverse();
    pairs.push_back(pair);
  }
  return pairs;
}

const std::vector<double> kAngles = {
    0.05, -0.08, 0.1, 0.03, -0.02, 0.07, 0.0, 0.0};

TEST(CheckRotationAngleUnits, AcceptsAgreeingAngles) {
  CheckRotationAngleUnits(TurningPairs(kAngles, 1.0), "odometry.csv");
  // Straight driving decides nothing.
  CheckRotationAngleUnits(TurningPairs({0.0, 0.001, 0.0}, 180.0 / kPi),
                          "odometry.csv");
}

TEST(CheckRotationAngleUnits, DegreesAreNamed) {
  const std::string error = FormatErrorOf([] {
    CheckRotationAngleUnits(TurningPairs(kAngles, 180.0 / kPi), "odometry.csv");
  });
  EXPECT_TRUE(Contains(
      error,
      "odometry.csv: the odometry turns 57.3 times as far as the camera"))
      << error;
  EXPECT_TRUE(Contains(
      error,
      "over 6 motion pairs): the odometry yaw looks like degrees; name "
      "the column yaw_deg in the header or convert it to radians"))
      << error;
  // Turns of more than 180 "degrees-as-radians" per pair wrap; still found.
  const std::vector<double> large = {0.1, -0.2, 0.15, 0.3, -0.25};
  EXPECT_TRUE(Contains(FormatErrorOf([&] {
                         CheckRotationAngleUnits(
                             TurningPairs(large, 180.0 / kPi), "o.csv");
                       }),
                       "looks like degrees"));
}

TEST(CheckRotationAngleUnits, RadiansNamedAsDegreesAreNamed) {
  const std::string error = FormatErrorOf([] {
    CheckRotationAngleUnits(TurningPairs({0.5, -0.8, 1.0, 0.3}, kPi / 180.0),
                            "o.csv");
  });
  EXPECT_TRUE(
      Contains(error,
               "the odometry yaw looks like radians read as degrees; name the "
               "column yaw or yaw_rad in the header"))
      << error;
}

TEST(CheckImageTimesAreNotFrameNumbers, FrameNumbersAreNamed) {
  EXPECT_EQ(
      FormatErrorOf([] {
        CheckImageTimesAreNotFrameNumbers(
            {3, 1, 2, 4}, "sparse", "read from the image names as ns");
      }),
      "sparse: the image times were read from the image names as ns and are "
      "1e-09 s "
      "apart (median): the names look like frame numbers, not times; pass "
      "--image_timestamps with a CSV image_name,timestamp (or "
      "--file_name_time_unit "
      "if the names are times)");
  // 30 Hz times, in ns since the start or since the epoch.
  CheckImageTimesAreNotFrameNumbers({0, 33333333, 66666666}, "sparse", "as ns");
  CheckImageTimesAreNotFrameNumbers(
      {kStart, kStart + 33333333}, "sparse", "as ns");
  CheckImageTimesAreNotFrameNumbers({5}, "sparse", "as ns");
}

TEST(TimeSpansText, BothSpansAndTheOffset) {
  Trajectory camera;
  camera.poses.resize(2);
  camera.poses[0].stamp_ns = 0;
  camera.poses[1].stamp_ns = 3900000000;
  const Trajectory odometry = StraightLog(0.5);
  EXPECT_EQ(
      TimeSpansText({camera}, "read from the image names as ns", 0, odometry),
      "camera times 0.000-3.900 s (read from the image names as ns), odometry "
      "1700000000.000-1700000001.980 s");
  EXPECT_EQ(TimeSpansText({camera}, "", 3600000000000, odometry),
            "camera times 0.000-3.900 s (then shifted by 3600.000 s), odometry "
            "1700000000.000-1700000001.980 s");
  // An estimated offset is named as such, even when it is zero.
  EXPECT_EQ(TimeSpansText({camera}, "", 301000000, odometry, true),
            "camera times 0.000-3.900 s (then shifted by the estimated offset "
            "0.301 s), odometry 1700000000.000-1700000001.980 s");
  EXPECT_EQ(TimeSpansText({camera}, "", 0, odometry, true),
            "camera times 0.000-3.900 s (then shifted by the estimated offset "
            "0.000 s), odometry 1700000000.000-1700000001.980 s");
}

TEST(ExtrinsicDistanceWarning, OnlyBeyondFiveMetres) {
  EXPECT_FALSE(ExtrinsicDistanceWarning(Rigid3d(Eigen::Quaterniond::Identity(),
                                                Eigen::Vector3d(4.0, 2.0, 0.5)))
                   .has_value());
  EXPECT_EQ(*ExtrinsicDistanceWarning(Rigid3d(Eigen::Quaterniond::Identity(),
                                              Eigen::Vector3d(25.0, 5.0, 0.0))),
            "the camera is 25.50 m from the odometry origin, more than 5 m: "
            "check that the "
            "odometry positions are in metres (name the columns x_cm,y_cm or "
            "x_mm,y_mm "
            "otherwise)");
}

}  // namespace
}  // namespace odomcal
