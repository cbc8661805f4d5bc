#include "odomcal/solver/joint_extrinsic.h"

#include "odomcal/solver/angles.h"

#include <cmath>

namespace odomcal {

void AdoptJointExtrinsic(const JointAdjustmentResult& joint,
                         CalibrationResult* result) {
  result->odom_from_cam.rotation = joint.odom_from_cam.rotation;
  result->odom_from_cam.translation.head<2>() =
      joint.odom_from_cam.translation.head<2>();
  if (result->covariance) {
    Eigen::MatrixXd& covariance = *result->covariance;
    covariance.topRows<5>().setZero();
    covariance.leftCols<5>().setZero();
    covariance.topLeftCorner<5, 5>() = joint.covariance;
  }
  const Eigen::Matrix3d rotation = joint.covariance.topLeftCorner<3, 3>();
  result->stddev_rotation_axes_deg =
      rotation.diagonal().cwiseSqrt() * kRadToDeg;
  const Eigen::Matrix3d rpy =
      RollPitchYawJacobian(result->odom_from_cam.rotation);
  result->stddev_roll_pitch_yaw_deg =
      (rpy * rotation * rpy.transpose()).diagonal().cwiseSqrt() * kRadToDeg;
  result->stddev_translation_xy_m =
      joint.covariance.bottomRightCorner<2, 2>().diagonal().cwiseSqrt();
}

std::vector<ExtrinsicDisagreement> ExtrinsicDisagreements(
    const Rigid3d& joint,
    const Rigid3d& two_step,
    const Eigen::Matrix<double, 5, 5>& two_step_covariance) {
  const Eigen::Matrix3d rpy = RollPitchYawJacobian(two_step.rotation);
  const Eigen::Vector3d rpy_stddev =
      (rpy * two_step_covariance.topLeftCorner<3, 3>() * rpy.transpose())
          .diagonal()
          .cwiseSqrt() *
      kRadToDeg;
  Eigen::Vector3d rpy_difference =
      (RollPitchYaw(joint.rotation) - RollPitchYaw(two_step.rotation)) *
      kRadToDeg;
  for (int k = 0; k < 3; ++k) {
    rpy_difference[k] = std::remainder(rpy_difference[k], 360.0);
  }
  std::vector<ExtrinsicDisagreement> disagreements;
  constexpr double kSigmas = 3.0;
  const char* const kRotationNames[] = {"roll", "pitch", "yaw"};
  for (int k = 0; k < 3; ++k) {
    if (std::abs(rpy_difference[k]) > kSigmas * rpy_stddev[k]) {
      disagreements.push_back(
          {kRotationNames[k], rpy_difference[k], rpy_stddev[k]});
    }
  }
  const char* const kTranslationNames[] = {"translation_x", "translation_y"};
  for (int k = 0; k < 2; ++k) {
    const double difference = joint.translation[k] - two_step.translation[k];
    const double stddev = std::sqrt(two_step_covariance(3 + k, 3 + k));
    if (std::abs(difference) > kSigmas * stddev) {
      disagreements.push_back({kTranslationNames[k], difference, stddev});
    }
  }
  return disagreements;
}

}  // namespace odomcal
