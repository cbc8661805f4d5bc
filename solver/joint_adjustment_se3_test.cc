// The joint adjustment with whole robot poses on ground that pitches and
// banks (datasets/simulation/joint_scene.h): a 3-D log's links
// (RobotMotionModel::kSE3) and a planar log's (kOnGround).
#include "odomcal/datasets/simulation/joint_scene.h"
#include "odomcal/solver/angles.h"
#include "odomcal/solver/joint_adjustment.h"
#include "odomcal/solver/joint_adjustment_jackknife.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

namespace odomcal {
namespace {

// 80 images, 0.5 px, the model's size drifting by 5 %, on ground sloped by
// up to `slope_deg`.
JointScene MakeSlopedScene(unsigned seed, double slope_deg, bool se3_odometry) {
  JointSceneOptions options;
  options.seed = seed;
  options.pixel_sigma = 0.5;
  options.drift = 0.05;
  options.ground_slope_deg = slope_deg;
  options.se3_odometry = se3_odometry;
  return SimulateJointScene(options);
}

// [roll, pitch, yaw, x, y] error over its stated standard deviation.
Eigen::Matrix<double, 5, 1> ErrorOverSigma(const JointAdjustmentResult& result,
                                           const Rigid3d& truth) {
  Eigen::Matrix<double, 5, 1> error;
  error.head<3>() =
      LogRotation(result.odom_from_cam.rotation * truth.rotation.conjugate());
  error.tail<2>() =
      (result.odom_from_cam.translation - truth.translation).head<2>();
  return error.cwiseQuotient(result.covariance.diagonal().cwiseSqrt());
}

TEST(AdjustJointlySe3, FollowsARobotThatPitchesAndBanks) {
  double sum_squares = 0.0;
  int count = 0;
  for (unsigned seed = 1; seed <= 3; ++seed) {
    const JointScene scene = MakeSlopedScene(seed, 3.0, true);
    ASSERT_EQ(scene.problem.motion_model, RobotMotionModel::kSE3);
    const JointAdjustmentResult result =
        AdjustJointly(scene.problem, JointAdjustmentOptions());
    ASSERT_TRUE(result.IsSuccess()) << result.message;
    // The images fit at their noise: the poses follow the ground.
    EXPECT_NEAR(result.pixel_sigma, 0.5, 0.05) << "seed " << seed;
    const Eigen::Matrix<double, 5, 1> ratio =
        ErrorOverSigma(result, scene.odom_from_cam);
    for (int k = 0; k < 5; ++k) {
      EXPECT_LT(std::abs(ratio[k]), 4.0) << "seed " << seed << ", " << k;
    }
    sum_squares += ratio.squaredNorm();
    count += 5;
    EXPECT_LT(std::sqrt(result.covariance(0, 0)), 0.2 * kDegToRad);
    double worst_position = 0.0;
    double worst_tilt = 0.0;
    double largest_true_tilt = 0.0;
    for (size_t i = 0; i < scene.poses.size(); ++i) {
      const Rigid3d& pose = result.origin_from_odom[i];
      worst_position =
          std::max(worst_position,
                   (pose.translation - scene.poses[i].translation).norm());
      // The odometry's z axis, which tilts with the ground.
      const Eigen::Vector3d up = pose.rotation * Eigen::Vector3d::UnitZ();
      const Eigen::Vector3d true_up =
          scene.poses[i].rotation * Eigen::Vector3d::UnitZ();
      worst_tilt =
          std::max(worst_tilt, std::acos(std::min(1.0, up.dot(true_up))));
      largest_true_tilt =
          std::max(largest_true_tilt, std::acos(std::min(1.0, true_up.z())));
    }
    EXPECT_LT(worst_position, 0.05) << "seed " << seed;
    // Tilts of 2-4 deg followed to a fraction of a degree (the odometry's
    // tilt, 0.05 deg per link, and the images).
    EXPECT_GT(largest_true_tilt, 2.0 * kDegToRad);
    EXPECT_LT(worst_tilt, 0.6 * kDegToRad) << "seed " << seed;
  }
  const double rms = std::sqrt(sum_squares / count);
  EXPECT_GT(rms, 0.3);
  EXPECT_LT(rms, 1.6);
}

// What planar robot poses make of the same ground: the images cannot fit
// (the pixel sigma is several times the noise) and the extrinsic's roll is
// tens of its sigma off. Why a 3-D log gets whole poses.
TEST(AdjustJointlySe3, PlanarPosesCannotFollowSlopedGround) {
  const JointScene scene = MakeSlopedScene(1, 3.0, false);
  ASSERT_EQ(scene.problem.motion_model, RobotMotionModel::kPlanar);
  const JointAdjustmentResult result =
      AdjustJointly(scene.problem, JointAdjustmentOptions());
  ASSERT_TRUE(result.IsSuccess()) << result.message;
  EXPECT_GT(result.pixel_sigma, 2.0);
  EXPECT_GT(ErrorOverSigma(result, scene.odom_from_cam).cwiseAbs().maxCoeff(),
            10.0);
}

// A 3-D log of level ground: the poses may tilt as far as the log's noise
// allows, so the extrinsic's roll and pitch are known from the log's tilt
// and height and the images, not from an assumed level floor: no more
// precisely than with level poses, and still within their sigma.
TEST(AdjustJointlySe3, OnLevelGroundStatesWhatTheLogLeaves) {
  const JointScene se3 = MakeSlopedScene(2, 0.0, true);
  const JointScene planar = MakeSlopedScene(2, 0.0, false);
  const JointAdjustmentResult a =
      AdjustJointly(se3.problem, JointAdjustmentOptions());
  const JointAdjustmentResult b =
      AdjustJointly(planar.problem, JointAdjustmentOptions());
  ASSERT_TRUE(a.IsSuccess()) << a.message;
  ASSERT_TRUE(b.IsSuccess()) << b.message;
  for (int k = 0; k < 5; ++k) {
    const double sigma_a = std::sqrt(a.covariance(k, k));
    const double sigma_b = std::sqrt(b.covariance(k, k));
    EXPECT_GT(sigma_a, 0.9 * sigma_b) << k;
  }
  EXPECT_LT(ErrorOverSigma(a, se3.odom_from_cam).cwiseAbs().maxCoeff(), 4.0);
  EXPECT_LT(ErrorOverSigma(b, planar.odom_from_cam).cwiseAbs().maxCoeff(), 4.0);
}

// A planar log on the same ground (kOnGround): the poses tilt with it, the
// images fit at their noise, and the extrinsic, which the ground's shape
// along the one drive biases, is within its sigma once the jackknife over
// stretches of the drive widened it (benchmarks/ground_poses_study: 10
// seeds).
TEST(AdjustJointlyOnGround, FollowsSlopedGroundWithAPlanarLog) {
  JointScene scene = MakeSlopedScene(1, 3.0, false);
  scene.problem.motion_model = RobotMotionModel::kOnGround;
  JointAdjustmentResult result =
      AdjustJointly(scene.problem, JointAdjustmentOptions());
  ASSERT_TRUE(result.IsSuccess()) << result.message;
  EXPECT_NEAR(result.pixel_sigma, 0.5, 0.05);
  EXPECT_GT(result.ground_tilt_rate_deg_per_m, 0.1);
  EXPECT_GT(result.max_robot_tilt_deg, 1.0);
  std::vector<int> order(scene.problem.images.size());
  std::iota(order.begin(), order.end(), 0);
  const JointJackknife jackknife =
      JackknifeJointExtrinsic(scene.problem,
                              JointAdjustmentOptions(),
                              order,
                              JointJackknifeOptions(),
                              &result);
  ASSERT_TRUE(jackknife.ran) << jackknife.reason;
  EXPECT_LT(ErrorOverSigma(result, scene.odom_from_cam).cwiseAbs().maxCoeff(),
            4.0);
}

// On level ground the estimated tilt rate is the images' noise, and the
// roll and pitch stay known to thousandths of a degree.
TEST(AdjustJointlyOnGround, OnLevelGroundFindsItLevel) {
  JointScene scene = MakeSlopedScene(3, 0.0, false);
  scene.problem.motion_model = RobotMotionModel::kOnGround;
  const JointAdjustmentResult result =
      AdjustJointly(scene.problem, JointAdjustmentOptions());
  ASSERT_TRUE(result.IsSuccess()) << result.message;
  EXPECT_LT(result.ground_tilt_rate_deg_per_m, 0.02);
  EXPECT_LT(result.max_robot_tilt_deg, 0.1);
  EXPECT_LT(std::sqrt(result.covariance(0, 0)), 0.02 * kDegToRad);
  EXPECT_LT(std::sqrt(result.covariance(1, 1)), 0.02 * kDegToRad);
  EXPECT_LT(ErrorOverSigma(result, scene.odom_from_cam).cwiseAbs().maxCoeff(),
            4.0);
}

TEST(AdjustJointlySe3, RefusesLinksWithoutTheWholeMotion) {
  JointScene scene = MakeSlopedScene(4, 3.0, true);
  scene.problem.links[3].motion_3d.reset();
  JointAdjustmentResult result =
      AdjustJointly(scene.problem, JointAdjustmentOptions());
  EXPECT_EQ(result.status, JointAdjustmentStatus::kInvalidInput);
  EXPECT_NE(result.message.find("whole motion"), std::string::npos);

  scene = MakeSlopedScene(4, 3.0, true);
  scene.problem.links[3].motion_3d->covariance(1, 1) = 0.0;
  scene.problem.links[3].motion_3d->covariance(1, 0) = 0.0;
  scene.problem.links[3].motion_3d->covariance(0, 1) = 0.0;
  result = AdjustJointly(scene.problem, JointAdjustmentOptions());
  EXPECT_EQ(result.status, JointAdjustmentStatus::kInvalidInput);
  EXPECT_NE(result.message.find("positive definite"), std::string::npos);

  scene = MakeSlopedScene(4, 3.0, true);
  scene.problem.systematics = JointSystematics();
  result = AdjustJointly(scene.problem, JointAdjustmentOptions());
  EXPECT_EQ(result.status, JointAdjustmentStatus::kInvalidInput);
  EXPECT_NE(result.message.find("planar log"), std::string::npos);
}

}  // namespace
}  // namespace odomcal
