// The robot state is integrated exactly over each odometry period (constant
// twist: the SE(2) exponential). The SfM frame is a random similarity of the
// odometry origin: x_sfm = (R_g x_origin + t_g) / metric_scale, so camera
// translations come out in reconstruction units.

#include "odomcal/datasets/simulation/drive_simulator.h"

#include "odomcal/datasets/simulation/unicycle_path.h"
#include "odomcal/solver/angles.h"

#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

namespace odomcal {
namespace {

constexpr double kWheelBaseM = 0.4;

struct Manoeuvre {
  double speed_mps = 0.0;
  double yaw_rate_radps = 0.0;
  double duration_s = 0.0;
};

std::vector<Manoeuvre> PlanManoeuvres(const DriveSimulatorOptions& options,
                                      std::mt19937_64* rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Manoeuvre> plan;
  double total = 0.0;
  int turn_sign = 1;
  int kind = 0;
  while (total < options.duration_s) {
    Manoeuvre m;
    m.duration_s = 1.5 + 2.5 * unit(*rng);
    const double speed = options.max_speed_mps * (0.4 + 0.6 * unit(*rng));
    const double rate = options.max_yaw_rate_radps * (0.3 + 0.7 * unit(*rng));
    if (options.straight_only) {
      m.speed_mps = speed;
    } else {
      // Cycle through the kinds so every drive mixes them; alternate the
      // turn direction so both signs of yaw are excited.
      switch (kind++ % 5) {
        case 0:
          m.speed_mps = speed;
          break;
        case 1:
        case 3:
          m.speed_mps = speed;
          m.yaw_rate_radps = turn_sign * rate;
          turn_sign = -turn_sign;
          break;
        case 2:
          m.yaw_rate_radps = turn_sign * rate;
          turn_sign = -turn_sign;
          break;
        case 4:
          m.duration_s = 0.5 + unit(*rng);  // stop
          break;
      }
    }
    total += m.duration_s;
    plan.push_back(m);
  }
  return plan;
}

}  // namespace

SimulatedDrive SimulateDrive(const DriveSimulatorOptions& options) {
  if (!(options.duration_s > 0.0) || !(options.odometry_rate_hz > 0.0) ||
      !(options.camera_rate_hz > 0.0) || !(options.metric_scale > 0.0)) {
    throw std::invalid_argument(
        "SimulateDrive: duration, rates and metric_scale must be > 0");
  }
  const double ratio = options.odometry_rate_hz / options.camera_rate_hz;
  const int odometry_per_camera = static_cast<int>(std::lround(ratio));
  if (odometry_per_camera < 1 || std::abs(ratio - odometry_per_camera) > 1e-9) {
    throw std::invalid_argument(
        "SimulateDrive: camera_rate_hz must divide odometry_rate_hz");
  }
  std::mt19937_64 rng(options.seed);
  const std::vector<Manoeuvre> plan = PlanManoeuvres(options, &rng);

  SimulatedDrive drive;
  drive.odom_from_cam = options.odom_from_cam;
  drive.metric_scale = options.metric_scale;
  drive.odometry.planar = true;
  drive.odometry.source = "simulated odometry";
  drive.true_odometry.planar = true;
  drive.true_odometry.source = "simulated true odometry";
  drive.camera.source = "simulated camera";

  // Random similarity from the odometry origin into the SfM frame.
  std::normal_distribution<double> gauss(0.0, 1.0);
  const Eigen::Quaterniond sfm_rotation =
      Eigen::Quaterniond(gauss(rng), gauss(rng), gauss(rng), gauss(rng))
          .normalized();
  const Eigen::Vector3d sfm_translation(gauss(rng), gauss(rng), gauss(rng));
  drive.sfm_from_origin_rotation_translation =
      Rigid3d(sfm_rotation, sfm_translation);

  const int64_t period_ns =
      static_cast<int64_t>(std::llround(1e9 / options.odometry_rate_hz));
  const double dt = 1e-9 * static_cast<double>(period_ns);
  PlanarPose truth, measured;
  size_t manoeuvre = 0;
  double time_in_manoeuvre = 0.0;
  const int64_t num_steps =
      static_cast<int64_t>(std::floor(options.duration_s / dt));
  const double deg = kPi / 180.0;
  for (int64_t k = 0; k <= num_steps; ++k) {
    const int64_t stamp_ns = options.start_stamp_ns + k * period_ns;
    drive.true_odometry.poses.push_back({stamp_ns, truth.ToRigid3d()});
    drive.odometry.poses.push_back({stamp_ns, measured.ToRigid3d()});
    if (k % odometry_per_camera == 0) {
      const Rigid3d origin_from_cam = truth.ToRigid3d() * options.odom_from_cam;
      Rigid3d world_from_cam(
          sfm_rotation * origin_from_cam.rotation,
          (sfm_rotation * origin_from_cam.translation + sfm_translation) /
              options.metric_scale);
      const Eigen::Vector3d rotation_noise(gauss(rng), gauss(rng), gauss(rng));
      const Eigen::Vector3d position_noise(gauss(rng), gauss(rng), gauss(rng));
      world_from_cam.rotation =
          (ExpRotation(rotation_noise * options.camera_rotation_noise_deg *
                       deg) *
           world_from_cam.rotation)
              .normalized();
      world_from_cam.translation +=
          position_noise * options.camera_position_noise;
      drive.camera.poses.push_back({stamp_ns, world_from_cam});
    }
    // Advance both the truth and the wheel-odometry estimate by one period.
    while (manoeuvre + 1 < plan.size() &&
           time_in_manoeuvre >= plan[manoeuvre].duration_s) {
      time_in_manoeuvre -= plan[manoeuvre].duration_s;
      ++manoeuvre;
    }
    const Manoeuvre& m = plan[manoeuvre];
    truth = UnicycleStep(truth, m.speed_mps, m.yaw_rate_radps, dt);
    const double left = (m.speed_mps - 0.5 * kWheelBaseM * m.yaw_rate_radps) *
                        (1.0 + options.wheel_scale_error_left);
    const double right = (m.speed_mps + 0.5 * kWheelBaseM * m.yaw_rate_radps) *
                         (1.0 + options.wheel_scale_error_right);
    measured =
        UnicycleStep(measured,
                     0.5 * (left + right),
                     (right - left) / kWheelBaseM + options.yaw_rate_bias_radps,
                     dt);
    time_in_manoeuvre += dt;
  }
  return drive;
}

}  // namespace odomcal
