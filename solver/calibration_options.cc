#include "odomcal/solver/calibration_options.h"

#include <cmath>
#include <stdexcept>

namespace odomcal {
namespace {

void CheckNonNegative(double value, const char* name) {
  if (!(std::isfinite(value) && value >= 0.0)) {
    throw std::invalid_argument(std::string(name) +
                                " must be finite and >= 0, got " +
                                std::to_string(value));
  }
}

void CheckPositive(double value, const char* name) {
  if (!(std::isfinite(value) && value > 0.0)) {
    throw std::invalid_argument(std::string(name) +
                                " must be finite and > 0, got " +
                                std::to_string(value));
  }
}

}  // namespace

void NoiseModel::Check() const {
  CheckNonNegative(odom_yaw_sigma_deg, "noise.odom_yaw_sigma_deg");
  CheckNonNegative(odom_yaw_sigma_rel, "noise.odom_yaw_sigma_rel");
  CheckNonNegative(odom_tilt_sigma_deg, "noise.odom_tilt_sigma_deg");
  // A zero constant part would make short odometry steps infinitely precise.
  CheckPositive(odom_translation_sigma_m, "noise.odom_translation_sigma_m");
  CheckNonNegative(odom_translation_sigma_rel,
                   "noise.odom_translation_sigma_rel");
  // The camera rotation noise keeps the rotation residual covariance full
  // rank when the odometry reports no tilt noise.
  CheckPositive(cam_rotation_sigma_deg, "noise.cam_rotation_sigma_deg");
  CheckNonNegative(cam_translation_sigma_rel,
                   "noise.cam_translation_sigma_rel");
  if (odom_yaw_sigma_deg == 0.0 && odom_yaw_sigma_rel == 0.0) {
    throw std::invalid_argument(
        "noise.odom_yaw_sigma_deg and noise.odom_yaw_sigma_rel are both 0");
  }
}

void CalibrationOptions::Check() const {
  noise.Check();
  if (max_num_iterations < 1) {
    throw std::invalid_argument("max_num_iterations must be >= 1, got " +
                                std::to_string(max_num_iterations));
  }
  CheckPositive(robust_loss_scale, "robust_loss_scale");
  if (!std::isfinite(fixed_translation_z_m)) {
    throw std::invalid_argument("fixed_translation_z_m must be finite");
  }
  CheckPositive(ransac_max_rotation_error_deg, "ransac_max_rotation_error_deg");
  CheckPositive(ransac_max_translation_error_m,
                "ransac_max_translation_error_m");
  CheckNonNegative(ransac_max_translation_error_rel,
                   "ransac_max_translation_error_rel");
  if (!(ransac_min_inlier_ratio >= 0.0 && ransac_min_inlier_ratio <= 1.0)) {
    throw std::invalid_argument(
        "ransac_min_inlier_ratio must be in [0, 1], got " +
        std::to_string(ransac_min_inlier_ratio));
  }
  if (!(ransac_confidence > 0.0 && ransac_confidence < 1.0)) {
    throw std::invalid_argument("ransac_confidence must be in (0, 1), got " +
                                std::to_string(ransac_confidence));
  }
  if (ransac_min_iterations < 1 ||
      ransac_max_iterations < ransac_min_iterations) {
    throw std::invalid_argument(
        "ransac iterations need 1 <= ransac_min_iterations <= "
        "ransac_max_iterations");
  }
  CheckNonNegative(min_rotation_deg, "min_rotation_deg");
  if (min_num_rotating_pairs < 1) {
    throw std::invalid_argument("min_num_rotating_pairs must be >= 1");
  }
  if (min_num_pairs < 2) {
    throw std::invalid_argument("min_num_pairs must be >= 2");
  }
  CheckPositive(max_angle_mismatch_deg, "max_angle_mismatch_deg");
  CheckPositive(max_rotation_stddev_deg, "max_rotation_stddev_deg");
  CheckPositive(max_translation_stddev_m, "max_translation_stddev_m");
  CheckPositive(max_scale_stddev_rel, "max_scale_stddev_rel");
  CheckPositive(max_relative_translation_residual,
                "max_relative_translation_residual");
}

std::string ToString(LinearMethod method) {
  return method == LinearMethod::kAlsp ? "alsp" : "als";
}

std::string ToString(PlaneProjection projection) {
  return projection == PlaneProjection::kLengthPreserving ? "length_preserving"
                                                          : "orthogonal";
}

std::string ToString(RobustLoss loss) {
  switch (loss) {
    case RobustLoss::kNone:
      return "none";
    case RobustLoss::kHuber:
      return "huber";
    case RobustLoss::kCauchy:
      return "cauchy";
  }
  return "none";
}

LinearMethod LinearMethodFromString(const std::string& name) {
  if (name == "alsp") return LinearMethod::kAlsp;
  if (name == "als") return LinearMethod::kAls;
  throw std::invalid_argument("unknown method '" + name +
                              "' (expected alsp or als)");
}

PlaneProjection PlaneProjectionFromString(const std::string& name) {
  if (name == "length_preserving") return PlaneProjection::kLengthPreserving;
  if (name == "orthogonal") return PlaneProjection::kOrthogonal;
  throw std::invalid_argument("unknown projection '" + name +
                              "' (expected length_preserving or orthogonal)");
}

RobustLoss RobustLossFromString(const std::string& name) {
  if (name == "none") return RobustLoss::kNone;
  if (name == "huber") return RobustLoss::kHuber;
  if (name == "cauchy") return RobustLoss::kCauchy;
  throw std::invalid_argument("unknown robust loss '" + name +
                              "' (expected none, huber or cauchy)");
}

}  // namespace odomcal
