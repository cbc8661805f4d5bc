#include "odomcal/solver/scale_consistency.h"

#include "odomcal/datasets/simulation/motion_simulator.h"
#include "odomcal/solver/calibrate.h"
#include "odomcal/solver/stretch_consistency.h"
#include "odomcal/tests/test_seed.h"

#include <gtest/gtest.h>

#include <cmath>

namespace odomcal {
namespace {

TEST(PerPairMetricScales, ExactDataGiveTheTrueScaleForEveryTranslatingPair) {
  auto rng = SeededRng(80);
  MotionSimulatorOptions simulation;
  simulation.num_pairs = 30;
  const SimulatedMotions truth = SimulateMotions(simulation, &rng);
  const std::vector<PairMetricScale> scales = PerPairMetricScales(
      truth.pairs, truth.odom_from_cam, truth.metric_scales, NoiseModel());
  ASSERT_EQ(scales.size(), truth.pairs.size());
  for (const PairMetricScale& value : scales) {
    EXPECT_NEAR(value.scale / truth.metric_scales[0], 1.0, 1e-9);
    EXPECT_GT(value.stddev, 0.0);
  }
}

TEST(PerPairMetricScales, PureRotationDeterminesNoScale) {
  auto rng = SeededRng(81);
  MotionSimulatorOptions simulation;
  simulation.num_pairs = 1;
  SimulatedMotions truth = SimulateMotions(simulation, &rng);
  truth.pairs[0].cam_i_from_cam_j.translation.setZero();
  const std::vector<PairMetricScale> scales = PerPairMetricScales(
      truth.pairs, truth.odom_from_cam, truth.metric_scales, NoiseModel());
  EXPECT_FALSE(std::isfinite(scales[0].stddev));
}

// Noisy data of one segment whose reconstruction scale changes by `change`
// from pair `at` on (SfM scale drift joining two parts).
SimulatedMotions SegmentWithScaleChange(uint64_t seed,
                                        int num_pairs,
                                        int at,
                                        double change) {
  auto rng = SeededRng(seed);
  MotionSimulatorOptions simulation;
  simulation.num_pairs = num_pairs;
  simulation.add_noise = true;
  simulation.noise.odom_translation_sigma_rel = 0.003;
  simulation.noise.cam_translation_sigma_rel = 0.003;
  SimulatedMotions truth = SimulateMotions(simulation, &rng);
  for (int i = at; i < num_pairs; ++i) {
    truth.pairs[i].cam_i_from_cam_j.translation /=
        change;  // metric scale * change
  }
  return truth;
}

TEST(FindScaleChanges, FindsAThreePercentStepWhereItIs) {
  const SimulatedMotions truth =
      SegmentWithScaleChange(TestSeed(82), 60, 35, 1.03);
  const std::vector<ScaleChange> changes = FindScaleChanges(
      truth.pairs,
      PerPairMetricScales(
          truth.pairs, truth.odom_from_cam, truth.metric_scales, NoiseModel()),
      ScaleChangeOptions());
  ASSERT_EQ(changes.size(), 1u);
  EXPECT_NEAR(changes[0].first_pair_after, 35, 2);
  EXPECT_NEAR(changes[0].scale_after / changes[0].scale_before, 1.03, 0.006);
  EXPECT_GT(changes[0].f_statistic, ScaleChangeOptions().min_f_statistic);
}

// False alarms cut good segments and cost accuracy: none over 40 noisy
// problems without a change, at the default noise model's level.
TEST(FindScaleChanges, NoFalseAlarmsOnConsistentSegments) {
  int num_false_alarms = 0;
  for (uint64_t trial = 0; trial < 40; ++trial) {
    auto rng = SeededRng(TestSeed(83) * 1000 + trial);
    MotionSimulatorOptions simulation;
    simulation.num_pairs = 80;
    simulation.add_noise = true;
    const SimulatedMotions truth = SimulateMotions(simulation, &rng);
    num_false_alarms += static_cast<int>(
        FindScaleChanges(truth.pairs,
                         PerPairMetricScales(truth.pairs,
                                             truth.odom_from_cam,
                                             truth.metric_scales,
                                             NoiseModel()),
                         ScaleChangeOptions())
            .size());
  }
  EXPECT_EQ(num_false_alarms, 0);
}

TEST(FindScaleChanges, IgnoresChangesBelowTheMinimum) {
  const SimulatedMotions truth =
      SegmentWithScaleChange(TestSeed(84), 60, 30, 1.005);
  ScaleChangeOptions options;
  options.min_relative_change = 0.01;
  EXPECT_TRUE(FindScaleChanges(truth.pairs,
                               PerPairMetricScales(truth.pairs,
                                                   truth.odom_from_cam,
                                                   truth.metric_scales,
                                                   NoiseModel()),
                               options)
                  .empty());
}

// End to end through the stretch check: every pair still passes RANSAC's
// per-pair thresholds, yet one scale for all would bias the extrinsic; the
// cut gives each part its own scale.
TEST(CalibrateWithStretchCheck, CutsASegmentWhoseScaleChanges) {
  const SimulatedMotions truth =
      SegmentWithScaleChange(TestSeed(85), 80, 40, 1.04);
  CalibrationOptions options;
  options.fixed_translation_z_m = truth.odom_from_cam.translation.z();
  const StretchCheckResult check =
      CalibrateWithStretchCheck(truth.pairs, options, StretchOptions());
  ASSERT_EQ(check.result.status, CalibrationStatus::kSuccess)
      << check.result.message;
  ASSERT_EQ(check.scale_changes.size(), 1u);
  EXPECT_TRUE(check.split);
  EXPECT_EQ(check.scale_changes[0].input_segment, 0);
  ASSERT_EQ(check.result.metric_scales.size(), 2u);
  EXPECT_NEAR(
      check.result.metric_scales[0] / truth.metric_scales[0], 1.0, 0.01);
  EXPECT_NEAR(check.result.metric_scales[1] / (1.04 * truth.metric_scales[0]),
              1.0,
              0.01);
  ASSERT_EQ(check.input_segment_of_output_segment.size(), 2u);
  EXPECT_EQ(check.input_segment_of_output_segment[1], 0);

  StretchOptions off;
  off.check_scale_changes = false;
  const StretchCheckResult unchecked =
      CalibrateWithStretchCheck(truth.pairs, options, off);
  EXPECT_TRUE(unchecked.scale_changes.empty());
  EXPECT_EQ(unchecked.result.metric_scales.size(), 1u);
}

}  // namespace
}  // namespace odomcal
