// For each motion: draw the robot motion, derive the true camera motion from
// the extrinsic, perturb the odometry, then measure the camera motion either
// parametrically or through landmarks and the two-view estimator; attach the
// covariances of what was applied, plus a tiny floor. The random draws
// happen in a fixed order per motion, so a seed reproduces a simulation
// exactly; landmark redraws after a failed two-view estimate consume
// further draws of the same generator.

#include "odomcal/datasets/paper/paper_simulation.h"

#include "odomcal/datasets/paper/two_view_pose.h"
#include "odomcal/datasets/simulation/motion_simulator.h"
#include "odomcal/solver/angles.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace odomcal {
namespace {

// Attempts at drawing one landmark visible in both views before giving up.
constexpr int kMaxLandmarkDraws = 1000;

void CheckNonNegative(double value, const char* name) {
  if (!(value >= 0.0) || !std::isfinite(value)) {
    throw std::invalid_argument(std::string(name) + " must be >= 0, got " +
                                std::to_string(value));
  }
}

void CheckPositive(double value, const char* name) {
  if (!(value > 0.0) || !std::isfinite(value)) {
    throw std::invalid_argument(std::string(name) + " must be > 0, got " +
                                std::to_string(value));
  }
}

void AddFloor(double translation_length, MotionCovariance* covariance) {
  const double t_floor =
      kCovarianceFloorRel * std::max(translation_length, 1e-3);
  covariance->diagonal().head<3>().array() +=
      kCovarianceFloorRad * kCovarianceFloorRad;
  covariance->diagonal().tail<3>().array() += t_floor * t_floor;
}

// Two unit vectors completing u to an orthonormal basis.
void OrthonormalComplement(const Eigen::Vector3d& u,
                           Eigen::Vector3d* e1,
                           Eigen::Vector3d* e2) {
  const Eigen::Vector3d helper = std::abs(u.x()) < 0.9
                                     ? Eigen::Vector3d::UnitX()
                                     : Eigen::Vector3d::UnitY();
  *e1 = u.cross(helper).normalized();
  *e2 = u.cross(*e1);
}

// Parametric camera measurement of `motion` and its covariance.
Rigid3d ParametricCameraMeasurement(const Rigid3d& motion,
                                    const PaperSimulationOptions& options,
                                    std::mt19937_64* rng,
                                    MotionCovariance* covariance) {
  std::normal_distribution<double> unit(0.0, 1.0);
  const double sigma_r = options.cam_rotation_sigma_rad;
  const double sigma_d = options.cam_direction_sigma_rad;
  Eigen::Vector3d phi;
  for (int k = 0; k < 3; ++k) phi(k) = sigma_r * unit(*rng);
  const double length = motion.translation.norm();
  Eigen::Vector3d translation = motion.translation;
  Eigen::Matrix3d direction_projector = Eigen::Matrix3d::Zero();
  if (length > 0.0) {
    const Eigen::Vector3d u = motion.translation / length;
    Eigen::Vector3d e1, e2;
    OrthonormalComplement(u, &e1, &e2);
    const double n1 = unit(*rng);
    const double n2 = unit(*rng);
    translation = ExpRotation(sigma_d * (n1 * e1 + n2 * e2)) * translation;
    direction_projector = Eigen::Matrix3d::Identity() - u * u.transpose();
  }
  covariance->setZero();
  covariance->topLeftCorner<3, 3>() =
      sigma_r * sigma_r * Eigen::Matrix3d::Identity();
  covariance->bottomRightCorner<3, 3>() =
      length * length * sigma_d * sigma_d * direction_projector;
  return Rigid3d((ExpRotation(phi) * motion.rotation).normalized(),
                 translation);
}

// Landmark camera measurement: true motion `metric_motion` (scale 1),
// reported with translation length `length` (reconstruction units).
bool LandmarkCameraMeasurement(const Rigid3d& metric_motion,
                               double length,
                               const PaperSimulationOptions& options,
                               std::mt19937_64* rng,
                               Rigid3d* measured,
                               MotionCovariance* covariance,
                               MotionCovariance* core_covariance) {
  std::uniform_real_distribution<double> depth(options.min_depth_m,
                                               options.max_depth_m);
  std::uniform_real_distribution<double> coordinate(
      -options.max_normalized_coordinate, options.max_normalized_coordinate);
  // Unit normal times sigma: std::normal_distribution requires sigma > 0.
  std::normal_distribution<double> unit(0.0, 1.0);
  const double sigma = options.pixel_sigma / options.focal_length_px;
  const Rigid3d cam_j_from_cam_i = Inverse(metric_motion);
  TwoViewOptions two_view;
  two_view.focal_length_px = options.focal_length_px;
  two_view.pixel_sigma = options.pixel_sigma;
  two_view.multi_start = options.two_view_multi_start;
  two_view.num_minimal_samples = options.two_view_minimal_samples;
  two_view.covariance_of_other_minima =
      options.two_view_covariance_of_other_minima;
  two_view.direction_scan_points = options.two_view_direction_scan_points;
  for (int attempt = 0; attempt < options.max_two_view_attempts; ++attempt) {
    std::vector<Eigen::Vector2d> observed_i, observed_j;
    for (int k = 0; k < options.num_landmarks; ++k) {
      for (int draw = 0; draw < kMaxLandmarkDraws; ++draw) {
        const double z = depth(*rng);
        const double x = coordinate(*rng);
        const double y = coordinate(*rng);
        const Eigen::Vector3d p_in_cam_i(x * z, y * z, z);
        const Eigen::Vector3d p_in_cam_j = cam_j_from_cam_i * p_in_cam_i;
        if (p_in_cam_j.z() < options.min_depth_m) continue;
        // Draws in statement order: argument evaluation order is unspecified.
        Eigen::Vector4d n;
        for (int c = 0; c < 4; ++c) n(c) = sigma * unit(*rng);
        observed_i.emplace_back(x + n(0), y + n(1));
        const Eigen::Vector2d u_j = p_in_cam_j.head<2>() / p_in_cam_j.z();
        observed_j.emplace_back(u_j.x() + n(2), u_j.y() + n(3));
        break;
      }
    }
    if (static_cast<int>(observed_i.size()) < options.num_landmarks) continue;
    const TwoViewEstimate estimate =
        EstimateTwoViewPose(observed_i, observed_j, two_view);
    if (!estimate.success) continue;
    *measured = Rigid3d(estimate.cam_i_from_cam_j.rotation,
                        length * estimate.cam_i_from_cam_j.translation);
    *covariance = estimate.covariance;
    covariance->bottomRows<3>() *= length;
    covariance->rightCols<3>() *= length;
    *core_covariance = estimate.core_covariance;
    core_covariance->bottomRows<3>() *= length;
    core_covariance->rightCols<3>() *= length;
    return true;
  }
  return false;
}

}  // namespace

std::string ToString(CameraNoiseMode mode) {
  return mode == CameraNoiseMode::kParametric ? "parametric" : "landmarks";
}

CameraNoiseMode CameraNoiseModeFromString(const std::string& name) {
  if (name == "parametric") return CameraNoiseMode::kParametric;
  if (name == "landmarks") return CameraNoiseMode::kLandmarks;
  throw std::invalid_argument("unknown camera noise mode '" + name +
                              "' (parametric, landmarks)");
}

void PaperSimulationOptions::Check() const {
  if (num_motions < 1) {
    throw std::invalid_argument("num_motions must be >= 1, got " +
                                std::to_string(num_motions));
  }
  if (num_segments < 1 || num_segments > num_motions) {
    throw std::invalid_argument(
        "num_segments must be in [1, num_motions], got " +
        std::to_string(num_segments));
  }
  CheckPositive(translation_sigma_m, "translation_sigma_m");
  CheckNonNegative(max_abs_yaw_rad, "max_abs_yaw_rad");
  CheckPositive(min_metric_scale, "min_metric_scale");
  CheckPositive(max_metric_scale, "max_metric_scale");
  if (max_metric_scale < min_metric_scale) {
    throw std::invalid_argument("max_metric_scale must be >= min_metric_scale");
  }
  CheckNonNegative(odom_yaw_sigma_rad, "odom_yaw_sigma_rad");
  CheckNonNegative(odom_translation_sigma_rel, "odom_translation_sigma_rel");
  CheckNonNegative(cam_rotation_sigma_rad, "cam_rotation_sigma_rad");
  CheckNonNegative(cam_direction_sigma_rad, "cam_direction_sigma_rad");
  if (num_landmarks < 8) {
    throw std::invalid_argument("num_landmarks must be >= 8, got " +
                                std::to_string(num_landmarks));
  }
  CheckPositive(focal_length_px, "focal_length_px");
  CheckNonNegative(pixel_sigma, "pixel_sigma");
  CheckPositive(min_depth_m, "min_depth_m");
  if (!(max_depth_m > min_depth_m) || !std::isfinite(max_depth_m)) {
    throw std::invalid_argument("max_depth_m must be > min_depth_m");
  }
  CheckPositive(max_normalized_coordinate, "max_normalized_coordinate");
  if (max_two_view_attempts < 1) {
    throw std::invalid_argument("max_two_view_attempts must be >= 1");
  }
  if (two_view_direction_scan_points < 0) {
    throw std::invalid_argument(
        "two_view_direction_scan_points must be >= 0, got " +
        std::to_string(two_view_direction_scan_points));
  }
  if (two_view_minimal_samples < 0) {
    throw std::invalid_argument("two_view_minimal_samples must be >= 0, got " +
                                std::to_string(two_view_minimal_samples));
  }
  if (!(outlier_fraction >= 0.0 && outlier_fraction <= 1.0)) {
    throw std::invalid_argument("outlier_fraction must be in [0, 1], got " +
                                std::to_string(outlier_fraction));
  }
}

PaperSimulation SimulatePaperMotions(const PaperSimulationOptions& options,
                                     const Rigid3d& odom_from_cam,
                                     const std::vector<double>& metric_scales,
                                     std::mt19937_64* rng) {
  options.Check();
  if (metric_scales.empty()) {
    throw std::invalid_argument("SimulatePaperMotions: no metric scales");
  }
  PaperSimulation result;
  result.odom_from_cam = odom_from_cam;
  result.metric_scales = metric_scales;
  const int num_segments = static_cast<int>(metric_scales.size());
  std::normal_distribution<double> step(0.0, options.translation_sigma_m);
  std::uniform_real_distribution<double> yaw(-options.max_abs_yaw_rad,
                                             options.max_abs_yaw_rad);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (int i = 0; i < options.num_motions; ++i) {
    MotionPair truth;
    truth.segment =
        std::min(num_segments - 1, i * num_segments / options.num_motions);
    truth.stamp_i_ns = static_cast<int64_t>(i) * 100000000;
    truth.stamp_j_ns = truth.stamp_i_ns + 100000000;
    const double phi = yaw(*rng);
    const double tx = step(*rng);
    const double ty = step(*rng);
    truth.odom_i_from_odom_j =
        Rigid3d(YawRotation(phi), Eigen::Vector3d(tx, ty, 0.0));
    const double scale = metric_scales[truth.segment];
    const Rigid3d metric_cam_motion = CameraMotionFromOdometryMotion(
        truth.odom_i_from_odom_j, odom_from_cam, 1.0);
    truth.cam_i_from_cam_j = CameraMotionFromOdometryMotion(
        truth.odom_i_from_odom_j, odom_from_cam, scale);

    MotionPair pair = truth;
    const double odom_length = truth.odom_i_from_odom_j.translation.norm();
    const double sigma_t = options.odom_translation_sigma_rel * odom_length;
    const double sigma_yaw = options.odom_yaw_sigma_rad;
    pair.odom_i_from_odom_j =
        PerturbMotion(truth.odom_i_from_odom_j,
                      Eigen::Vector3d(0.0, 0.0, sigma_yaw),
                      Eigen::Vector3d(sigma_t, sigma_t, 0.0),
                      rng);
    MotionCovariance odom_covariance = MotionCovariance::Zero();
    odom_covariance.diagonal() << 0.0, 0.0, sigma_yaw * sigma_yaw,
        sigma_t * sigma_t, sigma_t * sigma_t, 0.0;
    AddFloor(odom_length, &odom_covariance);
    pair.odom_covariance = odom_covariance;

    const double cam_length = truth.cam_i_from_cam_j.translation.norm();
    MotionCovariance cam_covariance;
    MotionCovariance cam_core_covariance;
    if (options.camera_noise == CameraNoiseMode::kParametric) {
      pair.cam_i_from_cam_j = ParametricCameraMeasurement(
          truth.cam_i_from_cam_j, options, rng, &cam_covariance);
      cam_core_covariance = cam_covariance;
    } else if (!LandmarkCameraMeasurement(metric_cam_motion,
                                          cam_length,
                                          options,
                                          rng,
                                          &pair.cam_i_from_cam_j,
                                          &cam_covariance,
                                          &cam_core_covariance)) {
      ++result.num_two_view_failures;
      continue;
    }
    AddFloor(cam_length, &cam_covariance);
    AddFloor(cam_length, &cam_core_covariance);
    pair.cam_covariance = cam_covariance;
    result.cam_core_covariances.push_back(cam_core_covariance);

    const bool outlier = uniform(*rng) < options.outlier_fraction;
    if (outlier) {
      Eigen::Vector3d axis, direction;
      for (int c = 0; c < 3; ++c) axis(c) = uniform(*rng) - 0.5;
      const double angle = (0.2 + 0.8 * uniform(*rng)) * kPi / 2.0;
      for (int c = 0; c < 3; ++c) direction(c) = uniform(*rng) - 0.5;
      axis.normalize();
      pair.cam_i_from_cam_j.rotation =
          Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis)) *
          pair.cam_i_from_cam_j.rotation;
      pair.cam_i_from_cam_j.translation = direction.normalized() * cam_length;
    }
    result.is_outlier.push_back(outlier ? 1 : 0);
    result.pairs.push_back(pair);
    result.true_pairs.push_back(truth);
  }
  return result;
}

PaperSimulation SimulatePaperMotions(const PaperSimulationOptions& options,
                                     std::mt19937_64* rng) {
  options.Check();
  const Rigid3d odom_from_cam = RandomOdomFromCam(rng);
  std::uniform_real_distribution<double> log_scale(
      std::log(options.min_metric_scale), std::log(options.max_metric_scale));
  std::vector<double> scales;
  scales.reserve(options.num_segments);
  for (int k = 0; k < options.num_segments; ++k) {
    scales.push_back(std::exp(log_scale(*rng)));
  }
  return SimulatePaperMotions(options, odom_from_cam, scales, rng);
}

}  // namespace odomcal
