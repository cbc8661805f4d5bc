// The robot state is integrated exactly over each odometry period (constant
// twist: the SE(2) exponential). The SfM frame is a random similarity of the
// odometry origin: x_sfm = (R_g x_origin + t_g) / metric_scale, so camera
// translations come out in reconstruction units.

#include "odomcal/datasets/simulation/drive_simulator.h"

#include "odomcal/datasets/simulation/unicycle_path.h"
#include "odomcal/solver/angles.h"

#include <array>
#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

namespace odomcal {
namespace {

constexpr double kWheelBaseM = kSimulatedWheelTrackM;

struct Manoeuvre {
  double speed_mps = 0.0;
  double yaw_rate_radps = 0.0;
  double duration_s = 0.0;
};

// The rolling ground of DriveSimulatorOptions::ground_tilt_deg.
struct Ground {
  double amplitude_m = 0.0;  // a
  double wavenumber = 0.0;   // k, radians per metre
  Eigen::Vector2d u, v;      // orthogonal unit directions
  double phase_u = 0.0, phase_v = 0.0;

  double Height(const Eigen::Vector2d& p) const {
    return amplitude_m * (std::sin(wavenumber * u.dot(p) + phase_u) +
                          std::sin(wavenumber * v.dot(p) + phase_v));
  }
  Eigen::Vector2d Gradient(const Eigen::Vector2d& p) const {
    const double ak = amplitude_m * wavenumber;
    return ak * std::cos(wavenumber * u.dot(p) + phase_u) * u +
           ak * std::cos(wavenumber * v.dot(p) + phase_v) * v;
  }

  // The body standing on the ground at the planar pose: z along the ground
  // normal, x the heading lifted onto the ground (its ground-plane projection
  // keeps the heading `yaw`).
  Rigid3d BodyPose(const PlanarPose& pose) const {
    const Eigen::Vector2d p(pose.x, pose.y);
    const Eigen::Vector2d g = Gradient(p);
    const Eigen::Vector2d heading(std::cos(pose.yaw_rad),
                                  std::sin(pose.yaw_rad));
    const Eigen::Vector3d x =
        Eigen::Vector3d(heading.x(), heading.y(), g.dot(heading)).normalized();
    const Eigen::Vector3d z = Eigen::Vector3d(-g.x(), -g.y(), 1.0).normalized();
    Eigen::Matrix3d rotation;
    rotation << x, z.cross(x), z;
    return Rigid3d(Eigen::Quaterniond(rotation).normalized(),
                   Eigen::Vector3d(pose.x, pose.y, Height(p)));
  }
};

// Drawn from a generator of its own so that a flat drive (tilt 0) is
// bit-identical to one simulated before the option existed.
Ground MakeGround(const DriveSimulatorOptions& options) {
  Ground ground;
  ground.wavenumber = 2.0 * kPi / options.ground_wavelength_m;
  ground.amplitude_m =
      std::tan(options.ground_tilt_deg * kDegToRad) / ground.wavenumber;
  std::mt19937_64 rng(options.seed ^ 0x9e3779b97f4a7c15ULL);
  std::uniform_real_distribution<double> angle(0.0, 2.0 * kPi);
  const double direction = angle(rng);
  ground.u = Eigen::Vector2d(std::cos(direction), std::sin(direction));
  ground.v = Eigen::Vector2d(-ground.u.y(), ground.u.x());
  ground.phase_u = angle(rng);
  ground.phase_v = angle(rng);
  return ground;
}

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

// DriveProfile::kSmooth: slow sinusoids with periods and phases drawn from
// a generator of their own (manoeuvre drives stay as they were).
struct SmoothProfile {
  std::array<double, 4> period_s{};
  std::array<double, 4> phase{};

  explicit SmoothProfile(const DriveSimulatorOptions& options) {
    std::mt19937_64 rng(options.seed ^ 0x51700751700751ULL);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (int k = 0; k < 4; ++k) {
      period_s[k] = 8.0 + 22.0 * unit(rng);
      phase[k] = 2.0 * kPi * unit(rng);
    }
  }
  double Wave(int k, double t) const {
    return std::sin(2.0 * kPi * t / period_s[k] + phase[k]);
  }
  Manoeuvre At(const DriveSimulatorOptions& options, double t) const {
    Manoeuvre m;
    m.speed_mps = 0.5 * options.max_speed_mps *
                  (1.0 + 0.5 * Wave(0, t) + 0.3 * Wave(1, t));
    m.yaw_rate_radps = options.straight_only
                           ? 0.0
                           : options.max_yaw_rate_radps *
                                 (0.6 * Wave(2, t) + 0.4 * Wave(3, t));
    return m;
  }
};

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
  if (!(options.ground_tilt_deg >= 0.0 && options.ground_tilt_deg < 45.0) ||
      !(options.ground_wavelength_m > 0.0)) {
    throw std::invalid_argument(
        "SimulateDrive: ground_tilt_deg must be in [0, 45) and "
        "ground_wavelength_m > 0");
  }
  const bool tilted = options.ground_tilt_deg > 0.0;
  const Ground ground = MakeGround(options);
  auto true_pose = [&](const PlanarPose& pose) {
    return tilted ? ground.BodyPose(pose) : pose.ToRigid3d();
  };
  std::mt19937_64 rng(options.seed);
  const std::vector<Manoeuvre> plan = PlanManoeuvres(options, &rng);
  const SmoothProfile smooth(options);

  SimulatedDrive drive;
  drive.odom_from_cam = options.odom_from_cam;
  drive.metric_scale = options.metric_scale;
  drive.odometry.planar = true;
  drive.odometry.source = "simulated odometry";
  drive.true_odometry.planar = !tilted;
  drive.true_odometry.source = "simulated true odometry";
  drive.camera.source = "simulated camera";
  drive.wheel_travels.source = "simulated wheel travels";

  // Random similarity from the odometry origin into the SfM frame.
  std::normal_distribution<double> gauss(0.0, 1.0);
  const Eigen::Quaterniond sfm_rotation =
      Eigen::Quaterniond(gauss(rng), gauss(rng), gauss(rng), gauss(rng))
          .normalized();
  const Eigen::Vector3d sfm_translation(gauss(rng), gauss(rng), gauss(rng));
  drive.sfm_from_origin_rotation_translation =
      Rigid3d(sfm_rotation, sfm_translation);

  // Its own generator, so that drives without this noise stay as they were.
  std::mt19937_64 step_rng(options.seed ^ 0x5eed5eed5eed5eedULL);
  bool have_previous_camera = false;
  Rigid3d previous_true_world_from_cam, previous_vo_world_from_cam;
  std::mt19937_64 walk_rng(options.seed ^ 0x5ca1e5ca1e5ca1e5ULL);
  double scale_walk = 0.0;  // e(t) of camera_scale_walk_per_sqrt_s
  bool have_previous_position = false;
  Eigen::Vector3d previous_true_position = Eigen::Vector3d::Zero();
  Eigen::Vector3d previous_walked_position = Eigen::Vector3d::Zero();

  const int64_t period_ns =
      static_cast<int64_t>(std::llround(1e9 / options.odometry_rate_hz));
  const double dt = 1e-9 * static_cast<double>(period_ns);
  const double true_track_m = kWheelBaseM * (1.0 + options.wheel_track_error);
  const int64_t camera_offset_ns =
      static_cast<int64_t>(std::llround(1e9 * options.camera_time_offset_s));
  PlanarPose truth, measured;
  double left_m = 0.0, right_m = 0.0;  // cumulative measured wheel travels
  size_t manoeuvre = 0;
  double time_in_manoeuvre = 0.0;
  const int64_t num_steps =
      static_cast<int64_t>(std::floor(options.duration_s / dt));
  const double deg = kPi / 180.0;
  for (int64_t k = 0; k <= num_steps; ++k) {
    const int64_t stamp_ns = options.start_stamp_ns + k * period_ns;
    drive.true_odometry.poses.push_back({stamp_ns, true_pose(truth)});
    drive.odometry.poses.push_back({stamp_ns, measured.ToRigid3d()});
    drive.wheel_travels.samples.push_back({stamp_ns, left_m, right_m});
    if (k % odometry_per_camera == 0) {
      const bool knocked =
          options.mount_knock_deg != 0.0 &&
          static_cast<double>(k) * dt >= options.mount_knock_time_s;
      const Rigid3d odom_from_cam =
          knocked ? Rigid3d(ExpRotation(options.mount_knock_axis.normalized() *
                                        options.mount_knock_deg * deg) *
                                options.odom_from_cam.rotation,
                            options.odom_from_cam.translation)
                  : options.odom_from_cam;
      const Rigid3d origin_from_cam = true_pose(truth) * odom_from_cam;
      Rigid3d world_from_cam(
          sfm_rotation * origin_from_cam.rotation,
          (sfm_rotation * origin_from_cam.translation + sfm_translation) /
              options.metric_scale);
      if (options.camera_scale_walk_per_sqrt_s > 0.0) {
        const Eigen::Vector3d true_position = world_from_cam.translation;
        if (have_previous_position) {
          scale_walk += options.camera_scale_walk_per_sqrt_s *
                        std::sqrt(dt * odometry_per_camera) * gauss(walk_rng);
          world_from_cam.translation =
              previous_walked_position +
              (1.0 + scale_walk) * (true_position - previous_true_position);
        }
        have_previous_position = true;
        previous_true_position = true_position;
        previous_walked_position = world_from_cam.translation;
      }
      if (options.camera_step_rotation_noise_deg > 0.0 ||
          options.camera_step_translation_noise_rel > 0.0) {
        const Rigid3d true_world_from_cam = world_from_cam;
        if (have_previous_camera) {
          Rigid3d step =
              Inverse(previous_true_world_from_cam) * true_world_from_cam;
          const Eigen::Vector3d rotation_noise(
              gauss(step_rng), gauss(step_rng), gauss(step_rng));
          const Eigen::Vector3d translation_noise(
              gauss(step_rng), gauss(step_rng), gauss(step_rng));
          step.rotation =
              (ExpRotation(rotation_noise *
                           options.camera_step_rotation_noise_deg * deg) *
               step.rotation)
                  .normalized();
          step.translation += translation_noise *
                              options.camera_step_translation_noise_rel *
                              step.translation.norm();
          world_from_cam = previous_vo_world_from_cam * step;
        }
        have_previous_camera = true;
        previous_true_world_from_cam = true_world_from_cam;
        previous_vo_world_from_cam = world_from_cam;
      }
      const Eigen::Vector3d rotation_noise(gauss(rng), gauss(rng), gauss(rng));
      const Eigen::Vector3d position_noise(gauss(rng), gauss(rng), gauss(rng));
      world_from_cam.rotation =
          (ExpRotation(rotation_noise * options.camera_rotation_noise_deg *
                       deg) *
           world_from_cam.rotation)
              .normalized();
      world_from_cam.translation +=
          position_noise * options.camera_position_noise;
      drive.camera.poses.push_back(
          {stamp_ns - camera_offset_ns, world_from_cam});
    }
    // Advance both the truth and the wheel-odometry estimate by one period.
    while (manoeuvre + 1 < plan.size() &&
           time_in_manoeuvre >= plan[manoeuvre].duration_s) {
      time_in_manoeuvre -= plan[manoeuvre].duration_s;
      ++manoeuvre;
    }
    const Manoeuvre m = options.profile == DriveProfile::kSmooth
                            ? smooth.At(options, static_cast<double>(k) * dt)
                            : plan[manoeuvre];
    truth = UnicycleStep(truth, m.speed_mps, m.yaw_rate_radps, dt);
    double left = (m.speed_mps - 0.5 * true_track_m * m.yaw_rate_radps) *
                  (1.0 + options.wheel_scale_error_left);
    double right = (m.speed_mps + 0.5 * true_track_m * m.yaw_rate_radps) *
                   (1.0 + options.wheel_scale_error_right);
    if (options.wheel_travel_noise_rel > 0.0) {
      left *= 1.0 + options.wheel_travel_noise_rel * gauss(step_rng);
      right *= 1.0 + options.wheel_travel_noise_rel * gauss(step_rng);
    }
    left_m += left * dt;
    right_m += right * dt;
    measured =
        UnicycleStep(measured,
                     0.5 * (left + right),
                     (right - left) / kWheelBaseM + options.yaw_rate_bias_radps,
                     dt);
    time_in_manoeuvre += dt;
  }
  return drive;
}

DriveSimulatorOptions CarDriveOptions(uint64_t seed,
                                      double scale_walk_per_sqrt_s) {
  DriveSimulatorOptions options;
  options.seed = seed;
  options.duration_s = 90.0;
  options.profile = DriveProfile::kSmooth;
  options.max_speed_mps = 8.0;
  options.max_yaw_rate_radps = 0.3;
  options.camera_rotation_noise_deg = 0.02;
  options.camera_position_noise = 0.002;
  options.camera_scale_walk_per_sqrt_s = scale_walk_per_sqrt_s;
  return options;
}

}  // namespace odomcal
