#include "odomcal/adapters/camera_pose_drift.h"

#include "odomcal/adapters/association.h"
#include "odomcal/datasets/simulation/drive_simulator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace odomcal {
namespace {

enum class CameraErrors { kNone, kDrifting, kPerPose };

// 60 s of the drive simulator's differential drive, 10 Hz camera.
SimulatedDrive Drive(CameraErrors errors, uint64_t seed) {
  DriveSimulatorOptions options;
  options.seed = seed;
  if (errors == CameraErrors::kDrifting) {
    // Visual odometry: each pose composed from the last, with the noise of
    // the statistics benchmark's VO-like camera.
    options.camera_step_rotation_noise_deg = 0.05;
    options.camera_step_translation_noise_rel = 0.01;
  } else if (errors == CameraErrors::kPerPose) {
    options.camera_rotation_noise_deg = 0.02;
    options.camera_position_noise = 0.002;
  }
  return SimulateDrive(options);
}

TEST(CameraPoseDrift, VisualOdometryPosesDrift) {
  for (const uint64_t seed : {1u, 2u, 3u}) {
    const CameraPoseDriftTest test =
        TestCameraPoseDrift({Drive(CameraErrors::kDrifting, seed).camera},
                            CameraPoseDriftOptions());
    ASSERT_TRUE(test.decided) << seed;
    EXPECT_TRUE(test.drifting) << seed;
    EXPECT_EQ(test.span, 8);
    EXPECT_EQ(test.threshold, 4.5);
    // Variance growing with the span: about 8 for 8 frames.
    EXPECT_GT(test.rotation_ratio, 5.5) << seed;
    EXPECT_LT(test.rotation_ratio, 12.0) << seed;
    EXPECT_GT(test.translation_ratio, 5.5) << seed;
    EXPECT_LT(test.translation_ratio, 14.0) << seed;
  }
}

TEST(CameraPoseDrift, PerPoseErrorsDoNotDrift) {
  for (const uint64_t seed : {1u, 2u, 3u}) {
    const CameraPoseDriftTest test = TestCameraPoseDrift(
        {Drive(CameraErrors::kPerPose, seed).camera}, CameraPoseDriftOptions());
    ASSERT_TRUE(test.decided) << seed;
    EXPECT_FALSE(test.drifting) << seed;
    EXPECT_NEAR(test.rotation_ratio, 1.0, 0.3) << seed;
    EXPECT_NEAR(test.translation_ratio, 1.0, 0.3) << seed;
  }
}

TEST(CameraPoseDrift, SegmentsArePooledWithoutPairsAcrossThem) {
  // Two halves of a drifting trajectory, each in its own world frame: the
  // test pools them and no pair spans the cut.
  const Trajectory camera = Drive(CameraErrors::kDrifting, 4).camera;
  Trajectory first = camera, second = camera;
  const size_t half = camera.poses.size() / 2;
  first.poses.resize(half);
  second.poses.erase(second.poses.begin(), second.poses.begin() + half);
  const Rigid3d other_world(ExpRotation(Eigen::Vector3d(0.3, -1.0, 2.0)),
                            Eigen::Vector3d(5.0, -2.0, 1.0));
  for (StampedPose& pose : second.poses) {
    pose.world_from_sensor = other_world * pose.world_from_sensor;
  }
  const CameraPoseDriftTest test =
      TestCameraPoseDrift({first, second}, CameraPoseDriftOptions());
  EXPECT_EQ(test.num_pairs, static_cast<int>(camera.poses.size()) - 2 * 8);
  EXPECT_TRUE(test.drifting);
}

TEST(CameraPoseDrift, ExactOrTooFewPosesAreNotDecided) {
  const CameraPoseDriftTest exact = TestCameraPoseDrift(
      {Drive(CameraErrors::kNone, 1).camera}, CameraPoseDriftOptions());
  EXPECT_GT(exact.num_pairs, 500);
  EXPECT_FALSE(exact.decided);
  EXPECT_FALSE(exact.drifting);

  Trajectory few = Drive(CameraErrors::kDrifting, 1).camera;
  few.poses.resize(37);  // 29 pairs of 8 frames
  const CameraPoseDriftTest test =
      TestCameraPoseDrift({few}, CameraPoseDriftOptions());
  EXPECT_EQ(test.num_pairs, 29);
  EXPECT_FALSE(test.decided);
  EXPECT_FALSE(test.drifting);
}

TEST(CameraPoseDrift, MotionThatIsNotPlanarIsNotDecided) {
  // A camera that also rolls back and forth (a rocking boom, not a ground
  // robot's camera): its real motion leaves the plane and would read as
  // drift.
  Trajectory camera = Drive(CameraErrors::kPerPose, 6).camera;
  for (size_t k = 0; k < camera.poses.size(); ++k) {
    const double roll = 0.3 * std::sin(0.05 * static_cast<double>(k));
    camera.poses[k].world_from_sensor.rotation =
        camera.poses[k].world_from_sensor.rotation *
        ExpRotation(Eigen::Vector3d(roll, 0.0, 0.0));
  }
  const CameraPoseDriftTest test =
      TestCameraPoseDrift({camera}, CameraPoseDriftOptions());
  EXPECT_FALSE(test.decided);
  EXPECT_FALSE(test.drifting);
}

TEST(CameraPoseDrift, RejectsBadOptions) {
  CameraPoseDriftOptions options;
  options.span = 1;
  EXPECT_THROW(TestCameraPoseDrift({}, options), std::invalid_argument);
  options = CameraPoseDriftOptions();
  options.min_num_pairs = 0;
  EXPECT_THROW(TestCameraPoseDrift({}, options), std::invalid_argument);
}

TEST(CameraPoseDrift, AutomaticKeyframesFollowTheTest) {
  const SimulatedDrive drifting = Drive(CameraErrors::kDrifting, 5);
  const SimulatedDrive per_pose = Drive(CameraErrors::kPerPose, 5);
  const AssociationResult vo = AssociateCameraWithOdometry(
      {drifting.camera}, drifting.odometry, AssociationOptions());
  EXPECT_TRUE(vo.keyframe_spacing_automatic);
  EXPECT_TRUE(vo.camera_pose_drift.drifting);
  EXPECT_EQ(vo.keyframe_min_rotation_deg, 1.0);
  EXPECT_EQ(vo.keyframe_min_translation_m, 0.02);
  const AssociationResult model = AssociateCameraWithOdometry(
      {per_pose.camera}, per_pose.odometry, AssociationOptions());
  EXPECT_FALSE(model.camera_pose_drift.drifting);
  EXPECT_EQ(model.keyframe_min_rotation_deg, 5.0);
  EXPECT_EQ(model.keyframe_min_translation_m, 0.10);
  // The short spacing pairs more frames.
  EXPECT_GT(vo.pairs.size(), 1.5 * model.pairs.size());

  // A threshold given is kept; the other still follows the test.
  AssociationOptions one_given;
  one_given.keyframe_min_rotation_deg = 3.0;
  const AssociationResult mixed = AssociateCameraWithOdometry(
      {drifting.camera}, drifting.odometry, one_given);
  EXPECT_TRUE(mixed.keyframe_spacing_automatic);
  EXPECT_EQ(mixed.keyframe_min_rotation_deg, 3.0);
  EXPECT_EQ(mixed.keyframe_min_translation_m, 0.02);
  // Both given: no test.
  one_given.keyframe_min_translation_m = 0.1;
  const AssociationResult given = AssociateCameraWithOdometry(
      {drifting.camera}, drifting.odometry, one_given);
  EXPECT_FALSE(given.keyframe_spacing_automatic);
  EXPECT_FALSE(given.camera_pose_drift.decided);
  EXPECT_EQ(given.keyframe_min_translation_m, 0.1);
}

TEST(CameraPoseDrift, AutomaticKeyframesSpanAnOdometryInterval) {
  // 2 Hz odometry (every 25th sample of 50 Hz) under a 10 Hz camera: the
  // drifting poses' 1 deg / 0.02 m would pair consecutive frames, five to an
  // interpolated odometry interval.
  SimulatedDrive drive = Drive(CameraErrors::kDrifting, 7);
  std::vector<StampedPose> kept;
  for (size_t k = 0; k < drive.odometry.poses.size(); k += 25) {
    kept.push_back(drive.odometry.poses[k]);
  }
  drive.odometry.poses = kept;
  const AssociationResult automatic = AssociateCameraWithOdometry(
      {drive.camera}, drive.odometry, AssociationOptions());
  ASSERT_TRUE(automatic.camera_pose_drift.drifting);
  EXPECT_NEAR(automatic.keyframe_min_span_s, 0.45, 1e-9);
  ASSERT_GT(automatic.pairs.size(), 50u);
  for (const MotionPair& pair : automatic.pairs) {
    EXPECT_GE(pair.stamp_j_ns - pair.stamp_i_ns, 450000000);
  }
  // Thresholds given: no minimum span.
  AssociationOptions given;
  given.keyframe_min_rotation_deg = 1.0;
  given.keyframe_min_translation_m = 0.02;
  const AssociationResult explicit_spacing =
      AssociateCameraWithOdometry({drive.camera}, drive.odometry, given);
  EXPECT_EQ(explicit_spacing.keyframe_min_span_s, 0.0);
  EXPECT_GT(explicit_spacing.pairs.size(), 3 * automatic.pairs.size());
}

}  // namespace
}  // namespace odomcal
