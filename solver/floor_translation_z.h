// Translation z from the floor: the calibration's held z replaced by the
// camera's height above the fitted floor minus the odometry frame's height
// (floor_plane.h), with its covariance.
#pragma once

#include "odomcal/solver/calibration_result.h"
#include "odomcal/solver/floor_plane.h"

#include <string>

namespace odomcal {

// When options.use is kEstimateZ, the floor is fitted, z is held (not
// estimated from SE(3) odometry) and the result has a covariance: sets
// odom_from_cam's z to floor.camera_height_m - options.odometry_height_m,
// translation_z to kEstimated from kFloorPlane, and appends z to the
// covariance (last row and column):
//   var(z) = var(H | plane) + g^T C_ss g,  cov(z, v) = sum_k g_k cov(s_k, v),
// g = floor.height_per_scale over the covariance's scale rows (the plane's
// errors are independent of the motion's). A standard deviation of z above
// max_stddev_m (the calibration's max_translation_stddev_m, the limit of x
// and y) leaves z held. Where z is under its prior with a row in the
// covariance (result->translation_z_prior.moved_by_data: SE(3) odometry
// that informs z without determining it), the floor's height is instead one
// more measurement of z that updates every parameter and the covariance
// (a Kalman update). Returns the reason z stays held otherwise (empty when
// z was set).
std::string SetTranslationZFromFloor(const FloorPlane& floor,
                                     const FloorPlaneOptions& options,
                                     double max_stddev_m,
                                     CalibrationResult* result);

// The motion's covariance of the rotation's x and y components (left
// perturbation about the odometry axes, radians^2); zero without one.
Eigen::Matrix2d RollPitchCovariance(const CalibrationResult& result);

}  // namespace odomcal
