#include "odomcal/solver/stretch_consistency.h"

#include "odomcal/datasets/simulation/motion_simulator.h"
#include "odomcal/solver/noise_estimation.h"
#include "odomcal/tests/test_seed.h"

#include <gtest/gtest.h>

#include <cmath>

namespace odomcal {
namespace {

// One SfM segment of 90 pairs with a folded stretch (pairs 30-39: wrong
// camera motions) and a last part (pairs 60-89) at another scale, as COLMAP
// produces when it silently breaks a model.
TEST(CalibrateWithStretchCheck, DropsAFoldAndSplitsOffAPartAtAnotherScale) {
  auto rng = SeededRng(70);
  MotionSimulatorOptions simulation;
  simulation.num_pairs = 90;
  simulation.add_noise = true;
  simulation.noise.odom_yaw_sigma_rel = 0.0;
  SimulatedMotions truth = SimulateMotions(simulation, &rng);
  MotionSimulatorOptions outliers = simulation;
  outliers.outlier_fraction = 1.0;
  const SimulatedMotions folded =
      SimulateMotions(outliers, truth.odom_from_cam, truth.metric_scales, &rng);
  for (int i = 30; i < 40; ++i) {
    truth.pairs[i].cam_i_from_cam_j = folded.pairs[i].cam_i_from_cam_j;
    truth.pairs[i].odom_i_from_odom_j = folded.pairs[i].odom_i_from_odom_j;
  }
  for (int i = 60; i < 90; ++i) {
    truth.pairs[i].cam_i_from_cam_j.translation /= 1.6;  // scale becomes 1.6 s
  }
  CalibrationOptions options;
  options.fixed_translation_z_m = truth.odom_from_cam.translation.z();
  const StretchCheckResult check =
      CalibrateWithStretchCheck(truth.pairs, options, StretchOptions());
  ASSERT_TRUE(check.split);
  ASSERT_EQ(check.result.status, CalibrationStatus::kSuccess)
      << check.result.message;
  // Within 4 predicted standard deviations, as if the bad parts were absent.
  ASSERT_TRUE(check.result.covariance.has_value());
  const Eigen::MatrixXd& covariance = *check.result.covariance;
  EXPECT_LT(RotationAngle(check.result.odom_from_cam.rotation.conjugate() *
                          truth.odom_from_cam.rotation),
            4.0 * std::sqrt(covariance.topLeftCorner<3, 3>().trace()));
  EXPECT_LT(
      (check.result.odom_from_cam.translation - truth.odom_from_cam.translation)
          .head<2>()
          .norm(),
      4.0 * std::sqrt(covariance.block<2, 2>(3, 3).trace()));
  // The fold is found and dropped; the part at another scale is kept as its
  // own segment with the right scale.
  bool fold_dropped = false, part_kept = false;
  for (const InconsistentStretch& run : check.stretches) {
    if (run.first_pair >= 30 && run.last_pair <= 39) {
      fold_dropped = !run.kept_as_segment;
    }
    if (run.first_pair >= 60 && run.kept_as_segment) {
      part_kept = true;
      EXPECT_NEAR(check.result.metric_scales[run.output_segment] /
                      (1.6 * truth.metric_scales[0]),
                  1.0,
                  0.02);
    }
  }
  EXPECT_TRUE(fold_dropped);
  EXPECT_TRUE(part_kept);
  for (const int input : check.input_pair_of_output) {
    EXPECT_FALSE(input >= 30 && input < 40)
        << "folded pair " << input << " used";
  }
}

TEST(CalibrateWithStretchCheck, LeavesConsistentDataAlone) {
  auto rng = SeededRng(71);
  MotionSimulatorOptions simulation;
  simulation.num_pairs = 60;
  simulation.add_noise = true;
  const SimulatedMotions truth = SimulateMotions(simulation, &rng);
  CalibrationOptions options;
  const StretchCheckResult check =
      CalibrateWithStretchCheck(truth.pairs, options, StretchOptions());
  EXPECT_FALSE(check.split);
  EXPECT_TRUE(check.stretches.empty());
  EXPECT_EQ(check.pairs.size(), truth.pairs.size());
}

// The drift's standard deviation must follow the noise the covariance uses:
// with the given model 4x too pessimistic (in standard deviation), the noise
// estimated from the data brings it back to what the true model gives;
// computed under the given model it would be about 4x too large.
TEST(CalibrateWithStretchCheck, DriftStddevUsesTheNoiseEstimatedFromTheData) {
  auto rng = SeededRng(72);
  MotionSimulatorOptions simulation;
  simulation.num_pairs = 120;
  simulation.add_noise = true;
  simulation.min_metric_scale = 1.0;
  simulation.max_metric_scale = 1.0;
  SimulatedMotions truth = SimulateMotions(simulation, &rng);
  const int n = simulation.num_pairs;
  for (int i = 0; i < n; ++i) {  // scale grows by 15 % along the drive
    truth.pairs[i].cam_i_from_cam_j.translation /= 1.0 + 0.15 * i / (n - 1);
  }
  CalibrationOptions options;
  options.fixed_translation_z_m = truth.odom_from_cam.translation.z();
  options.noise = simulation.noise;
  const StretchCheckResult reference =
      CalibrateWithStretchCheck(truth.pairs, options, StretchOptions());
  options.noise = ScaleNoise(simulation.noise, {16.0, 16.0, 16.0, 16.0});
  const StretchCheckResult pessimistic =
      CalibrateWithStretchCheck(truth.pairs, options, StretchOptions());
  ASSERT_EQ(reference.scale_drifts.size(), 1u);
  ASSERT_EQ(pessimistic.scale_drifts.size(), 1u);
  ASSERT_TRUE(pessimistic.result.noise_estimate.has_value());
  const ScaleDrift& expected = reference.scale_drifts[0];
  const ScaleDrift& drift = pessimistic.scale_drifts[0];
  ASSERT_TRUE(expected.trend_measured);
  ASSERT_TRUE(drift.trend_measured);
  EXPECT_NEAR(
      drift.relative_drift_stddev / expected.relative_drift_stddev, 1.0, 0.3);
  EXPECT_NEAR(drift.relative_drift, 0.15, 3.0 * drift.relative_drift_stddev);
}

}  // namespace
}  // namespace odomcal
