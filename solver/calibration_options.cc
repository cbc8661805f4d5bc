#include "odomcal/solver/calibration_options.h"

#include "odomcal/solver/format_number.h"

#include <cmath>
#include <stdexcept>

namespace odomcal {
namespace {

void CheckNonNegative(double value, const char* name) {
  if (!(std::isfinite(value) && value >= 0.0)) {
    throw std::invalid_argument(std::string(name) +
                                " must be finite and >= 0, got " +
                                FormatNumber(value));
  }
}

void CheckPositive(double value, const char* name) {
  if (!(std::isfinite(value) && value > 0.0)) {
    throw std::invalid_argument(std::string(name) +
                                " must be finite and > 0, got " +
                                FormatNumber(value));
  }
}

}  // namespace

void NoiseModel::Check() const {
  CheckNonNegative(odom_yaw_sigma_deg, "odom_yaw_sigma_deg");
  CheckNonNegative(odom_yaw_sigma_rel, "odom_yaw_sigma_rel");
  CheckNonNegative(odom_tilt_sigma_deg, "odom_tilt_sigma_deg");
  // A zero constant part would make short odometry steps infinitely precise.
  CheckPositive(odom_translation_sigma_m, "odom_translation_sigma_m");
  CheckNonNegative(odom_translation_sigma_rel, "odom_translation_sigma_rel");
  // The camera rotation noise keeps the rotation residual covariance full
  // rank when the odometry reports no tilt noise.
  CheckPositive(cam_rotation_sigma_deg, "cam_rotation_sigma_deg");
  CheckNonNegative(cam_translation_sigma_rel, "cam_translation_sigma_rel");
  if (odom_yaw_sigma_deg == 0.0 && odom_yaw_sigma_rel == 0.0) {
    throw std::invalid_argument(
        "odom_yaw_sigma_deg and odom_yaw_sigma_rel are both 0 (the odometry "
        "yaw would be exact)");
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
    throw std::invalid_argument("fixed_translation_z_m must be finite, got " +
                                FormatNumber(fixed_translation_z_m));
  }
  CheckNonNegative(translation_z_prior_sigma_m, "translation_z_prior_sigma_m");
  CheckPositive(ransac_max_rotation_error_deg, "ransac_max_rotation_error_deg");
  CheckPositive(ransac_max_translation_error_m,
                "ransac_max_translation_error_m");
  CheckNonNegative(ransac_max_translation_error_rel,
                   "ransac_max_translation_error_rel");
  if (!(ransac_min_inlier_ratio >= 0.0 && ransac_min_inlier_ratio <= 1.0)) {
    throw std::invalid_argument(
        "ransac_min_inlier_ratio must be in [0, 1], got " +
        FormatNumber(ransac_min_inlier_ratio));
  }
  if (!(ransac_confidence > 0.0 && ransac_confidence < 1.0)) {
    throw std::invalid_argument("ransac_confidence must be in (0, 1), got " +
                                FormatNumber(ransac_confidence));
  }
  if (ransac_min_iterations < 1 ||
      ransac_max_iterations < ransac_min_iterations) {
    throw std::invalid_argument(
        "ransac_min_iterations and ransac_max_iterations must satisfy 1 <= "
        "min <= max, got " +
        std::to_string(ransac_min_iterations) + " and " +
        std::to_string(ransac_max_iterations));
  }
  CheckNonNegative(min_rotation_deg, "min_rotation_deg");
  if (min_num_rotating_pairs < 1) {
    throw std::invalid_argument("min_num_rotating_pairs must be >= 1, got " +
                                std::to_string(min_num_rotating_pairs));
  }
  if (min_num_pairs < 2) {
    throw std::invalid_argument("min_num_pairs must be >= 2, got " +
                                std::to_string(min_num_pairs));
  }
  CheckPositive(max_angle_mismatch_deg, "max_angle_mismatch_deg");
  CheckPositive(max_rotation_stddev_deg, "max_rotation_stddev_deg");
  CheckPositive(max_translation_stddev_m, "max_translation_stddev_m");
  CheckPositive(max_scale_stddev_rel, "max_scale_stddev_rel");
  CheckPositive(max_relative_translation_residual,
                "max_relative_translation_residual");
  CheckNonNegative(noise_prior_weight, "noise_prior_weight");
  if (num_threads != -1 && num_threads < 1) {
    throw std::invalid_argument(
        "num_threads must be -1 (the hardware's) or >= 1, got " +
        std::to_string(num_threads));
  }
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
