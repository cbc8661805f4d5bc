#include "odomcal/solver/camera_pair.h"

#include "odomcal/solver/angles.h"

#include <cmath>

namespace odomcal {
namespace {

using Matrix6d = Eigen::Matrix<double, 6, 6>;

Eigen::Vector3d SqrtDiagonal(const Eigen::Matrix3d& m) {
  return m.diagonal().cwiseMax(0.0).cwiseSqrt();
}

}  // namespace

std::optional<ExtrinsicWithCovariance> ExtrinsicOf(
    const CalibrationResult& result) {
  const Observability& o = result.observability;
  constexpr Determination kEstimated = Determination::kEstimated;
  if (!result.IsSuccess() || !result.has_estimate || !result.covariance ||
      o.rotation != kEstimated || o.translation_x != kEstimated ||
      o.translation_y != kEstimated) {
    return std::nullopt;
  }
  const Eigen::MatrixXd& c = *result.covariance;
  ExtrinsicWithCovariance out;
  out.odom_from_cam = result.odom_from_cam;
  // Rows 0-4 are rx ry rz tx ty; tz, when estimated or moved by its prior,
  // is the last row (calibration_result.h).
  out.covariance.topLeftCorner<5, 5>() = c.topLeftCorner(5, 5);
  out.z_held = !(o.translation_z == kEstimated ||
                 result.translation_z_prior.moved_by_data);
  if (!out.z_held) {
    const Eigen::Index z = c.rows() - 1;
    for (int k = 0; k < 5; ++k) {
      out.covariance(5, k) = c(z, k);
      out.covariance(k, 5) = c(k, z);
    }
    out.covariance(5, 5) = c(z, z);
  }
  return out;
}

CameraPairTransform CameraPairOf(const ExtrinsicWithCovariance& a,
                                 const ExtrinsicWithCovariance& b,
                                 const Matrix6d& a_b_covariance) {
  CameraPairTransform pair;
  pair.camb_from_cama = Inverse(b.odom_from_cam) * a.odom_from_cam;
  const Eigen::Matrix3d rb_t =
      b.odom_from_cam.rotation.toRotationMatrix().transpose();
  const Eigen::Vector3d offset =
      a.odom_from_cam.translation - b.odom_from_cam.translation;
  // R_BA = R_B^T R_A and t_BA = R_B^T (t_A - t_B) to first order in the
  // perturbations of A and of B.
  Matrix6d ja = Matrix6d::Zero();
  ja.topLeftCorner<3, 3>() = rb_t;
  ja.bottomRightCorner<3, 3>() = rb_t;
  Matrix6d jb = Matrix6d::Zero();
  jb.topLeftCorner<3, 3>() = -rb_t;
  jb.bottomLeftCorner<3, 3>() = rb_t * CrossProductMatrix(offset);
  jb.bottomRightCorner<3, 3>() = -rb_t;
  const Matrix6d cross = ja * a_b_covariance * jb.transpose();
  pair.covariance = ja * a.covariance * ja.transpose() +
                    jb * b.covariance * jb.transpose() + cross +
                    cross.transpose();
  pair.covariance = 0.5 * (pair.covariance + pair.covariance.transpose());

  const Eigen::Matrix3d rotation = pair.covariance.topLeftCorner<3, 3>();
  pair.stddev_rotation_axes_deg = SqrtDiagonal(rotation) * kRadToDeg;
  const Eigen::Matrix3d rpy_jacobian =
      RollPitchYawJacobian(pair.camb_from_cama.rotation);
  pair.stddev_roll_pitch_yaw_deg =
      SqrtDiagonal(rpy_jacobian * rotation * rpy_jacobian.transpose()) *
      kRadToDeg;
  pair.stddev_translation_m =
      SqrtDiagonal(pair.covariance.bottomRightCorner<3, 3>());

  pair.odom_offset_m = offset;
  const Eigen::Matrix3d offset_cross = a_b_covariance.bottomRightCorner<3, 3>();
  pair.stddev_odom_offset_m =
      SqrtDiagonal(a.covariance.bottomRightCorner<3, 3>() +
                   b.covariance.bottomRightCorner<3, 3>() - offset_cross -
                   offset_cross.transpose());
  pair.odom_offset_z_held = a.z_held || b.z_held;
  pair.angle_deg = RotationAngle(pair.camb_from_cama.rotation) * kRadToDeg;
  return pair;
}

}  // namespace odomcal
