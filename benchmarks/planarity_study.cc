// Not a Google Benchmark: planar odometry (x, y, yaw, as wheel odometry
// gives) on a climbing, banking road (datasets/simulation/climbing_road.h)
// with the default calibration (noise estimated from the data): how often
// the planarity check names the ground, and whether roll, pitch, yaw, x and
// y lie within their stated 3 sigma. Prints a markdown row per case
// (docs/non_planar_motion.md).
//   <build>/benchmarks/planarity_study 50 [max_grade_deg] [max_bank_deg]
//       [roll_sigma_deg] [height] [verbose]
// "height": the camera's height given to 10 cm (--fixed_translation_z_m
// 1.65 --translation_z_prior_sigma_m 0.1); otherwise held at the default 0
// under its 1 m prior.
// Grade 0, bank 0 and roll 0 is flat ground (the false-alarm rate).

#include "odomcal/datasets/simulation/climbing_road.h"
#include "odomcal/solver/angles.h"
#include "odomcal/solver/calibrate.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace odomcal {
namespace {

struct Tally {
  int runs = 0;
  int success = 0;
  int named = 0;  // either warning
  int seen = 0;   // the ground's tilt seen (its covariance added)
  int inflated = 0;
  int axis_covered[3] = {0, 0, 0};
  int x_covered = 0;
  int y_covered = 0;
  int all_covered = 0;
  // Without the ground tilt's covariance (GroundTiltCovariance subtracted):
  // the result as the chi-square check alone leaves it.
  int roll_covered_without = 0;
  int all_covered_without = 0;
  double sum_error2[5] = {0, 0, 0, 0, 0};  // roll, pitch, yaw (deg), x, y (m)
  double sum_variance[5] = {0, 0, 0, 0, 0};
};

void Add(const CalibrationResult& result,
         const ClimbingRoadOptions& road,
         const CalibrationOptions& options,
         bool verbose,
         int seed,
         Tally* tally) {
  ++tally->runs;
  const PlanarityCheck& check = result.diagnostics.planarity;
  tally->named += check.named || check.ground_named;
  tally->seen += check.ground_tilt_seen;
  tally->inflated += check.covariance_inflation > 1.0;
  if (!result.IsSuccess() || !result.covariance) {
    if (verbose) std::printf("seed %d: %s\n", seed, result.message.c_str());
    return;
  }
  ++tally->success;
  const Rigid3d& truth = road.odom_from_cam;
  const Eigen::Vector3d error =
      result.odom_from_cam.translation - truth.translation;
  const Eigen::Vector3d phi_deg =
      kRadToDeg *
      LogRotation(truth.rotation * result.odom_from_cam.rotation.conjugate());
  bool all = true;
  for (int k = 0; k < 3; ++k) {
    const bool covered =
        std::abs(phi_deg(k)) <= 3.0 * result.stddev_rotation_axes_deg(k);
    tally->axis_covered[k] += covered;
    all &= covered;
    tally->sum_error2[k] += phi_deg(k) * phi_deg(k);
    tally->sum_variance[k] += std::pow(result.stddev_rotation_axes_deg(k), 2);
  }
  for (int k = 0; k < 2; ++k) {
    const bool covered =
        std::abs(error(k)) <= 3.0 * result.stddev_translation_xy_m(k);
    (k == 0 ? tally->x_covered : tally->y_covered) += covered;
    all &= covered;
    tally->sum_error2[3 + k] += error(k) * error(k);
    tally->sum_variance[3 + k] +=
        std::pow(result.stddev_translation_xy_m(k), 2);
  }
  tally->all_covered += all;
  // The covariance without the ground's term, subtracted as calibrate.cc
  // adds it (rx, ry, tx, ty; the height within its prior's 2 sigma).
  const double height_bound = std::abs(options.fixed_translation_z_m) +
                              2.0 * options.translation_z_prior_sigma_m;
  const Eigen::Matrix4d ground = GroundTiltCovariance(
      check, options.fixed_translation_z_m, height_bound * height_bound);
  const double without[5] = {
      std::sqrt(std::max(0.0, (*result.covariance)(0, 0) - ground(0, 0))),
      std::sqrt(std::max(0.0, (*result.covariance)(1, 1) - ground(1, 1))),
      std::sqrt((*result.covariance)(2, 2)),
      std::sqrt(std::max(0.0, (*result.covariance)(3, 3) - ground(2, 2))),
      std::sqrt(std::max(0.0, (*result.covariance)(4, 4) - ground(3, 3)))};
  const double errors[5] = {phi_deg(0) * kDegToRad,
                            phi_deg(1) * kDegToRad,
                            phi_deg(2) * kDegToRad,
                            error(0),
                            error(1)};
  bool all_without = true;
  for (int k = 0; k < 5; ++k) {
    all_without &= std::abs(errors[k]) <= 3.0 * without[k];
  }
  tally->roll_covered_without += std::abs(errors[0]) <= 3.0 * without[0];
  tally->all_covered_without += all_without;
  if (verbose) {
    std::printf(
        "seed %d: roll %.3f (3s %.3f) pitch %.3f (3s %.3f) yaw %.3f (3s %.3f) "
        "deg, x %.2f (3s %.2f) y %.2f (3s %.2f) cm; chi2 %.0f / %.0f, corr "
        "%.2f, infl %.2f, named %d, tilt rms %.3f deg, noise rot factor "
        "%.2f; ground F %.1f / %.1f, roll %.2f pitch %.2f deg, named %d\n",
        seed,
        phi_deg(0),
        3 * result.stddev_rotation_axes_deg(0),
        phi_deg(1),
        3 * result.stddev_rotation_axes_deg(1),
        phi_deg(2),
        3 * result.stddev_rotation_axes_deg(2),
        100 * error(0),
        300 * result.stddev_translation_xy_m(0),
        100 * error(1),
        300 * result.stddev_translation_xy_m(1),
        check.chi_square,
        check.chi_square_threshold,
        check.correlation_length,
        check.covariance_inflation,
        static_cast<int>(check.named),
        check.tilt_rms_deg,
        result.noise_estimate
            ? result.noise_estimate->noise.cam_rotation_sigma_deg / 0.05
            : 1.0,
        check.ground_f_statistic,
        check.ground_f_threshold,
        check.ground_roll_rms_deg,
        check.ground_pitch_rms_deg,
        static_cast<int>(check.ground_named));
    for (const std::string& warning : result.warnings) {
      std::printf("  warning: %s\n", warning.c_str());
    }
  }
}

}  // namespace
}  // namespace odomcal

int main(int argc, char** argv) {
  using namespace odomcal;
  const int num_seeds = argc > 1 ? std::atoi(argv[1]) : 50;
  ClimbingRoadOptions road;
  road.planar_odometry = true;
  if (argc > 2) road.max_grade_deg = std::atof(argv[2]);
  if (argc > 3) road.max_bank_deg = std::atof(argv[3]);
  if (argc > 4) road.roll_sigma_deg = std::atof(argv[4]);
  CalibrationOptions options;
  bool verbose = false;
  for (int k = 5; k < argc; ++k) {
    const std::string arg = argv[k];
    if (arg == "verbose") verbose = true;
    // The camera's height given (--fixed_translation_z_m), as the planarity
    // warning asks.
    if (arg == "height") {
      options.fixed_translation_z_m = road.odom_from_cam.translation.z();
      options.translation_z_prior_sigma_m = 0.1;
    }
  }
  Tally t;
  for (int seed = 1; seed <= num_seeds; ++seed) {
    const MotionPairs pairs = ClimbingRoadPairs(road, &options.noise, seed);
    Add(CalibrateOdomCam(pairs, options), road, options, verbose, seed, &t);
  }
  const double n = std::max(1, t.success);
  std::printf(
      "| max grade (deg) | max bank (deg) | roll noise (deg) | runs | success "
      "| named | ground seen | inflated | roll within 3 sigma | pitch | yaw | "
      "x | y | all 5 "
      "| roll, all 5 without the ground's term | RMS error / RMS stated sigma: "
      "roll, pitch, yaw (deg) | x, y (cm) "
      "|\n| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- "
      "| --- | --- | --- | --- | --- | --- |\n");
  std::printf(
      "| %.1f | %.1f | %.1f | %d | %d | %d | %d | %d | %d | %d | %d | %d | %d "
      "| %d | %d, %d "
      "| %.3f / %.3f, %.3f / %.3f, %.3f / %.3f | %.2f / %.2f, %.2f / %.2f "
      "|\n",
      road.max_grade_deg,
      road.max_bank_deg,
      road.roll_sigma_deg,
      t.runs,
      t.success,
      t.named,
      t.seen,
      t.inflated,
      t.axis_covered[0],
      t.axis_covered[1],
      t.axis_covered[2],
      t.x_covered,
      t.y_covered,
      t.all_covered,
      t.roll_covered_without,
      t.all_covered_without,
      std::sqrt(t.sum_error2[0] / n),
      std::sqrt(t.sum_variance[0] / n),
      std::sqrt(t.sum_error2[1] / n),
      std::sqrt(t.sum_variance[1] / n),
      std::sqrt(t.sum_error2[2] / n),
      std::sqrt(t.sum_variance[2] / n),
      100 * std::sqrt(t.sum_error2[3] / n),
      100 * std::sqrt(t.sum_variance[3] / n),
      100 * std::sqrt(t.sum_error2[4] / n),
      100 * std::sqrt(t.sum_variance[4] / n));
  return 0;
}
