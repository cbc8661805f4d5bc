#include "odomcal/solver/joint_extrinsic.h"

#include "odomcal/solver/angles.h"
#include "odomcal/solver/format_number.h"

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

void RefuseLooseAdoptedExtrinsic(const CalibrationOptions& limits,
                                 CalibrationResult* result) {
  std::string loose;
  const auto name = [&loose](const std::string& quantity,
                             double stddev,
                             double limit,
                             const char* unit) {
    loose += (loose.empty() ? "" : ", ") + quantity + " (" +
             FormatRounded(stddev, 3) + unit + " > " + FormatNumber(limit) +
             unit + ")";
  };
  const double rotation_deg = result->stddev_rotation_axes_deg.maxCoeff();
  if (!(rotation_deg <= limits.max_rotation_stddev_deg)) {
    result->observability.rotation = Determination::kUndetermined;
    name("rotation", rotation_deg, limits.max_rotation_stddev_deg, " deg");
  }
  for (int k = 0; k < 2; ++k) {
    const double stddev_m = result->stddev_translation_xy_m[k];
    if (stddev_m <= limits.max_translation_stddev_m) continue;
    (k == 0 ? result->observability.translation_x
            : result->observability.translation_y) =
        Determination::kUndetermined;
    name(k == 0 ? "translation_x" : "translation_y",
         stddev_m,
         limits.max_translation_stddev_m,
         " m");
  }
  if (loose.empty()) return;
  result->status = CalibrationStatus::kUnobservable;
  result->message =
      "the joint adjustment's estimate (the one reported) does not "
      "determine: " +
      loose +
      " (standard deviation above the limit); look at the reconstruction "
      "(folds, scale drift) and drive turns of different sizes in both "
      "directions";
}

double ExtrinsicDisagreement::Sigmas() const {
  return std::abs(difference) / std::hypot(two_step_stddev, joint_stddev);
}

namespace {

// Standard deviations of roll, pitch, yaw (deg) and x, y (m) of an estimate
// with rotation `rotation` and covariance `covariance`.
Eigen::Matrix<double, 5, 1> QuantityStddevs(
    const Eigen::Quaterniond& rotation,
    const Eigen::Matrix<double, 5, 5>& covariance) {
  const Eigen::Matrix3d rpy = RollPitchYawJacobian(rotation);
  Eigen::Matrix<double, 5, 1> stddevs;
  stddevs.head<3>() = (rpy * covariance.topLeftCorner<3, 3>() * rpy.transpose())
                          .diagonal()
                          .cwiseSqrt() *
                      kRadToDeg;
  stddevs.tail<2>() =
      covariance.bottomRightCorner<2, 2>().diagonal().cwiseSqrt();
  return stddevs;
}

}  // namespace

std::vector<ExtrinsicDisagreement> ExtrinsicDisagreements(
    const Rigid3d& joint,
    const Eigen::Matrix<double, 5, 5>& joint_covariance,
    const Rigid3d& two_step,
    const Eigen::Matrix<double, 5, 5>& two_step_covariance,
    double min_sigmas) {
  const Eigen::Matrix<double, 5, 1> two_step_stddev =
      QuantityStddevs(two_step.rotation, two_step_covariance);
  const Eigen::Matrix<double, 5, 1> joint_stddev =
      QuantityStddevs(joint.rotation, joint_covariance);
  Eigen::Matrix<double, 5, 1> difference;
  difference.head<3>() =
      (RollPitchYaw(joint.rotation) - RollPitchYaw(two_step.rotation)) *
      kRadToDeg;
  for (int k = 0; k < 3; ++k) {
    difference[k] = std::remainder(difference[k], 360.0);
  }
  difference.tail<2>() =
      joint.translation.head<2>() - two_step.translation.head<2>();
  const char* const kNames[] = {
      "roll", "pitch", "yaw", "translation_x", "translation_y"};
  std::vector<ExtrinsicDisagreement> disagreements;
  for (int k = 0; k < 5; ++k) {
    const ExtrinsicDisagreement disagreement{
        kNames[k], difference[k], two_step_stddev[k], joint_stddev[k]};
    if (min_sigmas <= 0.0 || disagreement.Sigmas() > min_sigmas) {
      disagreements.push_back(disagreement);
    }
  }
  return disagreements;
}

}  // namespace odomcal
