// The joint adjustment of a rig (solver/joint_adjustment.h: several mounts
// on one robot trajectory), on the two-camera scenes of
// datasets/simulation/joint_scene.h.
#include "odomcal/datasets/simulation/joint_scene.h"
#include "odomcal/solver/angles.h"
#include "odomcal/solver/camera_pair.h"
#include "odomcal/solver/joint_adjustment.h"
#include "odomcal/solver/joint_adjustment_jackknife.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <vector>

namespace odomcal {
namespace {

JointScene MakeRigScene(unsigned seed, bool shared_points) {
  JointSceneOptions options;
  options.seed = seed;
  options.rear_camera = true;
  options.rear_shares_points = shared_points;
  return SimulateJointScene(options);
}

// Rotation (rad, about the odometry axes) and x/y (m) error of one mount.
Eigen::Matrix<double, 5, 1> MountError(const Rigid3d& estimate,
                                       const Rigid3d& truth) {
  Eigen::Matrix<double, 5, 1> error;
  error.head<3>() = LogRotation(estimate.rotation * truth.rotation.conjugate());
  error.tail<2>() = (estimate.translation - truth.translation).head<2>();
  return error;
}

// One mount of a rig result with its 6 x 6 covariance (z held).
ExtrinsicWithCovariance MountWithCovariance(const Rigid3d& odom_from_cam,
                                            const Eigen::MatrixXd& covariance,
                                            int mount) {
  ExtrinsicWithCovariance out;
  out.odom_from_cam = odom_from_cam;
  out.covariance.topLeftCorner<5, 5>() =
      covariance.block<5, 5>(5 * mount, 5 * mount);
  return out;
}

// The rear camera's rotation relative to the front one: error about camB's
// axes over its standard deviation, per axis.
Eigen::Vector3d PairRotationSigmas(const CameraPairTransform& pair,
                                   const JointScene& scene) {
  const Rigid3d truth = Inverse(scene.rear_odom_from_cam) * scene.odom_from_cam;
  const Eigen::Vector3d error =
      LogRotation(pair.camb_from_cama.rotation * truth.rotation.conjugate());
  return error.cwiseQuotient(
      pair.covariance.topLeftCorner<3, 3>().diagonal().cwiseSqrt());
}

TEST(AdjustJointlyRig, EstimatesEveryMountOnOneTrajectory) {
  const JointScene scene = MakeRigScene(1, true);
  const JointAdjustmentResult result =
      AdjustJointly(scene.problem, JointAdjustmentOptions());
  ASSERT_TRUE(result.IsSuccess()) << result.message;
  ASSERT_EQ(result.other_mounts.size(), 1u);
  ASSERT_EQ(result.mounts_covariance.rows(), 10);
  ASSERT_EQ(result.mounts_covariance_widening.size(), 10);
  EXPECT_EQ(result.num_components, 1);
  EXPECT_EQ(result.odom_from_cam.translation.z(), 0.5);    // held
  EXPECT_EQ(result.other_mounts[0].translation.z(), 0.6);  // held
  EXPECT_TRUE(
      result.covariance.isApprox(result.mounts_covariance.topLeftCorner(5, 5)));
  EXPECT_TRUE(
      result.mounts_covariance.isApprox(result.mounts_covariance.transpose()));
  EXPECT_GT(result.mounts_covariance.llt().info() == Eigen::Success, 0);
  const std::vector<std::pair<Rigid3d, Rigid3d>> mounts = {
      {result.odom_from_cam, scene.odom_from_cam},
      {result.other_mounts[0], scene.rear_odom_from_cam}};
  for (int m = 0; m < 2; ++m) {
    const Eigen::Matrix<double, 5, 1> error =
        MountError(mounts[m].first, mounts[m].second);
    for (int k = 0; k < 5; ++k) {
      const double sigma =
          std::sqrt(result.mounts_covariance(5 * m + k, 5 * m + k));
      EXPECT_GT(sigma, 0.0);
      EXPECT_LT(std::abs(error[k]), 4.0 * sigma)
          << "mount " << m << " component " << k;
    }
    // Started 0.5 deg and 2 cm off: moved to within tenths of that.
    EXPECT_LT(error.head<3>().norm(), 0.1 * kDegToRad) << "mount " << m;
    EXPECT_LT(error.tail<2>().norm(), 0.005) << "mount " << m;
  }
}

TEST(AdjustJointlyRig, PairCarriesTheCrossTermsOfOneTrajectory) {
  // The rear camera sees points of its own (a model of its own): the two
  // mounts meet only through the robot's trajectory, which both cameras'
  // images shape. The camera-to-camera transform is then known better than
  // either mount against the odometry: the cross terms say so.
  const JointScene scene = MakeRigScene(2, false);
  const JointAdjustmentResult result =
      AdjustJointly(scene.problem, JointAdjustmentOptions());
  ASSERT_TRUE(result.IsSuccess()) << result.message;
  const ExtrinsicWithCovariance front =
      MountWithCovariance(result.odom_from_cam, result.mounts_covariance, 0);
  const ExtrinsicWithCovariance rear =
      MountWithCovariance(result.other_mounts[0], result.mounts_covariance, 1);
  Eigen::Matrix<double, 6, 6> cross = Eigen::Matrix<double, 6, 6>::Zero();
  cross.topLeftCorner<5, 5>() = result.mounts_covariance.block<5, 5>(0, 5);
  const CameraPairTransform together = CameraPairOf(front, rear, cross);
  const CameraPairTransform apart = CameraPairOf(front, rear);
  const Eigen::Vector3d sigmas = PairRotationSigmas(together, scene);
  for (int k = 0; k < 3; ++k) {
    EXPECT_LT(std::abs(sigmas[k]), 4.0) << "axis " << k;
    EXPECT_LT(together.stddev_rotation_axes_deg[k],
              apart.stddev_rotation_axes_deg[k])
        << "axis " << k;
  }
}

TEST(AdjustJointlyRig, JackknifeWidensEveryMount) {
  const JointScene scene = MakeRigScene(3, true);
  const JointAdjustmentOptions options;
  JointAdjustmentResult result = AdjustJointly(scene.problem, options);
  ASSERT_TRUE(result.IsSuccess()) << result.message;
  const Eigen::MatrixXd before = result.mounts_covariance;
  // Time order: the front camera's image i, then the rear one's i.
  const int num_front = 80;
  std::vector<int> order;
  for (int i = 0; i < num_front; ++i) {
    order.push_back(i);
    if (i + 1 < num_front) order.push_back(num_front + i);
  }
  const JointJackknife jackknife =
      JackknifeJointExtrinsic(scene.problem, options, order, {}, &result);
  ASSERT_TRUE(jackknife.ran) << jackknife.reason;
  ASSERT_EQ(jackknife.mounts_ratio.size(), 10);
  for (int k = 0; k < 10; ++k) {
    EXPECT_GE(result.mounts_covariance(k, k), before(k, k) * (1.0 - 1e-12))
        << "component " << k;
    EXPECT_GT(jackknife.mounts_ratio[k], 0.3) << "component " << k;
    EXPECT_LT(jackknife.mounts_ratio[k], 3.0) << "component " << k;
  }
  EXPECT_TRUE(
      result.covariance.isApprox(result.mounts_covariance.topLeftCorner(5, 5)));
  // At least the jackknife's spread in every direction, a difference
  // between the cameras too (a camera-to-camera transform), not only on
  // the diagonal: C - V has no negative eigenvalue.
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> excess(
      result.mounts_covariance - jackknife.mounts_covariance);
  EXPECT_GE(excess.eigenvalues().minCoeff(),
            -1e-9 * jackknife.mounts_covariance.norm());
}

TEST(AdjustJointlyRig, RefusesAMountWithoutImagesOrAnImageWithoutAMount) {
  JointScene scene = MakeRigScene(4, true);
  JointAdjustmentProblem problem = scene.problem;
  problem.other_mounts.push_back(problem.other_mounts[0]);  // mount 2: none
  JointAdjustmentResult result =
      AdjustJointly(problem, JointAdjustmentOptions());
  EXPECT_EQ(result.status, JointAdjustmentStatus::kInvalidInput);
  EXPECT_NE(result.message.find("mount 2 has no image"), std::string::npos)
      << result.message;
  problem = scene.problem;
  problem.images.back().mount = 5;
  result = AdjustJointly(problem, JointAdjustmentOptions());
  EXPECT_EQ(result.status, JointAdjustmentStatus::kInvalidInput);
  EXPECT_NE(result.message.find("no mount 5"), std::string::npos)
      << result.message;
}

}  // namespace
}  // namespace odomcal
