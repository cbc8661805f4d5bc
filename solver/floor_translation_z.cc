#include "odomcal/solver/floor_translation_z.h"

#include "odomcal/solver/format_number.h"

#include <cmath>

namespace odomcal {

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
