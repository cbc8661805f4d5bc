#include "odomcal/datasets/simulation/wheel_odometry.h"

#include <cmath>
#include <random>
#include <stdexcept>

namespace odomcal {
namespace {

void CheckTimes(const std::vector<int64_t>& times) {
  if (times.empty() || times.front() < 0) {
    throw std::invalid_argument(
        "wheel odometry: sample times empty or negative");
  }
  for (size_t i = 1; i < times.size(); ++i) {
    if (times[i] <= times[i - 1]) {
      throw std::invalid_argument(
          "wheel odometry: sample times not increasing");
    }
  }
}

}  // namespace

void WheelOdometryNoise::Check() const {
  if (!(wheel_base_m > 0.0)) {
    throw std::invalid_argument("WheelOdometryNoise.wheel_base_m must be > 0");
  }
  if (!(std::abs(wheel_scale_error_left) < 0.5) ||
      !(std::abs(wheel_scale_error_right) < 0.5)) {
    throw std::invalid_argument(
        "WheelOdometryNoise.wheel_scale_error_*: must be in (-0.5, 0.5)");
  }
  if (!(wheel_slip_stddev >= 0.0) || !std::isfinite(yaw_rate_bias_radps)) {
    throw std::invalid_argument(
        "WheelOdometryNoise: wheel_slip_stddev must be >= 0, yaw bias finite");
  }
}

Trajectory SimulateWheelOdometryFromSteps(
    const std::vector<Eigen::Vector2d>& true_steps,
    const std::vector<int64_t>& sample_times_ns,
    int64_t stamp_offset_ns,
    const WheelOdometryNoise& noise) {
  CheckTimes(sample_times_ns);
  noise.Check();
  if (true_steps.size() + 1 != sample_times_ns.size()) {
    throw std::invalid_argument(
        "wheel odometry: need one step per sample period");
  }
  std::mt19937_64 rng(noise.seed);
  std::normal_distribution<double> slip(0.0, 1.0);
  Trajectory odometry;
  odometry.planar = true;
  odometry.source = "simulated wheel odometry";
  double x = 0.0, y = 0.0, yaw = 0.0;
  const double half_base = 0.5 * noise.wheel_base_m;
  for (size_t k = 0; k < sample_times_ns.size(); ++k) {
    if (k > 0) {
      const Eigen::Vector2d& true_step = true_steps[k - 1];
      const double left = (true_step[0] - half_base * true_step[1]) *
                          (1.0 + noise.wheel_scale_error_left) *
                          (1.0 + noise.wheel_slip_stddev * slip(rng));
      const double right = (true_step[0] + half_base * true_step[1]) *
                           (1.0 + noise.wheel_scale_error_right) *
                           (1.0 + noise.wheel_slip_stddev * slip(rng));
      const double dt = 1e-9 * (sample_times_ns[k] - sample_times_ns[k - 1]);
      const double distance = 0.5 * (left + right);
      const double dyaw =
          (right - left) / noise.wheel_base_m + noise.yaw_rate_bias_radps * dt;
      // Arc of constant curvature: chord of length distance * sinc(dyaw / 2)
      // along the mean heading.
      const double half = 0.5 * dyaw;
      const double chord =
          std::abs(half) < 1e-9 ? distance : distance * std::sin(half) / half;
      x += chord * std::cos(yaw + half);
      y += chord * std::sin(yaw + half);
      yaw += dyaw;
    }
    odometry.poses.push_back(
        {sample_times_ns[k] + stamp_offset_ns,
         Rigid3d(YawRotation(yaw), Eigen::Vector3d(x, y, 0.0))});
  }
  return odometry;
}

Trajectory SimulateWheelOdometry(const UnicyclePath& path,
                                 const std::vector<int64_t>& sample_times_ns,
                                 int64_t stamp_offset_ns,
                                 const WheelOdometryNoise& noise) {
  CheckTimes(sample_times_ns);
  std::vector<Eigen::Vector2d> steps;
  for (size_t k = 1; k < sample_times_ns.size(); ++k) {
    steps.push_back(
        path.DistanceAndYawBetween(sample_times_ns[k - 1], sample_times_ns[k]));
  }
  return SimulateWheelOdometryFromSteps(
      steps, sample_times_ns, stamp_offset_ns, noise);
}

Trajectory TrueWheelOdometry(const UnicyclePath& path,
                             const std::vector<int64_t>& sample_times_ns,
                             int64_t stamp_offset_ns) {
  CheckTimes(sample_times_ns);
  Trajectory odometry;
  odometry.planar = true;
  odometry.source = "true wheel odometry";
  const Rigid3d origin_from_room =
      Inverse(path.PoseAt(sample_times_ns.front()).ToRigid3d());
  for (const int64_t t : sample_times_ns) {
    odometry.poses.push_back(
        {t + stamp_offset_ns, origin_from_room * path.PoseAt(t).ToRigid3d()});
  }
  return odometry;
}

}  // namespace odomcal
