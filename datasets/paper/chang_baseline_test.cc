#include "odomcal/datasets/paper/chang_baseline.h"

#include "odomcal/datasets/simulation/motion_simulator.h"
#include "odomcal/solver/angles.h"
#include "odomcal/tests/test_seed.h"

#include <gtest/gtest.h>

namespace odomcal {
namespace {

TEST(SolveChangMinimal, ExactOnNoiseFreeMinimalData) {
  auto rng = SeededRng(50);
  int solved = 0;
  for (int trial = 0; trial < 200; ++trial) {
    MotionSimulatorOptions options;
    options.num_pairs = 3;
    const SimulatedMotions truth = SimulateMotions(options, &rng);
    Rigid3d estimate;
    double scale = 0.0;
    if (!SolveChangMinimal(truth.pairs[0],
                           truth.pairs[1],
                           truth.pairs[2],
                           truth.odom_from_cam.translation.z(),
                           &estimate,
                           &scale)) {
      continue;  // e.g. a yaw too small to give an axis
    }
    ++solved;
    EXPECT_LT(RotationAngle(estimate.rotation.conjugate() *
                            truth.odom_from_cam.rotation) *
                  kRadToDeg,
              1e-6);
    EXPECT_LT((estimate.translation - truth.odom_from_cam.translation).norm(),
              1e-9);
    EXPECT_NEAR(scale / truth.metric_scales[0], 1.0, 1e-9);
  }
  EXPECT_GT(solved, 195);
}

TEST(EstimateOdomFromCamChang, RecoversTheTruthWithOutliers) {
  auto rng = SeededRng(51);
  MotionSimulatorOptions options;
  options.num_pairs = 40;
  options.outlier_fraction = 0.2;
  const SimulatedMotions truth = SimulateMotions(options, &rng);
  CalibrationOptions calibration;
  calibration.fixed_translation_z_m = truth.odom_from_cam.translation.z();
  calibration.ransac_max_iterations = 300;
  const ChangEstimate estimate =
      EstimateOdomFromCamChang(truth.pairs, calibration);
  ASSERT_TRUE(estimate.success) << estimate.failure;
  EXPECT_LT(RotationAngle(estimate.odom_from_cam.rotation.conjugate() *
                          truth.odom_from_cam.rotation) *
                kRadToDeg,
            1e-6);
  for (size_t i = 0; i < truth.pairs.size(); ++i) {
    EXPECT_EQ(estimate.inlier_mask[i] != 0, truth.is_outlier[i] == 0) << i;
  }
}

}  // namespace
}  // namespace odomcal
