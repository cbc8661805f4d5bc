#include "odomcal/solver/noise_refinement.h"

#include "odomcal/datasets/simulation/motion_simulator.h"
#include "odomcal/solver/angles.h"
#include "odomcal/solver/calibrate.h"
#include "odomcal/tests/test_seed.h"

#include <gtest/gtest.h>

namespace odomcal {
namespace {

// Exact pairs pass; a pair with a camera motion turned by 10 degrees, and a
// pair of a segment without a positive scale, do not.
TEST(PairsWithinNoise, KeepsExactPairsOnly) {
  std::mt19937_64 rng(TestSeed(146));
  MotionSimulatorOptions simulation;
  simulation.num_pairs = 6;
  const SimulatedMotions truth = SimulateMotions(simulation, &rng);
  ASSERT_EQ(truth.metric_scales.size(), 1u);
  MotionPairs pairs = truth.pairs;
  Rigid3d& turned = pairs[2].cam_i_from_cam_j;
  turned.rotation =
      (Eigen::AngleAxisd(10.0 * kDegToRad, Eigen::Vector3d::UnitZ()) *
       turned.rotation)
          .normalized();
  pairs[4].segment = 1;  // no scale for segment 1
  EXPECT_EQ(PairsWithinNoise(
                pairs, truth.odom_from_cam, truth.metric_scales, NoiseModel()),
            (std::vector<int>{0, 1, 3, 5}));
  pairs[4].segment = 0;
  EXPECT_EQ(PairsWithinNoise(pairs, truth.odom_from_cam, {-1.0}, NoiseModel()),
            std::vector<int>{});
}

// Clean pairs three times as noisy as the given model says (standard
// deviations): RANSAC's first choice under the given noise and its 1 deg /
// 2 cm thresholds rejects many of them; the final chi-square test under the
// estimated noise rejects at most 2 % (expected: 0.1 %, the test's level).
TEST(NoiseRefinement, RejectsFewGoodPairsUnderTheEstimatedNoise) {
  const uint64_t seed = TestSeed(144);
  SCOPED_TRACE("seed " + std::to_string(seed));
  std::mt19937_64 rng(seed);
  MotionSimulatorOptions simulation;
  simulation.num_pairs = 2000;
  simulation.add_noise = true;
  simulation.noise = ScaleNoise(NoiseModel(), {9.0, 9.0, 9.0, 9.0});
  const SimulatedMotions truth = SimulateMotions(simulation, &rng);
  CalibrationOptions options;
  options.fixed_translation_z_m = truth.odom_from_cam.translation.z();
  const CalibrationResult result = CalibrateOdomCam(truth.pairs, options);
  ASSERT_EQ(result.status, CalibrationStatus::kSuccess) << result.message;
  const int rejected =
      result.diagnostics.num_pairs_in - result.diagnostics.num_pairs_used;
  EXPECT_LE(rejected, 0.02 * simulation.num_pairs);
  EXPECT_NEAR(
      result.noise_estimate->SigmaRatio(NoiseGroup::kCameraRotation), 3.0, 0.3);

  // The given noise trusted as it is (no estimation): the same pairs lose
  // many more to RANSAC's thresholds.
  options.estimate_noise = false;
  const CalibrationResult trusted = CalibrateOdomCam(truth.pairs, options);
  EXPECT_GT(
      trusted.diagnostics.num_pairs_in - trusted.diagnostics.num_pairs_used,
      5 * rejected + 40);
}

// The noise estimation's passes run on several threads over fixed chunks of
// pairs, added in order: the same result, to the bit, on any number.
TEST(NoiseRefinement, TheResultDoesNotDependOnTheNumberOfThreads) {
  std::mt19937_64 rng(TestSeed(147));
  MotionSimulatorOptions simulation;
  simulation.num_pairs = 1500;  // 6 chunks
  simulation.add_noise = true;
  simulation.noise = ScaleNoise(NoiseModel(), {4.0, 4.0, 4.0, 4.0});
  const SimulatedMotions truth = SimulateMotions(simulation, &rng);
  CalibrationOptions options;
  options.fixed_translation_z_m = truth.odom_from_cam.translation.z();
  options.num_threads = 1;
  const CalibrationResult one = CalibrateOdomCam(truth.pairs, options);
  ASSERT_EQ(one.status, CalibrationStatus::kSuccess) << one.message;
  ASSERT_TRUE(one.noise_estimate.has_value());
  for (const int threads : {2, 3}) {
    SCOPED_TRACE("threads " + std::to_string(threads));
    options.num_threads = threads;
    const CalibrationResult many = CalibrateOdomCam(truth.pairs, options);
    ASSERT_EQ(many.status, CalibrationStatus::kSuccess) << many.message;
    EXPECT_EQ(many.odom_from_cam.rotation.coeffs(),
              one.odom_from_cam.rotation.coeffs());
    EXPECT_EQ(many.odom_from_cam.translation, one.odom_from_cam.translation);
    EXPECT_EQ(many.metric_scales, one.metric_scales);
    ASSERT_TRUE(many.covariance.has_value() && one.covariance.has_value());
    EXPECT_TRUE(*many.covariance == *one.covariance);
    EXPECT_EQ(many.noise_estimate->component_factors,
              one.noise_estimate->component_factors);
    EXPECT_EQ(many.diagnostics.num_pairs_used, one.diagnostics.num_pairs_used);
  }
  options.num_threads = 0;
  EXPECT_THROW(CalibrateOdomCam(truth.pairs, options), std::invalid_argument);
}

// 20 % outliers among noisy pairs: the final test removes them all and keeps
// at least 98 % of the good ones.
TEST(NoiseRefinement, RemovesOutliersAndKeepsGoodPairs) {
  const uint64_t seed = TestSeed(145);
  SCOPED_TRACE("seed " + std::to_string(seed));
  std::mt19937_64 rng(seed);
  MotionSimulatorOptions simulation;
  simulation.num_pairs = 500;
  simulation.add_noise = true;
  simulation.noise = ScaleNoise(NoiseModel(), {4.0, 4.0, 4.0, 4.0});
  simulation.outlier_fraction = 0.2;
  const SimulatedMotions truth = SimulateMotions(simulation, &rng);
  CalibrationOptions options;
  options.fixed_translation_z_m = truth.odom_from_cam.translation.z();
  const CalibrationResult result = CalibrateOdomCam(truth.pairs, options);
  ASSERT_EQ(result.status, CalibrationStatus::kSuccess) << result.message;
  int good = 0, good_rejected = 0, outliers_used = 0;
  for (size_t i = 0; i < truth.pairs.size(); ++i) {
    const bool used = result.diagnostics.inlier_mask[i];
    if (truth.is_outlier[i]) {
      outliers_used += used;
    } else {
      ++good;
      good_rejected += !used;
    }
  }
  EXPECT_EQ(outliers_used, 0);
  EXPECT_LE(good_rejected, 0.02 * good);
}

}  // namespace
}  // namespace odomcal
