// A relative motion seen by both the wheel odometer and the camera.
//
// Both sides of the hand-eye equation are odom_i_from_cam_j:
//   odom_i_from_odom_j * odom_from_cam == odom_from_cam * cam_i_from_cam_j(s)
// where cam_i_from_cam_j(s) has its translation multiplied by the metric scale
// s of the camera's segment (metres per reconstruction unit).
#pragma once

#include "odomcal/solver/odometry_intrinsics.h"
#include "odomcal/solver/rigid3.h"

#include <Eigen/Core>

#include <cstdint>
#include <optional>
#include <vector>

namespace odomcal {

// 6x6 covariance of a relative motion, order [rotation(3), translation(3)];
// rotation as a left perturbation R = Exp(phi) * R_hat in radians, translation
// additive in the motion's own units (metres for odometry, reconstruction
// units for the camera).
using MotionCovariance = Eigen::Matrix<double, 6, 6>;

// The body twists of 3-D odometry at a pair's endpoints, per second:
// [rotation (rad/s), translation (m/s)] of the odometry frame at the endpoint,
// in that frame (origin_from_odom(t + h) = origin_from_odom(t) Exp(h xi)).
struct OdometryEndpointTwists {
  Eigen::Matrix<double, 6, 1> at_i = Eigen::Matrix<double, 6, 1>::Zero();
  Eigen::Matrix<double, 6, 1> at_j = Eigen::Matrix<double, 6, 1>::Zero();
};

struct MotionPair {
  Rigid3d odom_i_from_odom_j;  // metric, from the wheel odometry
  Rigid3d cam_i_from_cam_j;    // from SfM, translation in reconstruction units
  int segment = 0;             // index of the SfM segment (its own scale)
  int64_t stamp_i_ns = 0;
  int64_t stamp_j_ns = 0;
  // Optional per-motion covariances; when absent, CalibrationOptions' noise
  // parameters define them.
  std::optional<MotionCovariance> odom_covariance;
  std::optional<MotionCovariance> cam_covariance;
  // Added to the odometry covariance, whichever defines it: the error of
  // interpolating the odometry at the camera times (measured by the data, so
  // not scaled with the noise model).
  std::optional<MotionCovariance> odom_interpolation_covariance;
  // Optional: the logged planar odometry between the endpoints, for
  // estimating the clock offset and the odometry intrinsics with the
  // extrinsic (solver/systematics_refine.h).
  std::optional<OdometrySamples> odometry_samples;
  // Optional, 3-D odometry: the endpoint twists, for estimating the clock
  // offset with the extrinsic (solver/systematics_refine.h).
  std::optional<OdometryEndpointTwists> odometry_twists;
};

using MotionPairs = std::vector<MotionPair>;

// Number of segments: 1 + the largest segment index (0 for no pairs).
int NumSegments(const MotionPairs& pairs);

}  // namespace odomcal
