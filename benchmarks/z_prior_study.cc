// Not a Google Benchmark: coverage of x, y, the rotation and the scale on a
// climbing road with SE(3) odometry (datasets/simulation/climbing_road.h),
// with z held exactly at 0 (--translation_z_prior_sigma_m 0) and with the
// held z as a prior (the default 1 m), over seeds 1..N. Prints a markdown
// table (docs/non_planar_motion.md).
//   <build>/benchmarks/z_prior_study 50 [max_grade_deg] [given]
// "given": the noise model as given (--estimate_noise off), which is the
// noise the data are drawn from.

#include "odomcal/datasets/simulation/climbing_road.h"
#include "odomcal/solver/angles.h"
#include "odomcal/solver/calibrate.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace odomcal {
namespace {

struct Tally {
  int runs = 0;
  int success = 0;
  int x_covered = 0;
  int y_covered = 0;
  int rotation_covered = 0;
  int scale_covered = 0;
  int z_covered = 0;
  int z_moved = 0;
  int z_estimated = 0;
  double sum_x_error2 = 0.0;
  double sum_x_variance = 0.0;
  double sum_data_z_stddev = 0.0;
};

void Add(const CalibrationResult& result,
         const ClimbingRoadOptions& road,
         Tally* tally) {
  ++tally->runs;
  if (!result.IsSuccess() || !result.covariance) return;
  ++tally->success;
  const Rigid3d& truth = road.odom_from_cam;
  const Eigen::Vector3d error =
      result.odom_from_cam.translation - truth.translation;
  const Eigen::Vector3d phi =
      LogRotation(truth.rotation * result.odom_from_cam.rotation.conjugate());
  tally->x_covered +=
      std::abs(error.x()) <= 3.0 * result.stddev_translation_xy_m.x();
  tally->y_covered +=
      std::abs(error.y()) <= 3.0 * result.stddev_translation_xy_m.y();
  bool rotation = true;
  for (int k = 0; k < 3; ++k) {
    rotation &= std::abs(phi(k)) <=
                3.0 * result.stddev_rotation_axes_deg(k) * kDegToRad;
  }
  tally->rotation_covered += rotation;
  tally->scale_covered +=
      std::abs(result.metric_scales[0] / road.metric_scale - 1.0) <=
      3.0 * result.stddev_metric_scales_rel[0];
  const bool z_row =
      result.observability.translation_z == Determination::kEstimated ||
      result.translation_z_prior.moved_by_data;
  tally->z_covered +=
      z_row && std::abs(error.z()) <= 3.0 * result.stddev_translation_z_m;
  tally->z_moved += result.translation_z_prior.moved_by_data;
  tally->z_estimated +=
      result.observability.translation_z == Determination::kEstimated;
  tally->sum_x_error2 += error.x() * error.x();
  tally->sum_x_variance +=
      result.stddev_translation_xy_m.x() * result.stddev_translation_xy_m.x();
  if (std::isfinite(result.translation_z_prior.data_stddev_m)) {
    tally->sum_data_z_stddev += result.translation_z_prior.data_stddev_m;
  }
}

void Print(const std::string& name, const Tally& t) {
  std::printf(
      "| %s | %d | %d | %d | %d | %d | %d | %d | %d | %d | %.2f | %.2f | "
      "%.1f |\n",
      name.c_str(),
      t.runs,
      t.success,
      t.x_covered,
      t.y_covered,
      t.rotation_covered,
      t.scale_covered,
      t.z_covered,
      t.z_moved,
      t.z_estimated,
      100.0 * std::sqrt(t.sum_x_error2 / std::max(1, t.success)),
      100.0 * std::sqrt(t.sum_x_variance / std::max(1, t.success)),
      t.z_moved > 0 ? 100.0 * t.sum_data_z_stddev / t.z_moved : 0.0);
}

}  // namespace
}  // namespace odomcal

int main(int argc, char** argv) {
  using namespace odomcal;
  const int num_seeds = argc > 1 ? std::atoi(argv[1]) : 50;
  ClimbingRoadOptions road;
  if (argc > 2) road.max_grade_deg = std::atof(argv[2]);
  CalibrationOptions prior;
  prior.noise.odom_tilt_sigma_deg = 0.05;  // an INS's relative tilt
  if (argc > 3 && std::string(argv[3]) == "given") prior.estimate_noise = false;
  CalibrationOptions hold = prior;
  hold.translation_z_prior_sigma_m = 0.0;
  Tally held_tally, prior_tally;
  for (int seed = 1; seed <= num_seeds; ++seed) {
    const MotionPairs pairs = ClimbingRoadPairs(road, &prior.noise, seed);
    Add(CalibrateOdomCam(pairs, hold), road, &held_tally);
    Add(CalibrateOdomCam(pairs, prior), road, &prior_tally);
  }
  std::printf(
      "| z | runs | success | x within 3 sigma | y | rotation (3 axes) | "
      "scale | z | z moved by the data | z estimated (determined) | x RMS "
      "error (cm) | x RMS stated sigma (cm) | the data's sigma of z, mean "
      "where moved (cm) |\n"
      "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | "
      "--- | --- |\n");
  Print("held exactly (prior sigma 0)", held_tally);
  Print("prior 1 m (default)", prior_tally);
  return 0;
}
