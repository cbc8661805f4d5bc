#include "odomcal/solver/calibrate.h"

#include "odomcal/datasets/simulation/motion_simulator.h"
#include "odomcal/solver/angles.h"
#include "odomcal/tests/test_seed.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace odomcal {
namespace {

bool Contains(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

// The JSON `unobservable` list of a result.
std::vector<std::string> Unobservable(const CalibrationResult& result) {
  return UnobservableNames(result.observability);
}

double RotationErrorDeg(const Rigid3d& a, const Rigid3d& b) {
  return RotationAngle(a.rotation.conjugate() * b.rotation) * kRadToDeg;
}

CalibrationOptions OptionsFor(const SimulatedMotions& truth) {
  CalibrationOptions options;
  options.fixed_translation_z_m = truth.odom_from_cam.translation.z();
  return options;
}

TEST(CalibrateOdomCam, ExactWithoutNoiseThroughTheWholePipeline) {
  const uint64_t seed = TestSeed(30);
  SCOPED_TRACE("seed " + std::to_string(seed));
  std::mt19937_64 rng(seed);
  for (int trial = 0; trial < 100; ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial));
    MotionSimulatorOptions simulation;
    simulation.num_pairs = 30;
    simulation.num_segments = 1 + trial % 3;
    const SimulatedMotions truth = SimulateMotions(simulation, &rng);
    CalibrationOptions options = OptionsFor(truth);
    options.use_ransac = trial % 2 == 0;
    const CalibrationResult result = CalibrateOdomCam(truth.pairs, options);
    ASSERT_EQ(result.status, CalibrationStatus::kSuccess) << result.message;
    EXPECT_LT(RotationErrorDeg(result.odom_from_cam, truth.odom_from_cam),
              1e-6);
    EXPECT_NEAR(result.odom_from_cam.translation.x(),
                truth.odom_from_cam.translation.x(),
                1e-9);
    EXPECT_NEAR(result.odom_from_cam.translation.y(),
                truth.odom_from_cam.translation.y(),
                1e-9);
    for (size_t k = 0; k < truth.metric_scales.size(); ++k) {
      EXPECT_NEAR(result.metric_scales[k] / truth.metric_scales[k], 1.0, 1e-9);
    }
    EXPECT_EQ(Unobservable(result), std::vector<std::string>{"translation_z"});
    EXPECT_EQ(result.diagnostics.num_pairs_used, simulation.num_pairs);
    ASSERT_TRUE(result.covariance.has_value());
    EXPECT_EQ(result.covariance->rows(), 5 + simulation.num_segments);
  }
}

// Accuracy on noisy data, and consistency of the covariance: the normalised
// estimation error squared (NEES) averages the number of estimated degrees
// of freedom, 5 + 1 scale, when the noise model is right.
TEST(CalibrateOdomCam, NoisyMonteCarloIsAccurateAndConsistent) {
  const uint64_t seed = TestSeed(31);
  SCOPED_TRACE("seed " + std::to_string(seed));
  std::mt19937_64 rng(seed);
  constexpr int kTrials = 300;
  double sum_nees = 0.0;
  double sum_rotation_error2 = 0.0, sum_translation_error2 = 0.0;
  double sum_rotation_variance = 0.0, sum_translation_variance = 0.0;
  for (int trial = 0; trial < kTrials; ++trial) {
    MotionSimulatorOptions simulation;
    simulation.num_pairs = 60;
    simulation.add_noise = true;
    const SimulatedMotions truth = SimulateMotions(simulation, &rng);
    CalibrationOptions options = OptionsFor(truth);
    options.use_ransac = false;
    const CalibrationResult result = CalibrateOdomCam(truth.pairs, options);
    ASSERT_EQ(result.status, CalibrationStatus::kSuccess) << result.message;
    Eigen::VectorXd error(6);
    // Left perturbation: R_true = Exp(phi) R_est.
    error.head<3>() = LogRotation(truth.odom_from_cam.rotation *
                                  result.odom_from_cam.rotation.conjugate());
    error.segment<2>(3) =
        (truth.odom_from_cam.translation - result.odom_from_cam.translation)
            .head<2>();
    error(5) = truth.metric_scales[0] - result.metric_scales[0];
    sum_nees += error.dot(result.covariance->ldlt().solve(error));
    sum_rotation_error2 += error.head<3>().squaredNorm();
    sum_translation_error2 += error.segment<2>(3).squaredNorm();
    sum_rotation_variance += result.covariance->topLeftCorner<3, 3>().trace();
    sum_translation_variance += result.covariance->block<2, 2>(3, 3).trace();
  }
  const double mean_nees = sum_nees / kTrials;
  // Standard error of the mean of a chi-square(6) over 300 trials is 0.2.
  EXPECT_NEAR(mean_nees, 6.0, 0.8);
  // The errors match the predicted standard deviations (RMS over trials,
  // within 15 %), and those are small: default noise (0.2 deg + 1 % odometry
  // yaw, 0.05 deg camera, 1 % steps) over 60 pairs.
  const double rotation_rmse = std::sqrt(sum_rotation_error2 / kTrials);
  const double translation_rmse = std::sqrt(sum_translation_error2 / kTrials);
  EXPECT_NEAR(
      rotation_rmse / std::sqrt(sum_rotation_variance / kTrials), 1.0, 0.15);
  EXPECT_NEAR(translation_rmse / std::sqrt(sum_translation_variance / kTrials),
              1.0,
              0.15);
  EXPECT_LT(rotation_rmse * kRadToDeg, 0.3);
  EXPECT_LT(translation_rmse, 0.01);
}

TEST(CalibrateOdomCam, RansacRejectsThirtyPercentOutliers) {
  auto rng = SeededRng(32);
  for (int trial = 0; trial < 10; ++trial) {
    MotionSimulatorOptions simulation;
    simulation.num_pairs = 100;
    simulation.num_segments = 1 + trial % 2;
    simulation.add_noise = true;
    simulation.outlier_fraction = 0.3;
    const SimulatedMotions truth = SimulateMotions(simulation, &rng);
    const CalibrationResult result =
        CalibrateOdomCam(truth.pairs, OptionsFor(truth));
    ASSERT_EQ(result.status, CalibrationStatus::kSuccess) << result.message;
    // Within 4 predicted standard deviations of the truth.
    ASSERT_TRUE(result.covariance.has_value());
    const double rotation_sigma_deg =
        std::sqrt(result.covariance->topLeftCorner<3, 3>().trace()) * kRadToDeg;
    const double translation_sigma_m =
        std::sqrt(result.covariance->block<2, 2>(3, 3).trace());
    EXPECT_LT(RotationErrorDeg(result.odom_from_cam, truth.odom_from_cam),
              4.0 * rotation_sigma_deg);
    EXPECT_LT(
        (result.odom_from_cam.translation - truth.odom_from_cam.translation)
            .head<2>()
            .norm(),
        4.0 * translation_sigma_m);
    int missed_outliers = 0, rejected_inliers = 0;
    for (size_t i = 0; i < truth.pairs.size(); ++i) {
      missed_outliers +=
          truth.is_outlier[i] && result.diagnostics.inlier_mask[i];
      rejected_inliers +=
          !truth.is_outlier[i] && !result.diagnostics.inlier_mask[i];
    }
    EXPECT_EQ(missed_outliers, 0);
    // Good pairs beyond the 99.9 % bound: about 0.2 % of 70.
    EXPECT_LE(rejected_inliers, 2);
  }
}

TEST(CalibrateOdomCam, WithoutRansacOutliersAreNotSilentlyAccepted) {
  auto rng = SeededRng(33);
  MotionSimulatorOptions simulation;
  simulation.num_pairs = 100;
  simulation.add_noise = true;
  simulation.outlier_fraction = 0.3;
  const SimulatedMotions truth = SimulateMotions(simulation, &rng);
  CalibrationOptions options = OptionsFor(truth);
  options.use_ransac = false;
  const CalibrationResult result = CalibrateOdomCam(truth.pairs, options);
  EXPECT_NE(result.status, CalibrationStatus::kSuccess);
}

TEST(CalibrateOdomCam, StraightDrivingIsUnobservable) {
  auto rng = SeededRng(34);
  MotionSimulatorOptions simulation;
  simulation.min_yaw_rad = simulation.max_yaw_rad = 0.0;
  simulation.add_noise = true;
  const SimulatedMotions truth = SimulateMotions(simulation, &rng);
  const CalibrationResult result =
      CalibrateOdomCam(truth.pairs, OptionsFor(truth));
  EXPECT_EQ(result.status, CalibrationStatus::kUnobservable);
  EXPECT_FALSE(result.has_estimate);
  EXPECT_TRUE(Contains(Unobservable(result), "rotation"));
  EXPECT_TRUE(Contains(Unobservable(result), "translation_x"));
  EXPECT_TRUE(Contains(Unobservable(result), "translation_y"));
}

TEST(CalibrateOdomCam, NoMotionIsUnobservable) {
  MotionPairs pairs(10);
  const CalibrationResult result = CalibrateOdomCam(pairs, {});
  EXPECT_EQ(result.status, CalibrationStatus::kUnobservable);
  EXPECT_TRUE(Contains(Unobservable(result), "rotation"));
}

// Driving a circle at constant speed repeats one motion: the lever arm, the
// yaw and the scale trade off along a curve and cannot be separated.
TEST(CalibrateOdomCam, RepeatedIdenticalMotionIsUnobservable) {
  auto rng = SeededRng(35);
  const Rigid3d odom_from_cam = RandomOdomFromCam(&rng);
  const Rigid3d step(YawRotation(0.4), Eigen::Vector3d(0.3, 0.05, 0.0));
  MotionPairs pairs;
  for (int i = 0; i < 40; ++i) {
    MotionPair pair;
    pair.odom_i_from_odom_j = PerturbMotion(step,
                                            Eigen::Vector3d(0, 0, 1e-3),
                                            Eigen::Vector3d::Constant(1e-3),
                                            &rng);
    pair.cam_i_from_cam_j =
        PerturbMotion(CameraMotionFromOdometryMotion(step, odom_from_cam, 0.5),
                      Eigen::Vector3d::Constant(1e-4),
                      Eigen::Vector3d::Constant(1e-3),
                      &rng);
    pairs.push_back(pair);
  }
  CalibrationOptions options;
  options.use_ransac = false;
  const CalibrationResult result = CalibrateOdomCam(pairs, options);
  EXPECT_EQ(result.status, CalibrationStatus::kUnobservable) << result.message;
  EXPECT_TRUE(Contains(Unobservable(result), "translation_x") ||
              Contains(Unobservable(result), "translation_y"))
      << result.message;
}

TEST(CalibrateOdomCam, InvertedCameraPosesAreInconsistent) {
  auto rng = SeededRng(36);
  MotionSimulatorOptions simulation;
  simulation.add_noise = true;
  const SimulatedMotions truth = SimulateMotions(simulation, &rng);
  MotionPairs inverted = truth.pairs;
  for (MotionPair& pair : inverted) {
    pair.cam_i_from_cam_j = Inverse(pair.cam_i_from_cam_j);
  }
  for (const bool ransac : {true, false}) {
    CalibrationOptions options = OptionsFor(truth);
    options.use_ransac = ransac;
    const CalibrationResult result = CalibrateOdomCam(inverted, options);
    EXPECT_EQ(result.status, CalibrationStatus::kInconsistentData)
        << result.message;
  }
}

TEST(CalibrateOdomCam, AssociationErrorsAreInconsistent) {
  auto rng = SeededRng(37);
  MotionSimulatorOptions simulation;
  const SimulatedMotions truth = SimulateMotions(simulation, &rng);
  // Camera motions shifted by one pair: a typical time-offset mistake.
  MotionPairs shifted = truth.pairs;
  for (size_t i = 0; i + 1 < shifted.size(); ++i) {
    shifted[i].cam_i_from_cam_j = truth.pairs[i + 1].cam_i_from_cam_j;
  }
  const CalibrationResult result = CalibrateOdomCam(shifted, OptionsFor(truth));
  EXPECT_EQ(result.status, CalibrationStatus::kInconsistentData)
      << result.message;
  EXPECT_NE(result.message.find("association"), std::string::npos);
}

TEST(CalibrateOdomCam, TooFewPairs) {
  auto rng = SeededRng(38);
  MotionSimulatorOptions simulation;
  simulation.num_pairs = 1;
  const SimulatedMotions truth = SimulateMotions(simulation, &rng);
  EXPECT_EQ(CalibrateOdomCam(truth.pairs, {}).status,
            CalibrationStatus::kNotEnoughMotion);
}

TEST(CalibrateOdomCam, NonFiniteInputThrows) {
  auto rng = SeededRng(39);
  MotionSimulatorOptions simulation;
  SimulatedMotions truth = SimulateMotions(simulation, &rng);
  truth.pairs[3].cam_i_from_cam_j.translation.x() = std::nan("");
  EXPECT_THROW(CalibrateOdomCam(truth.pairs, {}), std::invalid_argument);
}

// Turning on the spot: every odometry translation is zero, so the camera's
// circle about the odometry origin fixes the lever arm only in sfm units:
// the lever arm and the scale trade off, and the scale is named.
TEST(CalibrateOdomCam, PureRotationInPlaceLeavesTheScaleUnobservable) {
  auto rng = SeededRng(42);
  const Rigid3d odom_from_cam = RandomOdomFromCam(&rng);
  MotionPairs pairs;
  for (int i = 0; i < 30; ++i) {
    const double yaw = (i % 2 == 0 ? 1.0 : -1.0) * (0.2 + 0.05 * (i % 7));
    MotionPair pair;
    pair.odom_i_from_odom_j =
        Rigid3d(YawRotation(yaw), Eigen::Vector3d::Zero());
    pair.cam_i_from_cam_j = CameraMotionFromOdometryMotion(
        pair.odom_i_from_odom_j, odom_from_cam, 0.5);
    pairs.push_back(pair);
  }
  const CalibrationResult result = CalibrateOdomCam(pairs, {});
  EXPECT_EQ(result.status, CalibrationStatus::kUnobservable) << result.message;
  EXPECT_TRUE(Contains(Unobservable(result), "metric_scale")) << result.message;
}

// Every motion turns by the same yaw but the lengths differ: the differences
// between motions still fix the scale and yaw, and the common part the lever
// arm. Observable, with a warning that all turns go one way.
TEST(CalibrateOdomCam, SameYawInEveryMotionWithDifferentLengths) {
  auto rng = SeededRng(43);
  const Rigid3d odom_from_cam = RandomOdomFromCam(&rng);
  MotionPairs pairs;
  const double yaw = 0.3;
  for (int i = 0; i < 30; ++i) {
    // A unicycle arc of length 0.2 .. 1.6 m turning by `yaw`.
    const double length = 0.2 + 0.05 * i;
    const double radius = length / yaw;
    const Rigid3d step(
        YawRotation(yaw),
        Eigen::Vector3d(
            radius * std::sin(yaw), radius * (1.0 - std::cos(yaw)), 0.0));
    MotionPair pair;
    pair.odom_i_from_odom_j = PerturbMotion(step,
                                            Eigen::Vector3d(1e-4, 1e-4, 1e-3),
                                            Eigen::Vector3d::Constant(1e-3),
                                            &rng);
    pair.cam_i_from_cam_j =
        PerturbMotion(CameraMotionFromOdometryMotion(step, odom_from_cam, 0.5),
                      Eigen::Vector3d::Constant(1e-4),
                      Eigen::Vector3d::Constant(1e-3),
                      &rng);
    pairs.push_back(pair);
  }
  CalibrationOptions options;
  options.fixed_translation_z_m = odom_from_cam.translation.z();
  const CalibrationResult result = CalibrateOdomCam(pairs, options);
  ASSERT_EQ(result.status, CalibrationStatus::kSuccess) << result.message;
  EXPECT_LT(RotationErrorDeg(result.odom_from_cam, odom_from_cam), 0.5);
  EXPECT_TRUE(std::find(result.warnings.begin(),
                        result.warnings.end(),
                        "all turns are in one direction") !=
              result.warnings.end());
}

// Finite inputs at the edge of double precision: either refused naming the
// pair, or a status whose estimate is finite whenever it is reported as one.
TEST(CalibrateOdomCam, HugeTranslationsNeverGiveNonFiniteEstimates) {
  auto rng = SeededRng(44);
  MotionSimulatorOptions simulation;
  const SimulatedMotions truth = SimulateMotions(simulation, &rng);
  for (const double magnitude : {1e100, 1e140, 1e150, 1e160, 1e300}) {
    for (const bool ransac : {true, false}) {
      SCOPED_TRACE(std::to_string(magnitude) + (ransac ? " ransac" : ""));
      MotionPairs pairs = truth.pairs;
      for (MotionPair& pair : pairs) {
        pair.odom_i_from_odom_j.translation *= magnitude;
        pair.cam_i_from_cam_j.translation *= magnitude;
      }
      CalibrationOptions options = OptionsFor(truth);
      options.use_ransac = ransac;
      CalibrationResult result;
      try {
        result = CalibrateOdomCam(pairs, options);
      } catch (const std::invalid_argument& error) {
        EXPECT_GT(magnitude, 1e154);
        EXPECT_NE(std::string(error.what()).find("too large"),
                  std::string::npos);
        continue;
      }
      if (result.has_estimate) {
        EXPECT_TRUE(IsFinite(result.odom_from_cam)) << result.message;
      }
      if (result.status == CalibrationStatus::kSuccess) {
        for (const double scale : result.metric_scales)
          EXPECT_TRUE(std::isfinite(scale));
        ASSERT_TRUE(result.covariance.has_value());
        EXPECT_TRUE(result.covariance->allFinite());
      }
    }
  }
}

// A translation whose square overflows is refused like a NaN.
TEST(CalibrateOdomCam, TranslationTooLargeToSquareThrows) {
  auto rng = SeededRng(45);
  MotionSimulatorOptions simulation;
  SimulatedMotions truth = SimulateMotions(simulation, &rng);
  truth.pairs[3].cam_i_from_cam_j.translation.x() = 1e300;
  try {
    CalibrateOdomCam(truth.pairs, {});
    FAIL() << "accepted a translation of 1e300";
  } catch (const std::invalid_argument& error) {
    EXPECT_EQ(std::string(error.what()),
              "motion pair 3 has a translation too large to square in double "
              "precision (check the units)");
  }
}

TEST(CalibrationOptions, CheckNamesTheBadField) {
  CalibrationOptions options;
  options.noise.cam_rotation_sigma_deg = -1.0;
  try {
    options.Check();
    FAIL() << "Check() accepted a negative sigma";
  } catch (const std::invalid_argument& error) {
    // The field's name first (the CLI's flag name), the shortest number.
    EXPECT_EQ(std::string(error.what()),
              "cam_rotation_sigma_deg must be finite and > 0, got -1");
  }
  options = CalibrationOptions();
  options.ransac_min_inlier_ratio = 1.5;
  try {
    options.Check();
    FAIL() << "Check() accepted an inlier ratio above 1";
  } catch (const std::invalid_argument& error) {
    EXPECT_EQ(std::string(error.what()),
              "ransac_min_inlier_ratio must be in [0, 1], got 1.5");
  }
}

// One segment's undetermined scale is named, but does not void the
// extrinsic and the other scales.
TEST(CalibrateOdomCam, SegmentWithoutPairsHasAnUndeterminedScale) {
  auto rng = SeededRng(40);
  MotionSimulatorOptions simulation;
  SimulatedMotions truth = SimulateMotions(simulation, &rng);
  for (MotionPair& pair : truth.pairs) pair.segment = 0;
  truth.pairs.back().segment = 2;  // segment 1 has no pairs at all
  CalibrationOptions options = OptionsFor(truth);
  options.use_ransac = false;
  const CalibrationResult result = CalibrateOdomCam(truth.pairs, options);
  EXPECT_EQ(result.status, CalibrationStatus::kSuccess) << result.message;
  EXPECT_TRUE(Contains(Unobservable(result), "metric_scale[1]"));
  EXPECT_FALSE(Contains(Unobservable(result), "metric_scale[0]"));
  ASSERT_FALSE(result.warnings.empty());
  EXPECT_NE(result.warnings.back().find("metric_scale[1]"), std::string::npos);
}

TEST(CalibrateOdomCam, AllSegmentScalesUndeterminedIsUnobservable) {
  auto rng = SeededRng(41);
  MotionSimulatorOptions simulation;
  simulation.num_pairs = 6;
  SimulatedMotions truth = SimulateMotions(simulation, &rng);
  // Every pair its own segment: no scale is constrained by more than one
  // motion, so none is determined to 5 %.
  for (size_t i = 0; i < truth.pairs.size(); ++i) truth.pairs[i].segment = i;
  CalibrationOptions options = OptionsFor(truth);
  options.use_ransac = false;
  options.noise.odom_translation_sigma_m = 0.05;
  // Exact data: the noise estimated from them would be ~0 (so would every
  // standard deviation); the observability verdict under the given noise is
  // the subject here.
  options.estimate_noise = false;
  const CalibrationResult result = CalibrateOdomCam(truth.pairs, options);
  EXPECT_EQ(result.status, CalibrationStatus::kUnobservable) << result.message;
}

}  // namespace
}  // namespace odomcal
