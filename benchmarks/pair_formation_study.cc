// Which camera frames make the motion pairs: RMSE over simulated continuous
// drives (datasets/simulation/drive_simulator.h: differential drive, both turn
// directions, 50 Hz wheel odometry with random wheel-travel noise, 5 Hz
// camera) of the default calibration for several keyframe thresholds, for
// camera poses composed from noisy relative motions (VO-like, they drift) and
// for globally consistent poses with independent per-pose noise (COLMAP-
// like). The reference is a plain batch over all consecutive frames (no
// keyframe selection, no RANSAC). Numbers in docs/benchmarks.md.
//
//   pair_formation_study [num_seeds=30] [duration_s=120] [odometry_hz=50]
//                        [camera_hz=5] [odometry_keep_every=1]
// odometry_keep_every = k keeps every k-th odometry sample after simulating
// (the simulator's camera rate must divide its odometry rate: 28 Hz / 7 Hz
// with k = 7 gives 4 Hz odometry and a 7 Hz camera). The last row then
// repeats the second without the interpolation covariance.
#include "odomcal/adapters/association.h"
#include "odomcal/datasets/simulation/drive_simulator.h"
#include "odomcal/solver/angles.h"
#include "odomcal/solver/calibrate.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace odomcal {
namespace {

struct PairRule {
  const char* name;
  double min_rotation_deg;
  double min_translation_m;
  bool ransac;
};

struct Errors {
  double rotation_sq_deg2 = 0.0, xy_sq_mm2 = 0.0, scale_sq_pct2 = 0.0;
  double pairs = 0.0;
  int runs = 0, failures = 0;
  int rotation_within_3_sigma = 0, scale_within_3_sigma = 0;
};

int Main(int argc, char** argv) {
  const int num_seeds = argc > 1 ? std::atoi(argv[1]) : 30;
  const double duration_s = argc > 2 ? std::atof(argv[2]) : 120.0;
  const double odometry_hz = argc > 3 ? std::atof(argv[3]) : 50.0;
  const double camera_hz = argc > 4 ? std::atof(argv[4]) : 5.0;
  const int keep_every = argc > 5 ? std::atoi(argv[5]) : 1;
  const std::vector<PairRule> rules = {
      {"keyframes 5 deg / 0.10 m (old default)", 5.0, 0.10, true},
      {"keyframes 1 deg / 0.02 m", 1.0, 0.02, true},
      {"all consecutive frames", 0.0, 0.0, true},
      {"keyframes 15 deg / 0.30 m", 15.0, 0.30, true},
      {"keyframes 1 deg / 0.10 m", 1.0, 0.10, true},
      {"plain batch, all consecutive (reference)", 0.0, 0.0, false},
      {"keyframes 1 deg / 0.02 m, no interpolation covariance",
       1.0,
       0.02,
       true},
      {"keyframes 1 deg / 0.02 m, camera noise per pose known",
       1.0,
       0.02,
       true},
  };
  const size_t per_pose_noise_rule = 7;
  const size_t reference_rule = 5, no_interpolation_rule = 6;
  for (const bool vo : {true, false}) {
    std::vector<Errors> errors(rules.size());
    for (int seed = 0; seed < num_seeds; ++seed) {
      DriveSimulatorOptions drive_options;
      drive_options.seed = static_cast<uint64_t>(seed);
      drive_options.duration_s = duration_s;
      drive_options.odometry_rate_hz = odometry_hz;
      drive_options.camera_rate_hz = camera_hz;
      drive_options.wheel_scale_error_left = 0.003;
      drive_options.wheel_scale_error_right = -0.002;
      drive_options.wheel_travel_noise_rel = 0.02;
      if (vo) {
        drive_options.camera_step_rotation_noise_deg = 0.05;
        drive_options.camera_step_translation_noise_rel = 0.01;
      } else {
        drive_options.camera_rotation_noise_deg = 0.05;
        drive_options.camera_position_noise = 0.005;
      }
      SimulatedDrive drive = SimulateDrive(drive_options);
      std::vector<StampedPose> kept;
      for (size_t i = 0; i < drive.odometry.poses.size(); i += keep_every) {
        kept.push_back(drive.odometry.poses[i]);
      }
      drive.odometry.poses = kept;
      for (size_t r = 0; r < rules.size(); ++r) {
        AssociationOptions association;
        association.keyframe_min_rotation_deg = rules[r].min_rotation_deg;
        association.keyframe_min_translation_m = rules[r].min_translation_m;
        AssociationResult associated = AssociateCameraWithOdometry(
            {drive.camera}, drive.odometry, association);
        if (r == per_pose_noise_rule) {
          // The camera covariance as the simulation made it: the default
          // relative terms plus twice the per-pose noise (both ends).
          const NoiseModel noise;
          const double rotation_rad =
              (vo ? drive_options.camera_step_rotation_noise_deg
                  : drive_options.camera_rotation_noise_deg) *
              kDegToRad;
          for (MotionPair& pair : associated.pairs) {
            const double length = pair.cam_i_from_cam_j.translation.norm();
            const double relative =
                vo ? drive_options.camera_step_translation_noise_rel
                   : noise.cam_translation_sigma_rel;
            const double per_pose =
                vo ? 0.0 : drive_options.camera_position_noise;
            MotionCovariance covariance = MotionCovariance::Zero();
            covariance.diagonal().head<3>().setConstant(
                (vo ? 1.0 : 2.0) * rotation_rad * rotation_rad);
            covariance.diagonal().tail<3>().setConstant(
                relative * relative * length * length +
                2.0 * per_pose * per_pose);
            pair.cam_covariance = covariance;
          }
        }
        if (r == no_interpolation_rule) {
          for (MotionPair& pair : associated.pairs) {
            pair.odom_interpolation_covariance.reset();
          }
        }
        CalibrationOptions options;
        options.use_ransac = rules[r].ransac;
        options.fixed_translation_z_m = drive.odom_from_cam.translation.z();
        const CalibrationResult result =
            CalibrateOdomCam(associated.pairs, options);
        Errors& e = errors[r];
        ++e.runs;
        e.pairs += static_cast<double>(associated.pairs.size());
        if (!result.has_estimate) {
          ++e.failures;
          continue;
        }
        const double rotation_deg =
            RotationAngle(result.odom_from_cam.rotation *
                          drive.odom_from_cam.rotation.conjugate()) *
            kRadToDeg;
        const double xy_mm = 1e3 * (result.odom_from_cam.translation -
                                    drive.odom_from_cam.translation)
                                       .head<2>()
                                       .norm();
        const double scale_pct =
            100.0 * (result.metric_scales[0] / drive.metric_scale - 1.0);
        e.rotation_sq_deg2 += rotation_deg * rotation_deg;
        e.xy_sq_mm2 += xy_mm * xy_mm;
        e.scale_sq_pct2 += scale_pct * scale_pct;
        e.rotation_within_3_sigma +=
            rotation_deg <= 3.0 * result.stddev_rotation_axes_deg.norm();
        e.scale_within_3_sigma += std::abs(scale_pct) <=
                                  300.0 * result.stddev_metric_scales_rel.at(0);
        if (!result.IsSuccess()) ++e.failures;
      }
    }
    std::printf(
        "\n%s camera poses, %d seeds, %.0f s, %.1f Hz odometry, "
        "%.0f Hz camera\n",
        vo ? "VO-like (composed)" : "COLMAP-like (consistent)",
        num_seeds,
        duration_s,
        odometry_hz / keep_every,
        camera_hz);
    std::printf(
        "| pairs | mean pairs | rotation RMSE deg | x/y RMSE mm | "
        "scale RMSE %% | rot / reference | rot, scale within 3 sigma | "
        "not success |\n");
    const Errors& batch = errors[reference_rule];
    const double reference =
        std::sqrt(batch.rotation_sq_deg2 / (batch.runs - batch.failures));
    for (size_t r = 0; r < rules.size(); ++r) {
      const Errors& e = errors[r];
      const int n = e.runs - e.failures;
      const double rotation = std::sqrt(e.rotation_sq_deg2 / n);
      std::printf(
          "| %s | %.0f | %.4f | %.2f | %.3f | %.2f | %d, %d of %d | %d |\n",
          rules[r].name,
          e.pairs / e.runs,
          rotation,
          std::sqrt(e.xy_sq_mm2 / n),
          std::sqrt(e.scale_sq_pct2 / n),
          rotation / reference,
          e.rotation_within_3_sigma,
          e.scale_within_3_sigma,
          n,
          e.failures);
    }
  }
  return 0;
}

}  // namespace
}  // namespace odomcal

int main(int argc, char** argv) { return odomcal::Main(argc, argv); }
