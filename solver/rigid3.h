// Rigid-body transform value type used across odomcal.
//
// A Rigid3d named `b_from_a` maps coordinates of a point expressed in frame a
// into frame b:  x_in_b = b_from_a * x_in_a = R * x_in_a + t.
// Rotations are Hamilton unit quaternions (Eigen::Quaterniond; its constructor
// takes w, x, y, z while coeffs() stores x, y, z, w).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace odomcal {

struct Rigid3d {
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();

  Rigid3d() = default;
  Rigid3d(const Eigen::Quaterniond& rotation,
          const Eigen::Vector3d& translation)
      : rotation(rotation), translation(translation) {}

  // 4x4 homogeneous matrix [R t; 0 1].
  Eigen::Matrix4d ToMatrix() const;
  // Apply to a point.
  Eigen::Vector3d operator*(const Eigen::Vector3d& x) const {
    return rotation * x + translation;
  }
};

// c_from_a = c_from_b * b_from_a.
Rigid3d operator*(const Rigid3d& c_from_b, const Rigid3d& b_from_a);

// a_from_b from b_from_a.
Rigid3d Inverse(const Rigid3d& b_from_a);

// Rotation angle of a unit quaternion in [0, pi] radians.
double RotationAngle(const Eigen::Quaterniond& q);

// Rotation vector phi with q = Exp(phi), |phi| in [0, pi].
Eigen::Vector3d LogRotation(const Eigen::Quaterniond& q);

// Unit quaternion of the rotation vector phi (angle |phi| about phi / |phi|).
Eigen::Quaterniond ExpRotation(const Eigen::Vector3d& phi);

// Rotation about +z by yaw radians.
Eigen::Quaterniond YawRotation(double yaw_rad);

// [v]x, the cross product as a matrix: [v]x w = v x w.
Eigen::Matrix3d CrossProductMatrix(const Eigen::Vector3d& v);

// Angle of a rotation about +z, radians in (-pi, pi]; for a rotation with
// other components it is the z part of the twist-swing split, not the
// RollPitchYaw yaw.
double YawAboutZ(const Eigen::Quaterniond& q);

// The same rotation with a non-negative scalar part.
Eigen::Quaterniond WithPositiveScalar(const Eigen::Quaterniond& q);

// Intrinsic roll-pitch-yaw (R = Rz(yaw) * Ry(pitch) * Rx(roll)), radians.
Eigen::Vector3d RollPitchYaw(const Eigen::Quaterniond& q);

// d RollPitchYaw / d phi at q for a left perturbation Exp(phi) q
// (numerical), to carry a rotation covariance into roll, pitch and yaw.
Eigen::Matrix3d RollPitchYawJacobian(const Eigen::Quaterniond& q);

// True when every coefficient is finite.
bool IsFinite(const Rigid3d& transform);

}  // namespace odomcal
