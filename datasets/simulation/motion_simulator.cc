// Odometry motions are drawn first, camera motions follow from the hand-eye
// equation, then each side receives the noise the solver's NoiseModel
// describes (see NoiseModel and ResidualCovariance in the solver), so that
// consistency tests (NEES) compare like with like.

#include "odomcal/datasets/simulation/motion_simulator.h"

#include "odomcal/solver/angles.h"

#include <algorithm>
#include <cmath>

namespace odomcal {

Rigid3d RandomOdomFromCam(std::mt19937_64* rng) {
  std::uniform_real_distribution<double> translation(-0.1, 0.1);
  std::uniform_real_distribution<double> angle(-kPi, kPi);
  std::normal_distribution<double> axis(0.0, 0.1);
  Eigen::Vector3d direction(axis(*rng), axis(*rng), axis(*rng));
  direction.normalize();
  return Rigid3d(
      Eigen::Quaterniond(Eigen::AngleAxisd(angle(*rng), direction)),
      Eigen::Vector3d(translation(*rng), translation(*rng), translation(*rng)));
}

Rigid3d CameraMotionFromOdometryMotion(const Rigid3d& odom_i_from_odom_j,
                                       const Rigid3d& odom_from_cam,
                                       double metric_scale) {
  Rigid3d cam_i_from_cam_j =
      Inverse(odom_from_cam) * odom_i_from_odom_j * odom_from_cam;
  cam_i_from_cam_j.translation /= metric_scale;
  return cam_i_from_cam_j;
}

Rigid3d PerturbMotion(const Rigid3d& motion,
                      const Eigen::Vector3d& rotation_sigma_rad,
                      const Eigen::Vector3d& translation_sigma,
                      std::mt19937_64* rng) {
  std::normal_distribution<double> unit(0.0, 1.0);
  Eigen::Vector3d phi, dt;
  for (int k = 0; k < 3; ++k) {
    phi(k) = rotation_sigma_rad(k) * unit(*rng);
  }
  for (int k = 0; k < 3; ++k) {
    dt(k) = translation_sigma(k) * unit(*rng);
  }
  return Rigid3d((ExpRotation(phi) * motion.rotation).normalized(),
                 motion.translation + dt);
}

SimulatedMotions SimulateMotions(const MotionSimulatorOptions& options,
                                 const Rigid3d& odom_from_cam,
                                 const std::vector<double>& metric_scales,
                                 std::mt19937_64* rng) {
  SimulatedMotions result;
  result.odom_from_cam = odom_from_cam;
  result.metric_scales = metric_scales;
  const int num_segments = static_cast<int>(metric_scales.size());
  std::normal_distribution<double> step(0.0, options.translation_sigma_m);
  std::uniform_real_distribution<double> yaw(options.min_yaw_rad,
                                             options.max_yaw_rad);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const NoiseModel& noise = options.noise;
  for (int i = 0; i < options.num_pairs; ++i) {
    MotionPair pair;
    pair.segment = std::min(num_segments - 1,
                            i * num_segments / std::max(1, options.num_pairs));
    const double phi = yaw(*rng);
    const Rigid3d odom_motion(YawRotation(phi),
                              Eigen::Vector3d(step(*rng), step(*rng), 0.0));
    const double scale = metric_scales[pair.segment];
    Rigid3d cam_motion =
        CameraMotionFromOdometryMotion(odom_motion, odom_from_cam, scale);
    pair.odom_i_from_odom_j = odom_motion;
    pair.cam_i_from_cam_j = cam_motion;
    if (options.add_noise) {
      const double tilt = noise.odom_tilt_sigma_deg * kDegToRad;
      const double yaw_sigma = noise.odom_yaw_sigma_deg * kDegToRad +
                               noise.odom_yaw_sigma_rel * std::abs(phi);
      const double odom_t_sigma =
          noise.odom_translation_sigma_m +
          noise.odom_translation_sigma_rel * odom_motion.translation.norm();
      pair.odom_i_from_odom_j =
          PerturbMotion(odom_motion,
                        Eigen::Vector3d(tilt, tilt, yaw_sigma),
                        Eigen::Vector3d::Constant(odom_t_sigma),
                        rng);
      const double cam_r_sigma = noise.cam_rotation_sigma_deg * kDegToRad;
      const double cam_t_sigma =
          noise.cam_translation_sigma_rel * cam_motion.translation.norm();
      pair.cam_i_from_cam_j =
          PerturbMotion(cam_motion,
                        Eigen::Vector3d::Constant(cam_r_sigma),
                        Eigen::Vector3d::Constant(cam_t_sigma),
                        rng);
    }
    const bool outlier = uniform(*rng) < options.outlier_fraction;
    if (outlier) {
      // A plausible-looking but wrong camera motion: random rotation of up to
      // 90 degrees and a random direction of the same length.
      const Eigen::Vector3d axis =
          Eigen::Vector3d(
              uniform(*rng) - 0.5, uniform(*rng) - 0.5, uniform(*rng) - 0.5)
              .normalized();
      const double angle = (0.2 + 0.8 * uniform(*rng)) * kPi / 2.0;
      Eigen::Vector3d direction(
          uniform(*rng) - 0.5, uniform(*rng) - 0.5, uniform(*rng) - 0.5);
      pair.cam_i_from_cam_j.rotation =
          Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis)) *
          pair.cam_i_from_cam_j.rotation;
      pair.cam_i_from_cam_j.translation =
          direction.normalized() * cam_motion.translation.norm();
    }
    result.is_outlier.push_back(outlier ? 1 : 0);
    pair.stamp_i_ns = static_cast<int64_t>(i) * 100000000;
    pair.stamp_j_ns = pair.stamp_i_ns + 100000000;
    result.pairs.push_back(pair);
  }
  return result;
}

SimulatedMotions SimulateMotions(const MotionSimulatorOptions& options,
                                 std::mt19937_64* rng) {
  const Rigid3d odom_from_cam = RandomOdomFromCam(rng);
  std::uniform_real_distribution<double> log_scale(
      std::log(options.min_metric_scale), std::log(options.max_metric_scale));
  std::vector<double> scales;
  scales.reserve(std::max(options.num_segments, 0));
  for (int k = 0; k < options.num_segments; ++k) {
    scales.push_back(std::exp(log_scale(*rng)));
  }
  return SimulateMotions(options, odom_from_cam, scales, rng);
}

}  // namespace odomcal
