#include "odomcal/adapters/bag/odometry_conversion.h"

#include "odomcal/adapters/test_support.h"
#include "odomcal/adapters/trajectory_io.h"
#include "odomcal/solver/rigid3.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace odomcal::bag {
namespace {

constexpr int64_t kT0 = 1690000000123456789;
constexpr double kPi = 3.14159265358979323846;

OdometryMessage MakeOdometry(double x,
                             double y,
                             double z,
                             std::array<double, 4> xyzw) {
  OdometryMessage odometry;
  odometry.position = {x, y, z};
  odometry.orientation = xyzw;
  return odometry;
}

std::string TempPath(const std::string& name) {
  return (std::filesystem::path(::testing::TempDir()) / name).string();
}

TEST(OdometryConversionTest, RosQuaternionOrderIsXyzw) {
  const double s = std::sqrt(0.5);
  // 90 degrees about +z: x goes to y.
  Rigid3d pose = PoseFromOdometry(MakeOdometry(1, 2, 3, {0, 0, s, s}), "t");
  EXPECT_TRUE((pose.rotation * Eigen::Vector3d::UnitX())
                  .isApprox(Eigen::Vector3d::UnitY(), 1e-12));
  EXPECT_TRUE(pose.translation.isApprox(Eigen::Vector3d(1, 2, 3)));
  // 90 degrees about +x: y goes to z.
  pose = PoseFromOdometry(MakeOdometry(0, 0, 0, {s, 0, 0, s}), "t");
  EXPECT_TRUE((pose.rotation * Eigen::Vector3d::UnitY())
                  .isApprox(Eigen::Vector3d::UnitZ(), 1e-12));
  const std::string error = FormatErrorOf([&] {
    PoseFromOdometry(MakeOdometry(0, 0, 0, {0, 0, 0, 0}), "b: /odom");
  });
  EXPECT_TRUE(Contains(error, "b: /odom: ")) << error;
}

// A drive on a circle of radius 2 m, heading along the tangent.
std::vector<StampedPose> CirclePoses(double z_noise, double pitch) {
  std::vector<StampedPose> poses;
  for (int i = 0; i < 40; ++i) {
    const double angle = 0.2 * i;
    const double yaw = angle + kPi / 2;
    const Eigen::Quaterniond q =
        Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ())) *
        Eigen::Quaterniond(Eigen::AngleAxisd(i % 2 == 0 ? pitch : -pitch,
                                             Eigen::Vector3d::UnitY()));
    const double z = (i % 3 == 0 ? z_noise : 0.0);
    // Through the message, as the extraction converts it.
    const OdometryMessage odometry = MakeOdometry(2 * std::cos(angle),
                                                  2 * std::sin(angle),
                                                  z,
                                                  {q.x(), q.y(), q.z(), q.w()});
    poses.push_back({kT0 + i * 20000000LL, PoseFromOdometry(odometry, "t")});
  }
  return poses;
}

TEST(OdometryConversionTest, PlanarLogIsWrittenAsCsv) {
  // z wobbles by 0.5 mm, pitch by 0.0004 rad: inside the default tolerance.
  const Trajectory trajectory =
      OdometryTrajectory(CirclePoses(0.0005, 0.0004), "b: /odom");
  ASSERT_TRUE(trajectory.planar);
  const std::string path = TempPath("planar_odometry.csv");
  WriteOdometryCsv(trajectory, path);
  const Trajectory read = ReadOdometryCsv(path, TimeUnit::kSeconds);
  std::filesystem::remove(path);
  ASSERT_EQ(read.poses.size(), 40u);
  for (int i = 0; i < 40; ++i) {
    const double angle = 0.2 * i;
    EXPECT_EQ(read.poses[i].stamp_ns, kT0 + i * 20000000LL);
    EXPECT_NEAR(read.poses[i].world_from_sensor.translation.x(),
                2 * std::cos(angle),
                1e-12);
    EXPECT_NEAR(read.poses[i].world_from_sensor.translation.y(),
                2 * std::sin(angle),
                1e-12);
    const Eigen::Vector3d forward =
        read.poses[i].world_from_sensor.rotation * Eigen::Vector3d::UnitX();
    EXPECT_NEAR(forward.x(), -std::sin(angle), 1e-6);
    EXPECT_NEAR(forward.y(), std::cos(angle), 1e-6);
  }
}

TEST(OdometryConversionTest, TiltOrHeightMakesItSe3) {
  EXPECT_FALSE(OdometryTrajectory(CirclePoses(0.0, 0.01), "t").planar);
  EXPECT_FALSE(OdometryTrajectory(CirclePoses(0.02, 0.0), "t").planar);
  PlanarityTolerance loose;
  loose.max_tilt_rad = 0.02;
  EXPECT_TRUE(OdometryTrajectory(CirclePoses(0.0, 0.01), "t", loose).planar);

  const std::vector<StampedPose> poses = CirclePoses(0.0, 0.01);
  const Trajectory trajectory = OdometryTrajectory(poses, "t");
  const std::string path = TempPath("se3_odometry.tum");
  WriteTumTrajectory(trajectory, path);
  const Trajectory read = ReadTumTrajectory(path, TimeUnit::kSeconds);
  std::filesystem::remove(path);
  ASSERT_EQ(read.poses.size(), poses.size());
  for (size_t i = 0; i < poses.size(); ++i) {
    EXPECT_EQ(read.poses[i].stamp_ns, poses[i].stamp_ns);
    EXPECT_LT(RotationAngle(read.poses[i].world_from_sensor.rotation.inverse() *
                            poses[i].world_from_sensor.rotation),
              1e-9);
  }
}

TEST(OdometryConversionTest, StampsMustIncrease) {
  std::vector<StampedPose> poses = CirclePoses(0.0, 0.0);
  poses[5].stamp_ns = poses[4].stamp_ns - 1;
  const std::string error =
      FormatErrorOf([&] { OdometryTrajectory(poses, "b.bag: /odom"); });
  EXPECT_TRUE(Contains(error, "b.bag: /odom: ")) << error;
  EXPECT_TRUE(Contains(error, std::to_string(poses[5].stamp_ns))) << error;
  EXPECT_TRUE(Contains(error, std::to_string(poses[4].stamp_ns))) << error;
  FormatErrorOf([&] { OdometryTrajectory({}, "b.bag: /odom"); });
}

JointStateMessage Joints(std::vector<std::string> names,
                         std::vector<double> positions) {
  JointStateMessage joints;
  joints.name = std::move(names);
  joints.position = std::move(positions);
  return joints;
}

TEST(OdometryConversionTest, JointAnglesBecomeTravelsInAnyOrder) {
  WheelJointOptions options;
  options.wheel_radius_m = 0.1;
  WheelTravelCollector collector(options, "b.bag: /joint_states");
  EXPECT_TRUE(collector.Add(
      kT0, Joints({"Left_Wheel_Joint", "Right_Wheel_Joint"}, {0.0, 0.0})));
  EXPECT_FALSE(collector.Add(kT0 + 5, Joints({"arm_joint"}, {1.0})));
  // Reordered, with another joint between: the left wheel turned back by
  // 1 rad, the right one forward by 1 rad.
  EXPECT_TRUE(collector.Add(
      kT0 + 10,
      Joints({"Right_Wheel_Joint", "arm_joint", "Left_Wheel_Joint"},
             {1.0, 7.0, -1.0})));
  EXPECT_EQ(collector.left_joint(), "Left_Wheel_Joint");
  EXPECT_EQ(collector.skipped(), 1);
  const WheelTravels travels = collector.Finish();
  ASSERT_EQ(travels.samples.size(), 2u);
  EXPECT_DOUBLE_EQ(travels.samples[1].left_m, -0.1);
  EXPECT_DOUBLE_EQ(travels.samples[1].right_m, 0.1);

  // Through odomcal's wheel-travel reader: turning on the spot by
  // 2 * 0.1 m / 0.4 m = 0.5 rad.
  const std::string path = TempPath("wheels.csv");
  WriteWheelTravelCsv(travels, path);
  WheelTravelOptions wheels;
  wheels.track_m = 0.4;
  const Trajectory read = ReadOdometry(
      path, OdometryFormat::kAuto, TimeUnit::kSeconds, false, wheels);
  std::filesystem::remove(path);
  ASSERT_EQ(read.poses.size(), 2u);
  EXPECT_NEAR(YawAboutZ(read.poses[1].world_from_sensor.rotation), 0.5, 1e-12);
  EXPECT_NEAR(read.poses[1].world_from_sensor.translation.norm(), 0.0, 1e-12);
}

TEST(OdometryConversionTest, NamedJointsAndAmbiguity) {
  WheelJointOptions options;
  options.wheel_radius_m = 0.05;
  options.left_joint = "wheel_a";
  options.right_joint = "wheel_b";
  WheelTravelCollector named(options, "t");
  EXPECT_TRUE(named.Add(kT0, Joints({"wheel_b", "wheel_a"}, {2.0, 4.0})));
  EXPECT_DOUBLE_EQ(named.Finish().samples[0].left_m, 0.2);
  EXPECT_DOUBLE_EQ(named.Finish().samples[0].right_m, 0.1);

  WheelJointOptions automatic;
  automatic.wheel_radius_m = 0.05;
  WheelTravelCollector ambiguous(automatic, "b.bag: /joint_states");
  const std::string error = FormatErrorOf([&] {
    ambiguous.Add(kT0,
                  Joints({"front_left_wheel",
                          "rear_left_wheel",
                          "front_right_wheel",
                          "rear_right_wheel"},
                         {0, 0, 0, 0}));
  });
  EXPECT_TRUE(Contains(error, "b.bag: /joint_states: ")) << error;
  EXPECT_TRUE(Contains(error, "'rear_left_wheel'")) << error;
  EXPECT_TRUE(Contains(error, "--left_wheel_joint")) << error;

  WheelTravelCollector none(automatic, "b.bag: /joint_states");
  EXPECT_FALSE(none.Add(kT0, Joints({"pan", "tilt"}, {0, 0})));
  const std::string none_error = FormatErrorOf([&] { none.Finish(); });
  EXPECT_TRUE(Contains(none_error, "'pan', 'tilt'")) << none_error;

  automatic.wheel_radius_m = 0.0;
  EXPECT_THROW(WheelTravelCollector(automatic, "t"), std::invalid_argument);
}

}  // namespace
}  // namespace odomcal::bag
