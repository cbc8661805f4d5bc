#include "odomcal/solver/floor_translation_z.h"

#include "odomcal/solver/angles.h"
#include "odomcal/solver/format_number.h"
#include "odomcal/solver/rigid3.h"

#include <cmath>

namespace odomcal {
namespace {

// The standard deviations CalibrationResult derives from its covariance.
void SetStandardDeviations(CalibrationResult* result) {
  const Eigen::MatrixXd& covariance = *result->covariance;
  const Eigen::Matrix3d rotation = covariance.topLeftCorner<3, 3>();
  result->stddev_rotation_axes_deg =
      rotation.diagonal().cwiseSqrt() * kRadToDeg;
  const Eigen::Matrix3d rpy_jacobian =
      RollPitchYawJacobian(result->odom_from_cam.rotation);
  result->stddev_roll_pitch_yaw_deg =
      (rpy_jacobian * rotation * rpy_jacobian.transpose())
          .diagonal()
          .cwiseSqrt() *
      kRadToDeg;
  result->stddev_translation_xy_m =
      covariance.block<2, 2>(3, 3).diagonal().cwiseSqrt();
  for (size_t k = 0; k < result->covariance_segments.size(); ++k) {
    const int segment = result->covariance_segments[k];
    const Eigen::Index row = 5 + static_cast<Eigen::Index>(k);
    result->stddev_metric_scales_rel[segment] =
        std::sqrt(covariance(row, row)) / result->metric_scales[segment];
  }
  const Eigen::Index z = covariance.rows() - 1;
  result->stddev_translation_z_m = std::sqrt(covariance(z, z));
}

// z under its prior is the covariance's last row, correlated with the rest:
// the floor's height is one more measurement of it, y = z - g^T (s - s_hat)
// + e with var(e) = var(H | plane), and updates every parameter (a Kalman
// update; with a prior that tells nothing it is the floor's z of
// SetTranslationZFromFloor, and x, y, the rotation and the scales move with
// z as their correlation with it says).
void UpdateTranslationZUnderPrior(const FloorPlane& floor,
                                  const FloorPlaneOptions& options,
                                  const Eigen::VectorXd& g,
                                  CalibrationResult* result) {
  const Eigen::MatrixXd& covariance = *result->covariance;
  const Eigen::Index n = covariance.rows();
  Eigen::VectorXd h = -g;
  h(n - 1) = 1.0;
  const Eigen::VectorXd covariance_h = covariance * h;
  const double innovation_variance =
      h.dot(covariance_h) +
      floor.camera_height_stddev_m * floor.camera_height_stddev_m;
  const Eigen::VectorXd gain = covariance_h / innovation_variance;
  const double innovation = floor.camera_height_m - options.odometry_height_m -
                            result->odom_from_cam.translation.z();
  const Eigen::VectorXd step = gain * innovation;
  Rigid3d& odom_from_cam = result->odom_from_cam;
  odom_from_cam.rotation =
      (ExpRotation(step.head<3>()) * odom_from_cam.rotation).normalized();
  odom_from_cam.translation += Eigen::Vector3d(step(3), step(4), step(n - 1));
  for (size_t k = 0; k < result->covariance_segments.size(); ++k) {
    result->metric_scales[result->covariance_segments[k]] +=
        step(5 + static_cast<Eigen::Index>(k));
  }
  const Eigen::MatrixXd updated = covariance - gain * covariance_h.transpose();
  result->covariance = 0.5 * (updated + updated.transpose());
  SetStandardDeviations(result);
}

}  // namespace

std::string SetTranslationZFromFloor(const FloorPlane& floor,
                                     const FloorPlaneOptions& options,
                                     double max_stddev_m,
                                     CalibrationResult* result) {
  if (options.use == FloorPlaneUse::kOff) return "--floor_plane off";
  if (options.use == FloorPlaneUse::kCheck) {
    return "--fixed_translation_z_m given (the floor is only checked)";
  }
  if (!floor.Fitted()) return floor.reason;
  Observability& observability = result->observability;
  if (observability.translation_z != Determination::kHeld) {
    return "z is estimated from the motion (SE(3) odometry)";
  }
  if (!result->has_estimate || !result->covariance ||
      !observability.ExtrinsicDetermined()) {
    return "the extrinsic's rotation and x, y are not all determined";
  }
  const Eigen::MatrixXd& old = *result->covariance;
  const Eigen::Index n = old.rows();
  // The scale rows: 5 .. 5 + segments - 1.
  Eigen::VectorXd g = Eigen::VectorXd::Zero(n);
  for (size_t k = 0; k < result->covariance_segments.size(); ++k) {
    const int segment = result->covariance_segments[k];
    if (segment >= 0 &&
        segment < static_cast<int>(floor.height_per_scale.size())) {
      g(5 + static_cast<Eigen::Index>(k)) = floor.height_per_scale[segment];
    }
  }
  // z under its prior has the last row already (zero in g).
  if (result->translation_z_prior.moved_by_data) {
    const double stddev =
        std::sqrt(floor.camera_height_stddev_m * floor.camera_height_stddev_m +
                  g.dot(old * g));
    if (!(stddev <= max_stddev_m)) {
      return "the floor gives z only to " + FormatRounded(1000.0 * stddev, 3) +
             " mm (1 sigma), more than --max_translation_stddev_m";
    }
    UpdateTranslationZUnderPrior(floor, options, g, result);
    result->translation_z_prior.used = false;
    observability.translation_z = Determination::kEstimated;
    observability.translation_z_source = TranslationZSource::kFloorPlane;
    return "";
  }
  Eigen::MatrixXd covariance = Eigen::MatrixXd::Zero(n + 1, n + 1);
  covariance.topLeftCorner(n, n) = old;
  const Eigen::VectorXd cross = old * g;
  covariance.block(n, 0, 1, n) = cross.transpose();
  covariance.block(0, n, n, 1) = cross;
  covariance(n, n) =
      floor.camera_height_stddev_m * floor.camera_height_stddev_m +
      g.dot(cross);
  const double stddev = std::sqrt(covariance(n, n));
  if (!(stddev <= max_stddev_m)) {
    return "the floor gives z only to " + FormatRounded(1000.0 * stddev, 3) +
           " mm (1 sigma), more than --max_translation_stddev_m";
  }
  result->covariance = covariance;
  result->stddev_translation_z_m = std::sqrt(covariance(n, n));
  result->odom_from_cam.translation.z() =
      floor.camera_height_m - options.odometry_height_m;
  observability.translation_z = Determination::kEstimated;
  observability.translation_z_source = TranslationZSource::kFloorPlane;
  return "";
}

Eigen::Matrix2d RollPitchCovariance(const CalibrationResult& result) {
  if (!result.covariance || result.covariance->rows() < 2) {
    return Eigen::Matrix2d::Zero();
  }
  return result.covariance->topLeftCorner<2, 2>();
}

}  // namespace odomcal
