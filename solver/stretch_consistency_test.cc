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
      const double scale_stddev =
          std::sqrt(covariance(5 + run.output_segment, 5 + run.output_segment));
      EXPECT_NEAR(check.result.metric_scales[run.output_segment],
                  1.6 * truth.metric_scales[0],
                  4.0 * scale_stddev);
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

// A run of pairs a few tenths of a degree off (COLMAP at turns on the long
// drive) is beyond the noise estimated from the data but inside RANSAC's
// gate: its pairs are not used, yet they do not contradict the odometry, so
// the segment is not cut there (a cut would leave the run a segment of its
// own whose scale 10 pairs barely determine). Such pairs at the edges and
// in the middle of a fold (pairs 60-69 wrong but 65) go with the fold.
TEST(CalibrateWithStretchCheck, CutsOnlyWhereTheOdometryIsContradicted) {
  auto rng = SeededRng(73);
  MotionSimulatorOptions simulation;
  simulation.num_pairs = 100;
  simulation.add_noise = true;
  simulation.noise = ScaleNoise(NoiseModel(), {0.01, 0.01, 0.01, 0.01});
  SimulatedMotions truth = SimulateMotions(simulation, &rng);
  MotionSimulatorOptions outliers = simulation;
  outliers.outlier_fraction = 1.0;
  const SimulatedMotions folded =
      SimulateMotions(outliers, truth.odom_from_cam, truth.metric_scales, &rng);
  const auto tilt = [&](int i, double degrees) {
    Eigen::Quaterniond& rotation = truth.pairs[i].cam_i_from_cam_j.rotation;
    rotation =
        rotation * Eigen::Quaterniond(Eigen::AngleAxisd(
                       degrees * M_PI / 180.0, Eigen::Vector3d::UnitX()));
  };
  for (int i = 20; i < 30; ++i) tilt(i, 0.4);
  for (int i = 60; i < 70; ++i) {
    if (i == 65) continue;  // one right pair in the middle of the fold
    truth.pairs[i].cam_i_from_cam_j = folded.pairs[i].cam_i_from_cam_j;
  }
  for (const int i : {58, 59, 65, 70, 71}) tilt(i, 0.4);
  CalibrationOptions options;  // the given noise 10x the data's
  options.fixed_translation_z_m = truth.odom_from_cam.translation.z();
  const StretchCheckResult check =
      CalibrateWithStretchCheck(truth.pairs, options, StretchOptions());
  ASSERT_EQ(check.result.status, CalibrationStatus::kSuccess)
      << check.result.message;
  ASSERT_TRUE(check.result.noise_estimate.has_value());
  ASSERT_EQ(check.stretches.size(), 1u);
  const InconsistentStretch& fold = check.stretches[0];
  EXPECT_EQ(fold.first_pair, 58);
  EXPECT_EQ(fold.last_pair, 71);
  EXPECT_FALSE(fold.kept_as_segment);
  // Pairs 20-29 stay in the segment, unused but not contradicting.
  ASSERT_EQ(check.pairs.size(), truth.pairs.size() - 14);
  ASSERT_EQ(check.contradicts_odometry.size(), check.pairs.size());
  const std::vector<char>& used = check.result.diagnostics.inlier_mask;
  for (int i = 20; i < 30; ++i) {
    ASSERT_EQ(check.input_pair_of_output[i], i);
    EXPECT_EQ(used[i], 0) << "pair " << i << " 0.4 deg off was used";
    EXPECT_EQ(check.contradicts_odometry[i], 0) << "pair " << i;
  }
  // A pair 3 deg off is outside the gate: it contradicts the odometry.
  MotionPair wrong = truth.pairs[50];
  wrong.cam_i_from_cam_j.rotation =
      wrong.cam_i_from_cam_j.rotation *
      Eigen::Quaterniond(
          Eigen::AngleAxisd(3.0 * M_PI / 180.0, Eigen::Vector3d::UnitX()));
  EXPECT_TRUE(ContradictsOdometry(wrong, false, check.result, options));
  EXPECT_FALSE(ContradictsOdometry(wrong, true, check.result, options));
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
