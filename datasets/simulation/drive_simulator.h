// A simulated drive of a differential-drive robot with a rigidly mounted
// camera: timestamped wheel odometry (metres, odometry's origin frame) and a
// camera trajectory as an SfM system would report it (its own frame and
// scale), with a known extrinsic and metric scale.
//
// The path is a random sequence of manoeuvres at constant linear and angular
// velocity: straight runs, arcs of varying radius in both directions, turns
// in place and stops (DriveProfile::kManoeuvres); or, as real robots drive,
// smooth: speed and yaw rate sums of slow sinusoids (DriveProfile::kSmooth).
// Odometry integrates wheel speeds measured with per-wheel scale errors and a
// yaw-rate bias; camera poses receive small independent pose noise.
// Deterministic for a given seed.
//
// Tilted ground (ground_tilt_deg > 0): the robot drives over a rolling
// height field, so its true motion is 3-D (roll, pitch, height change) while
// the wheel odometry stays planar: it is the ground-plane projection of the
// true path (x, y, heading), blind to the tilt. The camera sees the 3-D
// motion. This is the modelling error the planarity check
// (solver/planarity_check.h) detects.
#pragma once

#include "odomcal/adapters/trajectory.h"
#include "odomcal/adapters/wheel_travel.h"
#include "odomcal/solver/rigid3.h"

#include <cstdint>

namespace odomcal {

// The nominal wheel track the simulated odometry assumes.
inline constexpr double kSimulatedWheelTrackM = 0.4;

enum class DriveProfile {
  // Manoeuvres at constant speed and yaw rate, switched abruptly.
  kManoeuvres,
  // Speed 0.5 max_speed_mps (1 + 0.5 sin + 0.3 sin) and yaw rate
  // max_yaw_rate_radps (0.6 sin + 0.4 sin) from sinusoids of periods 8-30 s
  // with random phases: no corners, turns both ways.
  kSmooth,
};

struct DriveSimulatorOptions {
  uint64_t seed = 0;
  double duration_s = 60.0;
  double odometry_rate_hz = 50.0;
  double camera_rate_hz = 10.0;                  // must divide odometry_rate_hz
  int64_t start_stamp_ns = 1700000000000000000;  // realistic epoch stamps

  // Default mount: camera looking forward (z_cam = x_odom, x_cam = -y_odom,
  // y_cam = -z_odom), 25 cm ahead, 5 cm left, 40 cm up.
  Rigid3d odom_from_cam = Rigid3d(Eigen::Quaterniond(0.5, -0.5, 0.5, -0.5),
                                  Eigen::Vector3d(0.25, 0.05, 0.40));
  double metric_scale = 0.37;  // metres per reconstruction unit

  // Manoeuvres.
  double max_speed_mps = 0.5;
  double max_yaw_rate_radps = 0.8;
  bool straight_only = false;  // no turns at all (an unobservable drive)
  DriveProfile profile = DriveProfile::kManoeuvres;

  // Tilted ground: height h(x, y) = a (sin(k u.p + phi_u) + sin(k v.p +
  // phi_v)) over two orthogonal random directions u, v, with a k =
  // tan(ground_tilt_deg) and k = 2 pi / ground_wavelength_m: the slope along
  // each of u and v varies smoothly within +-ground_tilt_deg along the drive.
  // 0: flat ground (the drive is then identical to one without this option).
  double ground_tilt_deg = 0.0;
  double ground_wavelength_m = 8.0;

  // Odometry errors: wheel radius errors (fraction), wheel base 0.4 m, and a
  // constant yaw-rate bias.
  double wheel_scale_error_left = 0.0;
  double wheel_scale_error_right = 0.0;
  double yaw_rate_bias_radps = 0.0;
  // Camera pose noise per pose: rotation (deg) and position (reconstruction
  // units).
  double camera_rotation_noise_deg = 0.0;
  double camera_position_noise = 0.0;

  // Visual-odometry-like camera: every relative motion between consecutive
  // camera poses gets noise, and the poses are composed from the noisy
  // motions (they drift, as VO does; the per-pose noise above is for
  // globally consistent poses, as from a COLMAP model): rotation noise per
  // axis in degrees, translation noise per axis as a fraction of the step's
  // length.
  double camera_step_rotation_noise_deg = 0.0;
  double camera_step_translation_noise_rel = 0.0;
  // SfM scale drift: the camera's positions are composed from its true steps
  // each scaled by (1 + e(t)), e a random walk in time from 0 at the start
  // with this standard deviation per square-root second (a COLMAP model
  // whose scale wanders along a forward drive). 0: none.
  double camera_scale_walk_per_sqrt_s = 0.0;
  // Random wheel odometry error: each wheel's travel per odometry period is
  // scaled by (1 + wheel_travel_noise_rel * N(0, 1)), so odometry errors
  // accumulate as a random walk with the distance driven.
  double wheel_travel_noise_rel = 0.0;
  // True wheel track over the nominal 0.4 m the odometry assumes, minus 1.
  double wheel_track_error = 0.0;
  // Clock offset: camera stamps are true time - this, so that
  // odometry_time = camera_time + camera_time_offset_s (odomcal's convention).
  double camera_time_offset_s = 0.0;
  // A knock of the camera mount: from mount_knock_time_s after the start on,
  // the camera is turned in place by mount_knock_deg about mount_knock_axis
  // (in the odometry frame; normalised): odom_from_cam's rotation becomes
  // Rot * rotation, its translation stays. 0: no knock.
  double mount_knock_deg = 0.0;
  double mount_knock_time_s = 0.0;
  Eigen::Vector3d mount_knock_axis = Eigen::Vector3d::UnitZ();
};

struct SimulatedDrive {
  Trajectory odometry;  // measured, planar, metres
  // The measured cumulative wheel travels at the odometry's stamps (wheel
  // scale errors and travel noise, not the yaw-rate bias): integrated with
  // the nominal 0.4 m track (adapters/wheel_travel.h) they give `odometry`
  // when yaw_rate_bias_radps is 0.
  WheelTravels wheel_travels;
  Trajectory true_odometry;  // exact, same stamps (3-D on tilted ground)
  Trajectory camera;         // world_from_cam in the SfM frame and units
  Rigid3d odom_from_cam;
  double metric_scale = 1.0;
  Rigid3d sfm_from_origin_rotation_translation;  // similarity part, see .cc
};

SimulatedDrive SimulateDrive(const DriveSimulatorOptions& options);

// A car's 90 s drive: smooth, up to 8 m/s with turns of 15-30 m radius both
// ways, camera poses with per-pose noise (0.02 deg, 0.002 units) and a
// reconstruction scale that wanders by `scale_walk_per_sqrt_s` (the case of
// scale_drift_covariance.h).
DriveSimulatorOptions CarDriveOptions(uint64_t seed,
                                      double scale_walk_per_sqrt_s);

}  // namespace odomcal
