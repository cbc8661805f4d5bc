#include "odomcal/solver/rigid3.h"

#include "odomcal/solver/angles.h"

#include <algorithm>
#include <cmath>

namespace odomcal {

Eigen::Matrix4d Rigid3d::ToMatrix() const {
  Eigen::Matrix4d matrix = Eigen::Matrix4d::Identity();
  matrix.topLeftCorner<3, 3>() = rotation.toRotationMatrix();
  matrix.topRightCorner<3, 1>() = translation;
  return matrix;
}

Rigid3d operator*(const Rigid3d& c_from_b, const Rigid3d& b_from_a) {
  return Rigid3d(
      (c_from_b.rotation * b_from_a.rotation).normalized(),
      c_from_b.rotation * b_from_a.translation + c_from_b.translation);
}

Rigid3d Inverse(const Rigid3d& b_from_a) {
  const Eigen::Quaterniond a_from_b_rotation = b_from_a.rotation.conjugate();
  return Rigid3d(a_from_b_rotation,
                 -(a_from_b_rotation * b_from_a.translation));
}

double RotationAngle(const Eigen::Quaterniond& q) {
  return LogRotation(q).norm();
}

Eigen::Vector3d LogRotation(const Eigen::Quaterniond& q) {
  const Eigen::Quaterniond positive = WithPositiveScalar(q.normalized());
  const double sin_half = positive.vec().norm();
  // atan2 keeps full precision for both tiny and near-pi angles.
  const double angle = 2.0 * std::atan2(sin_half, positive.w());
  if (sin_half < 1e-12) {
    return 2.0 * positive.vec();  // first order: q ~ [1, phi / 2]
  }
  return positive.vec() * (angle / sin_half);
}

Eigen::Quaterniond ExpRotation(const Eigen::Vector3d& phi) {
  const double angle = phi.norm();
  if (angle < 1e-12) {
    return Eigen::Quaterniond(1.0, 0.5 * phi.x(), 0.5 * phi.y(), 0.5 * phi.z())
        .normalized();
  }
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, phi / angle));
}

Eigen::Quaterniond YawRotation(double yaw_rad) {
  return Eigen::Quaterniond(
      std::cos(0.5 * yaw_rad), 0.0, 0.0, std::sin(0.5 * yaw_rad));
}

Eigen::Matrix3d CrossProductMatrix(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return m;
}

Eigen::Quaterniond WithPositiveScalar(const Eigen::Quaterniond& q) {
  return q.w() < 0.0 ? Eigen::Quaterniond(-q.coeffs()) : q;
}

double YawAboutZ(const Eigen::Quaterniond& q) {
  const Eigen::Quaterniond unit = WithPositiveScalar(q.normalized());
  return 2.0 * std::atan2(unit.z(), unit.w());
}

Eigen::Vector3d RollPitchYaw(const Eigen::Quaterniond& q) {
  const Eigen::Matrix3d r = q.normalized().toRotationMatrix();
  // atan2 rather than asin(-r(2, 0)): full precision near pitch +-pi/2.
  const double cos_pitch = std::hypot(r(0, 0), r(1, 0));
  const double pitch = std::atan2(-r(2, 0), cos_pitch);
  if (cos_pitch < 1e-10) {
    // Gimbal lock: only roll -+ yaw is determined; yaw = 0 takes it all.
    return Eigen::Vector3d(std::atan2(-r(1, 2), r(1, 1)), pitch, 0.0);
  }
  const double roll = std::atan2(r(2, 1), r(2, 2));
  const double yaw = std::atan2(r(1, 0), r(0, 0));
  return Eigen::Vector3d(roll, pitch, yaw);
}

bool IsFinite(const Rigid3d& transform) {
  return transform.rotation.coeffs().allFinite() &&
         transform.translation.allFinite();
}

Eigen::Matrix3d RollPitchYawJacobian(const Eigen::Quaterniond& q) {
  constexpr double kStep = 1e-7;
  Eigen::Matrix3d jacobian;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d delta = Eigen::Vector3d::Unit(k) * kStep;
    Eigen::Vector3d diff = RollPitchYaw(ExpRotation(delta) * q) -
                           RollPitchYaw(ExpRotation(-delta) * q);
    for (int j = 0; j < 3; ++j) {  // unwrap angles across +-pi
      diff(j) = std::remainder(diff(j), 2.0 * kPi);
    }
    jacobian.col(k) = diff / (2.0 * kStep);
  }
  return jacobian;
}

}  // namespace odomcal
