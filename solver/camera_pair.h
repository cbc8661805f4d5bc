// The transform between two cameras of a rig calibrated separately against
// one odometry: camB_from_camA = inverse(odom_from_camB) * odom_from_camA,
// with its covariance carried from the two cameras' covariances.
//
// Two cameras calibrated apart (each its own trajectory and solve) are
// treated as independent: they share the odometry, whose errors correlate
// the two extrinsics, and that correlation is not known. Two cameras
// adjusted together (a rig's joint adjustment: one trajectory) have their
// cross covariance, which the pair's covariance then holds.
//
// Translation z of each extrinsic is held at a given height unless the
// calibration estimated it (calibration_result.h): a held z carries no
// variance, so the pair's offset along the odometry's z axis is the
// difference of the held heights, not a measurement (`odom_offset_z_held`).
#pragma once

#include "odomcal/solver/calibration_result.h"
#include "odomcal/solver/rigid3.h"

#include <Eigen/Core>

#include <optional>

namespace odomcal {

// One extrinsic with its 6 x 6 covariance over [rx, ry, rz, tx, ty, tz]:
// rotation a left perturbation R = Exp(phi) R_hat in radians about the
// odometry axes, translation additive in metres; tz's row is zero when z is
// held.
struct ExtrinsicWithCovariance {
  Rigid3d odom_from_cam;
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
  bool z_held = true;
};

// From a calibration that succeeded with rotation, x and y estimated and a
// covariance; none otherwise.
std::optional<ExtrinsicWithCovariance> ExtrinsicOf(
    const CalibrationResult& result);

struct CameraPairTransform {
  Rigid3d camb_from_cama;
  // Over [rx, ry, rz, tx, ty, tz] of camb_from_cama: rotation a left
  // perturbation R = Exp(psi) R_hat in radians about camB's axes,
  // translation additive in metres in camB's frame.
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Vector3d stddev_rotation_axes_deg = Eigen::Vector3d::Zero();
  Eigen::Vector3d stddev_roll_pitch_yaw_deg = Eigen::Vector3d::Zero();
  Eigen::Vector3d stddev_translation_m = Eigen::Vector3d::Zero();
  // Camera A's origin minus camera B's, in the odometry frame (metres),
  // with its standard deviations; z is the difference of the held heights
  // when either height was held.
  Eigen::Vector3d odom_offset_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d stddev_odom_offset_m = Eigen::Vector3d::Zero();
  bool odom_offset_z_held = true;
  // Rotation angle between the two optical axes, degrees.
  double angle_deg = 0.0;
};

// `a_b_covariance`: the cross covariance of a's [rx, ry, rz, tx, ty, tz]
// (rows) with b's (columns), zero for independent estimates.
CameraPairTransform CameraPairOf(
    const ExtrinsicWithCovariance& a,
    const ExtrinsicWithCovariance& b,
    const Eigen::Matrix<double, 6, 6>& a_b_covariance =
        Eigen::Matrix<double, 6, 6>::Zero());

}  // namespace odomcal
