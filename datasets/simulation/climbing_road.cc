#include "odomcal/datasets/simulation/climbing_road.h"

#include "odomcal/datasets/simulation/motion_simulator.h"
#include "odomcal/datasets/simulation/seed.h"
#include "odomcal/solver/angles.h"
#include "odomcal/solver/hand_eye_residual.h"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include <cmath>
#include <random>
#include <vector>

namespace odomcal {
namespace {

Eigen::Quaterniond FromRollPitchYaw(double roll, double pitch, double yaw) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                            Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                            Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()));
}

// A measurement drawn from `covariance` (order [rotation, translation]):
// rotation Exp(n) * R, translation t + n_t, as the solver models it.
Rigid3d Measure(const Rigid3d& motion,
                const MotionCovariance& covariance,
                std::mt19937_64* rng) {
  std::normal_distribution<double> unit(0.0, 1.0);
  Eigen::Matrix<double, 6, 1> draw;
  for (int k = 0; k < 6; ++k) draw(k) = unit(*rng);
  const Eigen::Matrix<double, 6, 1> n = covariance.llt().matrixL() * draw;
  return Rigid3d((ExpRotation(n.head<3>()) * motion.rotation).normalized(),
                 motion.translation + n.tail<3>());
}

// The pose seen by planar odometry: x, y and the heading (yaw of the body x
// axis); roll, pitch and z dropped.
Rigid3d FlattenedPose(const Rigid3d& origin_from_odom) {
  const Eigen::Vector3d forward =
      origin_from_odom.rotation * Eigen::Vector3d::UnitX();
  const double heading = std::atan2(forward.y(), forward.x());
  return Rigid3d(
      Eigen::Quaterniond(Eigen::AngleAxisd(heading, Eigen::Vector3d::UnitZ())),
      Eigen::Vector3d(origin_from_odom.translation.x(),
                      origin_from_odom.translation.y(),
                      0.0));
}

// A planar measurement: yaw, x and y drawn from `covariance`, no tilt or
// height.
Rigid3d MeasurePlanar(const Rigid3d& motion,
                      const MotionCovariance& covariance,
                      std::mt19937_64* rng) {
  std::normal_distribution<double> unit(0.0, 1.0);
  const double yaw = std::sqrt(covariance(2, 2)) * unit(*rng);
  const double x = std::sqrt(covariance(3, 3)) * unit(*rng);
  const double y = std::sqrt(covariance(4, 4)) * unit(*rng);
  return Rigid3d(
      (Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ())) *
       motion.rotation)
          .normalized(),
      motion.translation + Eigen::Vector3d(x, y, 0.0));
}

}  // namespace

ClimbingRoadOptions::ClimbingRoadOptions()
    : odom_from_cam(FromRollPitchYaw(
                        -91.0 * kDegToRad, 1.0 * kDegToRad, -88.0 * kDegToRad),
                    Eigen::Vector3d(1.20, 0.05, 1.65)) {}

MotionPairs ClimbingRoadPairs(const ClimbingRoadOptions& options,
                              const NoiseModel* noise,
                              uint64_t seed) {
  std::mt19937_64 path_rng(DeriveSeed(seed, 0));
  std::mt19937_64 noise_rng(DeriveSeed(seed, 1));
  std::uniform_real_distribution<double> turn(-options.max_turn_deg,
                                              options.max_turn_deg);
  std::uniform_real_distribution<double> phase(0.0, 2.0 * kPi);
  std::normal_distribution<double> roll(0.0, options.roll_sigma_deg);
  const double start_phase = phase(path_rng);
  // Its own stream: the paths without banking stay as they are.
  std::mt19937_64 bank_rng(DeriveSeed(seed, 2));
  const double bank_phase = phase(bank_rng);
  std::vector<Rigid3d> origin_from_odom;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  double yaw = 0.0;
  for (int k = 0; k < options.num_keyframes; ++k) {
    const double distance = k * options.step_m;
    // Pitch about the car's y axis: negative is nose up.
    const double grade_deg =
        0.5 * options.max_grade_deg *
        (1.0 +
         std::sin(start_phase + 2.0 * kPi * distance / options.grade_period_m));
    const double bank_deg =
        0.5 * options.max_bank_deg *
        (1.0 +
         std::sin(bank_phase + 2.0 * kPi * distance / options.bank_period_m));
    const Eigen::Quaterniond rotation = FromRollPitchYaw(
        (roll(path_rng) + bank_deg) * kDegToRad, -grade_deg * kDegToRad, yaw);
    origin_from_odom.emplace_back(rotation, position);
    position += rotation * Eigen::Vector3d(options.step_m, 0.0, 0.0);
    yaw += turn(path_rng) * kDegToRad;
  }
  MotionPairs pairs;
  for (size_t k = 0; k + 1 < origin_from_odom.size(); ++k) {
    MotionPair pair;
    pair.odom_i_from_odom_j =
        Inverse(origin_from_odom[k]) * origin_from_odom[k + 1];
    pair.cam_i_from_cam_j = CameraMotionFromOdometryMotion(
        pair.odom_i_from_odom_j, options.odom_from_cam, options.metric_scale);
    if (options.planar_odometry) {
      pair.odom_i_from_odom_j = Inverse(FlattenedPose(origin_from_odom[k])) *
                                FlattenedPose(origin_from_odom[k + 1]);
    }
    if (noise) {
      const StepSize step = MeasuredStep(pair);  // the true steps
      const MotionCovariance odom = OdometryCovariance(pair, *noise, step);
      const MotionCovariance cam = CameraCovariance(pair, *noise, step);
      pair.odom_i_from_odom_j =
          options.planar_odometry
              ? MeasurePlanar(pair.odom_i_from_odom_j, odom, &noise_rng)
              : Measure(pair.odom_i_from_odom_j, odom, &noise_rng);
      pair.cam_i_from_cam_j = Measure(pair.cam_i_from_cam_j, cam, &noise_rng);
    }
    pair.stamp_i_ns = static_cast<int64_t>(k) * 500000000;
    pair.stamp_j_ns = pair.stamp_i_ns + 500000000;
    pairs.push_back(pair);
  }
  return pairs;
}

}  // namespace odomcal
