#include "odomcal/solver/joint_extrinsic.h"

#include "odomcal/solver/angles.h"
#include "odomcal/solver/joint_adjustment_covariance.h"

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <random>

namespace odomcal {
namespace {

TEST(ExtrinsicDisagreements, NameWhatLiesBeyondThreeSigmaOfTheDifference) {
  Rigid3d two_step;
  two_step.rotation = YawRotation(0.3);
  two_step.translation = Eigen::Vector3d(0.25, 0.05, 0.4);
  Eigen::Matrix<double, 5, 5> covariance = Eigen::Matrix<double, 5, 5>::Zero();
  const double rotation_sigma = 0.01 * kDegToRad;
  covariance.diagonal() << rotation_sigma * rotation_sigma,
      rotation_sigma * rotation_sigma, rotation_sigma * rotation_sigma, 1e-6,
      1e-6;
  // The adjustment far the more precise: the difference's sigma is the
  // two-step's.
  const Eigen::Matrix<double, 5, 5> precise = 1e-6 * covariance;
  Rigid3d joint = two_step;
  joint.rotation = YawRotation(0.3 + 0.02 * kDegToRad);  // 2 sigma
  joint.translation.x() += 0.0035;                       // 3.5 sigma
  const std::vector<ExtrinsicDisagreement> disagreements =
      ExtrinsicDisagreements(joint, precise, two_step, covariance);
  ASSERT_EQ(disagreements.size(), 1u);
  EXPECT_EQ(disagreements[0].quantity, "translation_x");
  EXPECT_NEAR(disagreements[0].difference, 0.0035, 1e-12);
  EXPECT_NEAR(disagreements[0].two_step_stddev, 0.001, 1e-12);
  EXPECT_NEAR(disagreements[0].joint_stddev, 1e-6, 1e-12);
  EXPECT_NEAR(disagreements[0].Sigmas(), 3.5, 1e-5);
  joint.rotation = YawRotation(0.3 - 0.04 * kDegToRad);  // 4 sigma
  const auto with_yaw =
      ExtrinsicDisagreements(joint, precise, two_step, covariance);
  ASSERT_EQ(with_yaw.size(), 2u);
  EXPECT_EQ(with_yaw[0].quantity, "yaw");
  EXPECT_NEAR(with_yaw[0].difference, -0.04, 1e-9);
  // An adjustment as uncertain as the two-step: 4 / sqrt(2) = 2.8 sigma of
  // the difference, no disagreement; all five with min_sigmas 0.
  EXPECT_TRUE(
      ExtrinsicDisagreements(joint, covariance, two_step, covariance).empty());
  const auto all =
      ExtrinsicDisagreements(joint, covariance, two_step, covariance, 0.0);
  ASSERT_EQ(all.size(), 5u);
  EXPECT_EQ(all[4].quantity, "translation_y");
  EXPECT_NEAR(all[2].Sigmas(), 4.0 / std::sqrt(2.0), 1e-6);
}

TEST(AdoptJointExtrinsic, ReplacesTheExtrinsicBlockAndKeepsTheScales) {
  CalibrationResult result;
  result.odom_from_cam.translation = Eigen::Vector3d(0.2, 0.1, 0.4);
  result.metric_scales = {0.5};
  result.covariance = Eigen::MatrixXd::Constant(6, 6, 1e-8);
  (*result.covariance)(5, 5) = 4e-6;
  JointAdjustmentResult joint;
  joint.odom_from_cam.rotation = YawRotation(0.1);
  joint.odom_from_cam.translation = Eigen::Vector3d(0.21, 0.11, 9.0);
  joint.covariance.diagonal() << 1e-8, 4e-8, 9e-8, 1e-6, 4e-6;
  AdoptJointExtrinsic(joint, &result);
  EXPECT_EQ(result.odom_from_cam.translation,
            Eigen::Vector3d(0.21, 0.11, 0.4));  // z stays
  const Eigen::MatrixXd extrinsic_block =
      result.covariance->topLeftCorner(5, 5);
  EXPECT_TRUE(extrinsic_block.isApprox(Eigen::MatrixXd(joint.covariance)));
  EXPECT_EQ((*result.covariance)(5, 5), 4e-6);
  EXPECT_EQ((*result.covariance)(0, 5), 0.0);
  EXPECT_NEAR(result.stddev_translation_xy_m.y(), 2e-3, 1e-15);
  EXPECT_NEAR(result.stddev_rotation_axes_deg.z(), 3e-4 * kRadToDeg, 1e-12);
}

TEST(RefuseLooseAdoptedExtrinsic, NamesWhatIsBeyondTheCalibrationsLimits) {
  CalibrationOptions limits;  // 2 deg, 0.05 m
  CalibrationResult result;
  result.status = CalibrationStatus::kSuccess;
  result.has_estimate = true;
  result.stddev_rotation_axes_deg = Eigen::Vector3d(0.5, 1.0, 1.9);
  result.stddev_translation_xy_m = Eigen::Vector2d(0.049, 0.04);
  RefuseLooseAdoptedExtrinsic(limits, &result);
  EXPECT_EQ(result.status, CalibrationStatus::kSuccess);
  EXPECT_TRUE(result.observability.ExtrinsicDetermined());

  result.stddev_translation_xy_m = Eigen::Vector2d(0.497, 0.04);
  RefuseLooseAdoptedExtrinsic(limits, &result);
  EXPECT_EQ(result.status, CalibrationStatus::kUnobservable);
  EXPECT_TRUE(result.has_estimate);
  EXPECT_EQ(result.observability.translation_x, Determination::kUndetermined);
  EXPECT_EQ(result.observability.translation_y, Determination::kEstimated);
  EXPECT_EQ(result.observability.rotation, Determination::kEstimated);
  EXPECT_NE(result.message.find("does not determine: translation_x (0.497 m "
                                "> 0.05 m) (standard deviation"),
            std::string::npos)
      << result.message;

  CalibrationResult rotation;
  rotation.status = CalibrationStatus::kSuccess;
  rotation.stddev_rotation_axes_deg = Eigen::Vector3d(0.5, 2.5, 0.1);
  RefuseLooseAdoptedExtrinsic(limits, &rotation);
  EXPECT_EQ(rotation.status, CalibrationStatus::kUnobservable);
  EXPECT_EQ(rotation.observability.rotation, Determination::kUndetermined);
  EXPECT_NE(rotation.message.find("rotation (2.5 deg > 2 deg)"),
            std::string::npos)
      << rotation.message;
}

// The sparse covariances against their dense formulas on a random
// least-squares problem: (J^T J)^-1 and the sandwich
// H^-1 (sum_c J_c^T r_c r_c^T J_c) H^-1 over clusters of rows.
TEST(LeadingCovariancesOf, MatchTheDenseFormulas) {
  std::mt19937 random(3);
  std::normal_distribution<double> normal;
  constexpr int kRows = 40, kCols = 7, kWanted = 3;
  Eigen::MatrixXd dense(kRows, kCols);
  for (int r = 0; r < kRows; ++r)
    for (int c = 0; c < kCols; ++c)
      dense(r, c) = (r + c) % 3 == 0 ? 0.0 : normal(random) * (1.0 + c);
  Eigen::VectorXd residuals(kRows);
  for (int r = 0; r < kRows; ++r) residuals[r] = normal(random);
  std::vector<int> clusters(kRows);
  for (int r = 0; r < kRows; ++r) clusters[r] = r / 4;
  const Eigen::SparseMatrix<double, Eigen::RowMajor> sparse =
      dense.sparseView();
  LeadingCovariances covariances;
  ASSERT_TRUE(
      LeadingCovariancesOf(sparse, residuals, clusters, kWanted, &covariances));
  const Eigen::MatrixXd inverse = (dense.transpose() * dense).inverse();
  EXPECT_TRUE(covariances.model.isApprox(
      inverse.topLeftCorner(kWanted, kWanted), 1e-9));
  Eigen::MatrixXd meat = Eigen::MatrixXd::Zero(kCols, kCols);
  for (int c = 0; c < kRows / 4; ++c) {
    const Eigen::VectorXd g =
        dense.middleRows(4 * c, 4).transpose() * residuals.segment(4 * c, 4);
    meat += g * g.transpose();
  }
  const Eigen::MatrixXd sandwich = inverse * meat * inverse;
  EXPECT_TRUE(covariances.robust.isApprox(
      sandwich.topLeftCorner(kWanted, kWanted), 1e-9));
  // A column nothing sees: singular.
  Eigen::MatrixXd blind = dense;
  blind.col(5).setZero();
  EXPECT_FALSE(LeadingCovariancesOf(
      blind.sparseView(), residuals, clusters, kWanted, &covariances));
}

}  // namespace
}  // namespace odomcal
