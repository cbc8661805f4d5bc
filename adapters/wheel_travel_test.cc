#include "odomcal/adapters/wheel_travel.h"

#include "odomcal/adapters/odometry_csv_header.h"
#include "odomcal/adapters/test_support.h"
#include "odomcal/adapters/trajectory_io.h"
#include "odomcal/datasets/simulation/drive_simulator.h"
#include "odomcal/solver/angles.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <string>

namespace odomcal {
namespace {

constexpr double kTrackM = 0.4;

std::string WriteTextFile(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + "odomcal_wheels_" + name;
  std::ofstream stream(path);
  stream << text;
  EXPECT_TRUE(stream.good()) << path;
  return path;
}

double YawOf(const Rigid3d& pose) {
  const Eigen::Quaterniond q = pose.rotation.normalized();
  return 2.0 * std::atan2(q.z(), q.w());
}

// Largest position and heading difference between poses of equal stamps.
void ExpectSamePoses(const Trajectory& actual,
                     const Trajectory& expected,
                     double tolerance) {
  ASSERT_EQ(actual.poses.size(), expected.poses.size());
  double position = 0.0, heading = 0.0;
  for (size_t i = 0; i < actual.poses.size(); ++i) {
    ASSERT_EQ(actual.poses[i].stamp_ns, expected.poses[i].stamp_ns) << i;
    const Rigid3d& a = actual.poses[i].world_from_sensor;
    const Rigid3d& e = expected.poses[i].world_from_sensor;
    position = std::max(position, (a.translation - e.translation).norm());
    heading = std::max(
        heading, std::abs(std::remainder(YawOf(a) - YawOf(e), 2.0 * kPi)));
  }
  EXPECT_LT(position, tolerance);
  EXPECT_LT(heading, tolerance);
}

// A circle of radius 1.3 m driven forward for 1.5 turns, then backwards half
// a turn, then a turn in place: the exact poses are known in closed form.
TEST(IntegrateWheelTravels, ArcsAreIntegratedExactly) {
  constexpr double kRadius = 1.3;
  constexpr int kSteps = 300;
  WheelTravels travels;
  Trajectory expected;
  double heading = 0.0;  // along the circle, then in place
  Eigen::Vector2d position(0.0, 0.0);
  for (int k = 0; k <= 3 * kSteps; ++k) {
    WheelTravelSample sample;
    sample.stamp_ns = 1000000000LL + 20000000LL * k;
    if (k <= 2 * kSteps) {
      // Forward 1.5 turns, then back by half a turn: heading along the arc.
      const int net = k <= kSteps * 3 / 2 ? k : 3 * kSteps - k;
      heading = 2.0 * kPi * net / kSteps;
      position =
          kRadius * Eigen::Vector2d(std::sin(heading), 1.0 - std::cos(heading));
      // Cumulative travels count backwards driving as negative.
      sample.left_m = (kRadius - 0.5 * kTrackM) * heading;
      sample.right_m = (kRadius + 0.5 * kTrackM) * heading;
    } else {
      // In place: the left wheel backwards, the right forwards.
      const double spin = 0.01 * (k - 2 * kSteps);
      const double base = 2.0 * kPi;  // the heading at k = 2 kSteps
      sample.left_m = (kRadius - 0.5 * kTrackM) * base - 0.5 * kTrackM * spin;
      sample.right_m = (kRadius + 0.5 * kTrackM) * base + 0.5 * kTrackM * spin;
      heading = base + spin;
    }
    travels.samples.push_back(sample);
    StampedPose pose;
    pose.stamp_ns = sample.stamp_ns;
    pose.world_from_sensor.rotation = YawRotation(heading);
    pose.world_from_sensor.translation =
        Eigen::Vector3d(position.x(), position.y(), 0.0);
    expected.poses.push_back(pose);
  }
  const Trajectory odometry = IntegrateWheelTravels(travels, kTrackM);
  EXPECT_TRUE(odometry.planar);
  ExpectSamePoses(odometry, expected, 1e-9);
}

// The drive simulator's measured wheel travels (unequal wheels, travel noise)
// integrate back to its measured odometry.
TEST(IntegrateWheelTravels, RecoversTheSimulatedDrivesOdometry) {
  DriveSimulatorOptions options;
  options.seed = 4;
  options.wheel_scale_error_left = 0.015;
  options.wheel_scale_error_right = -0.01;
  options.wheel_track_error = 0.03;
  options.wheel_travel_noise_rel = 0.01;
  const SimulatedDrive drive = SimulateDrive(options);
  ExpectSamePoses(
      IntegrateWheelTravels(drive.wheel_travels, kSimulatedWheelTrackM),
      drive.odometry,
      1e-9);
}

TEST(IntegrateWheelTravels, RefusesAMissingTrack) {
  WheelTravels travels;
  travels.samples.push_back({0, 0.0, 0.0});
  EXPECT_THROW(IntegrateWheelTravels(travels, 0.0), std::invalid_argument);
  EXPECT_THROW(IntegrateWheelTravels(WheelTravels(), 0.4),
               std::invalid_argument);
}

std::string Line(const char* format, double a, double b, double c) {
  char text[200];
  std::snprintf(text, sizeof(text), format, a, b, c);
  return text;
}

// Ticks (around 4e15, beyond a double's integer precision relative to 1,
// counting down on one wheel) read with ticks per metre equal the metres
// they stand for.
TEST(ReadWheelTravels, TicksEqualMetresTimesTicksPerMetre) {
  constexpr double kTicksPerM = 2048.0;
  constexpr long long kStart = 4000000000000000LL;
  std::string metres = "timestamp,left_m,right_m\n";
  std::string ticks = "Time_ms,RIGHT_ticks,left_ticks\n";
  for (int k = 0; k < 200; ++k) {
    const long long left = 37LL * k + (k % 7);
    const long long right = -23LL * k;  // backwards: a decreasing count
    metres += Line(
        "%.17g,%.17g,%.17g\n", 0.02 * k, left / kTicksPerM, right / kTicksPerM);
    ticks += std::to_string(20 * k) + "," + std::to_string(kStart + right) +
             "," + std::to_string(kStart + left) + "\n";
  }
  WheelTravelOptions wheels;
  wheels.track_m = 0.35;
  wheels.ticks_per_m = kTicksPerM;
  const std::string metres_path = WriteTextFile("metres.csv", metres);
  const std::string ticks_path = WriteTextFile("ticks.txt", ticks);
  // Ticks per metre only with ticks (ticks per metre given with distances
  // is refused: TicksPerMetreWithoutTicksIsRefused).
  const Trajectory from_metres = ReadOdometry(metres_path,
                                              OdometryFormat::kAuto,
                                              TimeUnit::kSeconds,
                                              false,
                                              {wheels.track_m, 0.0});
  const Trajectory from_ticks = ReadOdometry(
      ticks_path, OdometryFormat::kAuto, TimeUnit::kSeconds, false, wheels);
  EXPECT_TRUE(from_ticks.planar);
  EXPECT_EQ(from_ticks.source, ticks_path);
  EXPECT_EQ(from_ticks.poses[1].stamp_ns, 20000000);
  // The unit the times were read in (the header's, not the flag's).
  EXPECT_EQ(from_ticks.time_unit, TimeUnit::kMilliseconds);
  EXPECT_EQ(from_metres.time_unit, TimeUnit::kSeconds);
  ExpectSamePoses(from_ticks, from_metres, 1e-12);
  // And the heading is what the wheels say: (dr - dl) / b.
  const double last_left = (37.0 * 199 + 199 % 7) / kTicksPerM;
  const double last_right = -23.0 * 199 / kTicksPerM;
  EXPECT_NEAR(std::remainder(YawOf(from_ticks.poses.back().world_from_sensor) -
                                 (last_right - last_left) / 0.35,
                             2.0 * kPi),
              0.0,
              1e-12);
}

std::string ReadError(const std::string& name,
                      const std::string& text,
                      const WheelTravelOptions& wheels) {
  const std::string path = WriteTextFile(name, text);
  return FormatErrorOf([&] {
    ReadOdometry(
        path, OdometryFormat::kAuto, TimeUnit::kSeconds, false, wheels);
  });
}

TEST(ReadWheelTravels, ErrorsNameTheFileLineAndFlag) {
  const WheelTravelOptions none;
  const WheelTravelOptions track{0.4, 0.0};
  const WheelTravelOptions both{0.4, 1000.0};
  const std::string prefix = ::testing::TempDir() + "odomcal_wheels_";
  EXPECT_EQ(
      ReadError("no_track.csv", "timestamp,left_m,right_m\n0,0,0\n", none),
      prefix +
          "no_track.csv:1: wheel travels (timestamp,left_m,right_m) "
          "are integrated with the nominal wheel track: pass "
          "--wheel_track_m");
  EXPECT_EQ(
      ReadError(
          "no_ticks.csv", "# counts\nt,left_ticks,right_ticks\n0,0,0\n", track),
      prefix +
          "no_ticks.csv:2: wheel ticks (t,left_ticks,right_ticks) need "
          "the encoder ticks per metre: pass --wheel_ticks_per_m");
  EXPECT_EQ(ReadError("fraction.csv",
                      "t,left_ticks,right_ticks\n0,0,0\n0.1,12.5,3\n",
                      both),
            prefix +
                "fraction.csv:3: column 'left_ticks' is not an integer tick "
                "count: '12.5'");
  EXPECT_EQ(ReadError("nan.csv", "t,left_m,right_m\n0,0,nan\n", track),
            prefix +
                "nan.csv:2: column 'right_m' is not finite (NaN or "
                "Inf): 'nan'");
  EXPECT_EQ(ReadError("fields.csv", "t,left_m,right_m\n0,0,0\n1,2\n", track),
            prefix +
                "fields.csv:3: expected 3 fields (t,left_m,right_m), "
                "got 2");
  EXPECT_EQ(ReadError("order.csv", "t,left_m,right_m\n1,0,0\n0,0,0\n", track),
            prefix +
                "order.csv:3: timestamp not increasing: 0 after 1 on "
                "line 2");
  const std::string grammar =
      std::string("; accepted: ") + kWheelCsvHeaderGrammar +
      " (read as csv because of its first data line; --odometry_format csv "
      "or tum chooses)";
  EXPECT_EQ(ReadError("bare.csv", "t,left,right\n0,0,0\n", track),
            prefix +
                "bare.csv:1: wheel travel header column 'left' is not a "
                "wheel travel column" +
                grammar);
  EXPECT_EQ(ReadError("mixed.csv", "t,left_m,right_ticks\n0,0,0\n", both),
            prefix +
                "mixed.csv:1: wheel travel header mixes ticks and distances "
                "('right_ticks')" +
                grammar);
  EXPECT_EQ(ReadError("twice.csv", "t,left_m,left_m\n0,0,0\n", both),
            prefix +
                "twice.csv:1: wheel travel header names the left wheel "
                "column twice ('left_m' and 'left_m')" +
                grammar);
  EXPECT_EQ(ReadError("no_right.csv", "t,left_m,x\n0,0,0\n", both),
            prefix +
                "no_right.csv:1: wheel travel header column 'x' is not a "
                "wheel travel column" +
                grammar);
}

// --wheel_ticks_per_m with a log that has no tick columns would go unused:
// one line naming the flag and the file, whatever the log's format.
TEST(ReadWheelTravels, TicksPerMetreWithoutTicksIsRefused) {
  const WheelTravelOptions both{0.4, 1000.0};
  const std::string prefix = ::testing::TempDir() + "odomcal_wheels_";
  const std::string ending =
      ", not wheel ticks (timestamp,left_ticks,right_ticks); drop the flag";
  EXPECT_EQ(ReadError("poses.csv", "timestamp,x,y,yaw\n0,0,0,0\n", both),
            prefix +
                "poses.csv: --wheel_ticks_per_m is given, but this is a pose "
                "odometry log (timestamp,x,y,yaw)" +
                ending);
  EXPECT_EQ(ReadError("bare_poses.csv", "0,0,0,0\n1,1,0,0\n", both),
            prefix +
                "bare_poses.csv: --wheel_ticks_per_m is given, but this is a "
                "pose odometry log (timestamp,x,y,yaw)" +
                ending);
  EXPECT_EQ(ReadError("poses.tum", "0 0 0 0 0 0 0 1\n", both),
            prefix +
                "poses.tum: --wheel_ticks_per_m is given, but this is a TUM "
                "pose log (timestamp tx ty tz qx qy qz qw)" +
                ending);
  EXPECT_EQ(ReadError("metres.csv", "t,left_m,right_m\n0,0,0\n", both),
            prefix +
                "metres.csv: --wheel_ticks_per_m is given, but this is a "
                "wheel-travel log (t,left_m,right_m)" +
                ending);
}

}  // namespace
}  // namespace odomcal
